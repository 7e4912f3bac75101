"""Cell costs from Python (issue 32): a Grid with weights from a NumPy integer array or a
weight file, the path's cost in results, held to an independent Dijkstra written here
in exact integers, and the refusal of planners that cannot honour costs."""

import heapq
import math
from pathlib import Path

import numpy as np
import pytest

import gridplan

ROOT = Path(__file__).resolve().parents[2]

# Cost units of planner-api: 2^32 per unit length, sqrt 2 as the integer below.
ONE = 1 << 32
SQRT_2 = 6_074_001_000


def oracle(free, weights, start, goal, rule="mean", diagonal=True):
    """Least cost from start to goal in cost units (None if unreachable): 8-connected
    without corner cutting (a diagonal needs both side cells free), a move costing half
    its length's units times (a + b) (mean) or 2 b (entered)."""
    h, w = free.shape
    moves = [(1, 0), (-1, 0), (0, 1), (0, -1)]
    if diagonal:
        moves += [(1, 1), (1, -1), (-1, 1), (-1, -1)]
    dist = {start: 0}
    heap = [(0, start)]
    while heap:
        d, (x, y) = heapq.heappop(heap)
        if (x, y) == goal:
            return d
        if d > dist[(x, y)]:
            continue
        for dx, dy in moves:
            nx, ny = x + dx, y + dy
            if not (0 <= nx < w and 0 <= ny < h) or not free[ny, nx]:
                continue
            if dx and dy and not (free[y, nx] and free[ny, x]):
                continue
            half = (SQRT_2 if dx and dy else ONE) // 2
            a, b = int(weights[y, x]), int(weights[ny, nx])
            step = half * (a + b if rule == "mean" else 2 * b)
            if d + step < dist.get((nx, ny), math.inf):
                dist[(nx, ny)] = d + step
                heapq.heappush(heap, (d + step, (nx, ny)))
    return None


def random_weighted(seed, size=16):
    rng = np.random.default_rng(seed)
    free = rng.random((size, size)) >= 0.25
    free[0, 0] = free[-1, -1] = True
    weights = rng.integers(1, 256, size=(size, size), dtype=np.int64)
    return free, weights


@pytest.mark.parametrize("rule", ["mean", "entered"])
def test_weighted_plans_match_the_oracle(rule):
    found = 0
    for seed in range(40):
        free, weights = random_weighted(seed)
        grid = gridplan.Grid.from_numpy(free, free=True).with_weights(weights, cost_rule=rule)
        assert grid.cost_rule == rule
        assert (grid.weights == weights).all()
        goal = (15, 15)
        best = oracle(free, weights, (0, 0), goal, rule)
        for planner, params in [("astar", {"moves": 8, "heuristic": "octile"}), ("bidirectional_astar", {"moves": 8})]:
            out = gridplan.plan(grid, (0, 0), goal, planner=planner, **params)
            if best is None:
                assert out.status == "no_path"
                assert out.cost is None
                continue
            found += 1
            assert out.status == "found"
            assert out.cost == pytest.approx(best / ONE, rel=0, abs=1e-6)
        # lexastar, 4-connected: its first criterion is the cost.
        best4 = oracle(free, weights, (0, 0), goal, rule, diagonal=False)
        out = gridplan.plan(grid, (0, 0), goal, planner="lexastar")
        assert (out.cost is None) == (best4 is None)
        if best4 is not None:
            assert out.cost == pytest.approx(best4 / ONE, rel=0, abs=1e-6)
    assert found >= 40


def test_unweighted_results_have_no_cost_and_weights_of_one_cost_the_length():
    free, _ = random_weighted(3)
    grid = gridplan.Grid.from_numpy(free, free=True)
    assert grid.weights is None and grid.cost_rule is None
    plain = gridplan.plan(grid, (0, 0), (15, 15), planner="astar", moves=8, heuristic="octile")
    assert plain.cost is None
    ones = grid.with_weights(np.ones(free.shape, dtype=np.uint8))
    assert ones != grid
    out = gridplan.plan(ones, (0, 0), (15, 15), planner="astar", moves=8, heuristic="octile")
    assert out.cost == pytest.approx(plain.metrics["length"], abs=1e-6)


