"""nfdmodel.unlike: the vz law of unlike bodies, by the substitution or with the constants calibrated
for the pair, against closed forms and the counter-body parameter file (not against itself):

- the pair's Ca, Kc are its Ca_hat, Kc_hat over the yield point computed here in closed form
  (P_Y = pi^3 R*^2 p_Y^3 / (6 E*^2), a_Y = (3 P_Y R*/(4 E*))^(1/3), E* and R* of the two bodies);
- a counter-body parameter file (the form nfdcal calibrate --counter-E writes) read by
  load_parameters gives the same Ca, Kc as VZConstants.of(it) on the pair of sphere_sphere_params
  or sphere_wall_params (1e-12: E* summed in another order);
- the substitution takes the body with the lower A_Y(nu) sigma_y (not the lower sigma_y), in
  either order; below first yield the collision is Hertz's closed form whatever the constants;
- constants calibrated on a flat that yields first (``calibrate --counter-E 7e9 --counter-nu 0.3
  --counter-sigma-y 1e7``: P_Y 4.433 N, the flat's) are refused by sphere_wall_params in one line
  (the elastic wall would take the sphere's P_Y, 4433 N, and give e = 1.0000 at 0.02 m/s);
- bad input is one ValueError naming the constant and its range.
"""
from __future__ import annotations

import json
import math

import pytest

import nfdmodel
from nfdmodel import (CalibrationWindow, ContactPair, Material, VZConstants, parameter_record, sphere_sphere_params,
                      sphere_wall_params)
from nfdmodel.materials import yield_factor

pytestmark = pytest.mark.laws      # rerun on the numpy kernels by .ci/run (tests/test_markers.py)

WINDOW = CalibrationWindow.assumed_default()
BODY_A, R_A, HATS_A = Material(70e9, 0.0, 100e6, 2700.0), 0.01, VZConstants(0.03, 0.012, WINDOW)
BODY_B, R_B, HATS_B = Material(110e9, 0.45, 95e6, 7800.0), 0.006, VZConstants(0.015, 0.004, WINDOW)
PAIR = VZConstants(0.02, 0.006, WINDOW)


def closed_form_yield(E_star: float, R_star: float, p_Y: float) -> tuple[float, float]:
    P_Y = math.pi**3 * R_star**2 * p_Y**3 / (6.0 * E_star**2)
    return P_Y, (3.0 * P_Y * R_star / (4.0 * E_star)) ** (1.0 / 3.0)


def test_pair_constants_scale_with_the_pairs_closed_form_yield_point():
    params = sphere_sphere_params(BODY_A, R_A, HATS_A, BODY_B, R_B, HATS_B, pair=PAIR)
    E_star = 1.0 / ((1.0 - BODY_A.nu**2) / BODY_A.E + (1.0 - BODY_B.nu**2) / BODY_B.E)
    R_star = R_A * R_B / (R_A + R_B)
    P_Y, a_Y = closed_form_yield(E_star, R_star, yield_factor(BODY_A.nu) * BODY_A.sigma_y)
    assert params.Ca == pytest.approx(PAIR.Ca_hat * a_Y / P_Y, rel=1e-12)
    assert params.Kc == pytest.approx(PAIR.Kc_hat / P_Y, rel=1e-12)
    assert params.window is WINDOW

    wall = sphere_wall_params(BODY_B, R_B, HATS_B, 210e9, 0.3, pair=PAIR)
    E_star = 1.0 / ((1.0 - BODY_B.nu**2) / BODY_B.E + (1.0 - 0.3**2) / 210e9)
    P_Y, a_Y = closed_form_yield(E_star, R_B, yield_factor(BODY_B.nu) * BODY_B.sigma_y)
    assert wall.Ca == pytest.approx(PAIR.Ca_hat * a_Y / P_Y, rel=1e-12)
    assert sphere_wall_params(BODY_B, R_B, HATS_B, 210e9, 0.3).Ca_hat == pytest.approx(HATS_B.Ca_hat, rel=1e-12)


