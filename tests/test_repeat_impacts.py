"""Repeated impacts on one spot: the laws' (nfdmodel.collide_repeated, ``nfdcal
collide --repeat``: the contact's history carried over) and the dynamic FE's (calib.fe.impact_repeat,
``nfdcal impact --repeat``: the dent and residual stresses carried over), against each other.

Checked against what the code did not produce: a second impact below the first's turning point
returns its energy (e = 1: the law reloads along its unloading curve), and the law's e of impacts
1-3 against the FE's at 10 v_Y (the shipped vz-table law within 2 %), and of a material between the vz
master table's nodes at 50 v_Y (the laws of ``nfdcal material --v-max``, vz-table and vz-unload, within 2 %);
the FE's energy balance closes; refusals are one line with exit 2.
"""
import contextlib
import io
import json
from pathlib import Path

import numpy as np
import pytest

from calib.cli import main
from calib.fe import VonMisesMaterial
from calib.fe.impact_repeat import rest_state
from calib.fe.newmark import ImpactSolver
from meshes.sphere import SphereMeshSpec, sphere_mesh
from nfdmodel import (ContactPair, Material, VZTableParams, VZUnloadParams, collide, collide_repeated, get_law,
                      load_parameters, reference_case)

SHIPPED = Path(__file__).resolve().parent.parent / "results" / "calibration" / "parameters.json"   # vz-table
PAIR = ContactPair.sphere_flat(Material.reference(), reference_case.R)
BENT = VZTableParams(PAIR, (1.0, 3.0, 10.0, 41.0, 200.0, 1000.0), (0.0, 0.06, 0.25, 0.9, 3.0, 10.0),
                     (1.0, 1.02, 1.1, 1.4, 2.5, 6.0))
UNLOAD = VZUnloadParams.from_table(BENT, (1.0, 2.2, 7.1, 41.0), (0.0, 0.05, 0.2, 0.45), (1.5, 1.46, 1.41, 1.36))
V_10 = 10.0 * PAIR.v_Y            # m/s: 10 v_Y, P_max about 14 P_Y
COARSE = SphereMeshSpec(radius=reference_case.R, contact_size=1.6e-4, refined_radius=1.6e-3, refined_depth=5e-4,
                        far_size=1e-2, growth=0.3)


def laws():
    return {"vz-table": load_parameters(SHIPPED), "vz-unload": UNLOAD}


def one_line_refusal(argv, capsys, match):
    code = main(argv)
    err = capsys.readouterr().err.strip().splitlines()
    errors = [line for line in err if "warning" not in line]
    assert code == 2 and len(errors) == 1 and match in errors[0] and "Traceback" not in "".join(err), err
    return errors[0]


# ------------------------------------------------------------------------------ the law side
@pytest.mark.laws
@pytest.mark.parametrize("law", ["vz-table", "vz-unload"])
def test_a_second_impact_below_the_turning_point_reloads_elastically(law):
    """Impact 2 at 0.9 e_1 v_in brings back 0.81 of the energy impact 1 returned: it stays below the
    turning point, so the law reloads and unloads on one curve: e_2 = 1, the dent and the turning point
    unchanged, P_max below the first's."""
    params = laws()[law]
    virgin = get_law(law).initial_state(1)
    first, state = collide(law, params, [V_10], dt=None, start=virgin)
    assert virgin.delta_max[0] == 0.0                       # the start is not modified
    slower = 0.9 * first.e_velocity[0] * V_10
    second, after = collide(law, params, [slower], dt=first.dt, start=state)
    assert second.e_velocity[0] == pytest.approx(1.0, abs=2e-4)
    assert second.P_max[0] < first.P_max[0]
    assert after.delta_max[0] == state.delta_max[0] and after.delta_res[0] == state.delta_res[0]
    assert second.contact_time[0] < first.contact_time[0]


