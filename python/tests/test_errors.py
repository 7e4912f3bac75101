"""Every error kind as its exception, with the command line's message."""

import numpy as np
import pytest

import gridplan
from conftest import MAPS

ASTAR_KEYS = "`moves`, `corner_cutting`, `order`, `heuristic`, `weight`, `tie_break`"


def check(call, exception, message):
    """`call()` raises `exception` with exactly `message`; returns the exception."""
    with pytest.raises(exception) as info:
        call()
    assert str(info.value) == message
    assert isinstance(info.value, (gridplan.GridplanError, ValueError, TypeError))
    return info.value


def test_config_errors_name_file_line_column(tmp_path):
    config = tmp_path / "bad.toml"
    config.write_text('name = "bad"\nthreds = 2\n')
    error = check(
        lambda: gridplan.run_experiment(config),
        gridplan.ConfigError,
        f"{config}:2:1: unknown field `threds`, expected one of `name`, `description`, "
        "`output`, `threads`, `repeats`, `seed`, `budget`, `figures`, `figures_per_map`, "
        "`figures_pick`, `figures_expanded`, `charts`, `ompl`, `paths`, `outputs`, `published`, `test`, `sections`, "
        "`maps`, `planners`",
    )
    assert (error.file, error.line, error.column) == (str(config), 2, 1)
    assert isinstance(error, gridplan.GridplanError)


def test_config_planner_parameter_errors_are_positioned(tmp_path):
    config = tmp_path / "badparam.toml"
    map01 = (MAPS / "paper" / "map01.map").as_posix()
    config.write_text(
        f'name = "bad"\n[[maps]]\nfiles = ["{map01}"]\nproblems = "corners"\n'
        '[planners.a]\nplanner = "astar"\nwieght = 2\n'
    )
    check(
        lambda: gridplan.run_experiment(config),
        gridplan.ConfigError,
        f"{config}:7:1: planner `a` (astar): unknown field `wieght`, expected one of {ASTAR_KEYS}",
    )


def test_a_replanning_config_is_named_as_such():
    # run_experiment reads the runner's configs; a replanning one (configs/replan/) had
    # been refused as an unknown key `kind`.
    config = MAPS.parent / "configs" / "replan" / "navigate.toml"
    with pytest.raises(gridplan.ConfigError, match="a replanning experiment .* runs with `gridplan experiment`"):
        gridplan.run_experiment(config)


def test_missing_config():
    error = check(
        lambda: gridplan.run_experiment("/nonexistent/x.toml"),
        gridplan.ConfigError,
        "/nonexistent/x.toml: cannot read the config: No such file or directory (os error 2)",
    )
    assert error.line == 0


def test_map_errors_name_file_line_column(tmp_path):
    path = tmp_path / "bad.map"
    path.write_text("type octile\nheight 2\nwidth 3\nmap\n..x\n...\n")
    error = check(
        lambda: gridplan.read_map(path),
        gridplan.MapError,
        f"{path}:5:3: expected one of '.', 'G', 'S' (passable) or '@', 'O', 'T', 'W' "
        "(blocked), found 'x'",
    )
    assert (error.file, error.line, error.column) == (str(path), 5, 3)
    check(
        lambda: gridplan.read_map(tmp_path / "m.bmp"),
        gridplan.MapError,
        f"{tmp_path / 'm.bmp'}: unsupported file extension '.bmp', expected one of "
        ".map (Moving AI), .txt (seed 003), .csv (0/1 matrix), .yaml/.yml (ROS map_server), "
        ".pgm/.png (an occupancy image); .scen files hold scenarios, not maps",
    )


def test_problem_errors_name_the_cell(map10):
    error = check(
        lambda: gridplan.plan(map10, (10, 0), (11, 11)),
        gridplan.ProblemError,
        "start (10, 0) is blocked",
    )
    assert (error.endpoint, error.cell) == ("start", (10, 0))
    assert isinstance(error, ValueError)
    check(
        lambda: gridplan.plan(map10, (0, 0), (12, 3)),
        gridplan.ProblemError,
        "goal (12, 3) is outside the 12x12 grid",
    )
    error = check(
        lambda: gridplan.plan(map10, (-1, 0), (11, 11)),
        gridplan.ProblemError,
        "start (-1, 0) is outside the 12x12 grid",
    )
    assert error.cell == (-1, 0)


