"""The Parquet dataset runs.parquet/ (issue 29) read without gridplan: DuckDB's
median(n_expanded) per planner and map equals summary.md's aggregate table, DuckDB's
per-problem ratios against the first label equal its paired table, and pandas (pyarrow)
reads the directory as one table with runs.csv's rows, runs.csv beside it."""

import csv

# Imported, not skipped when absent: CI installs both (.ci/run's python block).
import duckdb
import pandas
import pytest

import gridplan
from conftest import MAPS

CONFIG = """name = "pq"
repeats = 3
[[maps]]
files = [{arena!r}]
scen = {scen!r}
every = 20
[[maps]]
files = [{map01!r}, {map02!r}]
problems = "corners"
[planners.astar]
planner = "astar"
[planners.bfs]
planner = "bfs"
[planners.weighted]
planner = "astar"
weight = 2.0
"""


@pytest.fixture(scope="module")
def results(tmp_path_factory):
    root = tmp_path_factory.mktemp("parquet")
    config = root / "pq.toml"
    config.write_text(
        CONFIG.format(
            arena=str(MAPS / "movingai" / "arena.map"),
            scen=str(MAPS / "movingai" / "arena.map.scen"),
            map01=str(MAPS / "paper" / "map01.map"),
            map02=str(MAPS / "paper" / "map02.map"),
        )
    )
    out = root / "results"
    gridplan.run_experiment(config, output=out)
    return out


def format_number(value):
    """summary.md's number format (crates/report/src/aggregate.rs)."""
    return f"{value:.0f}" if float(value).is_integer() else f"{value:.2f}"


def aggregate_medians(summary):
    """(label, map) -> the median expansions cell of summary.md's aggregate table."""
    lines = summary.splitlines()
    start = next(i for i, l in enumerate(lines) if l.startswith("| Planner | Map | Runs |"))
    header = [c.strip() for c in lines[start].strip("|").split("|")]
    column = header.index("Median expansions")
    cells = {}
    for line in lines[start + 2 :]:
        if not line.startswith("|"):
            break
        row = [c.strip() for c in line.strip("|").split("|")]
        cells[(row[0], row[1])] = row[column]
    return cells


def test_duckdb_medians_equal_the_summary(results):
    rows = duckdb.sql(
        "SELECT planner, map, median(n_expanded) AS m, count(*) AS n "
        f"FROM read_parquet('{results}/runs.parquet/*.parquet') GROUP BY planner, map"
    ).fetchall()
    table = aggregate_medians((results / "summary.md").read_text())
    # 3 labels x 3 maps, every one in both.
    assert len(rows) == 9
    assert {(p, m) for p, m, _, _ in rows} == set(table)
    for planner, map_name, median, n in rows:
        assert n > 0
        assert format_number(median) == table[(planner, map_name)], (planner, map_name)


def table_rows(summary, head):
    """label -> the cells of the summary.md table whose header starts with `head`."""
    lines = summary.splitlines()
    start = next(i for i, l in enumerate(lines) if l.startswith(head))
    rows = {}
    for line in lines[start + 2 :]:
        if not line.startswith("|"):
            break
        row = [c.strip() for c in line.strip("|").split("|")]
        rows[row[0]] = row
    return rows


