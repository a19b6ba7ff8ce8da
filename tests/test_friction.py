"""Friction, rolling and twisting resistance and normal damping (nfdmodel/friction.py, the numpy
reference, and nfdmodel/nfd_friction.h, the C kernel's).

- The C kernel (nfd_contact_step through nfdmodel._native) equals the numpy reference to 1e-12
  (measured: 2e-15) in forces, torques, springs and contact radius over multi-step random
  histories of every law, every damping model, the four Mindlin variants, both twisting models,
  with and without update.
- Each model's definition, checked on one contact against a closed form: Coulomb sliding caps
  |F_t| at mu |F_n| exactly; a sticking spring gives F_t = -k_t a dt v_t; the spring rotates with
  the contact and keeps its length; the twisting torque of Marshall is k_t a^2/2 theta; the
  contact radius of each law (Hertz's until first yield, the law's own after).
- The C header compiles alone (-std=c99 -pedantic -Werror) and a C caller gets Python's numbers.
- Bad constants are refused in one line naming the constant and its range.
The comparison with LAMMPS's own granular models (the definitions are LAMMPS's) is in
tests/test_lammps_friction.py.
"""
from __future__ import annotations

import shutil
import subprocess
from pathlib import Path

import numpy as np
import pytest

import nfdmodel
from nfdmodel import ContactPair, Material, VZParams, VZTableParams, VZUnloadParams, WaltonBraunParams, get_law, native
from nfdmodel.friction import (Contact, Friction, FrictionState, compiled_contact_step, contact_radius, contact_step,
                               shear_coefficient)

pytestmark = pytest.mark.laws      # rerun on the numpy kernels by .ci/run (tests/test_markers.py)

ALUMINIUM = Material.reference()
PAIR = ContactPair.sphere_sphere(ALUMINIUM, 0.01, ALUMINIUM, 0.008)
NODES = np.array([1.0, 3.0, 10.0, 41.0, 200.0])
TABLE = VZTableParams(PAIR, tuple(NODES), tuple(0.025 * (NODES - 1.0) ** 0.9), tuple(1.0 + 0.01 * (NODES - 1.0)))
PARAMS = {"hertz": PAIR, "vz": VZParams.from_dimensionless(PAIR, 0.026, 0.0098), "vz-table": TABLE,
          "thornton": PAIR, "walton-braun": WaltonBraunParams.from_pair(PAIR),
          "vz-unload": VZUnloadParams.from_table(TABLE, (1.0, 2.2, 7.1, 41.0), (0.0, 0.05, 0.2, 0.45),
                                                 (1.5, 1.46, 1.41, 1.36))}
K_T = shear_coefficient(ALUMINIUM, ALUMINIUM)
FULL = dict(tangential="mindlin", k_t=K_T, x_gamma_t=0.5, mu=0.3, rolling="sds", k_roll=1000.0, gamma_roll=0.01,
            mu_roll=0.1)
MODELS = {
    "viscoelastic+marshall": Friction(damping="viscoelastic", damping_value=0.4, twisting="marshall", **FULL),
    "tsuji+sds": Friction(damping="tsuji", damping_value=0.8, twisting="sds", k_twist=0.01, gamma_twist=1e-4,
                          mu_twist=1e-3, **FULL),
    "coeff_restitution": Friction(damping="coeff_restitution", damping_value=0.7, **FULL),
    "undamped": Friction(tangential="mindlin", k_t=K_T, mu=0.3, twisting="marshall"),
    "rescale": Friction(damping="viscoelastic", damping_value=0.4, twisting="marshall",
                        **(FULL | {"tangential": "mindlin_rescale"})),
    "force": Friction(damping="tsuji", damping_value=0.8, **(FULL | {"tangential": "mindlin/force"})),
    "rescale/force": Friction(twisting="marshall", **(FULL | {"tangential": "mindlin_rescale/force"})),
}
needs_native = pytest.mark.skipif(native._native is None, reason="the compiled kernel is not built")


def unit(a: np.ndarray) -> np.ndarray:
    return a / np.linalg.norm(a, axis=1)[:, None]


