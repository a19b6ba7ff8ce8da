"""The counter-body of a calibration: what the sphere is pressed on when it is not a rigid flat.

A counter-body is a second material (Young's modulus E2 [Pa], Poisson's ratio nu2, yield stress
sigma_Y2 [Pa] or none: elastic, density rho2 [kg/m^3]) shaped as a sphere of radius R2 [m] or a flat (none: the
half-space of a wall, meshed as a block of radius and height L, its far face held, large enough that its size
does not matter: L = max(BLOCK_SIZE_OVER_R R1, BLOCK_SIZE_OVER_CONTACT x the sphere mesh's refined radius), its
far elements scaled with it. At the Hertz loads of tests/test_two_body.py::test_the_block_is_large_enough the
approach of the far points changes as 1/L, by 5e-4 of alpha from L = R1 to 2 R1, contact radius and pressure not
at all. A wide contact reaches further: at a/R* 0.445 (nu 0.3, E/sigma_Y 200, E1'/E2' = 1, finite strain, 773
P_Y) L = 2 R1 leaves e 3.0 % and the approach 1.0 % below a block 4 times the one L = 36 x 1.1 a_max gives
(17.6 R1), which is itself within 0.23 % in e and 0.15 % in approach of it (its far elements kept at R1 / 10
instead: within 0.03 %). The pair's Hertz constants
(E*, R*, the yield point of the body with the lower A_Y(nu) sigma_Y) come from
nfdmodel.ContactPair.sphere_counter; the FE is calib.fe.two_body.

The pair's reduced mass m* = m1 m2 / (m1 + m2) (m = 4/3 pi R^3 rho) needs a counter-sphere's
density: ``require_density`` refuses a counter-sphere without one (a flat is a held block, no
mass in m*: its density, for the dynamic FE's block only, defaults to the sphere's).

What the two-body FE can handle, checked before any mesh or FE work (``check_counter``, used by
calibrate, hertz and impact and their dry runs; one line naming the flag and the range):

- the counter's E2 / sigma_Y2 inside calib.fit.recipe.E_OVER_SIGMA_Y_RANGE (as the sphere's): a
  lower sigma_Y2 yields at contacts below 1e-5 R, finer than any mesh the recipe grades;
- the largest contact radius a_max <= the kinematics' reach min(R1, R2) (calib.fit.recipe.fe_reach: 0.2 in
  small strain, 0.45 in finite strain on an elastic flat);
- a counter-body softer than the sphere: (E2 / E1) (a_min / R1) >= SOFT_COUNTER_MIN at the
  smallest contact a_min (first load, or the impact's contact). Below it Newton stalls at a
  relative residual ~1e-8, the stiff sphere's round-off on the soft body's force. Measured on
  coarse meshes (contact element a/6, aluminium R = 0.1 m, E2/E1 = 1e-2 .. 1e-4, and a soft sphere
  on a stiff flat, which never stalls): the press converges from 4e-6 and stalls at 2e-6 (3.7e-6
  on a load ladder); the impact converges at 1e-5 and 1.5e-5 and stalls at 5e-6 and below;
- a counter-sphere wider than the sphere mesh's contact candidates (its refined zone).
"""
from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from typing import Callable

from scipy.optimize import brentq

from calib.fe.elastic import ElasticMaterial
from calib.fe.von_mises import VonMisesMaterial
from meshes.counter_body import BlockMeshSpec
from meshes.hemisphere import HemisphereMeshSpec
from nfdmodel import ContactPair, Material, check_real, limits
from nfdmodel.materials import check_radius
from nfdmodel.validation import bound_text, check_solid

from calib.fit.recipe import CONTACT_RADIUS_LIMIT, E_OVER_SIGMA_Y_RANGE, MESH_LEVELS
from meshes.hemisphere import MIN_CONTACT_SIZE_OVER_RADIUS

