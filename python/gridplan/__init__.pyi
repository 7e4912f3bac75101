"""Type stubs of the ``gridplan`` package (the native module's classes and functions, and
the Python half's)."""

import os
from typing import Any, Dict, List, Optional, Sequence, Tuple, Union, overload

import numpy as np
import numpy.typing as npt

_Cell = Tuple[int, int]
# A cell argument: any sequence of two integers (NumPy's included).
_CellLike = Union[Tuple[int, int], Sequence[int], npt.NDArray[np.integer[Any]]]

DEFAULT_PLAN_EXPANSIONS: int
"""The expansion budget ``plan`` applies when ``budget`` sets none (as the command line)."""

class GridplanError(Exception):
    """Base class of every error gridplan raises (besides ValueError and TypeError)."""

class GridplanWarning(UserWarning):
    """What gridplan read but doubted or ignored, raised through :mod:`warnings` (the
    command line prints it on stderr)."""

class ConfigError(GridplanError):
    """An experiment config that cannot be read: ``file:line:column: message``."""
    file: str
    line: int
    column: int
    def __init__(self, message: str, *, file: str = ..., line: int = ..., column: int = ...) -> None: ...

class MapError(GridplanError):
    """A map or scenario file that cannot be read: ``file:line:column: message``."""
    file: str
    line: int
    column: int
    def __init__(self, message: str, *, file: str = ..., line: int = ..., column: int = ...) -> None: ...

class OutputError(GridplanError):
    """A results directory gridplan may not replace (nothing was written), or a directory
    given to ``compare`` that does not hold a whole sweep's complete results (none, a
    shard's, a cut or damaged records stream)."""

class DeterminismError(GridplanError):
    """A run repeated to record expanded cells did not repeat its timed run (a bug)."""

class ProblemError(GridplanError, ValueError):
    """A start or goal outside the grid or on a blocked cell."""
    endpoint: str
    cell: _Cell
    def __init__(self, message: str, *, endpoint: str = ..., cell: _Cell = ...) -> None: ...

class ParameterError(GridplanError, ValueError):
    """A planner name, parameter or budget that is unknown or invalid; ``key`` names it."""
    key: Optional[str]
    def __init__(self, message: str, *, key: Optional[str] = ...) -> None: ...

class Grid:
    """An occupancy grid, ``width`` columns by ``height`` rows; cell ``(x, y)`` is
    ``array[y, x]`` of ``to_numpy()``. It pickles (and copies) with its weights and
    frame."""
    @classmethod
    def from_numpy(cls, array: npt.ArrayLike, *, free: bool) -> "Grid":
        """A grid from a 2-D array of shape (height, width) of bools or 0/1 numbers.
        ``free=True``: True/1 marks free cells; ``free=False``: True/1 marks obstacles."""
    def to_numpy(self, *, free: bool = True) -> npt.NDArray[np.bool_]:
        """A bool array of shape (height, width): True marks free cells (``free=True``) or
        obstacles (``free=False``)."""
    def with_weights(self, weights: npt.ArrayLike, *, cost_rule: str = "mean") -> "Grid":
        """This grid with a weight per cell: an integer array of shape (height, width),
        every value from 1 to 65535. ``cost_rule``: ``"mean"`` (a move costs its length
        times the mean of its two cells' weights) or ``"entered"`` (times the entered
        cell's weight)."""
    @property
    def weights(self) -> Optional[npt.NDArray[np.uint16]]:
        """The cell weights, shape (height, width); None on an unweighted grid."""
    @property
    def cost_rule(self) -> Optional[str]:
        """``"mean"`` or ``"entered"`` on a weighted grid; else None."""
    @property
    def width(self) -> int: ...
    @property
    def height(self) -> int: ...
    @property
    def shape(self) -> Tuple[int, int]:
        """``(height, width)``."""
    @property
    def n_free(self) -> int: ...
    def is_free(self, cell: _CellLike) -> bool:
        """Whether ``(x, y)`` lies on the grid and is free (False for any integers off
        it)."""
    @property
    def frame(self) -> Optional["MapFrame"]:
        """Where the cells lie in the ROS map frame, for a grid read from a
        ``map_server`` ``.yaml`` (kept by ``with_weights``); None for other grids."""
    def __eq__(self, other: object) -> bool:
        """Same size, free cells and weights; map frames are not compared."""

