"""What the readers doubt or ignore reaches Python as ``gridplan.GridplanWarning``, as the
command line prints it on stderr (``python/src/warn.rs``)."""

import threading
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


def warnings_of_two_threads(work):
    """Runs `work(name)` on two threads named "refused" and "plain", started together,
    and returns the warnings shown as (thread name, text) pairs."""
    shown = []
    lock = threading.Lock()
    barrier = threading.Barrier(2)

    def show(message, category, filename, lineno, file=None, line=None):
        with lock:
            shown.append((threading.current_thread().name, str(message)))

    def start():
        barrier.wait()
        work(threading.current_thread().name)

    with warnings.catch_warnings():
        warnings.simplefilter("always")
        warnings.showwarning = show
        threads = [threading.Thread(target=start, name=name) for name in ["refused", "plain"]]
        for thread in threads:
            thread.start()
        for thread in threads:
            thread.join()
    return shown


def test_two_threads_planning_at_once_each_get_their_own_warnings():
    """One thread's runs are refused (each call warns), the other's are not: every warning
    is raised on the thread whose call it belongs to, once, from every entry point."""
    grid = gridplan.Grid.from_numpy(np.zeros((50, 50), dtype=bool), free=False)
    refused = {"max_memory_mb": 0}
    planners = {
        "refused": gridplan.Planner(grid, "astar", budget=refused),
        "plain": gridplan.Planner(grid, "astar"),
    }
    budgets = {"refused": refused, "plain": None}
    rounds = 200

    def work(name):
        for _ in range(rounds):
            gridplan.plan(grid, (0, 0), (49, 49), budget=budgets[name])
            planners[name].plan((0, 0), (49, 49))
            planners[name].plan_many([[0, 0]], [[49, 49]], threads=2)

    shown = warnings_of_two_threads(work)
    assert {name for name, _ in shown} == {"refused"}
    assert len(shown) == 3 * rounds
    assert all("over the max_memory_mb = 0 budget; not run" in text for _, text in shown)


def sweep_config(folder, name, budget):
    """A config of 40 runs of A* on an open 50 x 50 map, with `budget` lines."""
    rows = "\n".join("." * 50 for _ in range(50))
    (folder / f"{name}.map").write_text(f"type octile\nheight 50\nwidth 50\nmap\n{rows}\n")
    path = folder / f"{name}.toml"
    path.write_text(
        f'name = "{name}"\nrepeats = 40\n\n[budget]\n{budget}\n\n'
        f'[[maps]]\nfiles = ["{name}.map"]\nproblems = "corners"\n\n'
        '[planners.astar]\nplanner = "astar"\n'
    )
    return path


def test_two_sweeps_at_once_each_get_their_own_warnings(tmp_path):
    """The runner's worker threads warn on behalf of the sweep that started them: one
    sweep's runs are all refused, the other's are not, and each warning is raised on the
    refused sweep's thread only."""
    configs = {
        "refused": sweep_config(tmp_path, "refused", "max_memory_mb = 0"),
        "plain": sweep_config(tmp_path, "plain", "max_expansions = 1_000_000"),
    }
    rounds = 20

    def work(name):
        for _ in range(rounds):
            gridplan.run_experiment(configs[name], threads=2)

    shown = warnings_of_two_threads(work)
    assert {name for name, _ in shown} == {"refused"}
    assert len(shown) == 40 * rounds
    assert all("over the max_memory_mb = 0 budget; not run" in text for _, text in shown)


def test_control_characters_in_warnings_are_escaped(tmp_path):
    """A warning's text holds no control character but line breaks and tabs: a path with
    an escape sequence reaches the terminal as \\u{1b}, as the command line writes it."""
    folder = tmp_path / "e\x1b[2Jx"
    folder.mkdir()
    path = tiny_ros_map(folder)
    with pytest.warns(gridplan.GridplanWarning) as caught:
        gridplan.read_map(path)
    texts = [str(w.message) for w in caught]
    assert any("e\\u{1b}[2Jx" in text for text in texts), texts
    assert not any("\x1b" in text for text in texts), texts


def test_a_scenario_naming_another_map_is_a_warning(tmp_path):
    """As `gridplan plan` warns (sc2.map.scen:2: the scenario names map other.map, not
    sc2.map), once per file; read_map said nothing."""
    (tmp_path / "sc2.map").write_text("type octile\nheight 3\nwidth 3\nmap\n...\n...\n...\n")
    (tmp_path / "sc2.map.scen").write_text(
        "version 1\n"
        "0\tother.map\t3\t3\t0\t0\t2\t2\t2.8\n"
        "0\tother.map\t3\t3\t0\t0\t1\t1\t1.4\n"
    )
    with pytest.warns(gridplan.GridplanWarning) as caught:
        _, problems = gridplan.read_map(tmp_path / "sc2.map")
    assert [str(w.message) for w in caught] == [
        f"{tmp_path / 'sc2.map.scen'}:2: the scenario names map other.map, not sc2.map"
    ]
    assert [p.goal for p in problems] == [(2, 2), (1, 1)]
    # A scenario of its own map (a path before the name is fine) says nothing.
    (tmp_path / "sc2.map.scen").write_text("version 1\n0\tmaps/sc2.map\t3\t3\t0\t0\t2\t2\t2.8\n")
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        gridplan.read_map(tmp_path / "sc2.map")