BLOCK_SIZE_OVER_R = 2.0   # the flat counter-body's block: radius and height L >= 2 R1
BLOCK_SIZE_OVER_CONTACT = 36.0   # ... and L >= this x the sphere mesh's refined radius (1.1 a_max): module doc
SOFT_COUNTER_MIN = 1e-5   # (E2/E1)(a_min/R1) below which the two-body FE stalls (module docstring)
FLAGS = {"E": "--counter-E", "sigma_y": "--counter-sigma-y", "R": "--counter-R"}
# the smallest largest-contact a mesh resolves, over R1: the default level's a_max / 37 elements,
# none below meshes.hemisphere's 1e-6 R1 (3.7e-5 R1)
SMALLEST_CONTACT_OVER_R = MIN_CONTACT_SIZE_OVER_RADIUS / MESH_LEVELS["default"]


@dataclass(frozen=True)
class CounterBody:
    """E [Pa], nu [-], sigma_y [Pa] (None: elastic), R [m] (None: a flat), rho [kg/m^3] (None:
    the sphere's); validated on construction (one line naming the parameter and its range)."""

    E: float
    nu: float
    sigma_y: float | None = None
    R: float | None = None
    rho: float | None = None

    def __post_init__(self):
        object.__setattr__(self, "E", check_solid("E", check_real("counter E", self.E, low=0.0, unit="Pa"),
                                                  "counter E"))
        object.__setattr__(self, "nu", check_real("counter nu", self.nu, low=0.0, low_inclusive=True,
                                                  high=limits.NU_MAX))
        if self.sigma_y is not None:
            object.__setattr__(self, "sigma_y", check_solid(
                "sigma_y", check_real("counter sigma_y", self.sigma_y, low=0.0, unit="Pa"), "counter sigma_y"))
        if self.R is not None:
            object.__setattr__(self, "R", check_radius("counter R", self.R))
        if self.rho is not None:
            object.__setattr__(self, "rho", check_solid(
                "rho", check_real("counter rho", self.rho, low=0.0, unit="kg/m^3"), "counter rho"))

    @property
    def is_flat(self) -> bool:
        return self.R is None

    def require_density(self, flag: str = "--counter-rho") -> "CounterBody":
        """This counter-body, or ValueError naming ``flag`` for a counter-sphere without a density
        (its mass enters the pair's m*; a flat's does not)."""
        if not self.is_flat and self.rho is None:
            raise ValueError(f"{flag} out of range: need the counter-sphere's density (> 0 kg/m^3; its mass enters the "
                             f"pair's m* = m1 m2 / (m1 + m2)), got none")
        return self

    def density(self, material: Material) -> float:
        """The counter-body's density [kg/m^3]: its own, else the sphere's (``material``)."""
        return material.rho if self.rho is None else self.rho

    def pair(self, material: Material, radius: float) -> ContactPair:
        """The Hertz pair of the sphere (``material``, R [m]) on this counter-body (m* with the
        counter-sphere's density, the sphere's when none is stated)."""
        return ContactPair.sphere_counter(material, radius, self.E, self.nu, self.sigma_y, self.R, self.rho)

    def check(self, material: Material, radius: float, contact, load: str,
              radius_over_R: float = CONTACT_RADIUS_LIMIT) -> None:
        """``check_counter`` of this counter-body under the sphere (``material``, R [m])."""
        check_counter(material, radius, self, contact, load, radius_over_R=radius_over_R)

    def fe_material(self):
        """The FE material: von Mises elastic-perfectly plastic, or elastic without sigma_Y."""
        if self.sigma_y is None:
            return ElasticMaterial(self.E, self.nu)
        return VonMisesMaterial(self.E, self.nu, self.sigma_y)

    def mesh_spec(self, sphere: HemisphereMeshSpec) -> HemisphereMeshSpec:
        """The counter-body's mesh for the sphere's ``sphere``: the same contact element and
        refined zone (clipped to 0.9 R2), the far field graded to the sphere's far element (at most its size),
        scaled with a block larger than BLOCK_SIZE_OVER_R R1 (``block_size``)."""
        size = self.block_size(sphere) if self.is_flat else self.R
        enlarged = size / (BLOCK_SIZE_OVER_R * sphere.radius) if self.is_flat else 1.0
        kind = BlockMeshSpec if self.is_flat else HemisphereMeshSpec
        refined_radius, refined_depth = min(sphere.refined_radius, 0.9 * size), min(sphere.refined_depth, 0.9 * size)
        contact = min(sphere.contact_size, min(refined_radius, refined_depth) / 2)
        fields = dataclasses.asdict(sphere)
        fields.update(radius=size, contact_size=contact, refined_radius=refined_radius, refined_depth=refined_depth,
                      far_size=min(max(sphere.far_size, contact) * enlarged, size))
        return kind(**fields)

    @staticmethod
    def block_size(sphere: HemisphereMeshSpec) -> float:
        """A flat's block L [m] under the sphere mesh ``sphere``: max(BLOCK_SIZE_OVER_R R1, BLOCK_SIZE_OVER_CONTACT
        x its refined radius), so the held far face stays far from every contact it meshes (module doc)."""
        return max(BLOCK_SIZE_OVER_R * sphere.radius, BLOCK_SIZE_OVER_CONTACT * sphere.refined_radius)

    def describe(self) -> dict:
        """The record of the parameter file and the result stamps (SI units)."""
        return {"shape": "flat" if self.is_flat else "sphere", "E": self.E, "nu": self.nu, "sigma_y": self.sigma_y,
                "R": self.R, "rho": self.rho}

    def label(self) -> str:
        """One line: 'steel flat, E = 2e+11 Pa, nu = 0.28, elastic'."""
        shape = "flat" if self.is_flat else f"sphere R = {self.R:g} m"
        plastic = "elastic" if self.sigma_y is None else f"sigma_Y = {self.sigma_y:.4g} Pa"
        density = "" if self.rho is None else f", rho = {self.rho:g} kg/m^3"
        return f"counter-body: {shape}, E = {self.E:.4g} Pa, nu = {self.nu:g}, {plastic}{density}"