class MapFrame:
    """A ROS map's frame: ``resolution`` (metres per cell) and ``origin`` (``(x, y, yaw)``
    of the bottom-left cell's lower-left corner; the yaw is ignored, as by nav2). Row 0 is
    the image's top row. The conversions are nav2's ``mapToWorld`` and ``worldToMap``.
    It pickles."""
    @property
    def resolution(self) -> float: ...
    @property
    def origin(self) -> Tuple[float, float, float]: ...
    @property
    def bounds(self) -> Tuple[float, float, float, float]:
        """``(min_x, min_y, max_x, max_y)`` in metres; the upper ends are outside."""
    @overload
    def world(self, cells: Union[_Cell, Sequence[int]]) -> Tuple[float, float]: ...
    @overload
    def world(self, cells: npt.ArrayLike) -> npt.NDArray[np.float64]:
        """The map-frame positions (metres) of cell centres: one ``(x, y)`` cell gives a
        tuple, an (N, 2) integer array (a path) an (N, 2) float64 array."""
    def cell(self, point: Tuple[float, float]) -> _Cell:
        """The cell holding map-frame point ``(x, y)`` (metres); ValueError outside the
        map."""
    def __eq__(self, other: object) -> bool: ...

class Problem:
    """A start-goal pair a map file states (or the ``.scen`` file beside a ``.map``). It
    pickles."""
    @property
    def start(self) -> _Cell: ...
    @property
    def goal(self) -> _Cell: ...
    @property
    def optimal_length(self) -> Optional[float]: ...
    @property
    def bucket(self) -> Optional[int]: ...
    def __eq__(self, other: object) -> bool: ...

class Outcome:
    """The result of ``plan``: a value. Its arrays are read-only and its dicts and lists
    are copies, so nothing done with them changes it; it pickles (a ``multiprocessing``
    worker can return it), and ``==`` compares every field but ``time_ms`` (arrays element
    by element)."""
    @property
    def status(self) -> str:
        """``"found"``, ``"no_path"`` or ``"budget_exhausted"``."""
    @property
    def path(self) -> npt.NDArray[np.int64]:
        """(N, 2) array of ``(x, y)`` rows; (0, 2) without a path. Read-only."""
    @property
    def metrics(self) -> Optional[Dict[str, Union[int, float]]]:
        """``steps``, ``turns``, ``score`` (seed 000's D, T, Score) and ``length``."""
    @property
    def counters(self) -> Dict[str, int]:
        """The planner's counters, in its order."""
    @property
    def marks(self) -> List[Tuple[str, _Cell]]:
        """``(label, (x, y))`` of the cells the planner marks."""
    @property
    def series(self) -> Dict[str, npt.NDArray[np.float64]]:
        """Recorded sequences: name -> (N, 2) array of points."""
    @property
    def seed(self) -> Optional[int]: ...
    @property
    def valid(self) -> Optional[bool]: ...
    @property
    def time_ms(self) -> float: ...
    @property
    def cost(self) -> Optional[float]:
        """On a weighted grid, the path's cost under the grid's cost rule; else None."""
    @property
    def expanded(self) -> Optional[npt.NDArray[np.int64]]:
        """With ``plan(..., record=True)``: the expanded cells in order, an (N, 2) array
        (empty for planners that do not record them); else None."""
    @property
    def events(self) -> Optional[Dict[str, npt.NDArray[Any]]]:
        """With ``plan(..., record=True)``: the search step by step where the planner
        records it (A*, any heuristic; bidirectional A*, Theta*, Lazy Theta*, JPS, weighted
        JPS): equal-length (read-only)
        arrays ``kind`` (``"generating"``,
        ``"updating"``, ``"expanding"``), ``x``, ``y``, ``parent_x``, ``parent_y`` (-1 for
        the start), ``g`` and ``f`` (``pandas.DataFrame(outcome.events)`` makes a table;
        empty for the other planners); else None."""
    def __eq__(self, other: object) -> bool:
        """Same status, path, metrics, counters, marks, series, seed, validity, cost and
        recording; ``time_ms`` is not compared."""