def test_planners_that_cannot_honour_costs_are_refused():
    free, weights = random_weighted(5)
    grid = gridplan.Grid.from_numpy(free, free=True).with_weights(weights)
    with pytest.raises(gridplan.ParameterError, match="does not honour cell costs") as e:
        gridplan.plan(grid, (0, 0), (15, 15), planner="bfs")
    assert e.value.key == "costs"
    with pytest.raises(gridplan.ParameterError):
        gridplan.Planner(grid, "bfs")
    out = gridplan.plan(grid, (0, 0), (15, 15), planner="bfs", costs="ignore")
    assert out.status in ("found", "no_path")
    with pytest.raises(gridplan.ParameterError, match="costs"):
        gridplan.plan(grid, (0, 0), (15, 15), planner="bfs", costs="yes")
    # A prepared planner honours the weights too.
    prepared = gridplan.Planner(grid, "astar", moves=8, heuristic="octile")
    assert prepared.plan((0, 0), (15, 15)).cost == gridplan.plan(
        grid, (0, 0), (15, 15), planner="astar", moves=8, heuristic="octile"
    ).cost


def test_bad_weights_are_refused_with_the_cell():
    grid = gridplan.Grid.from_numpy(np.ones((2, 3), dtype=bool), free=True)
    bad = np.ones((2, 3), dtype=np.int64)
    bad[1, 2] = 0
    with pytest.raises(ValueError, match=r"cell \(2, 1\) \(array\[1, 2\]\) has weight 0"):
        grid.with_weights(bad)
    bad[1, 2] = 70000
    with pytest.raises(ValueError, match="has weight 70000"):
        grid.with_weights(bad)
    # An unsigned value beyond i64 is named as itself (it was named -1).
    huge = np.ones((2, 3), dtype=np.uint64)
    huge[0, 1] = 2**64 - 1
    with pytest.raises(ValueError, match=r"cell \(1, 0\) .* has weight 18446744073709551615"):
        grid.with_weights(huge)
    assert grid.with_weights(np.full((2, 3), 65535, dtype=np.uint16)).weights.max() == 65535
    with pytest.raises(TypeError, match="integer array"):
        grid.with_weights(np.ones((2, 3)) * 1.5)
    with pytest.raises(ValueError, match="shape"):
        grid.with_weights(np.ones((3, 2), dtype=np.int64))
    with pytest.raises(ValueError, match="cost_rule"):
        grid.with_weights(np.ones((2, 3), dtype=np.int64), cost_rule="median")


def test_read_map_with_a_weight_file_and_a_graded_ros_map(tmp_path):
    arena = ROOT / "maps/movingai/arena.map"
    weights = ROOT / "maps/weighted/arena-weights.csv"
    grid, _ = gridplan.read_map(arena, weights=weights)
    assert grid.cost_rule == "mean"
    free = grid.to_numpy()
    best = oracle(free, grid.weights, (3, 1), (46, 47))
    out = gridplan.plan(grid, (3, 1), (46, 47), planner="astar", moves=8, heuristic="octile")
    assert out.cost == pytest.approx(best / ONE, abs=1e-6)
    graded, _ = gridplan.read_map(ROOT / "maps/ros-graded/TenByTen-scale.yaml", graded=True)
    assert graded.weights is not None and 56 in graded.weights
    # Graded costs are a ROS map's own: refused elsewhere and beside a weight file, as by
    # `plan --graded` (they were silently ignored on a .map).
    with pytest.raises(ValueError, match="graded=True applies to ROS maps"):
        gridplan.read_map(arena, graded=True)
    with pytest.raises(ValueError, match="does not go with graded=True"):
        gridplan.read_map(ROOT / "maps/ros-graded/TenByTen-scale.yaml", graded=True, weights=weights)
    # So are an obstacle value for a map that is not a .csv and a cost rule without costs.
    with pytest.raises(ValueError, match="obstacle=1 applies to .csv maps"):
        gridplan.read_map(arena, obstacle=1)
    with pytest.raises(ValueError, match="needs costs to apply to"):
        gridplan.read_map(arena, cost_rule="entered")
    assert gridplan.read_map(arena, weights=weights, cost_rule="entered")[0].cost_rule == "entered"
    bad = tmp_path / "bad.csv"
    bad.write_text("1 1\n1 0\n")
    tiny = tmp_path / "tiny.csv"
    tiny.write_text("1,1\n1,1\n")
    with pytest.raises(gridplan.MapError) as e:
        gridplan.read_map(tiny, weights=bad)
    assert (e.value.line, e.value.column) == (2, 3)
