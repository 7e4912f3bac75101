"""gridplan from Python: grid path planners and the experiment runner.

Grids come from NumPy (``Grid.from_numpy``) or map files (``read_map``); ``plan`` runs one
registered planner (``planners()`` lists them with their parameters) and returns an
``Outcome`` with the path as an (N, 2) array and the planner's counters;
``Planner`` keeps a planner and its per-grid tables for many queries (``plan_many``
runs a batch on threads and returns arrays); ``Replanner`` keeps an incremental planner
(D* Lite, LPA*) on a map that changes as a robot drives, repairing its path after each
update; ``run_experiment`` sweeps an experiment config (``configs/*.toml``) and returns its records
with runs.csv's columns, as a pandas DataFrame when pandas is installed. The planning runs
in Rust with the GIL released, so Python threads plan in parallel.

Coordinates: ``(x, y)`` = (column, row), ``(0, 0)`` the top-left cell; arrays are indexed
``[y, x]``. A grid read from a ROS ``map_server`` YAML has a ``frame`` (``MapFrame``) that
converts between cells and points of the map frame in metres.
"""

import os as _os
from typing import Any as _Any
from typing import Dict as _Dict
from typing import List as _List
from typing import Optional as _Optional
from typing import Union as _Union

from ._errors import (
    ConfigError,
    DeterminismError,
    GridplanError,
    GridplanWarning,
    MapError,
    OutputError,
    ParameterError,
    ProblemError,
)
from ._gridplan import (
    DEFAULT_PLAN_EXPANSIONS,
    Grid,
    MapFrame,
    Outcome,
    Planner,
    PlannerInfo,
    Problem,
    Replanner,
    compare,
    plan,
    planners,
    read_map,
)
from ._gridplan import run_experiment_rows as _run_experiment_rows

__all__ = [
    "DEFAULT_PLAN_EXPANSIONS",
    "ConfigError",
    "DeterminismError",
    "Grid",
    "GridplanError",
    "GridplanWarning",
    "MapError",
    "MapFrame",
    "Outcome",
    "OutputError",
    "ParameterError",
    "Planner",
    "PlannerInfo",
    "Problem",
    "ProblemError",
    "Replanner",
    "compare",
    "plan",
    "planners",
    "read_map",
    "run_experiment",
]


def run_experiment(
    config: _Union[str, "_os.PathLike[str]"],
    *,
    threads: int = 0,
    output: _Optional[_Union[str, "_os.PathLike[str]"]] = None,
    lock_wait: float = 120.0,
    resume: bool = False,
) -> _Union["pandas.DataFrame", _List[_Dict[str, _Any]]]:  # noqa: F821
    """Runs the experiment config ``config`` (a ``configs/*.toml`` file) and returns its
    records in the run order (map, problem, planner label, repeat), one per run, with
    runs.csv's columns: a pandas DataFrame when pandas is installed, else a list of dicts.

    ``threads``: worker threads, 0 for the config's ``threads`` (where 0 means one per
    core); records do not depend on it (their times and ``peak_heap_bytes`` aside).

    ``output``: a results directory to write as ``gridplan experiment --output`` does
    (runs.csv, runs.json, summary.md, figures, ...), under the same rules: only an absent,
    empty or gridplan-marked directory is replaced, atomically; anything else raises
    ``OutputError`` and is left untouched. The records returned are then runs.json's.
    Without it nothing is written.

    ``lock_wait``: with ``output``, how many seconds to wait for another sweep writing the
    same output (which holds its lock from start to end) before raising ``OutputError``.

    ``resume``: with ``output``, keep the runs that an interrupted sweep of the same config
    recorded there (a Ctrl-C, a killed kernel) and run the rest, as ``gridplan experiment
    --resume`` does; after a finished sweep of the same config nothing runs again. A
    ``GridplanWarning`` says how many runs were kept; an interrupted sweep of another
    config there raises ``ValueError`` (run without ``resume`` to start over).

    The DataFrame's dtypes are runs.parquet's types, every value exact: the integer
    columns (``problem``, ``start_x``, ``start_y``, ``goal_x``, ``goal_y``, ``repeat``,
    ``seed``, ``steps``, ``turns``, ``score``, ``peak_heap_bytes``, ``bucket`` and every
    counter) are pandas' nullable ``UInt64``, an empty runs.csv cell (an unseeded
    planner's seed, a counter the run's planner does not report) ``<NA>``; ``length``,
    ``optimal_length``, ``time_ms``, ``setup_ms`` and ``cost`` are ``float64`` (empty:
    NaN); ``valid`` is ``bool``, or the nullable ``boolean`` when some run has none;
    ``map``, ``planner``, ``algorithm``, ``status`` and ``error`` are ``object`` (str, or
    None). In the list of dicts an empty cell is None and integers are Python ints.
    """
    columns, kinds, rows = _run_experiment_rows(
        _os.fspath(config),
        threads=threads,
        output=None if output is None else _os.fspath(output),
        lock_wait=lock_wait,
        resume=resume,
    )
    try:
        import pandas
    except ImportError:
        return rows
    return _frame(pandas, columns, kinds, rows)


def _frame(pandas: _Any, columns: _List[str], kinds: _List[str], rows: _List[_Dict[str, _Any]]) -> _Any:
    """The records ``rows`` as a DataFrame of ``columns``, each of its kind's dtype (see
    ``run_experiment``): built column by column, so that no integer goes through float64
    (``DataFrame.from_records`` made a column with an empty cell float64, rounding
    integers above 2**53)."""
    data = {}
    for column, kind in zip(columns, kinds):
        values = [row[column] for row in rows]
        if kind == "uint":
            dtype = "UInt64"
        elif kind == "float":
            dtype = "float64"
        elif kind == "bool":
            dtype = "boolean" if any(v is None for v in values) else "bool"
        else:
            dtype = "object"
        data[column] = pandas.Series(values, dtype=dtype)
    return pandas.DataFrame(data, columns=columns, index=pandas.RangeIndex(len(rows)))
