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


def gridplan_binary():
    """The command line built beside the package (CI builds it before the package), if
    any: $GRIDPLAN_BIN, the target directory's release build, else one on PATH."""
    import os
    import shutil

    candidates = [os.environ.get("GRIDPLAN_BIN"), os.environ.get("CARGO_TARGET_DIR")]
    candidates = [candidates[0]] + [
        str(Path(d) / "release" / "gridplan") for d in (candidates[1], ROOT / "target") if d
    ]
    for candidate in candidates:
        if candidate and Path(candidate).is_file() and os.access(candidate, os.X_OK):
            return candidate
    return shutil.which("gridplan")


# `gridplan plan maps/ros-graded/TenByTen-raw.yaml --planner astar --set moves=8 --set
# heuristic=octile --start 0,0 --goal 9,9 --unknown 250 --json`'s cost (configs/
# weighted.toml's label `astar` on that map's first pair), run by hand with commit
# a58b52a's command line.
TENBYTEN_RAW_UNKNOWN_250 = 2340.2755749514326


def test_read_map_takes_the_command_line_s_cost_bands_and_terrain(tmp_path):
    """read_map had no lethal, unknown, swamp or water: configs/weighted.toml's
    `costs = { unknown = 250 }` on TenByTen-raw could not be read from Python."""
    import json
    import subprocess

    raw = ROOT / "maps/ros-graded/TenByTen-raw.yaml"
    grid, _ = gridplan.read_map(raw, unknown=250)
    out = gridplan.plan(grid, (0, 0), (9, 9), planner="astar", moves=8, heuristic="octile")
    binary = gridplan_binary()
    if binary is not None:
        cli = subprocess.run(
            [binary, "plan", str(raw), "--planner", "astar", "--set", "moves=8", "--set",
             "heuristic=octile", "--start", "0,0", "--goal", "9,9", "--unknown", "250", "--json"],
            check=True, capture_output=True, text=True,
        )
        assert out.cost == json.loads(cli.stdout)["cost"]
    assert out.cost == TENBYTEN_RAW_UNKNOWN_250
    # Unknown cells are blocked by default: the start (0, 0) is one.
    with pytest.raises(gridplan.ProblemError):
        gridplan.plan(gridplan.read_map(raw, graded=True)[0], (0, 0), (9, 9))
    # lethal and unknown imply graded; a lower lethal blocks more.
    assert gridplan.read_map(raw, unknown=250)[0] == gridplan.read_map(raw, graded=True, unknown=250)[0]
    # TenByTen-raw's costs: 0, 66, 129 and unknown (weights 1 + cost).
    low = gridplan.read_map(raw, unknown=100, lethal=129)[0]
    assert (grid.n_free, low.n_free) == (100, 98)
    assert sorted(set(low.weights[low.to_numpy()].tolist())) == [1, 67, 101]
    # Moving AI terrain: swamp S and water W weighted.
    terrain = tmp_path / "t.map"
    terrain.write_text("type octile\nheight 1\nwidth 4\nmap\n.SW.\n")
    swampy, _ = gridplan.read_map(terrain, swamp=5)
    assert swampy.n_free == 3 and swampy.weights.tolist() == [[1, 5, 1, 1]]
    wet, _ = gridplan.read_map(terrain, swamp=5, water=9)
    assert wet.n_free == 4 and wet.weights.tolist() == [[1, 5, 9, 1]]
    # The command line's refusals, naming the argument.
    weights = ROOT / "maps/weighted/arena-weights.csv"
    arena = ROOT / "maps/movingai/arena.map"
    for kwargs, message in [
        (dict(lethal=0), "read_map: lethal=0 would block every cell; costs from lethal up are blocked (254 is nav2's LETHAL_OBSTACLE; its planners block from 253, INSCRIBED, for the robot's centre)"),
        (dict(lethal=256), "read_map: lethal=256; the lethal cost is a costmap cost, from 1 to 255 (nav2's LETHAL_OBSTACLE: 254)"),
        (dict(unknown=255), "read_map: unknown=255; the cost of an unknown cell is from 0 to 254 (leave it out to block unknown cells)"),
        (dict(unknown=-1), "read_map: unknown=-1; the cost of an unknown cell is from 0 to 254 (leave it out to block unknown cells)"),
        (dict(unknown=2**70), f"read_map: unknown={2**70}; the cost of an unknown cell is from 0 to 254 (leave it out to block unknown cells)"),
        (dict(swamp=3), f"read_map: swamp and water weigh Moving AI terrain (.map files), not {raw}"),
    ]:
        with pytest.raises(ValueError) as e:
            gridplan.read_map(raw, **kwargs)
        assert str(e.value) == message
    for kwargs, message in [
        (dict(unknown=3), f"read_map: unknown=3 applies to ROS maps (.yaml, .pgm, .png), not {arena}"),
        (dict(lethal=3), f"read_map: lethal=3 applies to ROS maps (.yaml, .pgm, .png), not {arena}"),
        (dict(water=3), "read_map: water needs swamp (the weight of swamp `S`)"),
        (dict(swamp=0), "read_map: swamp=0; swamp and water are weights, from 1 to 65535"),
        (dict(swamp=2, water=65536), "read_map: water=65536; swamp and water are weights, from 1 to 65535"),
        (dict(swamp=2, weights=weights), "read_map: weights gives every cell's weight; it does not go with graded=True, lethal, unknown, swamp or water"),
    ]:
        with pytest.raises(ValueError) as e:
            gridplan.read_map(arena, **kwargs)
        assert str(e.value) == message
    assert gridplan.read_map(arena, swamp=2, cost_rule="entered")[0].cost_rule == "entered"
