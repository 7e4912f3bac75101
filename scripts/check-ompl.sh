#!/usr/bin/env bash
# Checks that OMPL's own converter (ompl 2.0.1 from PyPI, `ompl.ompl_benchmark_statistics`)
# turns gridplan's OMPL benchmark logs into a database with one `runs` row per run, every
# planner and every run property. Usage: scripts/check-ompl.sh [results-dir]
# (default: runs configs/movingai.toml, which sets `ompl = true`, into a temporary dir).
# The logs name a planner by its label as one word (crates/report/src/ompl.rs, `one_word`:
# `bfs ig\nnl` is `bfs_ig_nl-ec12bcf8`); the check compares the database's planners with
# the labels so reshaped, computed as that writer computes them (`ompl_name` below).
# `scripts/check-ompl.sh --ompl-names` reads a JSON list of labels on stdin and prints
# their OMPL names as a JSON list (no OMPL needed; crates/report's tests compare it with
# the writer's).
set -euo pipefail
cd "$(dirname "$0")/.."
# The OMPL writer's `one_word`: control characters (Unicode Cc, U+2028, U+2029) become
# spaces, runs of Unicode White_Space (Rust's `char::is_whitespace`) become one `_`, and
# a name so changed (or empty) gets `-` and the first 4 bytes of its SHA-256 in hex.
names_py='
import hashlib, unicodedata
WHITE_SPACE = {0x09, 0x0A, 0x0B, 0x0C, 0x0D, 0x20, 0x85, 0xA0, 0x1680, 0x2028, 0x2029,
               0x202F, 0x205F, 0x3000, *range(0x2000, 0x200B)}
def ompl_name(text):
    line = "".join(" " if unicodedata.category(c) == "Cc" or c in "\u2028\u2029" else c
                   for c in text)
    words, word = [], ""
    for c in line + " ":
        if ord(c) in WHITE_SPACE:
            words += [word] if word else []
            word = ""
        else:
            word += c
    word = "_".join(words)
    if word == text and word:
        return word
    return word + "-" + hashlib.sha256(text.encode("utf-8", "surrogatepass")).hexdigest()[:8]
'
if [ "${1:-}" = "--ompl-names" ]; then
  exec python3 -c "$names_py
import json, sys
print(json.dumps([ompl_name(label) for label in json.load(sys.stdin)]))"
fi
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
"$work/venv/bin/python" -c "$names_py
$(cat <<'PY'
import glob, json, sqlite3, sys
results, db = sys.argv[1], sys.argv[2]
with open(f"{results}/runs.json") as f:
    data = json.load(f)
# runs.json's table (columns, data rows) as one dict per run, its counters gathered.
table = data["runs"]
not_counters = {"map", "problem", "start_x", "start_y", "goal_x", "goal_y", "planner",
                "algorithm", "repeat", "seed", "status", "steps", "turns", "score", "length",
                "optimal_length", "valid", "time_ms", "setup_ms", "peak_heap_bytes", "bucket",
                "error", "admissible", "returns", "marks", "series", "cost"}
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
# Each label as the OMPL writer names it (one word).
names = {label: ompl_name(label) for label in data["planners"]}
labels = set(names)
assert planners == set(names.values()), f"planners {planners} != labels {names}"
n_exp = c.execute("SELECT COUNT(*) FROM experiments").fetchone()[0]
maps = {r["map"] for r in runs}
assert n_exp == len(maps), f"{n_exp} experiments, {len(maps)} maps"
columns = {row[1] for row in c.execute("PRAGMA table_info(runs)")}
counters = {k for r in runs for k in r["counters"]}
expected = {"problem", "repeat", "seed", "time", "solved", "status", "memory",
            "solution_length", "optimal_length", "steps", "turns", "valid"} | {ompl_name(k) for k in counters}
# A weighted map's runs carry their path cost.
if "cost" in table["columns"]:
    expected.add("cost")
missing = expected - columns
assert not missing, f"missing run properties {missing}"
# Every run's expansions reach the database unchanged.
for label in labels:
    ours = sorted(r["counters"].get("n_expanded", -1) for r in runs if r["planner"] == label)
    theirs = sorted(v if v is not None else -1 for (v,) in c.execute(
        "SELECT runs.n_expanded FROM runs JOIN plannerConfigs p ON p.id = runs.plannerid WHERE p.name = ?", (names[label],)))
    assert ours == theirs, f"{label}: n_expanded differs"
# Every run's status reaches the database as the `status` enum's value.
enum = dict(c.execute("SELECT value, description FROM enums WHERE name = 'status'"))
assert enum, "no status enum"
for label in labels:
    ours = sorted(r["status"] for r in runs if r["planner"] == label)
    theirs = sorted(enum[v] for (v,) in c.execute(
        "SELECT runs.status FROM runs JOIN plannerConfigs p ON p.id = runs.plannerid WHERE p.name = ?", (names[label],)))
    assert ours == theirs, f"{label}: statuses differ"
solved = c.execute("SELECT COUNT(*) FROM runs WHERE solved = 1").fetchone()[0]
assert solved == sum(r["status"] == "found" for r in runs)
print(f"ompl check: {n_runs} runs, {len(planners)} planners, {n_exp} experiments, {len(columns)} columns: 1 passed, 0 failed")
PY
)" "$results" "$work/benchmark.db"
