"""nfdmodel.materials: effective properties, A_Y(nu), the yield point."""
import math

import numpy as np
import pytest

from nfdmodel import ContactPair, Material, VZParams, limits, yield_factor
from nfdmodel.materials import axis_stress_difference

pytestmark = pytest.mark.laws      # rerun on the numpy kernels by .ci/run (tests/test_markers.py)


def test_yield_factor_matches_paper_at_nu_0_3():
    # Vu-Quoc & Zhang (1999): A_Y(0.3) = 1.61, maximum of |sigma_z - sigma_r| near zeta = 0.48.
    assert yield_factor(0.3) == pytest.approx(1.61, rel=2e-3)
    zeta = np.linspace(0.0, 3.0, 300001)
    assert zeta[np.argmax(axis_stress_difference(zeta, 0.3))] == pytest.approx(0.48, abs=0.01)


@pytest.mark.parametrize("nu", [0.0, 0.1, 0.25, 0.3, 0.4, 0.45, 0.49, 0.4999])
def test_yield_factor_equals_brute_force_maximum(nu):
    zeta = np.linspace(0.0, 5.0, 500001)
    brute = 1.0 / axis_stress_difference(zeta, nu).max()
    assert yield_factor(nu) == pytest.approx(brute, rel=1e-8)


def test_reference_yield_point_paper_anchor():
    pair = ContactPair.reference()
    # With the paper's rounded A_Y = 1.61, eq. 3.7 gives the paper's P_Y = 36.45 N.
    p_Y = 1.61 * pair.sigma_y
    P_Y_paper_rounding = math.pi**3 * pair.R_star**2 * p_Y**3 / (6 * pair.E_star**2)
    assert P_Y_paper_rounding == pytest.approx(36.45, rel=5e-4)
    # Our A_Y(0.3) = 1.6128 (not rounded): P_Y ~ A_Y^3 is 0.5 % higher.
    assert pair.P_Y == pytest.approx(36.45, rel=6e-3)
    assert pair.mass_star == pytest.approx(11.306, rel=1e-4)
    assert pair.delta_Y == pytest.approx(pair.a_Y**2 / pair.R_star)
    # Hertz: peak pressure at P_Y equals p_Y.
    p0 = 3 * pair.P_Y / (2 * math.pi * pair.a_Y**2)
    assert p0 == pytest.approx(pair.p_Y, rel=1e-12)
    # v_Y: energy definition equals Thornton's 3.194 (p_Y^5 R^3 / (E^4 m))^(1/2), paper 1.67e-3 m/s.
    thornton = 3.194 * math.sqrt(pair.p_Y**5 * pair.R_star**3 / (pair.E_star**4 * pair.mass_star))
    assert pair.v_Y == pytest.approx(thornton, rel=1e-4)
    assert pair.v_Y == pytest.approx(1.67e-3, rel=6e-3)


def test_identical_spheres_have_twice_the_approach_of_sphere_on_flat():
    mat = Material.reference()
    flat = ContactPair.sphere_flat(mat, 0.1)
    spheres = ContactPair.sphere_sphere(mat, 0.1, mat, 0.1)
    assert spheres.R_star == pytest.approx(0.05)
    assert spheres.P_Y == pytest.approx(flat.P_Y, rel=1e-12)        # paper: same formulas in alpha
    assert spheres.delta_Y == pytest.approx(2 * flat.delta_Y, rel=1e-12)
    assert spheres.mass_star == pytest.approx(flat.mass_star / 2)


def test_sphere_sphere_yields_in_the_body_with_the_lower_yield_pressure():
    """By hand: A_Y(0) = 1.2993 and A_Y(0.45) = 1.8061 (the axis maximum of |sigma_z - sigma_r|/p0),
    so a body with sigma_Y = 100 MPa and nu = 0.45 yields at p0 = 180.6 MPa, after one with
    sigma_Y = 110 MPa and nu = 0 (p0 = 142.9 MPa): the second yields first, although its yield
    stress is the higher one."""
    high_nu = Material(70e9, 0.45, 100e6, 2700)
    low_nu = Material(70e9, 0.0, 110e6, 2700)
    assert yield_factor(0.45) * 100e6 == pytest.approx(180.6e6, rel=1e-3)
    assert yield_factor(0.0) * 110e6 == pytest.approx(142.9e6, rel=1e-3)
    for pair in (ContactPair.sphere_sphere(high_nu, 0.01, low_nu, 0.02),
                 ContactPair.sphere_sphere(low_nu, 0.02, high_nu, 0.01)):
        assert (pair.sigma_y, pair.nu) == (110e6, 0.0)
        assert pair.p_Y == pytest.approx(142.9e6, rel=1e-3)


def test_sphere_sphere_uses_softer_body_for_yield():
    hard = Material(200e9, 0.29, 1e9, 7800)
    soft = Material(70e9, 0.33, 100e6, 2700)
    pair = ContactPair.sphere_sphere(hard, 0.01, soft, 0.02)
    assert pair.sigma_y == soft.sigma_y and pair.nu == soft.nu
    assert 1 / pair.E_star == pytest.approx((1 - 0.29**2) / 200e9 + (1 - 0.33**2) / 70e9)


