"""run_experiment: the paper config's records as a DataFrame with runs.csv's columns,
seed 000's Table 5, the list-of-dicts form without pandas, and output directories."""

import csv
import json
import sys

import pytest

import gridplan
from conftest import CONFIGS

# Seed 000, Table 5: A* on the 6x6 maps 1-6 (expanded, neighbour checks, blocked or
# out-of-bound rejections, skipped as closed, OPEN insertions, cost relaxations).
TABLE5 = {
    "n_expanded": [15, 21, 16, 17, 20, 14],
    "n_neighbor_checks": [56, 80, 60, 64, 76, 52],
    "n_blocked": [24, 36, 25, 26, 33, 25],
    "n_skipped": [15, 21, 16, 18, 21, 12],
    "n_open_insertions": [16, 22, 18, 17, 20, 16],
    "n_relaxations": [15, 21, 17, 16, 19, 15],
}
DETERMINISTIC = lambda c: c not in ("time_ms", "setup_ms", "peak_heap_bytes")  # noqa: E731


@pytest.fixture(scope="module")
def paper():
    pytest.importorskip("pandas")
    return gridplan.run_experiment(CONFIGS / "paper.toml")


def test_paper_config_has_60_rows(paper):
    assert len(paper) == 60  # 12 maps x 5 planners
    assert set(paper["planner"]) == {"astar", "backtracking", "bfs", "dfs", "lexastar"}
    assert (paper["status"] == "found").all()
    assert paper["valid"].all()
    assert (paper["peak_heap_bytes"] > 0).all()


def test_table5_from_the_dataframe(paper):
    maps = [f"map0{i}.map" for i in range(1, 7)]
    astar = paper[(paper["planner"] == "astar") & paper["map"].isin(maps)]
    table = astar.set_index("map")[list(TABLE5)].T
    assert list(table.columns) == [f"map0{i}.map" for i in range(1, 7)]
    assert {k: list(v) for k, v in table.iterrows()} == TABLE5


def test_columns_and_values_are_runs_csvs(tmp_path):
    pandas = pytest.importorskip("pandas")
    frame = gridplan.run_experiment(CONFIGS / "paper.toml", output=tmp_path / "paper")
    written = pandas.read_csv(tmp_path / "paper" / "runs.csv")
    assert list(frame.columns) == list(written.columns)
    assert len(frame) == len(written) == 60
    for column in filter(DETERMINISTIC, frame.columns):
        ours, theirs = frame[column], written[column]
        assert (ours.isna() == theirs.isna()).all(), column
        ours, theirs = ours[ours.notna()], theirs[theirs.notna()]
        if theirs.dtype.kind in "if":
            # runs.csv writes lengths with 6 decimals.
            assert ((ours.astype(float) - theirs.astype(float)).abs() < 1e-6).all(), column
        else:
            assert (ours == theirs).all(), column
    # The command line's results directory: marker, summary with the reproduction.
    summary = (tmp_path / "paper" / "summary.md").read_text()
    assert "Published numbers reproduced" in summary
    assert (tmp_path / "paper" / ".gridplan-results").is_file()


def test_without_pandas_a_list_of_dicts(monkeypatch):
    monkeypatch.setitem(sys.modules, "pandas", None)  # `import pandas` raises ImportError
    rows = gridplan.run_experiment(CONFIGS / "paper.toml", threads=1)
    assert isinstance(rows, list) and len(rows) == 60
    header = next(csv.reader([rows_header(rows)]))
    assert header[:3] == ["map", "problem", "start_x"]
    map10 = next(r for r in rows if r["map"] == "map10.map" and r["planner"] == "astar")
    assert (map10["n_expanded"], map10["n_neighbor_checks"]) == (70, 276)
    assert (map10["steps"], map10["turns"], map10["score"]) == (22, 6, 28)
    # Backtracking has no `peak_open`: an empty runs.csv cell is None.
    backtracking = next(r for r in rows if r["planner"] == "backtracking")
    assert backtracking["peak_open"] is None and backtracking["n_solutions"] > 0


def rows_header(rows):
    return ",".join(rows[0])


def test_threads_do_not_change_the_records(monkeypatch):
    monkeypatch.setitem(sys.modules, "pandas", None)
    one = gridplan.run_experiment(CONFIGS / "paper.toml", threads=1)
    two = gridplan.run_experiment(CONFIGS / "paper.toml", threads=2)
    strip = lambda rows: [{k: v for k, v in r.items() if DETERMINISTIC(k)} for r in rows]  # noqa: E731
    assert strip(one) == strip(two)