@pytest.mark.laws
@pytest.mark.parametrize("law", ["vz-table", "vz-unload"])
def test_repeated_impacts_at_one_speed_carry_the_history(law):
    """At the same v_in each impact passes the last turning point (it brings more energy than the
    reload stores): e rises towards 1, P_max, delta_max and the dent grow; impact 1 is collide's."""
    params = laws()[law]
    results = collide_repeated(law, params, [V_10, 5 * PAIR.v_Y], 4, dt=None)
    alone = collide(law, params, [V_10, 5 * PAIR.v_Y], dt=results[0].dt)
    np.testing.assert_allclose(results[0].e_velocity, alone.e_velocity, rtol=1e-9)
    e = np.array([r.e_velocity for r in results])
    assert (np.diff(e, axis=0) > 0).all() and (e < 1).all()
    for quantity in ("P_max", "delta_max", "delta_res"):
        assert (np.diff([getattr(r, quantity) for r in results], axis=0) > 0).all(), quantity
    np.testing.assert_allclose(e, [r.e_energy for r in results], rtol=1e-3)    # two measures of e agree


@pytest.mark.laws
def test_collide_repeat_prints_each_impact_with_its_index(capsys):
    assert main(["collide", "--params", str(SHIPPED), "--v-in", "0.0167", "0.01", "--repeat", "3", "--json"]) == 0
    records = json.loads(capsys.readouterr().out)
    assert [(r["v_in"], r["repeat"]) for r in records] == [(v, k) for v in (0.0167, 0.01) for k in (1, 2, 3)]
    expected = collide_repeated("vz-table", load_parameters(SHIPPED), [0.0167, 0.01], 3, dt=None)
    for r in records:
        assert r["e"] == r["e_velocity"] == pytest.approx(expected[r["repeat"] - 1].e_velocity[int(r["v_in"] < 0.015)],
                                                          rel=1e-12)
        assert r["dent"] > 0 and r["delta_max"] > r["dent"]


@pytest.mark.parametrize("argv, match", [
    (["collide", "--v-in", "0.02", "--repeat", "0"], "--repeat out of range"),
    (["collide", "--v-in", "0.02", "--repeat", "2.5"], "--repeat out of range: need an integer"),
    (["collide", "--v-in", "0.02", "--repeat", "two"], "--repeat must be a number"),
    (["collide", "--v-in", "0.02", "--repeat", "2", "--angle", "10"], "--repeat is for normal impacts"),
    (["collide", "--report", "--repeat", "2"], "do not combine it with --report"),
    (["impact", "--v-in", "0.02", "--repeat", "0"], "--repeat out of range"),
    (["impact", "--v-in", "0.02", "--repeat", "1.5"], "--repeat out of range: need an integer"),
    (["impact", "--repeat", "2"], "--repeat needs --v-in"),
    (["impact", "--v-in", "0.02", "--unload-params", "x.json"], "--unload-params applies to --repeat only"),
    (["impact", "--v-in", "0.02", "--repeat", "2", "--convergence"], "--convergence is not for repeated impacts"),
    (["impact", "--v-in", "0.02", "--repeat", "2", "--unload-params", str(SHIPPED)], "not the vz-unload law"),
])
def test_bad_repeat_is_one_line_and_exit_2(argv, match, capsys, tmp_path):
    one_line_refusal([*argv, "--out", str(tmp_path / "out")] if argv[0] == "impact" else argv, capsys, match)


# ------------------------------------------------------------------------------ the FE side
def test_the_rest_state_of_a_sphere_that_never_yielded_is_its_first_touch(mesh_cache):
    solver = ImpactSolver(sphere_mesh(COARSE, cache_dir=mesh_cache), VonMisesMaterial(
        reference_case.E, reference_case.NU, reference_case.SIGMA_Y), reference_case.RHO)
    first = solver.initial_state(0.5 * PAIR.v_Y)
    again = rest_state(solver, first, 0.5 * PAIR.v_Y)
    assert not again.q.any() and np.array_equal(again.velocity, first.velocity)
    assert solver.constraint.gaps(again.q).min() == 0.0
    assert again.elastic_energy == again.plastic_work == again.work_internal == 0.0


@pytest.fixture(scope="module")
def fe_series(tmp_path_factory):
    """``nfdcal impact --repeat 3`` at 10 v_Y on the coarse mesh beside the shipped vz-table law."""
    out = tmp_path_factory.mktemp("repeat")
    printed = io.StringIO()
    with contextlib.redirect_stdout(printed):
        code = main(["impact", "--v-in", f"{V_10:.6g}", "--repeat", "3", "--contact-size", "1.6e-4",
                     "--steps-per-contact", "40", "--table-params", str(SHIPPED), "--quiet", "--json",
                     "--out", str(out)])
    assert code == 0
    return json.loads(printed.getvalue()), out