def random_contacts(rng, n: int, step: int, delta_scale: float) -> Contact:
    delta = delta_scale * np.abs(np.sin(step / 10.0 + rng.uniform(0.0, 3.0, n)))
    return Contact(unit(rng.normal(size=(n, 3))), delta, 0.01, 0.008, 0.3 * rng.normal(size=(n, 3)),
                   30.0 * rng.normal(size=(n, 3)), 30.0 * rng.normal(size=(n, 3)), 0.003, 1e-6)


@needs_native
@pytest.mark.parametrize("law_name", list(PARAMS))
@pytest.mark.parametrize("model", list(MODELS))
def test_the_c_kernel_equals_the_numpy_reference(law_name, model):
    """60 steps of 100 contacts loading, unloading and reloading (up to 20 delta_Y: most yield),
    with random normals, velocities and spins; every 7th step a set-up step (update = 0)."""
    rng = np.random.default_rng(7)
    law, params, friction = get_law(law_name), PARAMS[law_name], MODELS[model]
    n = 100
    state = c_state = law.initial_state(n)
    springs, c_springs = FrictionState.virgin(n), FrictionState.virgin(n)
    worst = 0.0
    for step in range(60):
        contact = random_contacts(rng, n, step, 20.0 * PAIR.delta_Y)
        update = step % 7 != 3
        mine, state, springs = contact_step(law, params, friction, contact, state, springs, update)
        theirs, c_state, c_springs = compiled_contact_step(law, params, friction, contact, c_state, c_springs, update)
        for a, b in ((mine.force, theirs.force), (mine.torque_i, theirs.torque_i), (mine.torque_j, theirs.torque_j),
                     (mine.a, theirs.a), (mine.F_n, theirs.F_n), (springs.xi_t, c_springs.xi_t),
                     (springs.xi_roll, c_springs.xi_roll), (springs.theta_twist, c_springs.theta_twist),
                     (springs.a_previous, c_springs.a_previous)):
            worst = max(worst, float(np.abs(a - b).max() / (np.abs(a).max() + 1e-300)))
    assert worst < 1e-12


def one(delta, v, omega_i=(0.0, 0.0, 0.0), omega_j=(0.0, 0.0, 0.0), n=(1.0, 0.0, 0.0), R_j=0.008, dt=1e-6):
    return Contact(np.array([n]), np.array([delta]), 0.01, R_j, np.array([v]), np.array([omega_i]),
                   np.array([omega_j]), 0.003, dt)


def test_a_sticking_spring_and_coulomb_sliding():
    """A first step with tangential velocity v_t: F_t = -k_t a dt v_t while below the cap; far
    beyond it |F_t| = mu |F_n| exactly, the spring set back to F_t / (-k_t a)."""
    law, delta = get_law("hertz"), 2.0 * PAIR.delta_Y
    friction = Friction(tangential="mindlin", k_t=K_T, mu=0.3)
    a = np.sqrt(delta * PAIR.R_star)
    P = PAIR.hertz_stiffness * delta ** 1.5
    slow = 1e-3 * 0.3 * P / (K_T * a * 1e-6)          # 1e-3 of the cap after one step
    forces, _, springs = contact_step(law, PAIR, friction, one(delta, (0.0, slow, 0.0)), law.initial_state(1),
                                      FrictionState.virgin(1))
    assert forces.a[0] == pytest.approx(a, rel=1e-15)
    assert forces.F_t[0] == pytest.approx([0.0, -K_T * a * 1e-6 * slow, 0.0], rel=1e-14)
    assert springs.xi_t[0] == pytest.approx([0.0, 1e-6 * slow, 0.0], rel=1e-15)
    forces, _, springs = contact_step(law, PAIR, friction, one(delta, (0.0, 1e4 * slow, 0.0)), law.initial_state(1),
                                      FrictionState.virgin(1))
    assert np.linalg.norm(forces.F_t[0]) == pytest.approx(0.3 * forces.F_n[0], rel=1e-15)
    np.testing.assert_allclose(springs.xi_t[0], forces.F_t[0] / (-K_T * a), rtol=1e-15)


