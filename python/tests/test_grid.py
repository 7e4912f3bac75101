"""Grid to and from NumPy (both conventions) and read_map for every format."""

import numpy as np
import pytest

import gridplan
from conftest import MAPS


def parse_movingai(path):
    """The `.map` rows as a bool array (True = free), read independently of gridplan."""
    lines = path.read_text().splitlines()
    rows = lines[lines.index("map") + 1 :]
    return np.array([[c in ".GS" for c in row] for row in rows if row])


def check_round_trip(array, free):
    grid = gridplan.Grid.from_numpy(array, free=free)
    assert grid.shape == array.shape == (grid.height, grid.width)
    back = grid.to_numpy(free=free)
    assert back.dtype == np.bool_
    assert (back == array.astype(bool)).all()
    # The other convention is the complement.
    assert (grid.to_numpy(free=not free) == ~array.astype(bool)).all()
    assert gridplan.Grid.from_numpy(back, free=free) == grid
    return grid


def test_round_trip_free_convention():
    array = np.random.default_rng(0).random((7, 11)) < 0.7
    grid = check_round_trip(array, free=True)
    assert grid.n_free == int(array.sum())
    assert grid.is_free((3, 5)) == bool(array[5, 3])


def test_round_trip_obstacle_convention():
    array = np.random.default_rng(1).random((9, 4)) < 0.3
    grid = check_round_trip(array, free=False)
    assert grid.n_free == int((~array).sum())
    assert grid.is_free((2, 6)) == (not array[6, 2])


@pytest.mark.parametrize("dtype", [np.uint8, np.int64, np.float32, np.float64])
def test_zero_one_arrays_of_any_numeric_dtype(dtype):
    array = (np.random.default_rng(2).random((5, 6)) < 0.5).astype(dtype)
    for free in (True, False):
        check_round_trip(array, free=free)


def test_lists_and_non_contiguous_arrays():
    grid = gridplan.Grid.from_numpy([[1, 0, 1], [1, 1, 0]], free=True)
    assert grid.to_numpy().tolist() == [[True, False, True], [True, True, False]]
    array = np.random.default_rng(3).random((8, 10)) < 0.5
    check_round_trip(array[::2, ::3], free=True)
    check_round_trip(array.T, free=False)


def test_read_map_matches_the_file():
    path = MAPS / "paper" / "map10.map"
    grid, problems = gridplan.read_map(path)
    assert (grid.to_numpy() == parse_movingai(path)).all()
    assert gridplan.Grid.from_numpy(parse_movingai(path), free=True) == grid
    assert problems == []


def test_read_map_every_format():
    # Seed 003's text maps carry their start-goal pairs.
    grid, problems = gridplan.read_map(str(MAPS / "wpi" / "map1.txt"))
    assert problems and all(grid.is_free(p.start) and grid.is_free(p.goal) for p in problems)
    # A Moving AI map takes the scenarios beside it, with their optimal lengths.
    grid, problems = gridplan.read_map(MAPS / "movingai" / "arena.map")
    first = (MAPS / "movingai" / "arena.map.scen").read_text().splitlines()[1].split("\t")
    assert problems[0].start == (int(first[4]), int(first[5]))
    assert problems[0].goal == (int(first[6]), int(first[7]))
    assert problems[0].optimal_length == pytest.approx(float(first[8]))
    assert problems[0].bucket == int(first[0])
    # ROS map_server maps.
    yaml = sorted((MAPS / "ros-nav2").glob("*.yaml"))
    assert yaml
    grid, problems = gridplan.read_map(yaml[0])
    assert grid.width > 0 and problems == []


def test_read_map_csv(tmp_path):
    path = tmp_path / "m.csv"
    path.write_text("1,1,0\n0,1,1\n")
    grid, _ = gridplan.read_map(path)
    assert grid.to_numpy().tolist() == [[True, True, False], [False, True, True]]
    # The other convention, as `plan --obstacle 1` reads it.
    grid, _ = gridplan.read_map(path, obstacle=1)
    assert grid.to_numpy().tolist() == [[False, False, True], [True, False, False]]
    with pytest.raises(ValueError):
        gridplan.read_map(path, obstacle=2)
