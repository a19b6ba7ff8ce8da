"""The r-z section of the whole sphere, for impacts: meshed by gmsh, refined at the bottom pole, cached.

Domain: the half disc

    {(r, z): r >= 0, r^2 + (z - R)^2 <= R^2}                     [m]

whose bottom pole (0, 0) touches the flat z = 0 and whose centre is (0, R). Boundaries: the axis
r = 0 and the curved surface (every surface point may touch the flat; a solver restricts the
candidates to the refined zone). No face is held: the sphere is free, its mass the whole
sphere's, (4/3) pi R^3 rho.

Elements and size: those of meshes.hemisphere (6-node triangles with their mid-side nodes on
the circle; h(r, z) = min(far_size, contact_size + growth d(r, z)), uniformly fine inside the
quarter ellipse of semi-axes refined_radius, refined_depth about the bottom pole), so the lower
half is meshed as the hemisphere is and the upper half at far_size. The spec has the
hemisphere's fields and ranges; its cache key adds the domain, so a sphere and a hemisphere of
the same sizes are two files (``sphere-<key>.msh`` beside ``hemisphere-<key>.msh``).
"""
from __future__ import annotations

from dataclasses import asdict, dataclass
from pathlib import Path

import numpy as np

from meshes.hemisphere import (GENERATOR_VERSION, HemisphereMeshSpec, SectionMesh, SectionMeshSpec, cache_path,
                               cached_mesh, estimate_dofs, identify_boundaries, mesh_section,
                               read_quadratic_triangles)
from meshes.keys import stable_key


@dataclass(frozen=True)
class SphereMeshSpec(SectionMeshSpec):
    """Sizes of the sphere mesh [m] (meshes.hemisphere.SectionMeshSpec states each field and its
    range, and validates them)."""

    @classmethod
    def from_hemisphere(cls, spec: HemisphereMeshSpec) -> "SphereMeshSpec":
        """The sphere meshed with the sizes of a hemisphere spec (its lower half is that mesh's section)."""
        return cls(**asdict(spec))

    @property
    def contact_zone(self) -> HemisphereMeshSpec:
        """The hemisphere spec of the same sizes (the lower half of this mesh)."""
        return HemisphereMeshSpec(**asdict(self))

    def estimate_dofs(self) -> int:
        """Degrees of freedom without meshing: the hemisphere's estimate plus the upper half at
        far_size (P2: about 2 nodes, 4 dofs per triangle of area sqrt(3)/4 far_size^2)."""
        upper = np.pi * self.radius ** 2 / 2 / (np.sqrt(3) / 4 * self.far_size ** 2)
        return int(estimate_dofs(self.contact_zone) + 4 * upper)

    def cache_key(self) -> str:
        """The mesh cache's key: a hash of the spec, the generator version and the domain."""
        return stable_key({"spec": self.key_fields(), "generator": GENERATOR_VERSION, "domain": "sphere"})

    def describe(self) -> dict:
        """A JSON-able description (for result stamps)."""
        return {**asdict(self), "domain": "whole sphere (half disc r-z section)",
                "element": "P2 triangle (6-node, isoparametric)", "key": self.cache_key()}


@dataclass(frozen=True)
class SphereMesh(SectionMesh):
    """A loaded sphere mesh; ``boundaries``: 'axis', 'surface'."""

    HEIGHT = 2.0


def mesh_path(spec: SphereMeshSpec, cache_dir=None) -> Path:
    """Where the .msh file of ``spec`` is cached (the user's mesh cache by default)."""
    return cache_path(spec, "sphere", cache_dir)


def build_msh(spec: SphereMeshSpec, path) -> Path:
    """Mesh the half disc with gmsh and write ``path`` (.msh 4.1), atomically."""

    def half_disc(geo):
        bottom = geo.addPoint(0.0, 0.0, 0.0)
        centre = geo.addPoint(0.0, 1.0, 0.0)
        top = geo.addPoint(0.0, 2.0, 0.0)
        equator = geo.addPoint(1.0, 1.0, 0.0)
        axis = geo.addLine(bottom, top)
        upper = geo.addCircleArc(top, centre, equator)          # each arc below pi
        lower = geo.addCircleArc(equator, centre, bottom)
        loop = geo.addCurveLoop([axis, upper, lower])
        body = geo.addPlaneSurface([loop])
        return (("axis", 1, [axis]), ("surface", 1, [upper, lower]), ("body", 2, [body]))

    return mesh_section(spec, path, "sphere", half_disc)


def load_msh(path, spec: SphereMeshSpec | None = None) -> SphereMesh:
    """Read a sphere .msh (FileNotFoundError if missing, ValueError if it is not this section)."""
    mesh = read_quadratic_triangles(path)
    radius = spec.radius if spec is not None else float(mesh.p[1].max()) / SphereMesh.HEIGHT
    return SphereMesh(spec=spec, path=Path(path), mesh=mesh, boundaries=identify_boundaries(mesh, radius, top=False))


def sphere_mesh(spec: SphereMeshSpec | None = None, cache_dir=None, rebuild: bool = False) -> SphereMesh:
    """The mesh of ``spec`` (default ``SphereMeshSpec()``), from the cache or freshly built
    (meshes.hemisphere.cached_mesh)."""
    spec = spec if spec is not None else SphereMeshSpec()
    return cached_mesh(mesh_path(spec, cache_dir), lambda path: build_msh(spec, path),
                       lambda path: load_msh(path, spec), rebuild)
