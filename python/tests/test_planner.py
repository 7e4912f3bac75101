"""Planner: prepared once, then plan() and plan_many() give gridplan.plan's results."""

from pathlib import Path

import numpy as np
import pytest

import gridplan
from conftest import MAPS

STUB_DOC = Path(gridplan.__file__).with_name("__init__.pyi")

ARENA = MAPS / "movingai" / "arena.map"
PARAMS = dict(moves=8, heuristic="octile", tie_break="high_g")


@pytest.fixture(scope="module")
def arena():
    return gridplan.read_map(ARENA)


def test_plan_equals_gridplan_plan(arena):
    grid, problems = arena
    planner = gridplan.Planner(grid, "astar", **PARAMS)
    assert planner.name == "astar"
    for p in problems[:40]:
        ours = planner.plan(p.start, p.goal)
        theirs = gridplan.plan(grid, p.start, p.goal, planner="astar", **PARAMS)
        assert ours.status == theirs.status
        assert ours.counters == theirs.counters
        assert ours.metrics == theirs.metrics
        assert np.array_equal(ours.path, theirs.path)
        assert ours.valid is True


def test_plan_many_equals_plan_for_any_thread_count(arena):
    grid, problems = arena
    chosen = problems[::4]
    starts = np.array([p.start for p in chosen])
    goals = np.array([p.goal for p in chosen])
    planner = gridplan.Planner(grid, "jps", variant="jps_plus")
    one = planner.plan_many(starts, goals, threads=1, paths=True)
    two = planner.plan_many(starts, goals, threads=2, paths=True)
    assert list(one["status"]) == ["found"] * len(chosen)
    for key in ["length", "steps", "turns"]:
        assert np.array_equal(one[key], two[key]), key
    assert one["counters"].keys() == two["counters"].keys()
    for name, values in one["counters"].items():
        assert values.dtype == np.int64
        assert np.array_equal(values, two["counters"][name]), name
    for i, p in enumerate(chosen):
        single = planner.plan(p.start, p.goal)
        assert one["length"][i] == pytest.approx(single.metrics["length"], abs=0)
        assert one["counters"]["n_expanded"][i] == single.counters["n_expanded"]
        assert np.array_equal(one["paths"][i], single.path)
        # The scenario file's optimum (8-connected, no corner cutting).
        assert one["length"][i] == pytest.approx(p.optimal_length, rel=1e-4)
    assert "paths" not in planner.plan_many(starts, goals)


def test_plan_many_reports_no_path_and_budget_as_rows():
    grid = gridplan.Grid.from_numpy(
        np.array([[1, 0, 1], [1, 0, 1], [1, 0, 1]], dtype=bool), free=True
    )
    for budget, goal, status in [(None, [2, 2], "no_path"), (1, [0, 2], "budget_exhausted")]:
        out = gridplan.Planner(grid, "astar", budget=budget).plan_many([[0, 0]], [goal])
        assert list(out["status"]) == [status]
        assert np.isnan(out["length"]).all()
        assert list(out["steps"]) == [-1]


def test_plan_many_without_queries_gives_empty_arrays_of_the_usual_types(map10):
    none = np.zeros((0, 2), dtype=np.int64)
    out = gridplan.Planner(map10, "astar").plan_many(none, none)
    assert out["status"].dtype.kind == "U" and out["status"].shape == (0,)
    assert out["length"].dtype == np.float64 and out["steps"].dtype == np.int64
    assert out["length"].shape == out["steps"].shape == out["time_ms"].shape == (0,)


def test_plan_many_takes_empty_sequences_as_no_queries(map10):
    # `plan_many([], [])` raised `expected an (N, 2) array ..., got shape (0,)`.
    planner = gridplan.Planner(map10, "astar")
    for starts, goals in [([], []), ((), None), (np.array([]), [])]:
        out = planner.plan_many(starts, goals)
        assert out["status"].shape == out["length"].shape == (0,)


