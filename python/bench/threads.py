"""Shows that gridplan releases the GIL while planning: the same A* queries planned by one
Python thread, then split between two, timed (best of --repeats, alternating), with the
speedup. Not a test: run it on a quiet machine with two cores or more.

    python python/bench/threads.py [--map maps/movingai/den520d.map] [--queries 400] [--repeats 3]

Both sides plan the same queries with the same planner and parameters and expand the
same nodes (checked), so the ratio of their times is the parallel speedup. Each side also
reports the process's CPU time over its wall time: above 1.0 the two threads ran Rust code
at the same moment, which they could not if the GIL were held (on a loaded machine the
speedup falls, while this ratio still shows the overlap).
"""

import argparse
import os
import threading
import time
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import gridplan

ROOT = Path(__file__).resolve().parents[2]


def plan_all(grid, queries):
    """(n_expanded, search time in ms) of each query."""
    outcomes = [
        gridplan.plan(grid, start, goal, planner="astar", moves=8, heuristic="octile")
        for start, goal in queries
    ]
    return [(o.counters["n_expanded"], o.time_ms) for o in outcomes]


def one_thread(grid, queries):
    # On a worker thread too, so that both sides allocate the same way (glibc gives
    # threads other than the main one their own arenas).
    with ThreadPoolExecutor(max_workers=1) as pool:
        return pool.submit(plan_all, grid, queries).result()


def two_threads(grid, queries):
    halves = [queries[0::2], queries[1::2]]
    with ThreadPoolExecutor(max_workers=2) as pool:
        even, odd = pool.map(lambda q: plan_all(grid, q), halves)
    merged = [None] * len(queries)
    merged[0::2], merged[1::2] = even, odd
    return merged


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--map", default=str(ROOT / "maps" / "movingai" / "den520d.map"))
    parser.add_argument("--queries", type=int, default=400, help="the last N scenarios (the longest)")
    parser.add_argument("--repeats", type=int, default=3)
    args = parser.parse_args()
    grid, problems = gridplan.read_map(args.map)
    queries = [(p.start, p.goal) for p in problems[-args.queries :]]
    best = {"1 thread": float("inf"), "2 threads": float("inf")}
    cpu = {}
    expansions = {}
    search = {}
    for _ in range(args.repeats):
        for name, run in (("1 thread", one_thread), ("2 threads", two_threads)):
            started, cpu_started = time.perf_counter(), time.process_time()
            results = run(grid, queries)
            wall = time.perf_counter() - started
            expansions[name] = [n for n, _ in results]
            if wall < best[name]:
                best[name] = wall
                cpu[name] = time.process_time() - cpu_started
                search[name] = sum(t for _, t in results) / 1e3
    assert expansions["1 thread"] == expansions["2 threads"], "the two sides did different work"
    total = sum(expansions["1 thread"])
    print(f"{Path(args.map).name}: {len(queries)} A* queries (8-connected, octile), "
          f"{total:,} expansions per side, best of {args.repeats}, "
          f"load average {os.getloadavg()[0]:.2f}, {os.cpu_count()} cores, "
          f"threading.active_count() = {threading.active_count()}")
    for name, seconds in best.items():
        print(f"  {name:9}: {seconds * 1e3:8.1f} ms wall, {cpu[name] * 1e3:8.1f} ms CPU "
              f"(CPU/wall {cpu[name] / seconds:.2f})")
    print(f"  speedup  : {best['1 thread'] / best['2 threads']:.2f}x (2 threads against 1)")
    one = search["1 thread"]
    print(f"  1 thread : the searches' own time_ms add up to {one * 1e3:.1f} ms "
          f"({100 * one / best['1 thread']:.0f}% of the wall time; the rest builds each "
          f"call's planner and per-grid tables, and the outcome)")


if __name__ == "__main__":
    main()
