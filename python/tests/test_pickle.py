"""Results are values: Outcome, Grid, MapFrame, Problem and PlannerInfo pickle and copy (a
``multiprocessing`` worker returns them), and an Outcome equals one of the same results."""

import copy
import multiprocessing
import pickle

import numpy as np
import pytest

import gridplan
from conftest import MAPS

ARENA = MAPS / "movingai" / "arena.map"
SANDBOX = MAPS / "ros-nav2" / "tb3_sandbox.yaml"


def round_trips(value):
    """`value` pickled and unpickled, and deep-copied."""
    return [pickle.loads(pickle.dumps(value)), copy.deepcopy(value), copy.copy(value)]


def test_an_outcome_pickles_and_equals_one_of_the_same_results():
    grid, problems = gridplan.read_map(ARENA)
    p = problems[40]
    outcome = gridplan.plan(grid, p.start, p.goal, moves=8, heuristic="octile", record=True)
    for back in round_trips(outcome):
        assert back == outcome and not back != outcome
        assert back.time_ms == outcome.time_ms and back.counters == outcome.counters
        np.testing.assert_array_equal(back.path, outcome.path)
        np.testing.assert_array_equal(back.expanded, outcome.expanded)
        assert back.events.keys() == outcome.events.keys()
        assert not back.path.flags.writeable and not back.events["g"].flags.writeable
    # Equal results, another time: equal (time_ms is a measurement).
    again = gridplan.plan(grid, p.start, p.goal, moves=8, heuristic="octile", record=True)
    assert again == outcome
    assert gridplan.plan(grid, p.start, p.goal, moves=8, heuristic="octile") != outcome
    assert gridplan.plan(grid, p.start, p.goal) != outcome
    assert outcome != "an outcome"
    # Series (arrays in a dict) and a weighted grid's cost pickle too.
    rrt = gridplan.plan(grid, p.start, p.goal, planner="rrt_star", seed=3)
    assert rrt.series and pickle.loads(pickle.dumps(rrt)) == rrt
    weighted = grid.with_weights(np.full(grid.shape, 2))
    cost = gridplan.plan(weighted, p.start, p.goal)
    assert cost.cost is not None and pickle.loads(pickle.dumps(cost)) == cost


def test_an_outcome_cannot_be_changed_through_what_it_gives():
    grid, problems = gridplan.read_map(ARENA)
    p = problems[40]
    outcome = gridplan.plan(grid, p.start, p.goal, planner="rrt_star", seed=3, record=True)
    kept = pickle.loads(pickle.dumps(outcome))
    # `outcome.path[:] = 0` changed the outcome for good.
    for array in [outcome.path, outcome.expanded, *outcome.series.values()]:
        with pytest.raises(ValueError, match="read-only"):
            array[:] = 0
    outcome.counters["n_expanded"] = -1
    outcome.metrics["steps"] = -1
    outcome.marks.append(("x", (0, 0)))
    outcome.series.clear()
    outcome.events.clear()
    assert outcome == kept


def test_grids_frames_problems_and_planner_infos_pickle():
    grid, problems = gridplan.read_map(ARENA)
    for back in round_trips(grid):
        assert back == grid and back.frame is None
    assert pickle.loads(pickle.dumps(problems)) == problems
    ros, _ = gridplan.read_map(SANDBOX)
    weighted = ros.with_weights(np.arange(ros.width * ros.height).reshape(ros.shape) % 9 + 1, cost_rule="entered")
    for back in round_trips(weighted):
        assert back == weighted and back.cost_rule == "entered"
        assert back.frame == ros.frame
        np.testing.assert_array_equal(back.weights, weighted.weights)
    assert pickle.loads(pickle.dumps(ros.frame)) == ros.frame
    infos = gridplan.planners()
    for info, back in zip(infos, pickle.loads(pickle.dumps(infos))):
        fields = ["name", "summary", "task", "seeded", "admissible", "cell_costs", "path_rule", "parameters"]
        assert [getattr(back, f) for f in fields] == [getattr(info, f) for f in fields]


def _plan_in_worker(i):
    grid, problems = gridplan.read_map(ARENA)
    p = problems[i]
    return gridplan.plan(grid, p.start, p.goal), grid, p, gridplan.planners()[0]


def test_a_pool_worker_returns_outcomes():
    """A multiprocessing worker's results come back pickled: they raised MaybeEncodingError."""
    grid, problems = gridplan.read_map(ARENA)
    with multiprocessing.get_context("fork").Pool(2) as pool:
        results = pool.map(_plan_in_worker, [3, 40])
    for i, (outcome, their_grid, problem, info) in zip([3, 40], results):
        assert outcome == gridplan.plan(grid, problems[i].start, problems[i].goal)
        assert outcome.status == "found"
        assert their_grid == grid and problem == problems[i]
        assert info.name == gridplan.planners()[0].name