def test_parameter_errors_name_the_key(map10):
    error = check(
        lambda: gridplan.plan(map10, (0, 0), (11, 11), wieght=2),
        gridplan.ParameterError,
        f"planner `astar`: unknown field `wieght`, expected one of {ASTAR_KEYS}",
    )
    assert error.key == "wieght"
    assert isinstance(error, ValueError)
    error = check(
        lambda: gridplan.plan(map10, (0, 0), (11, 11), weight=-2),
        gridplan.ParameterError,
        "planner `astar`: parameter `weight` must be a finite number >= 0, got -2",
    )
    assert error.key == "weight"
    error = check(
        lambda: gridplan.plan(map10, (0, 0), (11, 11), planner="nope"),
        gridplan.ParameterError,
        "unknown planner `nope`, expected one of "
        + ", ".join(p.name for p in gridplan.planners()),
    )
    assert error.key == "planner"
    check(
        lambda: gridplan.plan(map10, (0, 0), (11, 11), heuristic=object()),
        gridplan.ParameterError,
        "planner `astar`: parameter `heuristic`: a planner parameter is a bool, int, float, str, list or dict, got object",
    )
    check(
        lambda: gridplan.plan(map10, (0, 0), (11, 11), budget={"max_expansion": 3}),
        gridplan.ParameterError,
        "budget: unknown field `max_expansion`, expected one of `max_expansions`, `max_time_ms`, "
            "`max_memory_mb`",
    )


def test_goal_rules(map10):
    check(
        lambda: gridplan.plan(map10, (0, 0)),
        ValueError,
        "`astar` plans from a start to a goal: give the goal",
    )
    check(
        lambda: gridplan.plan(map10, (0, 0), (11, 11), planner="coverage"),
        ValueError,
        "`coverage` is a coverage planner: it covers from the start and takes no goal",
    )


def test_array_errors():
    check(
        lambda: gridplan.Grid.from_numpy(np.zeros((2, 3, 4)), free=True),
        ValueError,
        "Grid.from_numpy: expected a 2-D array of shape (height, width), got shape (2, 3, 4)",
    )
    array = np.ones((3, 4))
    array[1, 2] = 2
    check(
        lambda: gridplan.Grid.from_numpy(array, free=True),
        ValueError,
        "Grid.from_numpy: cell (2, 1) (array[1, 2]) is 2, expected 0 or 1",
    )
    check(
        lambda: gridplan.Grid.from_numpy(np.array([["a"]]), free=True),
        TypeError,
        "Grid.from_numpy: expected a bool or 0/1 numeric array, got dtype <U1",
    )
    check(
        lambda: gridplan.Grid.from_numpy(np.zeros((0, 3), dtype=bool), free=True),
        ValueError,
        "Grid.from_numpy: a grid needs at least one row and one column",
    )
    with pytest.raises(TypeError):
        gridplan.Grid.from_numpy(np.ones((2, 2)))  # the convention is not optional


def test_huge_zero_stride_arrays_are_refused():
    # Issue 27: a zero-stride view of 10^10 cells aborted the interpreter (a 10 GB
    # allocation); the size is checked before any cell is read.
    for value in (True, 1, 1.0):
        check(
            lambda: gridplan.Grid.from_numpy(
                np.broadcast_to(value, (100000, 100000)), free=True
            ),
            ValueError,
            "Grid.from_numpy: an array of shape (100000, 100000) has 10000000000 cells, "
            "more than a grid's limit of 2147483648",
        )
    # NumPy's (rows, columns): one row of 2**40 columns is shape (1, 2**40).
    check(
        lambda: gridplan.Grid.from_numpy(np.broadcast_to(np.uint8(1), (1, 2**40)), free=True),
        ValueError,
        "Grid.from_numpy: an array of shape (1, 1099511627776) has 1099511627776 cells, "
        "more than a grid's limit of 2147483648",
    )
    # A zero-stride view within the limit is read cell by cell, like any array.
    grid = gridplan.Grid.from_numpy(np.broadcast_to(False, (300, 200)), free=False)
    assert (grid.width, grid.height, grid.n_free) == (200, 300, 60000)


def test_control_characters_in_messages_are_escaped(tmp_path, map10):
    """A config or parameter someone else wrote cannot send an escape sequence to the
    terminal through an exception's or a warning's message: control characters (but line
    breaks and tabs) are written as \\u{..}, as the command line writes them; the
    attribute keeps the text."""
    folder = tmp_path / "e\x1b[2Jx"
    folder.mkdir()
    config = folder / "esc.toml"
    map01 = (MAPS / "paper" / "map01.map").as_posix()
    config.write_text(
        f'name = "esc"\n[[maps]]\nfiles = ["{map01}"]\nproblems = "corners"\n'
        '[planners."\\u001b[2Jx"]\nplanner = "nosuch"\n'
    )
    with pytest.raises(gridplan.GridplanError) as info:
        gridplan.run_experiment(config)
    assert "\x1b" not in str(info.value)
    assert "\\u{1b}[2Jx" in str(info.value)
    # The file attribute is the path as it is, to open it with.
    assert info.value.file == str(config)
    with pytest.raises(ValueError) as info:
        gridplan.plan(map10, (0, 0), (11, 11), planner="astar\x07")
    assert "\x07" not in str(info.value) and "\\u{7}" in str(info.value)
    assert info.value.key is not None