class PlannerInfo:
    """A registered planner. It pickles (by name: the registry's entry is read again)."""
    @property
    def name(self) -> str: ...
    @property
    def summary(self) -> str: ...
    @property
    def task(self) -> str:
        """``"start_goal"`` or ``"coverage"``."""
    @property
    def seeded(self) -> bool: ...
    @property
    def admissible(self) -> Optional[bool]:
        """With its defaults: ``True`` when its paths are least-cost by design, ``False``
        when it trades optimality on purpose, ``None`` when it makes no claim."""
    @property
    def cell_costs(self) -> bool:
        """Whether it honours cell weights (else a weighted map is refused unless the call
        says ``costs="ignore"``)."""
    @property
    def incremental(self) -> bool:
        """Whether it can be fed map changes and repair its search."""
    @property
    def path_rule(self) -> str:
        """With its defaults: ``"any-angle"`` or the moves its paths step by, e.g.
        ``"8-connected"`` (``", corners cut"`` added when diagonals may pass a corner)."""
    @property
    def parameters(self) -> Dict[str, Any]:
        """Every parameter with its default (None for one without a value by default;
        passing None leaves a parameter at its default)."""

class Planner:
    """A registry planner built once for ``grid`` with its parameters; its per-grid tables
    are built by the first query and reused by every later one (``plan`` rebuilds them on
    every call). Results are the same as ``gridplan.plan``'s. Calls on one planner from
    several threads run one after another (for queries in parallel use ``plan_many``, or a
    planner per thread): a call waits while another holds the planner, and Ctrl-C ends the
    wait with ``KeyboardInterrupt``. In a process forked while another thread was using it
    (``os.fork``, ``multiprocessing``'s ``fork``), its calls raise ``GridplanError``: make a
    new ``Planner`` there."""
    def __init__(
        self,
        grid: Grid,
        planner: str = "astar",
        *,
        budget: Union[None, int, Dict[str, int]] = None,
        **params: Any,
    ) -> None: ...
    @property
    def name(self) -> str:
        """The registry name."""
    def plan(self, start: _CellLike, goal: Optional[_CellLike] = None) -> Outcome:
        """One query, as ``gridplan.plan(grid, start, goal, planner=..., **params)``, on the
        calling thread with the GIL released (a few microseconds beyond the search on den520d:
        ``python/bench/plan_calls.py``). Ctrl-C takes effect when the search ends: give the
        planner a budget, or use ``plan_many``, which it interrupts (handing each search
        to another thread to watch for signals meanwhile, as ``plan`` does, cost tens of
        microseconds a query)."""
    def plan_many(
        self,
        starts: npt.ArrayLike,
        goals: Optional[npt.ArrayLike] = None,
        *,
        threads: int = 0,
        paths: bool = False,
    ) -> Dict[str, Any]:
        """Plans query ``i`` from ``starts[i]`` to ``goals[i]`` (``(N, 2)`` arrays of
        ``(x, y)``, or empty sequences for no query; integers of any size or
        whole-numbered floats as ``np.floor`` gives them: 0.5, NaN or infinity raises
        ``ValueError`` naming the query, a boolean or string array ``TypeError``; no goals
        for coverage planners) on ``threads`` threads (0: one per core, at most 256 as in a
        config; more, or a negative number, raises ``ValueError``) with the GIL released.
        Returns arrays in query order, ``plan``'s outcome fields: ``status`` (str),
        ``length`` (float64, NaN without a path), ``cost`` (float64: ``Outcome.cost``, NaN
        where that is None, i.e. without a path or on an unweighted grid), ``steps``,
        ``turns`` and ``score`` (int64, -1 without a path), ``valid`` (bool:
        ``Outcome.valid``, False where that is None, without a path; ``status`` tells the
        two apart), ``error`` (str: why a run did not plan, e.g. its memory check refused
        it; empty when none), ``time_ms`` (float64, the search alone), ``counters`` (name
        -> int64 array: every counter that one of the batch's runs reported, -1 in a run
        that did not report it; a planner declares no fixed set, some report a counter only
        on some outcomes, e.g. ``path_cost_units`` only with a path, so the names are known
        from the runs alone and no queries give an empty dict), ``seed`` (not an array: the
        seed a seeded planner ran every query with, ``Outcome.seed``; None for other planners and for no queries) and, with
        ``paths=True``, ``paths`` (a list of (N, 2) arrays), ``marks`` and ``series``
        (lists of each query's ``Outcome.marks`` and ``Outcome.series``).
        Counters do not depend on ``threads``. A start or goal off the grid (whole numbers
        too large for any grid, as ``2**64`` or ``1e30``, included) or blocked raises
        ``ProblemError`` naming the query. Ctrl-C (a notebook's interrupt) raises
        ``KeyboardInterrupt``: no query starts after it and the running ones stop at their
        next budget check; the planner stays usable."""