def test_bad_queries_raise_and_name_the_query(map10):
    planner = gridplan.Planner(map10, "astar")
    with pytest.raises(gridplan.ProblemError, match="query 1") as error:
        planner.plan_many([[0, 0], [-1, 0]], [[11, 11], [11, 11]])
    assert error.value.endpoint == "start"
    with pytest.raises(gridplan.ProblemError):
        planner.plan((0, 0), (12, 0))
    with pytest.raises(ValueError, match=r"\(N, 2\)"):
        planner.plan_many([0, 0, 1], [[1, 1]])
    with pytest.raises(ValueError, match="2 starts"):
        planner.plan_many([[0, 0], [0, 0]], [[1, 1]])
    with pytest.raises(ValueError, match="give the goal"):
        planner.plan((0, 0))
    with pytest.raises(gridplan.ParameterError):
        gridplan.Planner(map10, "astar", moves=7)
    with pytest.raises(gridplan.ParameterError):
        gridplan.Planner(map10, "no_such_planner")
    # A config's limit on threads: a pool of a million threads took gigabytes and minutes
    # before this check.
    with pytest.raises(ValueError, match="threads: 1000000 is more than 256"):
        planner.plan_many([[0, 0]], [[11, 11]], threads=10**6)
    # The planner stays usable after errors.
    assert planner.plan((0, 0), (11, 11)).status == "found"


def test_plan_many_takes_whole_numbers_only(map10):
    planner = gridplan.Planner(map10, "astar")
    ints = planner.plan_many([[0, 0]], [[11, 11]])
    # Whole floats (as np.floor gives them) and unsigned integers are the same cells.
    floats = planner.plan_many(np.array([[0.0, 0.0]]), np.floor(np.array([[11.5, 11.2]])))
    unsigned = planner.plan_many(np.array([[0, 0]], dtype=np.uint8), np.array([[11, 11]], dtype=np.uint64))
    for out in (floats, unsigned):
        assert list(out["status"]) == list(ints["status"])
        assert list(out["length"]) == list(ints["length"])
    # A cast would plan another cell: refused, naming the query.
    for starts in ([[0, 0], [0.5, 0]], [[0, 0], [np.nan, 0]], [[0, 0], [np.inf, 1]]):
        with pytest.raises(ValueError, match="starts: query 1: .* is not a cell"):
            planner.plan_many(np.array(starts), [[11, 11], [11, 11]])
    with pytest.raises(TypeError, match="integer cells, got dtype bool"):
        planner.plan_many(np.array([[True, False]]), [[11, 11]])
    with pytest.raises(TypeError, match="integer cells"):
        planner.plan_many([["0", "0"]], [[11, 11]])


def test_plan_many_counters_are_those_the_runs_reported(map10):
    """A planner declares no fixed set of counters, and some report a counter only on some
    outcomes (LPA*'s `path_cost_units` only with a path): `counters` holds every name one
    of the batch's runs reported, -1 in a run without it, so no queries give no counters.
    The stub says so (it promised every counter as a name -> int64 array)."""
    planner = gridplan.Planner(map10, "lpastar")
    found = planner.plan_many([[0, 0]], [[11, 11]])
    # A blocked goal is refused; a goal walled off by obstacles has no path.
    walled = np.ones((3, 3), dtype=bool)
    walled[1, :] = False
    lone = gridplan.Planner(gridplan.Grid.from_numpy(walled, free=True), "lpastar")
    both = lone.plan_many([[0, 0], [0, 0]], [[2, 0], [0, 2]])
    assert list(both["status"]) == ["found", "no_path"]
    assert "path_cost_units" in found["counters"]
    assert list(both["counters"]["path_cost_units"]) == [both["counters"]["path_cost_units"][0], -1]
    assert both["counters"]["path_cost_units"][0] >= 0
    alone = lone.plan_many([[0, 0]], [[0, 2]])
    assert "path_cost_units" not in alone["counters"]
    assert planner.plan_many(np.empty((0, 2), dtype=np.int64), np.empty((0, 2), dtype=np.int64))["counters"] == {}
    doc = " ".join(STUB_DOC.read_text().split())
    assert "so the names are known from the runs alone and no queries give an empty dict" in doc