def test_the_substitution_takes_the_body_that_yields_first():
    assert yield_factor(BODY_A.nu) * BODY_A.sigma_y < yield_factor(BODY_B.nu) * BODY_B.sigma_y
    assert BODY_B.sigma_y < BODY_A.sigma_y
    for params in (sphere_sphere_params(BODY_A, R_A, HATS_A, BODY_B, R_B, HATS_B),
                   sphere_sphere_params(BODY_B, R_B, HATS_B, BODY_A, R_A, HATS_A)):
        assert params.Ca_hat == pytest.approx(HATS_A.Ca_hat, rel=1e-12)
        assert params.Kc_hat == pytest.approx(HATS_A.Kc_hat, rel=1e-12)


@pytest.mark.parametrize("counter", [{"shape": "sphere", "E": 205e9, "nu": 0.29, "sigma_y": 655e6, "R": 0.006,
                                      "rho": 7850.0},
                                     {"shape": "flat", "E": 205e9, "nu": 0.29, "sigma_y": None, "R": None}])
def test_a_counter_body_file_gives_the_pairs_law(tmp_path, counter):
    aluminium = Material(70e9, 0.3, 100e6, 2699.0)
    pair = ContactPair.sphere_counter(aluminium, 0.01, counter["E"], counter["nu"], counter["sigma_y"], counter["R"],
                                      counter.get("rho"))
    path = tmp_path / "pair.json"
    path.write_text(json.dumps(parameter_record(PAIR.params(pair), 0.01, aluminium, counter)))
    read = nfdmodel.load_parameters(path)
    constants = VZConstants.of(read)
    own = VZConstants(0.026, 0.0098)         # the sphere's own: unused when the pair's are given
    if counter["R"] is None:
        law = sphere_wall_params(aluminium, 0.01, own, counter["E"], counter["nu"], pair=constants)
    else:
        steel = Material(counter["E"], counter["nu"], counter["sigma_y"], counter["rho"])
        law = sphere_sphere_params(aluminium, 0.01, own, steel, counter["R"], own, pair=constants)
    assert law.Ca == pytest.approx(read.Ca, rel=1e-12) and law.Kc == pytest.approx(read.Kc, rel=1e-12)
    assert law.pair.P_Y == pytest.approx(read.pair.P_Y, rel=1e-12)
    assert law.pair.mass_star == pytest.approx(read.pair.mass_star, rel=1e-12)


def test_below_first_yield_the_collision_is_hertz_of_the_pair():
    params = sphere_sphere_params(BODY_A, R_A, HATS_A, BODY_B, R_B, HATS_B, pair=PAIR)
    pair = params.pair
    v_in = 0.5 * pair.v_Y
    result = nfdmodel.collide("vz", params, [v_in], dt=pair.hertz_contact_time(v_in) / 2000)
    k_H = 4.0 / 3.0 * pair.E_star * math.sqrt(pair.R_star)
    delta_max = (5.0 * pair.mass_star * v_in**2 / (4.0 * k_H)) ** 0.4
    assert result.P_max[0] == pytest.approx(k_H * delta_max**1.5, rel=1e-5)
    assert result.e_velocity[0] == pytest.approx(1.0, abs=1e-6)
    assert result.contact_time[0] == pytest.approx(pair.hertz_contact_time(v_in), rel=1e-3)


def flat_counter_file(folder, sigma_y2):
    """The parameter file of the reference sphere (aluminium, R = 0.1 m) calibrated on a flat of
    E 7e9 Pa, nu 0.3 and yield stress sigma_y2 (None: elastic), as calibrate --counter-E writes it
    (the paper's constants: the test is of the yield point, not of the FE)."""
    aluminium = Material.reference()
    counter = {"shape": "flat", "E": 7e9, "nu": 0.3, "sigma_y": sigma_y2, "R": None}
    pair = ContactPair.sphere_counter(aluminium, 0.1, 7e9, 0.3, sigma_y2)
    path = folder / "pair.json"
    path.write_text(json.dumps(parameter_record(VZConstants(0.026, 0.0098, WINDOW).params(pair), 0.1, aluminium,
                                                counter)))
    return path


