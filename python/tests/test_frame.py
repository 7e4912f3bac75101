"""A ROS map's frame from Python: cells and map-frame points (metres) both ways, as
``gridplan plan --start-world`` converts them (nav2's ``mapToWorld`` and ``worldToMap``)."""

from pathlib import Path

import numpy as np
import pytest

import gridplan

ROOT = Path(__file__).resolve().parents[2]
SANDBOX = ROOT / "maps" / "ros-nav2" / "tb3_sandbox.yaml"


def test_a_yaml_map_has_its_frame():
    grid, _ = gridplan.read_map(SANDBOX)
    frame = grid.frame
    assert frame.resolution == 0.05
    assert frame.origin == (-10.0, -10.0, 0.0)
    assert frame.bounds == pytest.approx((-10.0, -10.0, 9.2, 9.2))
    # Worked out by hand: column floor((x + 10) / 0.05), row 383 - floor((y + 10) / 0.05).
    assert frame.cell((-1.5, -0.5)) == (170, 193)
    assert frame.cell((-1.51, -0.51)) == (169, 194)
    assert frame.world((170, 193)) == pytest.approx((-1.475, -0.475))
    with pytest.raises(ValueError, match=r"lies outside the map, which spans x from -10"):
        frame.cell((-10.01, 0.0))
    with pytest.raises(ValueError, match="is not on the 384x384 map"):
        frame.world((384, 0))
    # A path's cells as an (N, 2) array of points, each the cell's centre.
    outcome = gridplan.plan(grid, frame.cell((-1.5, -0.5)), frame.cell((1.5, 0.5)))
    points = frame.world(outcome.path)
    assert points.shape == (len(outcome.path), 2) and points.dtype == np.float64
    expect = np.column_stack(
        [-10 + 0.05 * (outcome.path[:, 0] + 0.5), -10 + 0.05 * (383 - outcome.path[:, 1] + 0.5)]
    )
    np.testing.assert_allclose(points, expect, atol=1e-9)
    # Every cell back from its centre.
    for cell in outcome.path:
        assert frame.cell(tuple(frame.world(tuple(cell)))) == tuple(cell)


def test_only_yaml_maps_have_a_frame():
    grid, _ = gridplan.read_map(SANDBOX)
    assert grid.with_weights(np.ones(grid.shape, dtype=np.int64)).frame == grid.frame
    assert gridplan.Grid.from_numpy(grid.to_numpy(), free=True).frame is None
    assert gridplan.Grid.from_numpy(grid.to_numpy(), free=True) == grid
    moving_ai, _ = gridplan.read_map(ROOT / "maps" / "paper" / "map10.map")
    assert moving_ai.frame is None
    with pytest.raises(TypeError, match="integers"):
        grid.frame.world(np.array([[1.5, 2.0]]))


def test_large_metres_are_written_compactly():
    """MapFrame.cell((1e300, 1e300)) and the repr of a frame at origin 1e308 printed each
    number in some 300 digits."""
    frame = gridplan.read_map(SANDBOX)[0].frame
    with pytest.raises(ValueError) as e:
        frame.cell((1e300, -1.5e-300))
    assert str(e.value).startswith(
        "MapFrame.cell: point (1e300, -1.5e-300) lies outside the map, which spans"
    )
    far = type(frame)._from_state(0.05, [1e308, -1e308, 0.0], 4, 3)
    assert repr(far) == "MapFrame(resolution=0.05, origin=(1e308, -1e308, 0), width=4, height=3)"
    # Everyday numbers as before.
    assert repr(frame) == "MapFrame(resolution=0.05, origin=(-10, -10, 0), width=384, height=384)"