def test_duckdb_ratios_equal_the_paired_table(results):
    """The paired section (crates/report/src/paired.rs) recomputed in SQL: per problem and
    label the medians over the repeats, solved when every repeat found a path; over the
    problems both solved, the geometric means of label / astar and the counts below 1."""
    path = f"{results}/runs.parquet/*.parquet"
    rows = duckdb.sql(
        f"""
        WITH per AS (
            SELECT planner, map, problem,
                   median(time_ms) AS t, median(n_expanded) AS e,
                   median(length) FILTER (WHERE status = 'found') AS len,
                   bool_and(status = 'found') AS solved
            FROM read_parquet('{path}') WHERE status <> 'invalid_problem'
            GROUP BY planner, map, problem
        ),
        pairs AS (
            SELECT o.planner, o.solved AND b.solved AS shared,
                   o.t / b.t AS t, o.e / b.e AS e, o.len / b.len AS len
            FROM per o JOIN per b ON o.map = b.map AND o.problem = b.problem
            WHERE b.planner = 'astar' AND o.planner <> 'astar'
        )
        SELECT planner, count(*), count(*) FILTER (WHERE shared),
               exp(avg(ln(e)) FILTER (WHERE shared)), count(*) FILTER (WHERE shared AND e < 1),
               exp(avg(ln(t)) FILTER (WHERE shared)), count(*) FILTER (WHERE shared AND t < 1),
               exp(avg(ln(len)) FILTER (WHERE shared)), max(len) FILTER (WHERE shared)
        FROM pairs GROUP BY planner ORDER BY planner
        """
    ).fetchall()
    table = table_rows((results / "summary.md").read_text(), "| Planner | Problems | Solved by both |")
    assert sorted(table) == ["bfs", "weighted"]
    assert [r[0] for r in rows] == ["bfs", "weighted"]

    def close(printed, value):
        # Three decimals, or three significant digits below 0.01.
        return abs(float(printed) - value) <= max(5e-4, 5e-3 * value) + 1e-12

    for planner, problems, both, e, fewer, t, faster, length, longest in rows:
        row = table[planner]
        assert row[1] == str(problems) and row[2] == str(both), row
        assert close(row[5], e) and row[6] == f"{fewer} of {both}", (row, e, fewer)
        assert close(row[7].split(" ")[0], t) and row[8] == f"{faster} of {both}", (row, t, faster)
        assert close(row[9], length) and close(row[10], longest), (row, length, longest)


def test_duckdb_reads_the_types_and_metadata(results):
    path = f"{results}/runs.parquet/*.parquet"
    types = dict(
        duckdb.sql(f"SELECT column_name, column_type FROM (DESCRIBE SELECT * FROM read_parquet('{path}'))").fetchall()
    )
    assert types["map"] == "VARCHAR"
    assert types["n_expanded"] == "UBIGINT"
    assert types["length"] == "DOUBLE"
    assert types["valid"] == "BOOLEAN"
    keys = {
        k.decode(): v.decode()
        for k, v in duckdb.sql(f"SELECT key, value FROM parquet_kv_metadata('{path}')").fetchall()
    }
    assert keys["gridplan.experiment"] == "pq"
    assert '"weighted"' in keys["gridplan.planners"]


def test_pandas_reads_the_csv_rows(results):
    frame = pandas.read_parquet(results / "runs.parquet")
    with open(results / "runs.csv", newline="") as f:
        rows = list(csv.DictReader(f))
    assert list(frame.columns) == list(rows[0].keys())
    # 3 labels x (8 of the 160 scenarios, every 20th, and one corner problem on each of
    # map01 and map02) x 3 repeats.
    assert len(frame) == len(rows) == 3 * (8 + 2 * 1) * 3
    for column in frame.columns:
        for ours, theirs in zip(frame[column], (r[column] for r in rows)):
            if theirs == "":
                assert pandas.isna(ours), column
            elif column in ("time_ms", "setup_ms"):
                assert abs(float(ours) - float(theirs)) <= 1.5e-6, column
            elif column in ("length", "optimal_length"):
                # The shortest decimal that reads back as the same double.
                assert float(theirs) == ours, column
            elif column == "valid":
                assert str(bool(ours)).lower() == theirs, column
            elif isinstance(theirs, str) and not theirs.isdigit():
                assert ours == theirs, column
            else:
                assert int(ours) == int(theirs), column


def test_an_invalid_problem_has_no_measurements_in_the_frame_as_in_the_dataset(results, tmp_path):
    """An invalid problem was not run: its time_ms, setup_ms and peak_heap_bytes are
    missing in run_experiment's frame, as in runs.parquet (they were 0 in the frame)."""
    config = tmp_path / "invalid.toml"
    config.write_text(
        "name = \"invalid\"\n[[maps]]\n"
        f"files = [{str(MAPS / 'paper' / 'map01.map')!r}]\n"
        # The second goal is outside the map: an invalid problem.
        "pairs = [{ start = [0, 0], goal = [1, 1] }, { start = [0, 0], goal = [500, 500] }]\n"
        "[planners.bfs]\nplanner = \"bfs\"\n"
    )
    out = tmp_path / "out"
    frame = gridplan.run_experiment(config, output=out)
    invalid = frame["status"] == "invalid_problem"
    assert invalid.any(), "the config has invalid problems"
    dataset = pandas.read_parquet(out / "runs.parquet")
    for column in ("time_ms", "setup_ms", "peak_heap_bytes"):
        assert frame.loc[invalid, column].isna().all(), column
        assert frame.loc[~invalid, column].notna().all(), column
        assert dataset[column].isna().sum() == invalid.sum(), column