def test_output_directory_rules(tmp_path):
    mine = tmp_path / "mine"
    mine.mkdir()
    (mine / "notes.txt").write_text("my own file")
    with pytest.raises(gridplan.OutputError) as info:
        gridplan.run_experiment(CONFIGS / "paper.toml", output=mine)
    assert str(mine) in str(info.value)
    assert isinstance(info.value, gridplan.GridplanError)
    assert [p.name for p in mine.iterdir()] == ["notes.txt"]
    # A results directory gridplan wrote is replaced.
    out = tmp_path / "out"
    gridplan.run_experiment(CONFIGS / "paper.toml", output=out)
    first = (out / "runs.csv").read_text().splitlines()[0]
    gridplan.run_experiment(CONFIGS / "paper.toml", output=out)
    assert (out / "runs.csv").read_text().splitlines()[0] == first


def test_resume_keeps_the_recorded_runs(tmp_path, monkeypatch):
    """resume=True: a sweep interrupted by Ctrl-C keeps its finished runs and runs the
    rest, the records equal to an uninterrupted sweep's; after a finished sweep nothing
    runs again (the times are the recorded ones); without an output it is refused."""
    from test_planner import interrupted_output

    monkeypatch.setitem(sys.modules, "pandas", None)
    config = tmp_path / "many.toml"
    config.write_text(
        'name = "many"\nrepeats = 100\n[[maps]]\n'
        f'files = ["{CONFIGS.parent / "maps" / "movingai" / "den520d.map"}"]\n'
        f'scen = "{CONFIGS.parent / "maps" / "movingai" / "den520d.map.scen"}"\nevery = 8\n'
        '[planners.dijkstra]\nplanner = "astar"\nmoves = 8\nheuristic = "zero"\n'
    )
    out = tmp_path / "out"
    printed = interrupted_output(
        "import gridplan",
        f"gridplan.run_experiment({str(config)!r}, output={str(out)!r}, threads=1)",
        1.0,
    )
    assert printed == ["interrupted"]
    assert not (out / "runs.csv").exists()
    with pytest.warns(gridplan.GridplanWarning, match=r"resume: \d+ of 11100 runs already recorded") as caught:
        resumed = gridplan.run_experiment(config, output=out, resume=True)
    kept = int(str(caught[0].message).split()[1])
    assert 0 < kept < 11100
    whole = gridplan.run_experiment(config)
    strip = lambda rows: [{k: v for k, v in r.items() if DETERMINISTIC(k)} for r in rows]  # noqa: E731
    assert strip(resumed) == strip(whole)
    # Finished: the same records, their times included.
    with pytest.warns(gridplan.GridplanWarning, match="resume: 11100 of 11100 runs"):
        again = gridplan.run_experiment(config, output=out, resume=True)
    assert again == resumed
    with pytest.raises(ValueError, match="resume: .*give `output`"):
        gridplan.run_experiment(config, resume=True)


