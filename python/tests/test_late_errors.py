"""Failures found after a sweep has started (its config read, its output checked) raise
the exception class of the command line's exit status (planner-runner's
``RunnerError::class``), never a bare ``GridplanError`` when a closer class exists."""

import os

import pytest

import gridplan
from conftest import CONFIGS, MAPS


def small_config(tmp_path, map_file):
    config = tmp_path / "c.toml"
    config.write_text(
        f'name = "c"\n[[maps]]\nfiles = ["{map_file.as_posix()}"]\nproblems = "corners"\n'
        '[planners.a]\nplanner = "bfs"\n'
    )
    return config


def test_a_foreign_stream_area_is_an_output_error(tmp_path):
    # The sweep's stream area beside the output (`.out.stream`) is checked after the
    # config is read and the output accepted: one that is not gridplan's is refused.
    config = small_config(tmp_path, MAPS / "paper" / "map01.map")
    stream = tmp_path / ".out.stream"
    stream.mkdir()
    (stream / "notes.txt").write_text("mine")
    with pytest.raises(gridplan.OutputError) as info:
        gridplan.run_experiment(config, output=tmp_path / "out")
    assert ".out.stream" in str(info.value)
    assert [p.name for p in stream.iterdir()] == ["notes.txt"]
    assert not (tmp_path / "out").exists()


def test_a_linked_lock_is_an_output_error(tmp_path):
    config = small_config(tmp_path, MAPS / "paper" / "map01.map")
    target = tmp_path / "precious.txt"
    target.write_text("keep")
    os.symlink(target, tmp_path / ".out.lock")
    with pytest.raises(gridplan.OutputError) as info:
        gridplan.run_experiment(config, output=tmp_path / "out")
    assert "symbolic link" in str(info.value)
    assert target.read_text() == "keep"


def test_a_broken_map_of_a_config_is_a_config_error_naming_the_map(tmp_path):
    bad = tmp_path / "bad.map"
    bad.write_text("type octile\nheight x\n")
    config = small_config(tmp_path, bad)
    for output in (None, tmp_path / "out"):
        with pytest.raises(gridplan.ConfigError) as info:
            gridplan.run_experiment(config, output=output)
        assert "bad.map" in str(info.value)
        assert info.value.file == str(config)


def test_too_many_threads_is_a_value_error_in_memory_and_on_disk(tmp_path):
    for output in (None, tmp_path / "out"):
        with pytest.raises(ValueError) as info:
            gridplan.run_experiment(CONFIGS / "paper.toml", threads=100_000, output=output)
        assert not isinstance(info.value, gridplan.GridplanError)
        assert "100000 worker threads" in str(info.value)


def test_an_output_another_sweep_holds_is_an_output_error(tmp_path):
    # A sweep writing `out` holds an OS file lock (flock) on `.out.stream.lock` from its
    # start to its end, the file naming its pid. Taken here as the runner takes it, a
    # second sweep on `out` waits `lock_wait` seconds for it, then raises OutputError
    # naming the holder, and writes nothing.
    import fcntl

    config = small_config(tmp_path, MAPS / "paper" / "map01.map")
    output = tmp_path / "out"
    with open(tmp_path / ".out.stream.lock", "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX | fcntl.LOCK_NB)
        lock.write("4242\n")
        lock.flush()
        with pytest.raises(gridplan.OutputError) as info:
            gridplan.run_experiment(config, output=output, lock_wait=0.5)
        message = str(info.value)
        assert "is being written by another gridplan run (pid 4242)" in message, message
        assert ".out.stream.lock" in message, message
        assert not output.exists()
    # Released, the same sweep runs.
    rows = gridplan.run_experiment(config, output=output, lock_wait=0.5)
    unheld = gridplan.run_experiment(config, output=tmp_path / "unheld")
    assert len(rows) == len(unheld) > 0
    assert (output / "runs.csv").exists()
    assert (output / "runs.csv").is_file()


def test_a_negative_lock_wait_is_a_value_error(tmp_path):
    config = small_config(tmp_path, MAPS / "paper" / "map01.map")
    with pytest.raises(ValueError) as info:
        gridplan.run_experiment(config, output=tmp_path / "out", lock_wait=-1)
    assert "lock_wait" in str(info.value)
    assert not (tmp_path / "out").exists()
