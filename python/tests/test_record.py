"""``plan(..., record=True)``: the search step by step (A*'s events with parent, g and f)
and the expanded cells, consistent with the counters and the path."""

from pathlib import Path

import numpy as np

import gridplan

ROOT = Path(__file__).resolve().parents[2]


def test_astar_records_its_steps():
    grid, problems = gridplan.read_map(ROOT / "maps" / "movingai" / "arena.map")
    problem = problems[40]
    outcome = gridplan.plan(
        grid, problem.start, problem.goal, moves=8, heuristic="octile", record=True
    )
    plain = gridplan.plan(grid, problem.start, problem.goal, moves=8, heuristic="octile")
    assert plain.expanded is None and plain.events is None
    assert outcome.counters == plain.counters
    np.testing.assert_array_equal(outcome.path, plain.path)
    events = outcome.events
    n = len(events["kind"])
    assert all(len(column) == n for column in events.values())
    kinds = list(events["kind"])
    assert kinds.count("generating") == outcome.counters["n_open_insertions"]
    assert kinds.count("expanding") == outcome.counters["n_expanded"]
    expanding = np.array([k == "expanding" for k in kinds])
    np.testing.assert_array_equal(
        np.column_stack([events["x"][expanding], events["y"][expanding]]), outcome.expanded
    )
    # f = g + octile distance to the goal, written out here.
    dx = np.abs(events["x"] - problem.goal[0])
    dy = np.abs(events["y"] - problem.goal[1])
    h = np.maximum(dx, dy) + (np.sqrt(2) - 1) * np.minimum(dx, dy)
    np.testing.assert_allclose(events["f"], events["g"] + h, rtol=1e-9, atol=1e-9)
    # The goal's expansion ends the search with the path's length as its g, and the start
    # has no parent.
    assert kinds[-1] == "expanding"
    assert (events["x"][-1], events["y"][-1]) == problem.goal
    assert abs(events["g"][-1] - outcome.metrics["length"]) < 1e-9
    assert (events["parent_x"][0], events["parent_y"][0]) == (-1, -1)


def test_planners_without_steps_record_their_expanded_cells():
    grid, problems = gridplan.read_map(ROOT / "maps" / "movingai" / "arena.map")
    problem = problems[40]
    outcome = gridplan.plan(grid, problem.start, problem.goal, planner="bfs", record=True)
    assert len(outcome.expanded) == outcome.counters["n_expanded"]
    assert all(len(column) == 0 for column in outcome.events.values())
