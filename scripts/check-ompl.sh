#!/usr/bin/env bash
# Checks that OMPL's own converter (ompl 2.0.1 from PyPI, `ompl.ompl_benchmark_statistics`)
# turns gridplan's OMPL benchmark logs into a database with one `runs` row per run, every
# planner and every run property. Usage: scripts/check-ompl.sh [results-dir]
# (default: runs configs/movingai.toml, which sets `ompl = true`, into a temporary dir).
set -euo pipefail
cd "$(dirname "$0")/.."
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
results=${1:-}
if [ -z "$results" ]; then
  results="$work/results"
  cargo run -q -p xtask --release -- experiment configs/movingai.toml --output "$results"
fi
python3 -m venv "$work/venv"
"$work/venv/bin/pip" install -q ompl==2.0.1
"$work/venv/bin/python" -m ompl.ompl_benchmark_statistics "$results"/ompl/*.log -d "$work/benchmark.db" >/dev/null
"$work/venv/bin/python" - "$results" "$work/benchmark.db" <<'PY'
import glob, json, sqlite3, sys
results, db = sys.argv[1], sys.argv[2]
with open(f"{results}/runs.json") as f:
    data = json.load(f)
# runs.json's table (columns, data rows) as one dict per run, its counters gathered.
table = data["runs"]
not_counters = {"map", "problem", "start_x", "start_y", "goal_x", "goal_y", "planner",
                "algorithm", "repeat", "seed", "status", "steps", "turns", "score", "length",
                "optimal_length", "valid", "time_ms", "setup_ms", "peak_heap_bytes", "bucket",
                "error", "admissible", "returns", "marks", "series"}
counter_columns = [c for c in table["columns"] if c not in not_counters]
runs = []
for row in table["data"]:
    run = dict(zip(table["columns"], row))
    run["counters"] = {k: run[k] for k in counter_columns if run[k] is not None}
    runs.append(run)
conn = sqlite3.connect(db)
c = conn.cursor()
n_runs = c.execute("SELECT COUNT(*) FROM runs").fetchone()[0]
assert n_runs == len(runs), f"{n_runs} runs rows, {len(runs)} runs"
planners = {r[0] for r in c.execute("SELECT name FROM plannerConfigs")}
labels = set(data["planners"])
assert planners == labels, f"planners {planners} != labels {labels}"
n_exp = c.execute("SELECT COUNT(*) FROM experiments").fetchone()[0]
maps = {r["map"] for r in runs}
assert n_exp == len(maps), f"{n_exp} experiments, {len(maps)} maps"
columns = {row[1] for row in c.execute("PRAGMA table_info(runs)")}
counters = {k for r in runs for k in r["counters"]}
expected = {"problem", "repeat", "seed", "time", "solved", "memory", "solution_length",
            "optimal_length", "steps", "turns", "valid"} | counters
missing = expected - columns
assert not missing, f"missing run properties {missing}"
# Every run's expansions reach the database unchanged.
for label in labels:
    ours = sorted(r["counters"].get("n_expanded", -1) for r in runs if r["planner"] == label)
    theirs = sorted(v if v is not None else -1 for (v,) in c.execute(
        "SELECT runs.n_expanded FROM runs JOIN plannerConfigs p ON p.id = runs.plannerid WHERE p.name = ?", (label,)))
    assert ours == theirs, f"{label}: n_expanded differs"
solved = c.execute("SELECT COUNT(*) FROM runs WHERE solved = 1").fetchone()[0]
assert solved == sum(r["status"] == "found" for r in runs)
print(f"ompl check: {n_runs} runs, {len(planners)} planners, {n_exp} experiments, {len(columns)} columns: 1 passed, 0 failed")
PY
