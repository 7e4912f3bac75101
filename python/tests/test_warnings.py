"""What the readers doubt or ignore reaches Python as ``gridplan.GridplanWarning``, as the
command line prints it on stderr (``python/src/warn.rs``)."""

import warnings

import numpy as np
import pytest

import gridplan

YAML = """image: tiny.pgm
resolution: 0.05
origin: [0.0, 0.0, 0.0]
negate: 0
occupied_thresh: 0.65
free_thresh: 0.196
---
image: other.pgm
"""


def tiny_ros_map(folder):
    """A 3 x 2 map_server map whose YAML holds a second document (map_server ignores it)."""
    (folder / "tiny.pgm").write_bytes(b"P5\n3 2\n255\n" + bytes([254, 0, 254, 254, 254, 254]))
    path = folder / "tiny.yaml"
    path.write_text(YAML)
    return path


def test_a_map_readers_doubt_is_a_warning(tmp_path):
    path = tiny_ros_map(tmp_path)
    with pytest.warns(gridplan.GridplanWarning, match="second YAML document is ignored"):
        grid, _ = gridplan.read_map(path)
    assert grid.shape == (2, 3)
    # Raised once: the next call starts without it.
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        gridplan.read_map(tmp_path / "tiny.pgm")


def test_the_warnings_filter_decides(tmp_path):
    path = tiny_ros_map(tmp_path)
    with warnings.catch_warnings():
        warnings.simplefilter("error", gridplan.GridplanWarning)
        with pytest.raises(gridplan.GridplanWarning, match="tiny.yaml:7"):
            gridplan.read_map(path)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", gridplan.GridplanWarning)
        grid, _ = gridplan.read_map(path)
    assert grid.n_free == 5


def test_a_run_the_memory_limit_refuses_warns_from_every_plan_call():
    grid = gridplan.Grid.from_numpy(np.zeros((50, 50), dtype=bool), free=False)
    budget = {"max_memory_mb": 0}
    planner = gridplan.Planner(grid, "astar", budget=budget)
    calls = [
        lambda: gridplan.plan(grid, (0, 0), (49, 49), budget=budget).status,
        lambda: planner.plan((0, 0), (49, 49)).status,
        lambda: planner.plan_many([[0, 0]], [[49, 49]])["status"][0],
    ]
    for call in calls:
        with pytest.warns(gridplan.GridplanWarning, match="over the max_memory_mb = 0 budget; not run"):
            assert call() == "budget_exhausted"
