"""Materials, contact pairs and the incipient-yield point of Hertz contact.

Effective properties (Johnson 1985, Contact Mechanics, section 4.2):

    1/E* = (1 - nu_i^2)/E_i + (1 - nu_j^2)/E_j      [Pa]   (rigid flat: 1/E* = (1 - nu^2)/E)
    1/R* = 1/R_i + 1/R_j                            [m]    (rigid flat: R* = R)
    m*   = m_i m_j / (m_i + m_j)                    [kg]   (rigid flat: m* = m)

Incipient yield (Johnson 1985 eq. 3.45; Vu-Quoc & Zhang 1999 eq. 3.7): von Mises
yield first occurs on the axis below the surface when the peak Hertz pressure reaches
p_Y = A_Y(nu) sigma_Y, with 1/A_Y = max_zeta |sigma_z - sigma_r| / p0 along the axis; of two
bodies in contact (both carry the same Hertz pressure) the one with the lower p_Y yields first.

    P_Y = pi^3 R*^2 p_Y^3 / (6 E*^2)  [N],   a_Y = (3 P_Y R* / (4 E*))^(1/3)  [m]

This module is the one home of E*, R*, p_Y, P_Y, a_Y and the body that yields first (the functions
below and ContactPair; tests/test_formula_homes.py); Hertz's radius, pressure and impact are
nfdmodel.hertz_contact's.
"""
from __future__ import annotations

import math
import warnings
from dataclasses import dataclass
from functools import cached_property, lru_cache

import numpy as np
from scipy.optimize import minimize_scalar

from . import limits, reference_case
from .hertz_contact import (hertz_impact_time, hertz_peak_pressure, hertz_radius, hertz_stiffness)
from .validation import (LARGEST_POSSIBLE_RADIUS, LARGEST_USUAL_RADIUS, PlausibilityWarning, check_real, check_solid,
                         unit_slip)


def axis_stress_difference(zeta, nu: float):
    """|sigma_z - sigma_r| / p0 on the axis of a Hertz contact at depth zeta = z/a [-].

    Johnson (1985) eq. 3.45 with the contact radius a and peak pressure p0:
        sigma_z/p0 = -1/(1 + zeta^2)
        sigma_r/p0 = -(1 + nu)(1 - zeta atan(1/zeta)) + 1/(2 (1 + zeta^2))
    """
    zeta = np.asarray(zeta, dtype=float)
    # zeta*atan(1/zeta) -> 0 at the surface; arctan2 avoids dividing by zero there.
    zeta_atan = zeta * np.arctan2(1.0, zeta)
    sigma_z = -1.0 / (1.0 + zeta**2)
    sigma_r = -(1.0 + nu) * (1.0 - zeta_atan) + 0.5 / (1.0 + zeta**2)
    return np.abs(sigma_z - sigma_r)


@lru_cache(maxsize=256)
def _yield_factor_cached(nu: float) -> float:
    # The maximum lies at zeta ~ 0.4-0.8 for 0 <= nu < 0.5 (0.48 at nu = 0.3); the bounded
    # search on [0, 3] contains it and the surface value |nu - 0.5| is compared explicitly.
    result = minimize_scalar(lambda z: -axis_stress_difference(z, nu), bounds=(0.0, 3.0),
                             method="bounded", options={"xatol": 1e-12})
    peak = max(-float(result.fun), float(axis_stress_difference(0.0, nu)))
    return 1.0 / peak


def yield_factor(nu: float) -> float:
    """A_Y(nu) = 1 / max_zeta |sigma_z - sigma_r|/p0 on the Hertz axis (Johnson 1985 eq. 3.45).

    Incipient yield when p0 = A_Y sigma_Y (von Mises = Tresca on the axis). A_Y(0.3) = 1.61
    (Vu-Quoc & Zhang 1999, section 3). Valid for 0 <= nu < 0.5 [-].
    """
    nu = check_real("nu", nu, low=0.0, low_inclusive=True, high=limits.NU_MAX)
    return _yield_factor_cached(nu)


def plane_strain_modulus(E, nu):
    """E' = E / (1 - nu^2) [Pa] of a body of Young's modulus E [Pa] and Poisson's ratio nu: its share
    of the contact modulus, E* itself against a rigid flat (Johnson 1985 eq. 4.22)."""
    return E / (1.0 - nu ** 2)