def test_cells_are_any_two_integers(map10):
    """A start or goal given as a list, a NumPy array or NumPy integers is the cell (a list
    raised `'list' object is not an instance of 'tuple'`); anything else is a TypeError
    naming the argument."""
    expected = gridplan.plan(map10, (0, 0), (11, 11))
    planner = gridplan.Planner(map10, "astar")
    for start, goal in [([0, 0], np.array([11, 11])), ((np.int64(0), np.uint8(0)), [11, 11])]:
        assert gridplan.plan(map10, start, goal) == expected
        assert planner.plan(start, goal) == expected
    assert map10.is_free([0, 0]) and map10.is_free(np.array([0, 0]))
    for start in [(0.0, 0.0), [0, 0, 0], "00", np.array([[0, 0]])]:
        with pytest.raises(TypeError, match="^start: expected a cell"):
            gridplan.plan(map10, start, (11, 11))
        with pytest.raises(TypeError, match="^start: expected a cell"):
            planner.plan(start, (11, 11))
    with pytest.raises(TypeError, match="^goal: expected a cell"):
        gridplan.plan(map10, (0, 0), [11.5, 11])


def test_integers_out_of_range_name_the_argument(map10, tmp_path):
    """Integers beyond what a Rust type holds raised a bare OverflowError naming nothing."""
    huge = 2**70
    error = check(
        lambda: gridplan.plan(map10, (huge, 0), (11, 11)),
        gridplan.ProblemError,
        f"start ({huge}, 0) is outside the 12x12 grid",
    )
    assert (error.endpoint, error.cell) == ("start", (huge, 0))
    check(
        lambda: gridplan.Planner(map10, "astar").plan((0, 0), (11, -huge)),
        gridplan.ProblemError,
        f"goal (11, {-huge}) is outside the 12x12 grid",
    )
    check(
        lambda: gridplan.plan(map10, (np.uint64(2**64 - 1), 0), (11, 11)),
        gridplan.ProblemError,
        "start (18446744073709551615, 0) is outside the 12x12 grid",
    )
    assert map10.is_free((huge, 0)) is False
    planner = gridplan.Planner(map10, "astar")
    check(
        lambda: planner.plan_many([[0, 0]], [[11, 11]], threads=-1),
        ValueError,
        "threads: -1 is negative; use 0 for one per core",
    )
    check(
        lambda: planner.plan_many([[0, 0]], [[11, 11]], threads=huge),
        ValueError,
        f"threads: {huge} is more than 256; use 0 for one per core",
    )
    check(
        lambda: gridplan.run_experiment(MAPS.parent / "configs" / "paper.toml", threads=-1),
        ValueError,
        "threads: -1 is negative; use 0 for the config's threads",
    )
    check(
        lambda: gridplan.compare(tmp_path, tmp_path, examples=-1),
        ValueError,
        "examples: -1 is negative; give how many differing runs to list",
    )
    (tmp_path / "m.csv").write_text("1,0\n0,1\n")
    check(
        lambda: gridplan.read_map(tmp_path / "m.csv", obstacle=-1),
        ValueError,
        "read_map: obstacle=-1; the obstacle value of a .csv matrix is 0 or 1",
    )
    replanner = gridplan.Replanner(map10, "dstar_lite", start=(0, 0), goal=(11, 11))
    check(
        lambda: replanner.move_to((huge, 0)),
        ValueError,
        f"move_to: ({huge}, 0) is outside the 12x12 grid",
    )
    check(
        lambda: gridplan.Replanner(map10, "dstar_lite", start=[0, 0], goal=(huge, 11)),
        gridplan.ProblemError,
        f"goal ({huge}, 11) is outside the 12x12 grid",
    )
    frame = gridplan.read_map(MAPS / "ros-nav2" / "tb3_sandbox.yaml")[0].frame
    check(
        lambda: frame.world((huge, 0)),
        ValueError,
        f"MapFrame.world: cell ({huge}, 0) is not on the 384x384 map",
    )
    assert frame.world([1, 2]) == frame.world((1, 2))


def test_a_bad_budget_value_names_its_key(map10):
    for key, value in [("max_expansions", -1), ("max_time_ms", -5), ("max_memory_mb", -1)]:
        error = check(
            lambda: gridplan.plan(map10, (0, 0), (11, 11), budget={key: value}),
            gridplan.ParameterError,
            f"budget.{key}: {value} is negative; a budget is at least 0",
        )
        assert error.key == f"budget.{key}"
    error = check(
        lambda: gridplan.Planner(map10, budget={"max_expansions": 5, "max_time_ms": "soon"}),
        gridplan.ParameterError,
        'budget.max_time_ms: invalid type: string "soon", expected u64',
    )
    assert error.key == "budget.max_time_ms"


