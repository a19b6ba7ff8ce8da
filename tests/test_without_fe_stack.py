"""The commands that need no FE run without the FE stack (meshio, scikit-fem, gmsh, matplotlib),
as with ``pip install nfdcal[lammps]`` or a bare ``pip install nfdcal`` plus the CLI."""
import subprocess
import sys

import pytest

BLOCK = """
import builtins, sys
real = builtins.__import__
def blocked(name, *args, **kwargs):
    if name.split('.')[0] in ('meshio', 'skfem', 'gmsh', 'matplotlib'):
        raise ModuleNotFoundError(f"No module named {name!r}", name=name)
    return real(name, *args, **kwargs)
builtins.__import__ = blocked
from calib.cli import main
sys.exit(main(sys.argv[1:]))
"""


@pytest.mark.parametrize("argv", [
    ["collide", "--law", "vz", "--v-in", "0.05"],
    ["collide", "--law", "vz", "--v-in", "0.05", "--E", "205e9", "--nu", "0.29", "--sigma-y", "655e6", "--R", "0.005"],
    ["material", "--E", "205e9", "--nu", "0.29", "--sigma-y", "655e6", "--R", "0.005", "--params-out", "PARAMS"],
], ids=["collide", "collide another material", "material --params-out"])
def test_runs_without_the_fe_stack(argv, tmp_path):
    argv = [str(tmp_path / "p.json") if a == "PARAMS" else a for a in argv]
    proc = subprocess.run([sys.executable, "-c", BLOCK, *argv], capture_output=True, text=True, timeout=120,
                          cwd=tmp_path)
    assert proc.returncode == 0, proc.stderr
    assert "Traceback" not in proc.stderr