def test_the_spring_rotates_with_the_contact_and_keeps_its_length():
    """A spring left along y, the normal turned by 30 degrees in the x-y plane: the spring is
    projected into the new tangent plane with its length kept (then advanced by dt v_t = 0)."""
    law, delta = get_law("hertz"), 2.0 * PAIR.delta_Y
    friction = Friction(tangential="mindlin", k_t=K_T, mu=0.3)
    springs = FrictionState(np.array([[0.0, 1e-9, 0.0]]), np.zeros((1, 3)), np.zeros(1), np.zeros(1))
    turned = (np.cos(np.pi / 6), np.sin(np.pi / 6), 0.0)
    _, _, out = contact_step(law, PAIR, friction, one(delta, (0.0, 0.0, 0.0), n=turned), law.initial_state(1), springs)
    assert np.linalg.norm(out.xi_t[0]) == pytest.approx(1e-9, rel=1e-14)
    assert np.dot(out.xi_t[0], turned) == pytest.approx(0.0, abs=1e-24)


def test_marshall_twisting_and_sds_rolling_on_one_step():
    """Relative spin about the normal w: Marshall's torque -k_t a^2/2 dt w (below its cap); relative
    spin about y: the rolling spring R* dt (w x n), torque R* n x F_r on i and the opposite on j."""
    law, delta, w = get_law("hertz"), 2.0 * PAIR.delta_Y, 1e-3
    a = np.sqrt(delta * PAIR.R_star)
    twist = Friction(tangential="mindlin", k_t=K_T, mu=0.3, twisting="marshall")
    forces, _, springs = contact_step(law, PAIR, twist, one(delta, (0.0, 0.0, 0.0), omega_i=(w, 0.0, 0.0)),
                                      law.initial_state(1), FrictionState.virgin(1))
    assert springs.theta_twist[0] == pytest.approx(1e-6 * w, rel=1e-15)
    assert forces.torque_i[0] == pytest.approx([-0.5 * K_T * a * a * 1e-6 * w, 0.0, 0.0], rel=1e-14)
    assert forces.torque_j[0] == pytest.approx(-forces.torque_i[0], rel=1e-15)
    roll = Friction(rolling="sds", k_roll=1000.0, mu_roll=0.1)
    forces, _, springs = contact_step(law, PAIR, roll, one(delta, (0.0, 0.0, 0.0), omega_i=(0.0, w, 0.0)),
                                      law.initial_state(1), FrictionState.virgin(1))
    v_roll = PAIR.R_star * np.cross([0.0, w, 0.0], [1.0, 0.0, 0.0])
    np.testing.assert_allclose(springs.xi_roll[0], 1e-6 * v_roll, rtol=1e-15)
    np.testing.assert_allclose(forces.torque_i[0], PAIR.R_star * np.cross([1.0, 0.0, 0.0], -1000.0 * 1e-6 * v_roll),
                               rtol=1e-14)
    np.testing.assert_allclose(forces.torque_j[0], -forces.torque_i[0], rtol=1e-15)
    np.testing.assert_allclose(forces.force[0], [forces.P[0], 0.0, 0.0], rtol=1e-15)


def test_a_wall_turns_the_sphere_about_its_centre():
    """R_j = 0 (a flat wall): the torque arm is R_i, nothing acts on j."""
    law, delta = get_law("hertz"), 2.0 * PAIR.delta_Y
    flat = ContactPair.sphere_flat(ALUMINIUM, 0.01)
    friction = Friction(tangential="mindlin", k_t=shear_coefficient(ALUMINIUM), mu=0.3, rolling="sds", k_roll=1e3,
                        mu_roll=0.1, twisting="marshall")
    forces, _, _ = contact_step(law, flat, friction, one(delta, (0.0, 1e3, 0.0), R_j=0.0), law.initial_state(1),
                                FrictionState.virgin(1))
    np.testing.assert_allclose(forces.torque_i[0], -0.01 * np.cross([1.0, 0.0, 0.0], forces.F_t[0]), rtol=1e-15)
    assert not forces.torque_j.any()


