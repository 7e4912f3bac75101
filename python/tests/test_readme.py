"""The package README's example runs, and shows the numbers it claims: seed 000's Table 5
(the same values test_experiment.py asserts) and the plotted path's counters."""

import re
import textwrap

import pytest

from conftest import ROOT
from test_experiment import TABLE5

README = ROOT / "python" / "README.md"


def blocks(kind):
    return re.findall(rf"```{kind}\n(.*?)```", README.read_text(), flags=re.S)


def test_readme_table5_example(monkeypatch, capsys):
    pytest.importorskip("pandas")
    monkeypatch.chdir(ROOT)
    namespace = {}
    exec(blocks("python")[0], namespace)
    printed = capsys.readouterr().out
    table = namespace["table5"]
    assert {name: list(row) for name, row in table.iterrows()} == TABLE5
    # The output the README shows is what the example prints.
    shown = blocks("text")[0]
    assert printed.split() == shown.split()
    rows = {line.split()[0]: [int(v) for v in line.split()[1:]] for line in shown.splitlines()[1:]}
    assert rows == TABLE5


def test_readme_plot_example(monkeypatch):
    pytest.importorskip("pandas")
    matplotlib = pytest.importorskip("matplotlib")
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    monkeypatch.chdir(ROOT)
    namespace = {}
    exec(blocks("python")[0], namespace)
    exec(blocks("python")[1], namespace)
    title = plt.gca().get_title()
    plt.close("all")
    assert title == "A* on map10: 70 expansions, D=22, T=6"
    assert f'"{title}"' in README.read_text()


def test_readme_replanner_example(monkeypatch):
    import gridplan

    monkeypatch.chdir(ROOT)
    namespace = {"gridplan": gridplan}
    exec(textwrap.dedent(blocks("python")[2]), namespace)
    repaired, replanner = namespace["repaired"], namespace["replanner"]
    assert replanner.start == tuple(namespace["path"][3])
    assert repaired.status == "found" and repaired.valid
    scratch = gridplan.plan(
        replanner.grid,
        replanner.start,
        replanner.goal,
        planner="astar",
        moves=8,
        corner_cutting=False,
        heuristic="octile",
    )
    assert repaired.metrics["length"] == pytest.approx(scratch.metrics["length"], rel=1e-12)
    assert repaired.counters["n_expanded"] < scratch.counters["n_expanded"]