def test_plan_many_whole_numbers_beyond_any_grid_are_problem_errors(map10):
    """Whole numbers too large for any grid (a uint64 above 2**63 - 1, Python ints beyond
    64 bits, whole floats as 1e30) are a start or goal off the grid, as `plan` says of them:
    a ProblemError naming the query, the endpoint and the cell as given. They were a
    ValueError or TypeError saying they are no whole numbers."""
    planner = gridplan.Planner(map10, "astar")
    goals = [[11, 11], [11, 11]]
    cases = [
        (np.array([[0, 0], [1e30, 0]]), "start", r"\(1e30, 0\)", (1e30, 0)),
        (np.array([[0, 0], [2**63, 0]], dtype=np.uint64), "start",
         r"\(9223372036854775808, 0\)", (2**63, 0)),
        ([[0, 0], [2**64, 0]], "start", r"\(18446744073709551616, 0\)", (2**64, 0)),
        ([[0, 0], [3, -(2**70)]], "start", r"\(3, -1180591620717411303424\)", (3, -(2**70))),
    ]
    for starts, endpoint, shown, cell in cases:
        with pytest.raises(gridplan.ProblemError, match=rf"^query 1: start {shown} is outside the 12x12 grid") as raised:
            planner.plan_many(starts, goals)
        assert (raised.value.endpoint, raised.value.cell) == (endpoint, cell)
    # A goal too, and the same message `plan` gives (with the query).
    with pytest.raises(gridplan.ProblemError, match=r"^query 0: goal \(18446744073709551616, 1\) is outside") as raised:
        planner.plan_many([[0, 0]], [[2**64, 1]])
    assert raised.value.endpoint == "goal"
    with pytest.raises(gridplan.ProblemError, match=r"^goal \(18446744073709551616, 1\) is outside"):
        planner.plan((0, 0), (2**64, 1))
    with pytest.raises(gridplan.ProblemError, match="query 0: goal"):
        planner.plan_many([[0, 0]], np.array([[2**63, 1]], dtype=np.uint64))
    # Queries are checked in order: query 0's blocked start before query 1's huge one.
    with pytest.raises(gridplan.ProblemError, match="^query 0: "):
        planner.plan_many([[-1, 0], [2**64, 0]], goals)
    # Not whole numbers stay a ValueError, also among huge integers (an object array).
    for starts in ([[0, 0], [2**64, 0.5]], [[0, 0], [2**64, float("nan")]], [[0, 0], [float("inf"), 2**64]]):
        with pytest.raises(ValueError, match="starts: query 1: .* is not a cell") as raised:
            planner.plan_many(starts, goals)
        assert not isinstance(raised.value, gridplan.ProblemError)
    # Whole numbers in an object array (huge ones and small ones) are cells like any.
    small = planner.plan_many(np.array([[0, 0]], dtype=object), np.array([[11, 11.0]], dtype=object))
    assert list(small["status"]) == list(planner.plan_many([[0, 0]], [[11, 11]])["status"])
    with pytest.raises(TypeError, match="starts: query 0: expected integer cells"):
        planner.plan_many(np.array([[None, 0]], dtype=object), [[11, 11]])
    # The planner stays usable.
    assert planner.plan((0, 0), (11, 11)).status == "found"


def interrupted_output(setup, call, after):
    """What a child Python prints when it runs `setup`, then `call` inside a try that prints
    'interrupted' on KeyboardInterrupt (else 'finished'), and gets SIGINT `after` seconds
    into it. The child handles SIGINT as an interactive Python does, even when this test
    runs with SIGINT ignored (a background job), which it would inherit."""
    import signal
    import subprocess
    import sys
    import time

    script = (
        "import signal\n"
        "signal.signal(signal.SIGINT, signal.default_int_handler)\n"
        f"{setup}\n"
        "print('ready', flush=True)\n"
        "try:\n"
        f"    {call}\n"
        "    print('finished', flush=True)\n"
        "except KeyboardInterrupt:\n"
        "    print('interrupted', flush=True)\n"
    )
    proc = subprocess.Popen([sys.executable, "-c", script], stdout=subprocess.PIPE, text=True)
    try:
        assert proc.stdout.readline().strip() == "ready"
        time.sleep(after)
        proc.send_signal(signal.SIGINT)
        out, _ = proc.communicate(timeout=60)
    finally:
        proc.kill()
    return out.split()


def test_ctrl_c_interrupts_plan_many_and_the_planner_stays_usable():
    """Ctrl-C (a notebook's interrupt) stops a batch that would run for hours: the running
    search stops at its next budget check and KeyboardInterrupt is raised."""
    out = interrupted_output(
        "import gridplan, numpy as np\n"
        "grid = gridplan.Grid.from_numpy(np.ones((64, 64), dtype=bool), free=True)\n"
        "planner = gridplan.Planner(grid, 'backtracking', budget={'max_expansions': 10**18})\n"
        "import atexit\n"
        "atexit.register(lambda: print(planner.plan_many([[0, 0]], [[0, 0]])['status'][0]))",
        "planner.plan_many([[0, 0]], [[63, 63]], threads=1)",
        0.5,
    )
    assert out == ["interrupted", "found"]