@pytest.mark.parametrize("law_name", ["vz", "vz-table", "thornton"])
def test_the_contact_radius_is_hertz_s_until_first_yield_then_the_law_s(law_name):
    """Below first yield sqrt(R* delta); loaded beyond it, on the turning point: vz a_e + Ca (P -
    P_Y), vz-table a_Y (x^(1/3) + f(x)) (params.contact_radius_at), thornton a*^2 = (2 P + P_Y) /
    (2 pi p_Y); then unloaded, the Hertz radius at P plus the frozen plastic radius (vz, vz-table),
    or the Hertz radius of the enlarged curvature (thornton)."""
    law, params = get_law(law_name), PARAMS[law_name]
    state = law.initial_state(1)
    delta = np.array([0.5 * PAIR.delta_Y])
    P, new = law.force_function(delta, state, params)
    hertz = np.sqrt(delta[0] * PAIR.R_star)
    assert contact_radius(law_name, delta, P, new, params)[0] == pytest.approx(hertz, rel=1e-15)
    delta = np.array([30.0 * PAIR.delta_Y])
    P, loaded = law.force_function(delta, state, params)
    a = contact_radius(law_name, delta, P, loaded, params)[0]
    if law_name == "thornton":
        expected = np.sqrt((2.0 * P[0] + PAIR.P_Y) / (2.0 * np.pi * PAIR.p_Y))
    else:
        expected = params.contact_radius_at(P[0])
    assert a == pytest.approx(float(expected), rel=1e-12)
    P_un, unloaded = law.force_function(delta * 0.999, loaded, params)
    a_un = contact_radius(law_name, delta * 0.999, P_un, unloaded, params)[0]
    assert 0.0 < P_un[0] < P[0] and a_un < a
    if law_name != "thornton":
        assert a_un == pytest.approx(float(PAIR.hertz_radius(P_un[0]) + params.plastic_radius(P[0])), rel=1e-12)


def test_the_c_header_compiles_alone_and_a_c_caller_gets_python_s_numbers(tmp_path):
    compiler = shutil.which("cc") or shutil.which("gcc")
    if compiler is None:
        pytest.skip("no C compiler")
    source = Path(nfdmodel.__file__).parent
    delta, v = float(2.0 * PAIR.delta_Y), (0.1, 0.3, -0.2)
    main = tmp_path / "main.c"
    main.write_text(f"""
#include <stdio.h>
#include "nfd_friction.h"
int main(void) {{
  nfd_params p = nfd_pair({PAIR.R_star!r}, {PAIR.E_star!r}, {PAIR.p_Y!r});
  nfd_friction f = {{NFD_DAMPING_NONE, 0.0, NFD_TANGENTIAL_MINDLIN, {K_T!r}, 0.0, 0.3,
                     NFD_ROLLING_NONE, 0.0, 0.0, 0.0, NFD_TWISTING_MARSHALL, 0.0, 0.0, 0.0}};
  nfd_contact c = {{{{1.0, 0.0, 0.0}}, {delta!r}, 0.01, 0.008, {{{v[0]!r}, {v[1]!r}, {v[2]!r}}},
                    {{0.0, 5.0, 0.0}}, {{0.0, 0.0, 0.0}}, 0.003, 1e-6}};
  nfd_history h = {{0, 0, 0, 0, 0}}, h_out;
  nfd_friction_history fh = {{{{0, 0, 0}}, {{0, 0, 0}}, 0, 0}}, fh_out;
  nfd_contact_result r;
  int status = nfd_contact_step(NFD_LAW_HERTZ, &c, &p, NULL, &f, &h, &fh, 1, &h_out, &fh_out, &r);
  printf("%d %.17g %.17g %.17g %.17g %.17g %.17g\\n", status, r.force[0], r.force[1], r.force[2],
         r.torque_i[0], r.torque_i[1], r.torque_i[2]);
  return 0;
}}
""")
    binary = tmp_path / "main"
    subprocess.run([compiler, "-std=c99", "-Wall", "-Wextra", "-pedantic", "-Werror", "-O2", f"-I{source}",
                    str(main), str(source / "nfd_kernel.c"), "-lm", "-o", str(binary)], check=True)
    values = [float(t) for t in subprocess.run([str(binary)], capture_output=True, text=True,
                                                check=True).stdout.split()]
    friction = Friction(tangential="mindlin", k_t=K_T, mu=0.3, twisting="marshall")
    law = get_law("hertz")
    forces, _, _ = contact_step(law, PAIR, friction, one(delta, v, omega_i=(0.0, 5.0, 0.0)), law.initial_state(1),
                                FrictionState.virgin(1))
    assert values[0] == 0
    np.testing.assert_allclose(values[1:], np.concatenate([forces.force[0], forces.torque_i[0]]), rtol=1e-14)


