"""Replanner: an incremental planner's session; every repair equals A* from scratch on the
map as updated (the oracle the replanning experiments use), for less work."""

import numpy as np
import pytest

import gridplan
from conftest import MAPS

ARENA = MAPS / "movingai" / "arena.map"
# A* with D* Lite's and LPA*'s moves: 8, no corner cutting, exact costs.
ORACLE = dict(planner="astar", moves=8, corner_cutting=False, heuristic="octile")


@pytest.fixture(scope="module")
def arena():
    return gridplan.read_map(ARENA)


def oracle(grid, start, goal):
    return gridplan.plan(grid, start, goal, **ORACLE)


def same_answer(ours, theirs, weighted=False):
    assert ours.status == theirs.status
    if theirs.status != "found":
        assert ours.path.shape == (0, 2)
        return
    assert ours.valid is True
    if weighted:
        assert ours.cost == pytest.approx(theirs.cost, rel=1e-12)
    else:
        assert ours.metrics["length"] == pytest.approx(theirs.metrics["length"], rel=1e-12)


@pytest.mark.parametrize("name", ["dstar_lite", "lpastar"])
def test_repairs_equal_astar_from_scratch(arena, name):
    grid, problems = arena
    problem = max(problems[:60], key=lambda p: abs(p.goal[0] - p.start[0]) + abs(p.goal[1] - p.start[1]))
    replanner = gridplan.Replanner(grid, name, start=problem.start, goal=problem.goal)
    assert (replanner.name, replanner.start, replanner.goal) == (name, problem.start, problem.goal)
    first = replanner.plan()
    same_answer(first, oracle(grid, problem.start, problem.goal))
    repaired, scratch = 0, 0
    path = first.path
    for round in range(6):
        # Walls across the current path, away from its ends: the path must change.
        inner = [tuple(c) for c in path[3:-3]]
        if not inner:
            break
        middle = inner[len(inner) // 2]
        wall = [(middle[0] + dx, middle[1] + dy) for dx in (-1, 0, 1) for dy in (-1, 0, 1)]
        wall = [c for c in wall if 0 <= c[0] < grid.width and 0 <= c[1] < grid.height]
        wall = [c for c in wall if c not in (replanner.start, replanner.goal)]
        replanner.update(np.array(wall), free=False)
        assert not any(replanner.grid.is_free(c) for c in wall)
        ours = replanner.plan()
        theirs = oracle(replanner.grid, replanner.start, problem.goal)
        same_answer(ours, theirs)
        if ours.status != "found":
            break
        assert not {tuple(c) for c in ours.path} & set(wall)
        repaired += ours.counters["n_expanded"]
        scratch += theirs.counters["n_expanded"]
        # The agent drives three cells along the repaired path.
        replanner.move_to(tuple(ours.path[3]))
        assert replanner.start == tuple(ours.path[3])
        path = ours.path[3:]
    if name == "dstar_lite":
        # D* Lite's point: repairs expand fewer nodes than searches from scratch.
        assert 0 < repaired < scratch
    # The session's grid is a copy: the caller's is as it was.
    assert grid == gridplan.read_map(ARENA)[0]


def test_cutting_the_goal_off_and_freeing_it(map10):
    replanner = gridplan.Replanner(map10, "dstar_lite", start=(0, 0), goal=(11, 11))
    assert replanner.plan().status == "found"
    ring = [(11 + dx, 11 + dy) for dx in (-1, 0) for dy in (-1, 0) if (dx, dy) != (0, 0)]
    replanner.update(np.array(ring), free=False)
    cut = replanner.plan()
    assert cut.status == "no_path" and cut.path.shape == (0, 2) and cut.valid is None
    replanner.update(np.array(ring), free=np.array([True, False, False]))
    again = replanner.plan()
    same_answer(again, oracle(replanner.grid, (0, 0), (11, 11)))


def test_weights_change_the_costs(arena):
    grid, problems = arena
    problem = problems[40]
    weighted = grid.with_weights(np.ones(grid.shape, dtype=np.uint16))
    replanner = gridplan.Replanner(weighted, "dstar_lite", start=problem.start, goal=problem.goal)
    first = replanner.plan()
    same_answer(first, oracle(weighted, problem.start, problem.goal), weighted=True)
    # A swamp of weight 50 over the middle of the path; its state stays as it was.
    inner = first.path[2:-2]
    replanner.update(inner, weights=50)
    assert replanner.grid.weights[inner[:, 1], inner[:, 0]].tolist() == [50] * len(inner)
    ours = replanner.plan()
    same_answer(ours, oracle(replanner.grid, problem.start, problem.goal), weighted=True)
    # Raising weights never lowers the least cost (an equal detour may exist).
    assert ours.cost >= first.cost
    # One weight per cell, some of them back to 1.
    weights = np.where(np.arange(len(inner)) % 2 == 0, 1, 50)
    replanner.update(inner, weights=weights)
    same_answer(replanner.plan(), oracle(replanner.grid, problem.start, problem.goal), weighted=True)


def test_bad_arguments_raise_named_errors(map10):
    with pytest.raises(ValueError, match="not an incremental planner.*dstar_lite"):
        gridplan.Replanner(map10, "astar", start=(0, 0), goal=(11, 11))
    with pytest.raises(gridplan.ParameterError) as error:
        gridplan.Replanner(map10, "dstar_lite", start=(0, 0), goal=(11, 11), moves=6)
    assert error.value.key == "moves"
    blocked = tuple(int(v) for v in np.argwhere(~map10.to_numpy(free=True))[0][::-1])
    with pytest.raises(gridplan.ProblemError) as error:
        gridplan.Replanner(map10, "dstar_lite", start=blocked, goal=(11, 11))
    assert (error.value.endpoint, error.value.cell) == ("start", blocked)
    with pytest.raises(gridplan.ProblemError) as error:
        gridplan.Replanner(map10, "dstar_lite", start=(0, 0), goal=(-1, 99))
    assert error.value.endpoint == "goal"
    replanner = gridplan.Replanner(map10, "dstar_lite", start=(0, 0), goal=(11, 11))
    # No changes at all: a robot's step that saw none.
    replanner.update([], free=False)
    replanner.update(np.empty((0, 2), dtype=np.int64), free=False)
    before = replanner.grid
    assert before == map10
    with pytest.raises(ValueError, match=r"cells\[1\]: \(12, 0\) is outside the 12x12 grid"):
        replanner.update(np.array([(1, 0), (12, 0)]), free=False)
    assert replanner.grid == before, "a refused update applied a change"
    with pytest.raises(ValueError, match="the grid has no weights"):
        replanner.update(np.array([(1, 0)]), weights=3)
    with pytest.raises(TypeError, match="give `free`"):
        replanner.update(np.array([(1, 0)]))
    with pytest.raises(ValueError, match="one value or 2"):
        replanner.update(np.array([(1, 0), (2, 0)]), free=[True, False, True])
    with pytest.raises(TypeError, match="free: expected booleans"):
        replanner.update(np.array([(1, 0)]), free=1)
    with pytest.raises(ValueError, match=r"query 0: \(0.5, 0.0\) is not a cell"):
        replanner.update(np.array([(0.5, 0.0)]), free=False)
    # Whole numbers too large for any grid are cells off it, as (12, 0) is.
    for cells, shown in (([(1, 0), (2**64, 0)], "18446744073709551616, 0"),
                         (np.array([(1, 0), (2**63, 0)], dtype=np.uint64), "9223372036854775808, 0"),
                         (np.array([(1, 0), (0, 1e30)]), "0, 1e30")):
        with pytest.raises(ValueError, match=rf"cells\[1\]: \({shown}\) is outside the 12x12 grid"):
            replanner.update(cells, free=False)
    assert replanner.grid == before, "a refused update applied a change"
    with pytest.raises(ValueError, match="move_to"):
        replanner.move_to(blocked)
    with pytest.raises(ValueError, match=r"move_to: \(40, 0\) is outside"):
        replanner.move_to((40, 0))
    weighted = gridplan.Replanner(
        map10.with_weights(np.ones(map10.shape, dtype=np.uint16)),
        "dstar_lite",
        start=(0, 0),
        goal=(11, 11),
    )
    for bad in (0, 65536, -3):
        with pytest.raises(ValueError, match=rf"weights\[0\]: {bad} is not a weight"):
            weighted.update(np.array([(1, 0)]), weights=bad)
    # A uint64 weight is named as given, not as its value cast to int64.
    with pytest.raises(ValueError, match=r"weights\[0\]: 9223372036854775808 is not a weight"):
        weighted.update(np.array([(1, 0)]), weights=np.array([2**63], dtype=np.uint64))
    with pytest.raises(TypeError, match="weights: expected integers"):
        weighted.update(np.array([(1, 0)]), weights=2.5)
    assert replanner.plan().status == "found"


_REPLANNING = None


def test_a_process_forked_while_another_thread_replans_is_told_to_make_a_new_replanner():
    """A child forked while a thread of the parent held a Replanner (its first plan, on a
    map whose goal is walled off) would wait for it forever: its calls raise GridplanError."""
    import multiprocessing
    import threading
    import time

    global _REPLANNING
    # The first plan searches the goal's half, 8 million cells: about 1.3 s here.
    free = np.ones((4000, 4000), dtype=bool)
    free[:, 2000] = False
    grid = gridplan.Grid.from_numpy(free, free=True)
    replanner = gridplan.Replanner(
        grid, "dstar_lite", start=(0, 0), goal=(3999, 3999), budget={"max_time_ms": 5000}
    )
    busy = threading.Thread(target=replanner.plan)
    busy.start()
    time.sleep(0.2)
    _REPLANNING = replanner
    try:
        with multiprocessing.get_context("fork").Pool(1) as pool:
            result = pool.apply_async(_replan_after_fork).get(timeout=30)
    finally:
        busy.join()
    assert result == (
        "GridplanError: this Replanner was in use by another thread when the process forked, "
        "and that thread does not exist in this process: make a new Replanner here"
    )


def _replan_after_fork():
    try:
        _REPLANNING.plan()
        return "planned"
    except gridplan.GridplanError as error:
        return f"{type(error).__name__}: {error}"