def test_ctrl_c_interrupts_plan():
    """Ctrl-C stops a one-off `gridplan.plan` whose search would run for hours (it held the
    interpreter until the search ended), and a later call plans as before."""
    out = interrupted_output(
        "import gridplan, numpy as np\n"
        "grid = gridplan.Grid.from_numpy(np.ones((64, 64), dtype=bool), free=True)\n"
        "import atexit\n"
        "atexit.register(lambda: print(gridplan.plan(grid, (0, 0), (0, 0), planner='backtracking').status))",
        "gridplan.plan(grid, (0, 0), (63, 63), planner='backtracking', budget={'max_expansions': 10**18})",
        0.5,
    )
    assert out == ["interrupted", "found"]


def test_a_forked_process_plans_with_the_parents_planner():
    """A process forked after the parent planned (multiprocessing's `fork` start method)
    inherits the pools' memory but none of their threads: `plan`, `plan_many` and a
    `Planner` built in the parent still plan there (they waited forever)."""
    import multiprocessing

    global _FORKED
    grid = gridplan.Grid.from_numpy(np.ones((32, 32), dtype=bool), free=True)
    planner = gridplan.Planner(grid, "astar")
    assert gridplan.plan(grid, (0, 0), (31, 31)).status == "found"
    assert planner.plan_many([[0, 0]], [[31, 31]])["status"][0] == "found"
    # The child reads them from the memory it inherits (they are not picklable).
    _FORKED = (grid, planner)
    context = multiprocessing.get_context("fork")
    with context.Pool(1) as pool:
        child = pool.apply_async(_plan_in_child)
        assert child.get(timeout=60) == ["found", "found", "found"]


_FORKED = None


def _plan_in_child():
    grid, planner = _FORKED
    return [
        gridplan.plan(grid, (0, 0), (31, 31)).status,
        planner.plan((0, 0), (31, 31)).status,
        str(planner.plan_many([[0, 0]], [[31, 31]])["status"][0]),
    ]


def test_ctrl_c_interrupts_run_experiment(tmp_path):
    """Ctrl-C stops a sweep in memory whose search would run for hours."""
    (tmp_path / "open.map").write_text(
        "type octile\nheight 64\nwidth 64\nmap\n" + ("." * 64 + "\n") * 64
    )
    (tmp_path / "c.toml").write_text(
        'name = "forever"\n[[maps]]\nfiles = ["open.map"]\n'
        "pairs = [{ start = [0, 0], goal = [63, 63] }]\n"
        '[planners.bt]\nplanner = "backtracking"\n'
        "[budget]\nmax_expansions = 1_000_000_000_000_000\n"
    )
    out = interrupted_output(
        "import gridplan",
        f"gridplan.run_experiment({str(tmp_path / 'c.toml')!r})",
        1.0,
    )
    assert out == ["interrupted"]


BUSY = (
    "grid = gridplan.Grid.from_numpy(np.ones((64, 64), dtype=bool), free=True)\n"
    "planner = gridplan.Planner(grid, 'backtracking', budget={'max_expansions': 10**18, 'max_time_ms': %d})\n"
    "batch = threading.Thread(target=planner.plan_many, args=([[0, 0]], [[63, 63]]), kwargs={'threads': 1})\n"
    "batch.start()\n"
    "time.sleep(0.3)\n"
)
"""Python that leaves `planner` held by another thread's batch (a search that runs until its
time budget, in milliseconds, ends) and `grid`."""


def test_ctrl_c_interrupts_a_wait_for_a_planner_another_thread_holds():
    """Calls on one Planner run one after another: a call waits for another thread's batch,
    and Ctrl-C ends the wait (it raised only once the other batch had ended)."""
    import signal
    import subprocess
    import sys
    import time

    script = (
        "import signal, threading, time\n"
        "signal.signal(signal.SIGINT, signal.default_int_handler)\n"
        "import gridplan, numpy as np\n"
        + BUSY % 5000
        + "print('ready', flush=True)\n"
        "try:\n"
        "    planner.plan((0, 0), (0, 0))\n"
        "    print('finished', flush=True)\n"
        "except KeyboardInterrupt:\n"
        "    print('interrupted', flush=True)\n"
    )
    proc = subprocess.Popen([sys.executable, "-c", script], stdout=subprocess.PIPE, text=True)
    try:
        assert proc.stdout.readline().strip() == "ready"
        time.sleep(0.5)
        sent = time.monotonic()
        proc.send_signal(signal.SIGINT)
        line = proc.stdout.readline().strip()
        waited = time.monotonic() - sent
        proc.communicate(timeout=60)
    finally:
        proc.kill()
    assert line == "interrupted"
    assert waited < 2.5