def youngs_modulus(plane_strain, nu):
    """E = E' (1 - nu^2) [Pa]: Young's modulus of a body of plane-strain modulus E' [Pa] (a sphere's E
    from its E* on a rigid flat)."""
    return plane_strain * (1.0 - nu * nu)


def plane_strain_compliance(E, nu):
    """1/E' = (1 - nu^2) / E [1/Pa]: a body's term of 1/E* (Johnson 1985 eq. 4.22)."""
    return (1.0 - nu ** 2) / E


def contact_modulus(*compliances):
    """E* = 1 / (c_1 + c_2 + ...) [Pa] of bodies in contact, c_k [1/Pa] each body's compliance
    (1 - nu_k^2)/E_k or 1/E'_k (Johnson 1985 eq. 4.22: 1/E* = sum_k (1 - nu_k^2)/E_k), added in
    the order given."""
    total = compliances[0]
    for compliance in compliances[1:]:
        total = total + compliance
    return 1.0 / total


def effective_radius(R_i, R_j):
    """R* = 1 / (1/R_i + 1/R_j) [m] of two spheres of radii R_i, R_j [m] (Johnson 1985 section 4.2;
    a flat: R* = R)."""
    return 1.0 / (1.0 / R_i + 1.0 / R_j)


def yield_pressure(sigma_y, nu):
    """p_Y = A_Y(nu) sigma_y [Pa]: the peak Hertz pressure at which a body of yield stress sigma_y [Pa]
    and Poisson's ratio nu first yields (Johnson 1985 eq. 3.45)."""
    return yield_factor(nu) * sigma_y


def first_to_yield(*bodies) -> int:
    """The index of the body that yields first among ``bodies`` ((sigma_y [Pa], nu) each): the lowest
    p_Y = A_Y(nu) sigma_y (not simply the lowest sigma_y: A_Y grows from 1.30 at nu = 0 to 1.86 at
    nu = 0.49); on a tie the first of them."""
    return min(range(len(bodies)), key=lambda k: yield_pressure(*bodies[k]))


def yield_force(R_star, E_star, p_Y):
    """P_Y = pi^3 R*^2 p_Y^3 / (6 E*^2) [N]: the Hertz force whose peak pressure is p_Y [Pa]
    (Vu-Quoc & Zhang 1999 eq. 3.7; R* [m], E* [Pa])."""
    return math.pi**3 * R_star**2 * p_Y**3 / (6.0 * E_star**2)


@dataclass(frozen=True)
class Material:
    """Isotropic elastic-perfectly plastic material (validated, SI units).

    E [Pa] > 0, 0 <= nu < 0.5 [-], sigma_y [Pa] > 0 (uniaxial yield stress), rho [kg/m^3] > 0,
    each inside the range of real solids (nfdmodel.validation.SOLID_RANGES): a value outside
    it is refused naming the likely unit slip (E = 70: GPa typed as Pa).
    """

    E: float
    nu: float
    sigma_y: float
    rho: float

    def __post_init__(self):
        object.__setattr__(self, "E", check_solid("E", check_real("E", self.E, low=0.0, unit="Pa")))
        object.__setattr__(self, "nu", check_real("nu", self.nu, low=0.0, low_inclusive=True, high=limits.NU_MAX))
        object.__setattr__(self, "sigma_y", check_solid("sigma_y", check_real("sigma_y", self.sigma_y,
                                                                               low=0.0, unit="Pa")))
        object.__setattr__(self, "rho", check_solid("rho", check_real("rho", self.rho, low=0.0,
                                                                       unit="kg/m^3")))

    @classmethod
    def reference(cls) -> "Material":
        """The paper's aluminium: E = 70 GPa, nu = 0.3, sigma_Y = 100 MPa, rho = 2699 kg/m^3."""
        return cls(reference_case.E, reference_case.NU, reference_case.SIGMA_Y, reference_case.RHO)

    @property
    def plane_strain_modulus(self) -> float:
        """E / (1 - nu^2) [Pa]: the body's share of the contact modulus (Johnson 1985 eq. 4.22)."""
        return plane_strain_modulus(self.E, self.nu)

    def sphere_mass(self, R: float) -> float:
        """Mass of a sphere of radius R [m]: (4/3) pi R^3 rho [kg]."""
        try:
            mass = 4.0 / 3.0 * math.pi * R**3 * self.rho
        except OverflowError:
            mass = math.inf
        if not (math.isfinite(mass) and mass > 0.0):
            raise ValueError(f"R, rho out of range: the sphere mass (4/3) pi R^3 rho = {mass:g} kg is not "
                             f"a finite positive number (R = {R:g} m, rho = {self.rho:g} kg/m^3); "
                             f"give SI units (m, kg/m^3)")
        return mass