def test_none_keeps_a_parameters_default(map10):
    """planners() reports defaults of None (coverage's rotation, rrt_star's gamma):
    passed back, they were refused (`got NoneType`)."""
    infos = {info.name: info for info in gridplan.planners()}
    assert infos["coverage"].parameters["reference_side"] == "left"
    assert infos["coverage"].parameters["rotation"] is None
    assert infos["rrt_star"].parameters["gamma"] is None
    for info in infos.values():
        goal = None if info.task == "coverage" else (11, 11)
        budget = 10_000 if info.name == "backtracking" else None
        outcome = gridplan.plan(map10, (0, 0), goal, planner=info.name, budget=budget, **info.parameters)
        default = gridplan.plan(map10, (0, 0), goal, planner=info.name, budget=budget)
        assert outcome == default, info.name
    assert gridplan.plan(map10, (0, 0), (11, 11), weight=None, budget={"max_time_ms": None}).status == "found"


def test_integers_beyond_a_config_s_name_the_planner_and_the_range(map10):
    """A seed of 2**64 - 1 was refused with a message shaped unlike the others (no
    planner), saying nothing of the range; budgets alike."""
    for planner, key, value in [("rrt", "seed", 2**64 - 1), ("astar", "moves", 2**70),
                                ("rrt", "seed", np.uint64(2**64 - 1))]:
        error = check(
            lambda: gridplan.plan(map10, (0, 0), (11, 11), planner=planner, **{key: value}),
            gridplan.ParameterError,
            f"planner `{planner}`: parameter `{key}`: {int(value)} is more than "
            "9223372036854775807, the largest integer a parameter takes",
        )
        assert error.key == key
    check(
        lambda: gridplan.Planner(map10, "astar", weight=-(2**70)),
        gridplan.ParameterError,
        f"planner `astar`: parameter `weight`: {-(2**70)} is less than "
        "-9223372036854775808, the smallest integer a parameter takes",
    )
    check(
        lambda: gridplan.Replanner(map10, "dstar_lite", start=(0, 0), goal=(11, 11), moves=2**64),
        gridplan.ParameterError,
        f"planner `dstar_lite`: parameter `moves`: {2**64} is more than "
        "9223372036854775807, the largest integer a parameter takes",
    )
    # The largest seed a parameter takes runs.
    assert gridplan.plan(map10, (0, 0), (11, 11), planner="rrt", seed=2**63 - 1).seed == 2**63 - 1
    for budget, key in [(2**70, "budget"), ({"max_memory_mb": 2**64}, "budget.max_memory_mb"),
                        ({"max_expansions": 2**64 - 1}, "budget.max_expansions")]:
        value = budget if isinstance(budget, int) else next(iter(budget.values()))
        error = check(
            lambda: gridplan.plan(map10, (0, 0), (11, 11), budget=budget),
            gridplan.ParameterError,
            f"{key}: {value} is more than 9223372036854775807, the largest a budget takes",
        )
        assert error.key == key
    check(
        lambda: gridplan.plan(map10, (0, 0), (11, 11), budget={"max_time_ms": -(2**70)}),
        gridplan.ParameterError,
        f"budget.max_time_ms: {-(2**70)} is negative; a budget is at least 0",
    )
    check(
        lambda: gridplan.plan(map10, (0, 0), (11, 11), budget="soon"),
        gridplan.ParameterError,
        "budget: expected a number of expansions or a dict of `max_expansions`, "
        "`max_time_ms` and `max_memory_mb`, got string",
    )


def test_help_documents_the_arguments():
    """help(gridplan.plan) and help(gridplan.Planner) only said "see the stub"."""
    import pydoc

    plan = pydoc.plain(pydoc.render_doc(gridplan.plan))
    assert "plan(grid, start, goal=None, *, planner='astar', budget=None, record=False, **params)" in plan
    for word in ["`budget`", "max_memory_mb", "`record=True`", "ProblemError", "ParameterError"]:
        assert word in plan, word
    planner = pydoc.plain(pydoc.render_doc(gridplan.Planner))
    assert "Planner(grid, planner='astar', *, budget=None, **params)" in planner
    for word in ["plan_many(starts, goals=None", "`cost`", "`valid`", "`paths=True`"]:
        assert word in planner, word
    for thing in [gridplan.plan, gridplan.Planner, gridplan.Planner.plan,
                  gridplan.Planner.plan_many, gridplan.Replanner, gridplan.read_map]:
        assert "see the stub" not in thing.__doc__
