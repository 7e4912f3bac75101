"""gridplan from Python: grid path planners and the experiment runner.

Grids come from NumPy (``Grid.from_numpy``) or map files (``read_map``); ``plan`` runs one
registered planner (``planners()`` lists them with their parameters) and returns an
``Outcome`` with the path as an (N, 2) array and the planner's counters;
``run_experiment`` sweeps an experiment config (``configs/*.toml``) and returns its records
with runs.csv's columns, as a pandas DataFrame when pandas is installed. The planning runs
in Rust with the GIL released, so Python threads plan in parallel.

Coordinates: ``(x, y)`` = (column, row), ``(0, 0)`` the top-left cell; arrays are indexed
``[y, x]``.
"""

import os
from typing import Any, Dict, List, Optional, Union

from ._errors import ConfigError, GridplanError, MapError, ParameterError, ProblemError
from ._gridplan import (
    DEFAULT_PLAN_EXPANSIONS,
    Grid,
    Outcome,
    PlannerInfo,
    Problem,
    plan,
    planners,
    read_map,
)
from ._gridplan import run_experiment_rows as _run_experiment_rows

__all__ = [
    "DEFAULT_PLAN_EXPANSIONS",
    "ConfigError",
    "Grid",
    "GridplanError",
    "MapError",
    "Outcome",
    "ParameterError",
    "PlannerInfo",
    "Problem",
    "ProblemError",
    "plan",
    "planners",
    "read_map",
    "run_experiment",
]


def run_experiment(
    config: Union[str, "os.PathLike[str]"],
    *,
    threads: int = 0,
) -> Union["pandas.DataFrame", List[Dict[str, Any]]]:  # noqa: F821
    """Runs the experiment config ``config`` (a ``configs/*.toml`` file) and returns its
    records in the run order (map, problem, planner label, repeat), one per run, with
    runs.csv's columns: a pandas DataFrame when pandas is installed, else a list of dicts.

    ``threads``: worker threads, 0 for the config's ``threads`` (where 0 means one per
    core); records do not depend on it. ``peak_heap_bytes`` is 0 (the command line counts
    allocations with its own allocator; the Python package does not).
    """
    columns, rows = _run_experiment_rows(os.fspath(config), threads=threads)
    try:
        import pandas
    except ImportError:
        return rows
    return pandas.DataFrame.from_records(rows, columns=columns)
