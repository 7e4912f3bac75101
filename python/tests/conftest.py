"""Shared paths and the one `check` helper per area: tests run on the installed package
(`pip install ./python`) against the repository's maps and configs."""

from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
MAPS = ROOT / "maps"
CONFIGS = ROOT / "configs"


@pytest.fixture
def map10():
    import gridplan

    grid, problems = gridplan.read_map(MAPS / "paper" / "map10.map")
    return grid