class Replanner:
    """An incremental planner's session (``"dstar_lite"``, ``"lpastar"``: the planners whose
    ``PlannerInfo.incremental`` is true) on its own copy of ``grid``, from ``start`` to
    ``goal``, for a robot whose map changes as it drives. ``plan()`` computes the path the
    first time and repairs it after ``update`` and ``move_to``; each outcome's counters are
    that call's alone, so a repair's ``n_expanded`` shows what it saved against a search
    from scratch. Parameters are the planner's (``moves=4`` or ``8``), as in a config's
    table; another planner name raises ``ValueError`` listing the incremental ones, a bad
    start or goal ``ProblemError``. Each ``plan`` gets ``budget`` (as ``gridplan.plan``'s:
    10,000,000 expansions by default)."""
    def __init__(
        self,
        grid: Grid,
        planner: str = "dstar_lite",
        *,
        start: _CellLike,
        goal: _CellLike,
        budget: Union[None, int, Dict[str, int]] = None,
        **params: Any,
    ) -> None: ...
    @property
    def name(self) -> str:
        """The registry name."""
    @property
    def start(self) -> Optional[Tuple[int, int]]:
        """The current start: the agent's cell."""
    @property
    def goal(self) -> Tuple[int, int]: ...
    @property
    def grid(self) -> Optional[Grid]:
        """The planner's map: the grid it began with and every update since (a copy)."""
    def plan(self) -> Outcome:
        """The least-cost path from the current start to the goal on the current map
        (``status`` ``"no_path"`` when the updates cut it off), repaired from the last one.
        ``valid`` says it steps between free cells by the planner's moves from the start to
        the goal; ``cost`` is its cost on a weighted grid."""
    def update(
        self,
        cells: npt.ArrayLike,
        *,
        free: Union[None, bool, npt.ArrayLike] = None,
        weights: Union[None, int, npt.ArrayLike] = None,
    ) -> None:
        """Cells that changed, an ``(N, 2)`` array of ``(x, y)`` (empty: nothing changed):
        ``free`` says whether
        each is now free (one bool for all, or one per cell), ``weights`` its new weight on
        a weighted grid (1 to 65535; one for all or one per cell); give either or both (a
        cell given weights alone keeps its state). A cell off the grid, a weight out of
        range or weights on an unweighted grid raise ``ValueError`` naming it, and nothing
        is applied. The start or goal may be blocked: ``plan`` then finds no path."""
    def move_to(self, cell: _CellLike) -> None:
        """The agent moved to ``cell`` (free, on the grid, else ``ValueError``): the next
        ``plan`` starts there. D* Lite keeps its search; LPA* starts again from there."""

def read_map(
    path: Union[str, "os.PathLike[str]"],
    *,
    obstacle: int = 0,
    weights: Union[None, str, "os.PathLike[str]"] = None,
    graded: bool = False,
    lethal: Optional[int] = None,
    unknown: Optional[int] = None,
    swamp: Optional[int] = None,
    water: Optional[int] = None,
    cost_rule: str = "mean",
) -> Tuple[Grid, List[Problem]]:
    """Reads a ``.map``, ``.txt``, ``.csv`` or ROS ``.yaml`` map: the grid and its problems.
    ``obstacle``: the value marking obstacles in a ``.csv`` matrix (0 or 1). ``weights``:
    a ``.csv`` of cell weights for the map (``plan --weights``); ``graded=True``: a ROS
    map's graded values as costs (nav2's bands, ``plan --graded``); ``lethal``: ROS costs
    from it up are blocked (1 to 255, default 254, nav2's lethal; ``plan --lethal``);
    ``unknown``: the cost of a ROS map's unknown cells (0 to 254, default blocked; ``plan
    --unknown``), each implying ``graded=True``; ``swamp``: the weight of Moving AI swamp
    ``S`` (ground is 1) and ``water``: the weight of water ``W``, then passable (needs
    ``swamp``), both 1 to 65535 (``plan --swamp``, ``--water``); ``cost_rule``:
    ``"mean"`` or ``"entered"``. A config's map set ``costs = { unknown = 250 }`` is
    ``unknown=250``. As ``gridplan plan`` does, an option that would change nothing or
    contradicts another raises ``ValueError`` naming the argument: ``obstacle=1`` for a map
    that is not a ``.csv``, ``graded``, ``lethal`` or ``unknown`` for one that is not a
    ROS map, ``swamp`` or ``water`` for one that is not a ``.map``, any of them beside
    ``weights``, ``water`` without ``swamp``, a value out of its range,
    ``cost_rule="entered"`` without costs. A ``.scen`` file whose scenarios name another
    map file is read, with a ``GridplanWarning``."""

