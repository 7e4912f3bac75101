"""plan() from Python: seed 000's A* counters on the paper maps, outcomes, planners()."""

import sys

import numpy as np
import pytest

import gridplan
from conftest import MAPS

# Seed 000 (Chotikunnan et al. 2026), Table 7, map 10 ("Map 4" of the 12x12 maps), and
# Table 3's D, T, Score for A*; the same numbers as snapshots/paper.snap.
MAP10_ASTAR = {
    "n_expanded": 70,
    "n_neighbor_checks": 276,
    "n_blocked": 134,
    "n_skipped": 70,
    "n_open_insertions": 71,
    "n_relaxations": 70,
}

PAPER_ASTAR = dict(heuristic="manhattan", order="R L D U", tie_break="fifo")


def test_map10_astar_counters_are_seed_000s():
    grid, problems = gridplan.read_map(MAPS / "paper" / "map10.map")
    assert (grid.width, grid.height) == (12, 12)
    assert problems == []
    outcome = gridplan.plan(grid, (0, 0), (11, 11), planner="astar", **PAPER_ASTAR)
    assert outcome.status == "found"
    counters = {k: v for k, v in outcome.counters.items() if k in MAP10_ASTAR}
    assert counters == MAP10_ASTAR
    # The planner's order, not alphabetical, and its own extra counter last.
    assert list(outcome.counters) == list(MAP10_ASTAR) + ["peak_open"]
    assert outcome.metrics == {"steps": 22, "turns": 6, "score": 28, "length": 22.0}
    assert outcome.path.shape == (23, 2)
    assert outcome.path.dtype == np.int64
    assert tuple(outcome.path[0]) == (0, 0) and tuple(outcome.path[-1]) == (11, 11)
    # Every step is one 4-connected move onto a free cell.
    steps = np.abs(np.diff(outcome.path, axis=0)).sum(axis=1)
    assert (steps == 1).all()
    assert all(grid.is_free(tuple(c)) for c in outcome.path)
    assert outcome.valid is True
    assert outcome.seed is None
    assert outcome.marks == []


@pytest.mark.skipif(sys.version_info < (3, 11), reason="tomllib is Python 3.11+")
def test_every_published_astar_counter_of_seed_000():
    import tomllib

    published = tomllib.loads((MAPS / "paper" / "published.toml").read_text())
    checked = 0
    for stem, table in published.items():
        if not isinstance(table, dict) or "astar" not in table:
            continue
        grid, _ = gridplan.read_map(MAPS / "paper" / table.get("file", f"{stem}.map"))
        goal = (grid.width - 1, grid.height - 1)
        outcome = gridplan.plan(grid, (0, 0), goal, **PAPER_ASTAR)
        measured = dict(outcome.counters, **outcome.metrics)
        for metric, value in table["astar"].items():
            assert measured[metric] == value, (stem, metric)
            checked += 1
    assert checked == 12 * 9


def test_default_astar_parameters_are_the_papers():
    grid, _ = gridplan.read_map(MAPS / "paper" / "map10.map")
    explicit = gridplan.plan(grid, (0, 0), (11, 11), **PAPER_ASTAR)
    default = gridplan.plan(grid, (0, 0), (11, 11))
    assert default.counters == explicit.counters
    assert (default.path == explicit.path).all()


def test_budget_stops_the_search():
    grid, _ = gridplan.read_map(MAPS / "paper" / "map10.map")
    outcome = gridplan.plan(grid, (0, 0), (11, 11), budget=10)
    assert outcome.status == "budget_exhausted"
    assert outcome.counters["n_expanded"] == 10
    as_dict = gridplan.plan(grid, (0, 0), (11, 11), budget={"max_expansions": 10})
    assert as_dict.counters == outcome.counters


def test_unreachable_goal_is_no_path_not_an_error():
    free = np.ones((3, 5), dtype=bool)
    free[:, 2] = False
    grid = gridplan.Grid.from_numpy(free, free=True)
    outcome = gridplan.plan(grid, (0, 0), (4, 2))
    assert outcome.status == "no_path"
    assert outcome.path.shape == (0, 2)
    assert outcome.metrics is None and outcome.valid is None


def test_seeded_planner_reports_its_seed_and_repeats():
    grid, problems = gridplan.read_map(MAPS / "wpi" / "map1.txt")
    start, goal = problems[0].start, problems[0].goal
    a = gridplan.plan(grid, start, goal, planner="rrt", seed=7)
    b = gridplan.plan(grid, start, goal, planner="rrt", seed=7)
    assert a.seed == 7
    assert a.status == "found"
    assert a.counters == b.counters and (a.path == b.path).all()


def test_marks_and_coverage():
    grid, _ = gridplan.read_map(MAPS / "paper" / "map10.map")
    jps = gridplan.plan(grid, (0, 0), (11, 11), planner="jps")
    assert jps.status == "found" and jps.marks
    assert all(isinstance(label, str) and grid.is_free(cell) for label, cell in jps.marks)
    covered = gridplan.plan(grid, (0, 0), planner="coverage")
    assert covered.status == "found"
    assert covered.counters["n_covered"] == covered.counters["n_reachable"]


def test_planners_come_from_the_registry_with_their_defaults():
    infos = {p.name: p for p in gridplan.planners()}
    assert "astar" in infos and "coverage" in infos
    astar = infos["astar"]
    assert astar.task == "start_goal" and astar.seeded is False
    assert astar.parameters["heuristic"] == "manhattan"
    assert astar.parameters["order"] == "R L D U"
    assert infos["coverage"].task == "coverage"
    assert infos["rrt"].seeded is True and "seed" in infos["rrt"].parameters
    # What each planner declares it is, with its defaults.
    assert (astar.admissible, astar.cell_costs, astar.path_rule) == (True, True, "4-connected")
    assert infos["theta_star"].path_rule == "any-angle"
    assert infos["theta_star"].admissible is None and infos["theta_star"].cell_costs is False
    assert infos["dstar_lite"].incremental is True and astar.incremental is False
    assert infos["jps"].admissible is True and infos["jps"].path_rule == "8-connected"
    # The declared defaults are the defaults: passed back explicitly, every planner
    # plans map10 exactly as without them.
    grid, _ = gridplan.read_map(MAPS / "paper" / "map10.map")
    for info in infos.values():
        params = {k: v for k, v in info.parameters.items() if v is not None}
        goal = None if info.task == "coverage" else (11, 11)
        explicit = gridplan.plan(grid, (0, 0), goal, planner=info.name, **params)
        default = gridplan.plan(grid, (0, 0), goal, planner=info.name)
        assert explicit.status in ("found", "no_path"), info.name
        assert explicit.status == default.status, info.name
        assert explicit.counters == default.counters, info.name
        assert (explicit.path == default.path).all(), info.name
