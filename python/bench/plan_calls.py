"""Per-call time of ``gridplan.plan`` and ``Planner.plan`` on Moving AI scenarios, beside
``plan_many`` on one thread: what a call adds to the search. Not a test: run it on a quiet
machine.

    python python/bench/plan_calls.py [--map den520d] [--repeats 3] [--every 8]

A*, 8-connected, octile. Each repeat runs, in order: ``plan_many(threads=1)`` over every
scenario, ``Planner.plan`` over every scenario, and ``gridplan.plan`` over every
``--every``-th scenario (it builds the per-grid tables on each call). Reported, best of the
repeats: microseconds per query of each, and ``Planner.plan``'s extra over ``plan_many``.
``gridplan.plan`` runs its search on rayon's pool so that Ctrl-C interrupts it;
``Planner.plan`` runs on the calling thread (python/README.md).
"""

import argparse
import time
from pathlib import Path

import numpy as np

import gridplan

ROOT = Path(__file__).resolve().parents[2]
PARAMS = dict(moves=8, heuristic="octile")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--map", default="den520d")
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--every", type=int, default=8)
    args = parser.parse_args()
    grid, problems = gridplan.read_map(ROOT / "maps" / "movingai" / f"{args.map}.map")
    starts = np.array([p.start for p in problems])
    goals = np.array([p.goal for p in problems])
    pairs = [(tuple(map(int, s)), tuple(map(int, g))) for s, g in zip(starts, goals)]
    planner = gridplan.Planner(grid, "astar", **PARAMS)
    planner.plan_many(starts, goals, threads=1)
    best = [float("inf")] * 3
    for _ in range(args.repeats):
        t = time.perf_counter()
        planner.plan_many(starts, goals, threads=1)
        many = (time.perf_counter() - t) / len(pairs)
        t = time.perf_counter()
        for s, g in pairs:
            planner.plan(s, g)
        single = (time.perf_counter() - t) / len(pairs)
        some = pairs[:: args.every]
        t = time.perf_counter()
        for s, g in some:
            gridplan.plan(grid, s, g, planner="astar", **PARAMS)
        function = (time.perf_counter() - t) / len(some)
        best = [min(b, v) for b, v in zip(best, (many, single, function))]
    many, single, function = (b * 1e6 for b in best)
    print(
        f"map={args.map} queries={len(pairs)} plan_many_us={many:.1f} "
        f"planner_plan_us={single:.1f} planner_plan_extra_us={single - many:.1f} "
        f"gridplan_plan_us={function:.1f}"
    )


if __name__ == "__main__":
    main()