def check_radius(name: str, R) -> float:
    """A sphere radius [m] > 0; above LARGEST_USUAL_RADIUS a PlausibilityWarning names the slip
    it would be (R = 100: millimetres typed as metres)."""
    R = check_real(name, R, low=0.0, unit="m")
    if R > LARGEST_POSSIBLE_RADIUS:
        raise ValueError(f"{name} out of range for a particle: need 0 < {name} <= "
                         f"{LARGEST_POSSIBLE_RADIUS:g} m, got {R:g}{unit_slip('R', R)}")
    if R > LARGEST_USUAL_RADIUS:
        warnings.warn(f"{name} = {R:g} m is larger than DEM particles usually are (<= "
                      f"{LARGEST_USUAL_RADIUS:g} m){unit_slip('R', R)}", PlausibilityWarning, stacklevel=3)
    return R


@dataclass(frozen=True)
class ContactPair:
    """Effective contact properties of a pair and its incipient-yield point.

    Fields: R_star [m], E_star [Pa], sigma_y [Pa] and nu [-] of the body that yields first (the
    lower A_Y(nu) sigma_y), mass_star [kg]. Derived (Vu-Quoc & Zhang 1999 eq. 3.7):

        p_Y     = A_Y(nu) sigma_y                           contact yield pressure [Pa]
        P_Y     = pi^3 R*^2 p_Y^3 / (6 E*^2)                yield force [N]
        a_Y     = (3 P_Y R* / (4 E*))^(1/3)                 contact radius at yield [m]
        delta_Y = a_Y^2 / R*                                approach at yield [m]
        v_Y     = sqrt(4 P_Y delta_Y / (5 m*))              = 3.194 (p_Y^5 R*^3/(E*^4 m*))^(1/2)
                                                            (Thornton 1997 eq. 1.12) [m/s]
    """

    R_star: float
    E_star: float
    sigma_y: float
    nu: float
    mass_star: float

    def __post_init__(self):
        object.__setattr__(self, "R_star", check_real("R", self.R_star, low=0.0, unit="m"))
        object.__setattr__(self, "E_star", check_real("E", self.E_star, low=0.0, unit="Pa"))
        object.__setattr__(self, "sigma_y", check_real("sigma_y", self.sigma_y, low=0.0, unit="Pa"))
        object.__setattr__(self, "nu", check_real("nu", self.nu, low=0.0, low_inclusive=True, high=limits.NU_MAX))
        object.__setattr__(self, "mass_star", check_real("mass", self.mass_star, low=0.0, unit="kg"))
        self._check_yield_point()

    def _check_yield_point(self) -> None:
        """The yield point and impact scales must be finite positive floats: extreme inputs (R =
        1e200 m, E = 1e-300 Pa, values in the wrong unit) otherwise overflow deep inside."""
        try:
            derived = {"P_Y": self.P_Y, "a_Y": self.a_Y, "delta_Y": self.delta_Y, "v_Y": self.v_Y}
        except (OverflowError, ZeroDivisionError, FloatingPointError):
            derived = {"P_Y": math.inf}
        bad = {k: v for k, v in derived.items() if not (math.isfinite(v) and v > 0.0)}
        if bad:
            name, value = next(iter(bad.items()))
            raise ValueError(
                f"R, E, sigma_y out of range: the contact's {name} = {value:g} is not a finite "
                f"positive number (R* = {self.R_star:g} m, E* = {self.E_star:g} Pa, sigma_y = "
                f"{self.sigma_y:g} Pa, mass = {self.mass_star:g} kg); give SI units (m, Pa, kg/m^3)")

    @classmethod
    def sphere_flat(cls, material: Material, R: float) -> "ContactPair":
        """Sphere of radius R [m] on a rigid frictionless flat: R* = R, E* = E/(1 - nu^2), m* = m."""
        if not isinstance(material, Material):
            raise ValueError(f"material must be a Material, got {type(material).__name__}")
        R = check_radius("R", R)
        return cls(R, material.plane_strain_modulus, material.sigma_y, material.nu,
                   material.sphere_mass(R))

    @classmethod
    def sphere_wall(cls, material: Material, R: float, E_wall: float, nu_wall: float) -> "ContactPair":
        """Sphere of radius R [m] on a flat elastic wall of E_wall [Pa], nu_wall [-]: R* = R,
        1/E* = (1 - nu^2)/E + (1 - nu_wall^2)/E_wall, m* = m; first yield in the sphere (the wall
        stays elastic). The LAMMPS wall fixes' `wall_material E_w nu_w`."""
        if not isinstance(material, Material):
            raise ValueError(f"material must be a Material, got {type(material).__name__}")
        R = check_radius("R", R)
        E_wall = check_solid("E", check_real("E_wall", E_wall, low=0.0, unit="Pa"))
        nu_wall = check_real("nu_wall", nu_wall, low=0.0, low_inclusive=True, high=limits.NU_MAX)
        E_star = contact_modulus(1.0 / material.plane_strain_modulus, 1.0 / plane_strain_modulus(E_wall, nu_wall))
        return cls(R, E_star, material.sigma_y, material.nu, material.sphere_mass(R))

    @classmethod
    def sphere_sphere(cls, material_i: Material, R_i: float, material_j: Material,
                      R_j: float) -> "ContactPair":
        """Two spheres: 1/R* = 1/R_i + 1/R_j, 1/E* = sum (1 - nu^2)/E, m* = m_i m_j/(m_i + m_j).

        Both bodies carry the same Hertz pressure; body k yields first below its surface when
        p0 = A_Y(nu_k) sigma_y,k, so the yield point uses sigma_y and nu of the body with the
        lower A_Y(nu) sigma_y (not simply the lower sigma_y: A_Y grows from 1.30 at nu = 0 to
        1.86 at nu = 0.49). On a tie the first body is taken.
        """
        for name, mat in (("material_i", material_i), ("material_j", material_j)):
            if not isinstance(mat, Material):
                raise ValueError(f"{name} must be a Material, got {type(mat).__name__}")
        R_i = check_radius("R_i", R_i)
        R_j = check_radius("R_j", R_j)
        R_star = effective_radius(R_i, R_j)
        E_star = contact_modulus(1.0 / material_i.plane_strain_modulus, 1.0 / material_j.plane_strain_modulus)
        m_i, m_j = material_i.sphere_mass(R_i), material_j.sphere_mass(R_j)
        first = (material_i, material_j)[first_to_yield((material_i.sigma_y, material_i.nu),
                                                        (material_j.sigma_y, material_j.nu))]
        return cls(R_star, E_star, first.sigma_y, first.nu, m_i * m_j / (m_i + m_j))

    @classmethod
    def sphere_counter(cls, material: Material, R: float, E2: float, nu2: float, sigma_y2: float | None = None,
                       R2: float | None = None, rho2: float | None = None) -> "ContactPair":
        """Sphere (``material``, radius R [m]) on a deformable counter-body: Young's modulus E2 [Pa],
        Poisson's ratio nu2, yield stress sigma_y2 [Pa] (None: elastic, it never yields), radius R2
        [m] (None: a flat, the half-space of a wall), density rho2 [kg/m^3] (None: the sphere's).

            1/R* = 1/R + 1/R2,  1/E* = (1 - nu^2)/E + (1 - nu2^2)/E2   (Johnson 1985 eq. 4.22)

        the yield point from the body with the lower A_Y(nu) sigma_y (as sphere_sphere); m* the
        pair's reduced mass (the sphere's own against a flat)."""
        if not isinstance(material, Material):
            raise ValueError(f"material must be a Material, got {type(material).__name__}")
        R = check_radius("R", R)
        E2 = check_solid("E", check_real("counter E", E2, low=0.0, unit="Pa"), "counter E")
        nu2 = check_real("counter nu", nu2, low=0.0, low_inclusive=True, high=limits.NU_MAX)
        E_star = contact_modulus(1.0 / material.plane_strain_modulus, plane_strain_compliance(E2, nu2))
        yielding = [(material.sigma_y, material.nu)]
        if sigma_y2 is not None:
            sigma_y2 = check_solid("sigma_y", check_real("counter sigma_y", sigma_y2, low=0.0, unit="Pa"),
                                   "counter sigma_y")
            yielding.append((sigma_y2, nu2))
        sigma_y, nu = yielding[first_to_yield(*yielding)]
        mass = material.sphere_mass(R)
        if R2 is None:
            return cls(R, E_star, sigma_y, nu, mass)
        R2 = check_radius("counter R", R2)
        rho2 = material.rho if rho2 is None else check_solid("rho", check_real("counter rho", rho2, low=0.0,
                                                                                 unit="kg/m^3"), "counter rho")
        mass2 = 4.0 / 3.0 * math.pi * R2 ** 3 * rho2
        return cls(effective_radius(R, R2), E_star, sigma_y, nu, mass * mass2 / (mass + mass2))

    @classmethod
    def reference(cls) -> "ContactPair":
        """The paper's reference case: aluminium sphere R = 0.1 m on a rigid flat."""
        return cls.sphere_flat(Material.reference(), reference_case.R)

    @cached_property
    def A_Y(self) -> float:
        """Yield factor A_Y(nu) [-] (Johnson 1985 eq. 3.45)."""
        return yield_factor(self.nu)

    @cached_property
    def p_Y(self) -> float:
        """Contact yield pressure p_Y = A_Y sigma_y [Pa] (peak Hertz pressure at first yield)."""
        return yield_pressure(self.sigma_y, self.nu)

    @cached_property
    def P_Y(self) -> float:
        """Yield force P_Y = pi^3 R*^2 p_Y^3 / (6 E*^2) [N] (Vu-Quoc & Zhang 1999 eq. 3.7)."""
        return yield_force(self.R_star, self.E_star, self.p_Y)

    @cached_property
    def a_Y(self) -> float:
        """Hertz contact radius at yield a_Y = (3 P_Y R*/(4 E*))^(1/3) [m]."""
        return self.hertz_radius(self.P_Y)

    @cached_property
    def delta_Y(self) -> float:
        """Approach at yield delta_Y = a_Y^2 / R* [m]."""
        return self.a_Y**2 / self.R_star

    @cached_property
    def v_Y(self) -> float:
        """Impact velocity at which yield starts, from (1/2) m* v_Y^2 = (2/5) P_Y delta_Y [m/s]."""
        return math.sqrt(4.0 * self.P_Y * self.delta_Y / (5.0 * self.mass_star))

    @cached_property
    def hertz_stiffness(self) -> float:
        """k_H = (4/3) E* sqrt(R*) [N/m^1.5] in Hertz's P = k_H delta^(3/2)."""
        return hertz_stiffness(self.R_star, self.E_star)

    def hertz_radius(self, force):
        """Hertz contact radius a = (3 P R* / (4 E*))^(1/3) [m] at force P [N] (Johnson eq. 4.22)."""
        return hertz_radius(np.asarray(force, dtype=float), self.R_star, self.E_star)[()]

    def hertz_approach(self, force):
        """Hertz approach delta = a^2 / R* [m] at force P [N] (Johnson 1985 eq. 4.23)."""
        return (self.hertz_radius(force) ** 2 / self.R_star)[()]

    def hertz_peak_pressure(self, force):
        """Hertz peak pressure p0 = 3 P / (2 pi a^2) [Pa] at force P [N] (Johnson 1985 eq. 4.23)."""
        force = np.asarray(force, dtype=float)
        return hertz_peak_pressure(force, self.hertz_radius(force))[()]

    def hertz_pressure(self, r, force):
        """Hertz pressure p(r) = p0 sqrt(1 - r^2 / a^2) inside the contact, 0 outside [Pa], at
        radius r [m] and force P [N] (Johnson 1985 eq. 4.22)."""
        a = self.hertz_radius(force)
        inside = np.clip(1.0 - (np.asarray(r, dtype=float) / a) ** 2, 0.0, None)
        return (self.hertz_peak_pressure(force) * np.sqrt(inside))[()]

    def hertz_contact_time(self, v_in) -> float:
        """Duration of an elastic Hertz impact at v_in [m/s]: 2.8683 (m*^2/(R* E*^2 v_in))^(1/5) [s].

        (Johnson 1985 eq. 11.24.) It sizes time steps and step limits.
        """
        v_in = np.asarray(v_in, dtype=float)
        return hertz_impact_time(self.mass_star, self.R_star, self.E_star, v_in)[()]


def as_pair(params, law: str) -> ContactPair:
    """The ContactPair of a law's ``params`` (a ContactPair, or anything carrying one as .pair),
    else a ValueError naming the law."""
    if isinstance(params, ContactPair):
        return params
    pair = getattr(params, "pair", None)
    if isinstance(pair, ContactPair):
        return pair
    raise ValueError(f"params for law '{law}' must be a ContactPair or carry one as .pair, "
                     f"got {type(params).__name__}")