def test_fe_repeated_impacts_rise_towards_one_and_close_their_energy(fe_series):
    """The FE: e rises over the impacts (as drop tests show), each impact yields less (plastic work
    falls), P_max and the dent grow; each impact's energy balance closes to 1e-3 of m v_in^2 / 2 and
    the sphere leaves almost nothing vibrating (it starts from an equilibrium)."""
    records, out = fe_series
    assert [r["repeat"] for r in records] == [1, 2, 3]
    e = [r["e"] for r in records]
    assert e[0] < e[1] < e[2] < 1.0
    assert records[0]["plastic_work"] > records[1]["plastic_work"] > records[2]["plastic_work"] > 0
    assert records[0]["P_max"] < records[1]["P_max"] < records[2]["P_max"]
    assert records[0]["dent"] < records[1]["dent"] < records[2]["dent"]
    kinetic_in = 0.5 * 4.0 / 3.0 * np.pi * reference_case.R ** 3 * reference_case.RHO * V_10 ** 2
    for r in records:
        assert abs(r["balance_residual"]) < 1e-3 * kinetic_in and r["vibration_energy"] < 1e-4 * kinetic_in
    written = json.loads((out / "repeat.json").read_text())["records"]
    assert [r["e"] for r in written] == e and (out / "repeat.csv").is_file()


def test_the_shipped_law_repeats_the_fe_impacts_within_2_percent(fe_series):
    """The target: the 2nd and 3rd of repeated impacts within 2 % in e of the dynamic
    FE's (measured: 0.0 % and +0.7 % on this mesh); the 1st within 1 %."""
    records, _ = fe_series
    for r in records:
        bound = 0.01 if r["repeat"] == 1 else 0.02
        assert abs(r["e_vz-table_over_fe_minus_1"]) < bound, r
        assert r["e_vz-table"] == pytest.approx(r["e"] * (1 + r["e_vz-table_over_fe_minus_1"]), rel=1e-12)


def test_master_table_laws_repeat_the_fe_impacts_of_an_off_grid_material(tmp_path):
    """A material between the vz master table's nodes (nu 0.27, E/sigma_Y 450: E 120 GPa, sigma_Y 266.7 MPa,
    rho 7800 kg/m^3, R 10 mm) at 50 v_Y (0.191 m/s): the laws of ``nfdcal material --v-max`` (vz-table and
    vz-unload, no FE run) against ``nfdcal impact --repeat 3`` on the coarse mesh (contact element 2.48e-5 m,
    the reference test's relative to a_Y): e of impacts 2 and 3 within 2 % of the FE's, the 1st within 1 %
    (measured FE e 0.6654, 0.8016, 0.8689; vz-table -0.05, -0.03, +0.51 %; vz-unload -0.01, +0.02, +0.64 %)."""
    sphere = ["--E", "120e9", "--nu", "0.27", "--sigma-y", "266.7e6", "--R", "0.01", "--rho", "7800"]
    files = {}
    for law in ("vz-table", "vz-unload"):
        files[law] = tmp_path / f"{law}.json"
        with contextlib.redirect_stdout(io.StringIO()):
            assert main(["material", *sphere, "--v-max", "2", "--law", law, "--params-out", str(files[law]),
                         "--quiet"]) == 0
    printed = io.StringIO()
    with contextlib.redirect_stdout(printed):
        code = main(["impact", *sphere, "--v-in", "0.191", "--repeat", "3", "--contact-size", "2.48e-5",
                     "--table-params", str(files["vz-table"]), "--unload-params", str(files["vz-unload"]),
                     "--quiet", "--json", "--out", str(tmp_path / "fe")])
    assert code == 0
    records = json.loads(printed.getvalue())
    assert [r["repeat"] for r in records] == [1, 2, 3]
    for r in records:
        bound = 0.01 if r["repeat"] == 1 else 0.02
        for law in ("vz-table", "vz-unload"):
            assert abs(r[f"e_{law}_over_fe_minus_1"]) < bound, (law, r)
