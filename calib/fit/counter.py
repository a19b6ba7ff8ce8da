"""The counter-body of a calibration: what the sphere is pressed on when it is not a rigid flat.

A counter-body is a second material (Young's modulus E2 [Pa], Poisson's ratio nu2, yield stress
sigma_Y2 [Pa] or none: elastic, density rho2 [kg/m^3]) shaped as a sphere of radius R2 [m] or a flat (none: the
half-space of a wall, meshed as a block of radius and height BLOCK_SIZE_OVER_R R1, large enough
that its size does not matter: tests/test_two_body.py::test_the_block_is_large_enough measures
the approach of the far points changing as 1/L, by 5e-4 of alpha from L = R1 to 2 R1 at the
Hertz loads of the tests, contact radius and pressure not at all). The pair's Hertz constants
(E*, R*, the yield point of the body with the lower A_Y(nu) sigma_Y) come from
nfdmodel.ContactPair.sphere_counter; the FE is calib.fe.two_body.

The pair's reduced mass m* = m1 m2 / (m1 + m2) (m = 4/3 pi R^3 rho) needs a counter-sphere's
density: ``require_density`` refuses a counter-sphere without one (a flat is a held block, no
mass in m*: its density, for the dynamic FE's block only, defaults to the sphere's).
"""
from __future__ import annotations

import dataclasses
from dataclasses import dataclass

from calib.fe.elastic import ElasticMaterial
from calib.fe.von_mises import VonMisesMaterial
from meshes.counter_body import BlockMeshSpec
from meshes.hemisphere import HemisphereMeshSpec
from nfdmodel import ContactPair, Material, check_real, limits
from nfdmodel.materials import check_radius
from nfdmodel.validation import check_solid

BLOCK_SIZE_OVER_R = 2.0   # the flat counter-body's block: radius and height L = 2 R1


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

    def fe_material(self):
        """The FE material: von Mises elastic-perfectly plastic, or elastic without sigma_Y."""
        if self.sigma_y is None:
            return ElasticMaterial(self.E, self.nu)
        return VonMisesMaterial(self.E, self.nu, self.sigma_y)

    def mesh_spec(self, sphere: HemisphereMeshSpec) -> HemisphereMeshSpec:
        """The counter-body's mesh for the sphere's ``sphere``: the same contact element and
        refined zone (clipped to 0.9 R2), the far field graded to R1 / 10 (at most its size)."""
        size = BLOCK_SIZE_OVER_R * sphere.radius if self.is_flat else self.R
        kind = BlockMeshSpec if self.is_flat else HemisphereMeshSpec
        refined_radius, refined_depth = min(sphere.refined_radius, 0.9 * size), min(sphere.refined_depth, 0.9 * size)
        contact = min(sphere.contact_size, min(refined_radius, refined_depth) / 2)
        fields = dataclasses.asdict(sphere)
        fields.update(radius=size, contact_size=contact, refined_radius=refined_radius, refined_depth=refined_depth,
                      far_size=min(max(sphere.far_size, contact), size))
        return kind(**fields)

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