def planners() -> List[PlannerInfo]:
    """Every registered planner with its declared parameters and their defaults."""

def plan(
    grid: Grid,
    start: _CellLike,
    goal: Optional[_CellLike] = None,
    *,
    planner: str = "astar",
    budget: Union[None, int, Dict[str, int]] = None,
    record: bool = False,
    **params: Any,
) -> Outcome:
    """Plans from ``start`` to ``goal`` (cells: any two integers, as a tuple, list or NumPy
    array; no goal for coverage planners) with registry planner ``planner`` and its
    parameters (one given as None keeps its default). Integers, ``seed`` included, are a
    config's TOML integers: a parameter takes -2**63 to 2**63 - 1 (a ``seed`` 0 to
    2**63 - 1), a budget 0 to 2**63 - 1; beyond that ``ParameterError`` names the key.
    ``budget``: a number of expansions,
    or a dict of ``max_expansions``, ``max_time_ms`` and ``max_memory_mb`` (a bad value
    raises ``ParameterError`` with key ``budget.<key>``); without ``max_expansions``,
    ``DEFAULT_PLAN_EXPANSIONS``. On a weighted grid a planner that cannot honour cell
    costs is refused (``ParameterError``, key ``costs``) unless ``costs="ignore"``.
    ``record=True``: the search is run once more to record it (it must repeat the first
    run, else ``DeterminismError``), and the outcome's ``expanded`` and ``events`` hold
    it; with ``max_time_ms`` in the budget the recording run is not checked, as it stops
    at its own time limit, so ``expanded`` may hold more or fewer cells than
    ``counters["n_expanded"]``. Ctrl-C (a notebook's interrupt) stops the search at its
    next budget check and raises ``KeyboardInterrupt``."""

def compare(
    old: Union[str, "os.PathLike[str]"],
    new: Union[str, "os.PathLike[str]"],
    *,
    examples: int = 10,
) -> Dict[str, Any]:
    """Compares two results directories run by run, as ``gridplan compare OLD NEW --json``:
    ``old`` and ``new`` (``dir``, ``runs``, ``provenance``), ``both``, ``only_old``,
    ``only_new``, ``differing`` (runs of both whose computed fields differ: status, path,
    length, cost, counters, ...), ``same``, ``examples`` (the first ``examples`` differing
    runs, one per problem, each ``run`` and its ``fields`` as ``[name, old, new]``) and
    ``times`` (per label ``label``, ``problems``, ``ratio``: the geometric mean of NEW's
    median time over OLD's per problem, ``low`` and ``high``: its 95 % interval, and
    ``faster``). A directory that is not complete results (none, a shard's, a cut or
    damaged records stream) raises ``OutputError``; a negative
    ``examples`` ``ValueError``."""

def run_experiment(
    config: Union[str, "os.PathLike[str]"],
    *,
    threads: int = 0,
    output: Optional[Union[str, "os.PathLike[str]"]] = None,
    lock_wait: float = 120.0,
    resume: bool = False,
) -> Any:
    """Runs an experiment config; its records with runs.csv's columns, as a pandas
    DataFrame when pandas is installed, else a list of dicts. Ctrl-C (a notebook's
    interrupt) raises ``KeyboardInterrupt`` once the sweep has stopped: no run starts
    after it; in memory the running searches stop at their next budget check, while with
    ``output`` they finish and the finished runs stay in the output's stream area, which
    ``resume=True`` (or the command line's ``experiment --resume``) continues.

    The DataFrame's dtypes are runs.parquet's types, every value exact: the integer
    columns (``problem``, ``start_x``, ``start_y``, ``goal_x``, ``goal_y``, ``repeat``,
    ``seed``, ``steps``, ``turns``, ``score``, ``peak_heap_bytes``, ``bucket`` and every
    counter) are pandas' nullable ``UInt64``, an empty cell ``<NA>``; ``length``,
    ``optimal_length``, ``time_ms``, ``setup_ms`` and ``cost`` are ``float64`` (empty:
    NaN); ``valid`` is ``bool``, or the nullable ``boolean`` when some run has none;
    ``map``, ``planner``, ``algorithm``, ``status`` and ``error`` are ``object``."""
