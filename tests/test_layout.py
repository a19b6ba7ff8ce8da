"""The repository's shape: the fixed top level, and no unit of code over 700 lines (a module
holds one idea; LAMMPS's one class per .h/.cpp pair)."""
import subprocess
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
TOP_LEVEL = {"pyproject.toml", "calib", "meshes", "nfdmodel", "tests", "results", "README.md", ".ci", ".gitignore"}
LONGEST_UNIT = 700


def tracked() -> list[str]:
    try:
        return subprocess.run(["git", "ls-files"], cwd=ROOT, capture_output=True, text=True, check=True).stdout.split()
    except (OSError, subprocess.CalledProcessError):
        pytest.skip("not a git checkout")


def test_the_top_level_holds_only_the_fixed_entries():
    assert {path.split("/")[0] for path in tracked()} <= TOP_LEVEL


def test_no_unit_of_code_is_longer_than_700_lines():
    units = [p for p in tracked() if p.startswith(("calib/", "nfdmodel/", "meshes/"))
             and p.endswith((".py", ".c", ".h", ".cpp"))]
    long = {p: n for p in units if (n := len((ROOT / p).read_text(encoding="utf-8").splitlines())) > LONGEST_UNIT}
    assert not long, f"units over {LONGEST_UNIT} lines: {long}"