def test_compare_two_results_directories(tmp_path):
    """gridplan.compare: the same config run twice holds the same runs with the same
    computed fields (times differ, and are compared per label); a directory that is not
    results raises OutputError."""
    for name in ("a", "b"):
        rows = gridplan.run_experiment(CONFIGS / "paper.toml", output=tmp_path / name)
    rows = rows.to_dict("records") if hasattr(rows, "to_dict") else rows
    labels = list(dict.fromkeys(row["planner"] for row in rows))
    result = gridplan.compare(tmp_path / "a", tmp_path / "b")
    assert result["same"] is True
    assert result["both"] == result["old"]["runs"] == result["new"]["runs"] == 60
    assert (result["differing"], result["only_old"], result["only_new"]) == (0, 0, 0)
    assert result["examples"] == []
    # Per label, in the runs' order, over every problem (all 12 maps' corner problems).
    assert [t["label"] for t in result["times"]] == labels
    assert all(t["problems"] == 12 for t in result["times"])
    assert result["old"]["provenance"]["version"] == result["new"]["provenance"]["version"]
    with pytest.raises(gridplan.OutputError, match="compare"):
        gridplan.compare(tmp_path / "a", tmp_path)
    # A cut records.stream is refused (OutputError: results that are not complete, as
    # `gridplan report` classes the same damage), never read as fewer runs: they were
    # counted as runs only in the other.
    stream = tmp_path / "b" / "records.stream"
    whole = stream.read_bytes()
    # Halfway through the records, after the header line.
    header = whole.index(b"\n") + 1
    stream.write_bytes(whole[: header + (len(whole) - header) // 2])
    for old, new in (("a", "b"), ("b", "a")):
        with pytest.raises(gridplan.OutputError, match=r"^compare: .*records\.stream holds \d+ of 60 runs$"):
            gridplan.compare(tmp_path / old, tmp_path / new)


def test_errors_and_costs_are_columns(tmp_path):
    """runs.csv's `error` (a refused run) and `cost` (a weighted map) columns reach the
    records with their values (they were None: read as unknown counters)."""
    (tmp_path / "open.map").write_text("type octile\nheight 3\nwidth 4\nmap\n....\n.@@.\n....\n")
    (tmp_path / "open.csv").write_text("1,2,3,4\n1,1,1,1\n4,3,2,1\n")
    (tmp_path / "c.toml").write_text(
        'name = "columns"\n[[maps]]\nfiles = ["open.map"]\ncosts = { weights = "open.csv" }\n'
        "pairs = [{ start = [0, 0], goal = [3, 2] }, { start = [0, 0], goal = [1, 1] }]\n"
        '[planners.astar]\nplanner = "astar"\n'
    )
    with pytest.warns(gridplan.GridplanWarning, match="is blocked; not run"):
        rows = gridplan.run_experiment(tmp_path / "c.toml", output=tmp_path / "out")
    if not isinstance(rows, list):
        # The refused run has no `valid`: the nullable boolean, <NA> for it.
        assert str(rows["valid"].dtype) == "boolean"
        assert rows["valid"].isna().tolist() == [False, True]
        assert str(rows["error"].dtype) == "object" and str(rows["cost"].dtype) == "float64"
        rows = rows.to_dict("records")
    with open(tmp_path / "out" / "runs.csv", newline="") as f:
        table = list(csv.DictReader(f))
    assert [r["error"] for r in table] == ["", "goal (1, 1) is blocked"]
    assert rows[1]["error"] == "goal (1, 1) is blocked"
    assert rows[0]["cost"] == pytest.approx(float(table[0]["cost"]))
    assert rows[0]["cost"] > rows[0]["length"]


@pytest.mark.parametrize("seed", [9007199254740993, 9223372036854775807])
def test_integers_are_exact_in_the_dataframe(tmp_path, seed):
    """Integer columns are nullable UInt64, so a seed above 2**53 (2**53 + 1, 2**63 - 1)
    and its repeat's seed + 1 are the values runs.csv and runs.json hold, an unseeded
    planner's seed and the counters its planner does not report are <NA> (they made the
    columns float64, rounding the seeds: 2**53 + 1 read 2**53); floats stay float64,
    `valid` bool, text object; every value equals runs.json's and runs.csv's."""
    pandas = pytest.importorskip("pandas")
    (tmp_path / "tiny.map").write_text("type octile\nheight 4\nwidth 5\nmap\n.....\n.@@..\n.....\n.....\n")
    (tmp_path / "c.toml").write_text(
        f'name = "bigseed"\nseed = {seed}\nrepeats = 2\n[[maps]]\nfiles = ["tiny.map"]\n'
        "pairs = [{ start = [0, 0], goal = [4, 3] }]\n"
        '[planners.rrt]\nplanner = "rrt"\n[planners.astar]\nplanner = "astar"\n'
    )
    out = tmp_path / "out"
    frame = gridplan.run_experiment(tmp_path / "c.toml", output=out)
    assert list(frame["seed"][frame["planner"] == "rrt"]) == [seed, seed + 1]
    assert frame["seed"][frame["planner"] == "astar"].isna().all()
    assert frame["peak_open"][frame["planner"] == "rrt"].isna().all()
    assert frame["tree_size"][frame["planner"] == "astar"].isna().all()
    kinds = {
        "text": ["map", "planner", "algorithm", "status"],
        "float": ["length", "optimal_length", "time_ms", "setup_ms"],
        "bool": ["valid"],
    }
    for column in frame.columns:
        dtype = str(frame[column].dtype)
        if column in kinds["text"]:
            assert dtype == "object", column
        elif column in kinds["float"]:
            assert dtype == "float64", column
        elif column in kinds["bool"]:
            assert dtype == "bool", column
        else:
            assert dtype == "UInt64", column
    runs = json.loads((out / "runs.json").read_text())["runs"]
    assert list(frame.columns) == runs["columns"]
    with open(out / "runs.csv", newline="") as f:
        table = list(csv.DictReader(f))
    assert len(frame) == len(runs["data"]) == len(table) == 4
    for i, (written, line) in enumerate(zip(runs["data"], table)):
        for column, theirs in zip(runs["columns"], written):
            ours = frame[column].iloc[i]
            if theirs is None:
                assert pandas.isna(ours) and line[column] == "", (i, column, ours)
                continue
            assert ours == theirs and type(theirs)(ours) == theirs, (i, column, ours, theirs)
            if column in kinds["float"]:
                assert float(line[column]) == pytest.approx(theirs, abs=1e-6), (i, column)
            elif column in kinds["bool"]:
                assert line[column] == str(theirs).lower(), (i, column)
            elif column in kinds["text"]:
                assert line[column] == theirs, (i, column)
            else:
                assert int(line[column]) == int(ours) == theirs, (i, column, ours, line[column])
