"""Per-query time of ``Planner.plan_many`` on every scenario of a Moving AI map, beside the
search time alone, and 1 vs 2 threads. Not a test: run it on a quiet machine.

    python python/bench/plan_many.py [--map den520d] [--planner astar] [--repeats 3]

The planner is the Rust bench's (``cargo bench -p planner-astar --bench movingai``): A*,
8-connected, octile, no corner cutting, larger g first among equal f; ``--planner jps``
runs JPS+ (``cargo bench -p planner-jps --bench movingai``). Each repeat runs, alternating:
``plan_many`` on 1 thread, the same on 2 threads. Reported per side, best of the repeats:
wall time and process CPU time per query; and for 1 thread, the sum of the searches' own
times (``time_ms``, measured in Rust around the planner's ``plan`` alone), so that
wall / search is what ``plan_many`` adds over the bare search. Compare the 1-thread wall
time per query with the Rust bench's ``gridplan_ms`` / scenarios, run right before or
after. Every pass must give the same counters (checked), and every length the
scenario's optimum.
"""

import argparse
import os
import time
from pathlib import Path

import numpy as np

import gridplan

ROOT = Path(__file__).resolve().parents[2]

PLANNERS = {
    "astar": dict(moves=8, heuristic="octile", tie_break="high_g"),
    "jps": dict(variant="jps_plus", marks=False),
}


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--map", default="den520d")
    parser.add_argument("--planner", default="astar", choices=sorted(PLANNERS))
    parser.add_argument("--repeats", type=int, default=3)
    args = parser.parse_args()
    grid, problems = gridplan.read_map(ROOT / "maps" / "movingai" / f"{args.map}.map")
    starts = np.array([p.start for p in problems])
    goals = np.array([p.goal for p in problems])
    optimal = np.array([p.optimal_length for p in problems])
    planner = gridplan.Planner(grid, args.planner, budget={"max_expansions": 10**9}, **PLANNERS[args.planner])
    # Warm-up: builds the planner and its tables on each pool thread.
    reference = planner.plan_many(starts, goals, threads=2)
    planner.plan_many(starts, goals, threads=1)
    assert np.allclose(reference["length"], optimal, rtol=1e-4), "a length is off the optimum"
    best = {1: (float("inf"),) * 3, 2: (float("inf"),) * 3}
    for _ in range(args.repeats):
        for threads in (1, 2):
            wall0, cpu0 = time.perf_counter(), time.process_time()
            out = planner.plan_many(starts, goals, threads=threads)
            wall, cpu = time.perf_counter() - wall0, time.process_time() - cpu0
            for name, values in out["counters"].items():
                assert np.array_equal(values, reference["counters"][name]), name
            search = out["time_ms"].sum() / 1e3
            if wall < best[threads][0]:
                best[threads] = (wall, cpu, search)
    n = len(problems)
    expansions = int(reference["counters"]["n_expanded"].sum())
    print(f"map={args.map} planner={args.planner} queries={n} expansions={expansions} load={os.getloadavg()[0]:.2f}")
    for threads in (1, 2):
        wall, cpu, search = best[threads]
        print(
            f"threads={threads} wall_ms={wall * 1e3:.1f} cpu_ms={cpu * 1e3:.1f} "
            f"per_query_us={wall / n * 1e6:.1f} search_ms={search * 1e3:.1f}"
            + (f" wall/search={wall / search:.3f}" if threads == 1 else "")
        )
    print(f"speedup_2_threads={best[1][0] / best[2][0]:.2f}")


if __name__ == "__main__":
    main()