@pytest.mark.parametrize("sigma_y2, refused", [(1e7, True), (None, False), (1e9, False)])
def test_constants_of_a_flat_that_yields_first_are_refused_on_a_wall(tmp_path, sigma_y2, refused):
    """A soft flat (7 GPa, sigma_y 10 MPa) yields first: the file's P_Y is the flat's, 4.433 N, with
    which its law gives e near 0.72 at 0.02 m/s; the same constants on an elastic wall would take
    the sphere's P_Y, 4433 N (e = 1.0000): sphere_wall_params refuses them in one line. An elastic
    or a harder flat (the sphere yields first) gives the file's own law."""
    aluminium = Material.reference()
    read = nfdmodel.load_parameters(flat_counter_file(tmp_path, sigma_y2))
    own = VZConstants(0.026, 0.0098)
    wall = ContactPair.sphere_wall(aluminium, 0.1, 7e9, 0.3)
    assert wall.P_Y == pytest.approx(4433.1, rel=1e-4)
    if not refused:
        law = sphere_wall_params(aluminium, 0.1, own, 7e9, 0.3, pair=VZConstants.of(read))
        assert law.pair.P_Y == pytest.approx(read.pair.P_Y, rel=1e-12) and law.Ca == pytest.approx(read.Ca, rel=1e-12)
        return
    assert read.pair.P_Y == pytest.approx(4.4331, rel=1e-4)
    with pytest.raises(ValueError) as error:
        sphere_wall_params(aluminium, 0.1, own, 7e9, 0.3, pair=VZConstants.of(read))
    message = str(error.value)
    assert message.startswith("pair out of range: its constants were calibrated with first yield in the flat")
    assert "\n" not in message and "4433 N" in message
    # what the silent path gave, and what the pair's P_Y gives (the 1.0000 and 0.727)
    silent = sphere_wall_params(aluminium, 0.1, own, 7e9, 0.3, pair=VZConstants(read.Ca_hat, read.Kc_hat))
    with pytest.warns(nfdmodel.RangeWarning):
        e_silent = nfdmodel.collide("vz", silent, [0.02], dt=None).e_velocity[0]
        e_pair = nfdmodel.collide("vz", read, [0.02], dt=None).e_velocity[0]
    assert e_silent == pytest.approx(1.0, abs=1e-4) and 0.70 < e_pair < 0.75


@pytest.mark.parametrize("call, message", [
    (lambda: VZConstants(1e5, 0.01), "Ca_hat out of range"),
    (lambda: VZConstants(0.03, -1.0), "Kc_hat out of range"),
    (lambda: VZConstants(0.03, 0.01, window=41.2), "window must be a CalibrationWindow"),
    (lambda: VZConstants(0.03, 0.01, yielding=(-1.0, 0.3)), "yielding sigma_y out of range"),
    (lambda: VZConstants(0.03, 0.01, yielding=(1e8, 0.5)), "yielding nu out of range"),
    (lambda: VZConstants(0.03, 0.01, yielding=1e8), "yielding must be (sigma_y [Pa], nu) or None"),
    (lambda: VZConstants.of(ContactPair.reference()), "params must be VZParams"),
    (lambda: sphere_sphere_params(BODY_A, R_A, HATS_A, BODY_B, R_B, HATS_B, pair=(0.02, 0.006)),
     "pair must be VZConstants"),
    (lambda: sphere_wall_params(BODY_A, R_A, HATS_A, 70.0, 0.3), "E out of range for a solid"),
])
def test_bad_input_is_one_line(call, message):
    with pytest.raises(ValueError) as refused:
        call()
    assert message in str(refused.value) and "\n" not in str(refused.value)