@pytest.mark.parametrize("keywords, message", [
    (dict(tangential="coulomb"), r"^tangential out of range: need one of none, mindlin, mindlin_rescale, "
                                 r"mindlin/force, mindlin_rescale/force, got 'coulomb'"),
    (dict(tangential="mindlin", k_t=0.0, mu=0.3), r"^k_t out of range: need k_t > 0 Pa"),
    (dict(tangential="mindlin", k_t=K_T, mu=-0.1), r"^mu out of range: need mu >= 0 and mu <= 10000"),
    (dict(damping="tsuji", damping_value=1.5), r"^e out of range: need e >= 0 and e <= 1"),
    (dict(damping="coeff_restitution", damping_value=0.0), r"^e out of range: need e > 0 and e <= 1"),
    (dict(rolling="sds", k_roll=1.0, mu_roll=float("nan")), r"^mu_roll must be finite"),
    (dict(twisting="marshall"), r"^twisting out of range: marshall takes its stiffness from the tangential model"),
])
def test_bad_friction_constants_are_named(keywords, message):
    with pytest.raises(ValueError, match=message):
        Friction(**keywords)


AUDIT_MATERIAL = Material.reference()
AUDIT_PAIR = ContactPair.sphere_flat(AUDIT_MATERIAL, 0.01)
AUDIT_PARAMS = {"hertz": AUDIT_PAIR, "vz": VZParams.from_dimensionless(AUDIT_PAIR, 0.026, 0.0098)}
AUDIT_DAMPING = {"none": 0.0, "viscoelastic": 0.5, "tsuji": 0.2, "coeff_restitution": 0.5}


@pytest.mark.parametrize("tangential", ["mindlin", "mindlin_rescale", "mindlin/force", "mindlin_rescale/force"])
@pytest.mark.parametrize("damping", list(AUDIT_DAMPING))
def test_no_damping_and_tangential_model_creates_energy(damping, tangential):
    """An energy audit of oblique impacts on the flat (R 1 cm at 0.5 m/s, 0..80 deg, spins -500..500
    rad/s, mu 0.1 and 0.5, tangential damping x_gamma_t 0 and 30): the kinetic plus rotational
    energy out never exceeds the energy in (to 1e-5 of it: the integrator's O(dt^2) on the elastic
    Hertz contact, measured 1.1e-6 with no friction at all). Where LAMMPS stores the damping beyond
    the Coulomb cap in the spring (the spring left unlimited), tsuji 0.2 with mindlin returns 1.199
    times the energy in, mindlin_rescale 1.187 (vz, x_gamma_t 30)."""
    from nfdmodel.oblique import oblique_collide

    angle, spin = (a.ravel() for a in np.meshgrid([0.0, 20.0, 45.0, 80.0], [-500.0, 0.0, 500.0], indexing="ij"))
    R, m, speed = 0.01, AUDIT_PAIR.mass_star, 0.5
    energy_in = 0.5 * m * speed**2 + 0.2 * m * R * R * spin**2
    worst = 0.0
    for law, params in AUDIT_PARAMS.items():
        for mu in (0.1, 0.5):
            for x_gamma_t in (0.0, 30.0):
                friction = Friction.mindlin(mu, AUDIT_MATERIAL, variant=tangential, damping=damping,
                                            damping_value=AUDIT_DAMPING[damping], x_gamma_t=x_gamma_t)
                result = oblique_collide(law, params, friction, speed, angle, spin, dt=2e-7)
                worst = max(worst, float(np.max(-result.kinetic_energy_lost / energy_in)))
    assert worst <= 1e-5, worst