_BUSY = None


@pytest.mark.filterwarnings("ignore::DeprecationWarning")
def test_a_process_forked_while_another_thread_plans_is_told_to_make_a_new_planner():
    """A child forked while a thread of the parent held a Planner waited for it forever
    (that thread is not in the child): its calls raise GridplanError, and a new Planner
    plans there."""
    import multiprocessing
    import threading
    import time

    global _BUSY
    namespace = {"gridplan": gridplan, "np": np, "threading": threading, "time": time}
    exec(BUSY % 3000, namespace)
    _BUSY = namespace["grid"], namespace["planner"]
    try:
        with multiprocessing.get_context("fork").Pool(1) as pool:
            child = pool.apply_async(_plan_after_fork).get(timeout=30)
    finally:
        namespace["batch"].join()
    assert child == [
        "GridplanError: this Planner was in use by another thread when the process forked, "
        "and that thread does not exist in this process: make a new Planner here",
        "found",
    ]


def _plan_after_fork():
    grid, planner = _BUSY
    try:
        planner.plan((0, 0), (0, 0))
        held = "planned"
    except gridplan.GridplanError as error:
        held = f"{type(error).__name__}: {error}"
    return [held, gridplan.Planner(grid, "astar").plan((0, 0), (63, 63)).status]


def test_plan_many_gives_plan_s_cost_validity_and_score():
    """plan_many's dict had no cost (nor valid, score, error, seed) on weighted grids: a
    cost-aware planner's batch gives each query's Outcome.cost, NaN where it is None."""
    rng = np.random.default_rng(7)
    free = np.ones((16, 16), dtype=bool)
    # A wall across row 8 with a gap at its end, and a walled-in free cell (1, 14): a
    # query to it finds no path (cost NaN, valid False).
    free[8, :13] = False
    free[13:16, 0:3] = False
    free[14, 1] = True
    weights = rng.integers(1, 256, size=(16, 16))
    weighted = gridplan.Grid.from_numpy(free, free=True).with_weights(weights)
    starts = np.array([[0, 0], [15, 15], [0, 0], [15, 0]])
    goals = np.array([[15, 15], [0, 0], [1, 14], [15, 15]])
    aware = [
        info.name
        for info in gridplan.planners()
        if info.cell_costs and info.task == "start_goal"
    ]
    for name in ["astar", "weighted_jps", "bidirectional_astar", "lexastar", "dstar_lite", "lpastar"]:
        assert name in aware
    for name in aware:
        planner = gridplan.Planner(weighted, name)
        many = planner.plan_many(starts, goals, paths=True)
        assert many["cost"].dtype == np.float64, name
        assert many["valid"].dtype == np.bool_, name
        assert many["score"].dtype == np.int64, name
        assert list(many["error"]) == [""] * len(starts), name
        for i in range(len(starts)):
            single = gridplan.plan(weighted, starts[i], goals[i], planner=name)
            assert many["status"][i] == single.status, (name, i)
            if single.cost is None:
                assert np.isnan(many["cost"][i]), (name, i)
            else:
                assert many["cost"][i] == single.cost, (name, i)
            assert many["valid"][i] == bool(single.valid), (name, i)
            score = single.metrics["score"] if single.metrics else -1
            assert many["score"][i] == score, (name, i)
            assert many["marks"][i] == single.marks, (name, i)
            assert many["series"][i].keys() == single.series.keys(), (name, i)
        assert many["seed"] == single.seed, name
        assert list(many["status"][2:3]) == ["no_path"], name
    # Unweighted: no cost, as Outcome.cost is None.
    plain = gridplan.Grid.from_numpy(free, free=True)
    many = gridplan.Planner(plain, "astar").plan_many(starts, goals)
    assert np.isnan(many["cost"]).all()
    assert gridplan.plan(plain, (0, 0), (15, 15)).cost is None
    assert list(many["valid"]) == [True, True, False, True]
    # A seeded planner's seed, as plan's.
    rrt = gridplan.Planner(plain, "rrt", seed=5).plan_many(starts[:1], goals[:1])
    assert rrt["seed"] == gridplan.plan(plain, (0, 0), (15, 15), planner="rrt", seed=5).seed == 5