def test_dimensionless_parameters_round_trip():
    ref = VZParams.reference()
    assert ref.Ca_hat == pytest.approx(0.0258, rel=0.01)            # the dimensionless constant of the paper's case
    assert ref.Kc_hat == pytest.approx(0.0098, rel=0.01)
    again = VZParams.from_dimensionless(ref.pair, ref.Ca_hat, ref.Kc_hat)
    assert again.Ca == pytest.approx(ref.Ca) and again.Kc == pytest.approx(ref.Kc)


@pytest.mark.parametrize("kwargs, name", [
    (dict(E=0, nu=0.3, sigma_y=1e8, rho=2700), "E"),
    (dict(E=-1e9, nu=0.3, sigma_y=1e8, rho=2700), "E"),
    (dict(E=70e9, nu=0.5, sigma_y=1e8, rho=2700), "nu"),
    (dict(E=70e9, nu=-0.1, sigma_y=1e8, rho=2700), "nu"),
    (dict(E=70e9, nu=float("nan"), sigma_y=1e8, rho=2700), "nu"),
    (dict(E=70e9, nu=0.3, sigma_y=0.0, rho=2700), "sigma_y"),
    (dict(E=70e9, nu=0.3, sigma_y=1e8, rho=0.0), "rho"),
    (dict(E=float("inf"), nu=0.3, sigma_y=1e8, rho=2700), "E"),
    (dict(E="abc", nu=0.3, sigma_y=1e8, rho=2700), "E"),
])
def test_bad_material_raises_value_error_naming_parameter(kwargs, name):
    with pytest.raises(ValueError, match=rf"^{name}\b"):
        Material(**kwargs)


def test_bad_radius_and_vz_parameters():
    mat = Material.reference()
    for R in (0.0, -1.0, float("nan")):
        with pytest.raises(ValueError, match=r"^R\b"):
            ContactPair.sphere_flat(mat, R)
    pair = ContactPair.reference()
    with pytest.raises(ValueError, match=r"^Ca\b.*> 0"):
        VZParams(pair, 0.0, 2.69e-4)
    with pytest.raises(ValueError, match=r"^Kc\b.*>= 0"):
        VZParams(pair, 2.33e-7, -1e-6)
    VZParams(pair, 2.33e-7, 0.0)                                       # Kc = 0 is allowed
    # A curvature rate so large that the loading curve delta(P) turns back: a clear error.
    with pytest.raises(ValueError, match=r"^Kc out of range"):
        VZParams(pair, 2.33e-7, 1e3 * 2.69e-4)


def test_nfdmodel_imports_numpy_and_scipy_only():
    import subprocess
    import sys

    code = ("import sys, nfdmodel; heavy = [m for m in ('gmsh', 'skfem', 'meshio', 'matplotlib', 'calib') "
            "if m in sys.modules]; print(heavy)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert out.strip() == "[]"


def test_sphere_wall_is_hertz_of_the_two_bodies_with_first_yield_in_the_sphere():
    """ContactPair.sphere_wall (the LAMMPS wall fixes' wall_material): E* of Johnson 1985 section
    4.2 written out, R* = R, P_Y = (pi A_Y(nu) sigma_Y)^3 R^2 / (6 E*^2) of the sphere's nu and
    sigma_Y; an aluminium sphere on steel: the rigid flat is E'/E* = 4/3 as stiff and yields at
    (E*/E')^2 = 0.5625 of the load; the stiffest wall of the range is the rigid flat to E'/E'_w."""
    aluminium = Material.reference()
    pair = ContactPair.sphere_wall(aluminium, 0.01, 210e9, 0.3)
    E_star = 1.0 / ((1 - 0.3**2) / 70e9 + (1 - 0.3**2) / 210e9)
    assert pair.E_star == pytest.approx(E_star, rel=1e-15) and pair.R_star == 0.01
    assert pair.P_Y == pytest.approx((math.pi * yield_factor(0.3) * 1e8) ** 3 * 0.01**2 / (6 * E_star**2), rel=1e-14)
    flat = ContactPair.sphere_flat(aluminium, 0.01)
    assert flat.E_star / pair.E_star == pytest.approx(4.0 / 3.0, rel=1e-14)
    assert flat.P_Y / pair.P_Y == pytest.approx(0.5625, rel=1e-14)
    assert pair.mass_star == flat.mass_star and pair.sigma_y == flat.sigma_y and pair.nu == flat.nu
    gel = Material(limits.E_MIN, 0.3, limits.SIGMA_Y_MIN, 1000.0)
    stiffest = ContactPair.sphere_wall(gel, 0.01, limits.E_MAX, 0.3)
    assert stiffest.E_star / ContactPair.sphere_flat(gel, 0.01).E_star == pytest.approx(
        1.0 / (1.0 + limits.E_MIN / limits.E_MAX), rel=1e-15)
    with pytest.raises(ValueError, match=r"^E out of range for a solid: need 100000 <= E <= 2e\+12 Pa"):
        ContactPair.sphere_wall(aluminium, 0.01, 210.0, 0.3)
    with pytest.raises(ValueError, match=r"^nu_wall out of range: need nu_wall >= 0 and nu_wall < 0.5"):
        ContactPair.sphere_wall(aluminium, 0.01, 210e9, 0.5)