def check_counter(material: Material, radius: float, counter: CounterBody,
                  contact: Callable[[ContactPair], tuple[float, float]], load: str, flags: dict = FLAGS,
                  radius_over_R: float = CONTACT_RADIUS_LIMIT) -> None:
    """ValueError naming the counter flag (``flags``) and the range the two-body FE handles, before
    any mesh (module docstring). ``contact(pair)``: the (smallest, largest) contact radius [m] the
    run plans on ``pair``; ``load``: what sets it, for the message ("loads 1 .. 100 N"); ``radius_over_R``:
    the largest contact radius over min(R1, R2) of the FE's kinematics (calib.fit.recipe.REACH; default the
    small strain's)."""
    if counter.sigma_y is not None:
        low, high = E_OVER_SIGMA_Y_RANGE
        if not low <= counter.E / counter.sigma_y <= high:
            raise ValueError(f"{flags['sigma_y']} out of range for the FE: need {low:g} <= E2/sigma_Y2 <= {high:g} "
                             f"(as the sphere's), i.e. {counter.E / high:.4g} <= {flags['sigma_y']} <= "
                             f"{counter.E / low:.4g} Pa for E2 = {counter.E:.4g} Pa, got {counter.sigma_y:g}")

    def with_E(E2: float) -> CounterBody:
        return dataclasses.replace(counter, E=E2)

    def contact_of(body: CounterBody) -> tuple[float, float]:
        return contact(body.pair(material, radius))

    a_min, a_max = contact_of(counter)
    smallest = SMALLEST_CONTACT_OVER_R * radius
    if counter.R is not None and a_max < smallest:

        def short(R2: float) -> float:
            return contact_of(dataclasses.replace(counter, R=R2))[1] - smallest
        need = (f"need {flags['R']} >= {brentq(short, counter.R, radius, rtol=1e-3) * 1.001:.4g} m here"
                if short(radius) > 0.0 else "raise the load")
        raise ValueError(f"{flags['R']} out of range for the FE: on this counter-sphere the contact at {load} reaches "
                         f"only {a_max:.3g} m = {a_max / radius:.3g} R1; the sphere's mesh resolves contacts from "
                         f"{SMALLEST_CONTACT_OVER_R:.2g} R1 (elements >= {MIN_CONTACT_SIZE_OVER_RADIUS:g} R1): {need}, "
                         f"got {counter.R:g}")
    bound = radius_over_R * min(radius, counter.R or radius)
    if a_max > bound:
        if counter.R is not None and counter.R < radius and a_max <= radius_over_R * radius:
            R2 = brentq(lambda R: contact_of(dataclasses.replace(counter, R=R))[1] - radius_over_R * R,
                        counter.R, radius, rtol=1e-3)
            raise ValueError(f"{flags['R']} out of range for the FE: at {load} the contact radius reaches "
                             f"{a_max:.3g} m = {a_max / counter.R:.3g} R2; the FE needs a <= {radius_over_R:g} "
                             f"min(R1, R2): need {flags['R']} >= {bound_text(R2 * 1.001, '>=')} m here (or a lower "
                             f"load), got {counter.R:g} m")
        stiffest = limits.E_MAX
        if counter.E < material.E and contact_of(with_E(stiffest))[1] <= bound:
            E2 = brentq(lambda E: contact_of(with_E(E))[1] - bound, counter.E, stiffest, rtol=1e-3)
            raise ValueError(f"{flags['E']} out of range for the FE: on this counter-body the contact radius at "
                             f"{load} reaches {a_max:.3g} m = {a_max / bound * radius_over_R:.3g} R; the FE "
                             f"needs a <= {radius_over_R:g} R: need {flags['E']} >= {E2 * 1.001:.4g} Pa here, "
                             f"got {counter.E:g}")
        raise ValueError(f"{load} out of range for the FE on this counter-body: the contact radius reaches "
                         f"{a_max:.3g} m; the FE needs a <= {radius_over_R:g} min(R1, R2) = {bound:.3g} m")
    if counter.E < material.E:
        def softness(E2: float) -> float:
            return E2 / material.E * contact_of(with_E(E2))[0] / radius - SOFT_COUNTER_MIN
        if softness(counter.E) < 0.0:
            need = (f"need {flags['E']} >= {brentq(softness, counter.E, material.E, rtol=1e-3) * 1.001:.4g} Pa here"
                    if softness(material.E) > 0.0 else f"raise the smallest load")
            raise ValueError(f"{flags['E']} out of range for the two-body FE: a counter-body {material.E / counter.E:.3g}x "
                             f"softer than the sphere needs (E2/E1)(a/R1) >= {SOFT_COUNTER_MIN:g} at the smallest "
                             f"contact (a = {a_min:.3g} m at {load}; below it Newton stalls): {need}, got "
                             f"{counter.E:g}")


def check_counter_covers(counter: CounterBody, sphere_mesh, flags: dict = FLAGS) -> None:
    """ValueError naming --counter-R when a counter-sphere is narrower than the contact candidates
    of ``sphere_mesh`` (its refined zone, radius [m]): the counter's surface must cover them."""
    if counter.R is not None and not counter.R > sphere_mesh.refined_radius:
        raise ValueError(f"{flags['R']} out of range for the FE: the sphere's contact zone is meshed to r = "
                         f"{sphere_mesh.refined_radius:.3g} m; need {flags['R']} > {sphere_mesh.refined_radius:.3g} m "
                         f"(a counter-sphere wider than it), got {counter.R:g}")


def hertz_contact(loads) -> Callable[[ContactPair], tuple[float, float]]:
    """``check_counter``'s contact of an elastic press at ``loads`` [N]: Hertz's radii at the
    smallest and largest (nfdmodel.ContactPair.hertz_radius)."""
    smallest, largest = min(loads), max(loads)
    return lambda pair: (float(pair.hertz_radius(smallest)), float(pair.hertz_radius(largest)))
