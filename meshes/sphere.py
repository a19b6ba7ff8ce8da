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

import time
from dataclasses import asdict, dataclass, field, fields, replace
from pathlib import Path

import numpy as np

from meshes.hemisphere import (GENERATOR_VERSION, HemisphereMeshSpec, default_cache_dir, estimate_dofs,
                               mesh_section, read_quadratic_triangles)
from meshes.keys import stable_key


@dataclass(frozen=True)
class SphereMeshSpec:
    """Sizes of the sphere mesh [m] (meshes.hemisphere.HemisphereMeshSpec states each field and
    its range; validated by it, with the same messages)."""

    radius: float = 0.1
    contact_size: float = 4.0e-5
    refined_radius: float = 1.6e-3
    refined_depth: float = 0.5e-3
    far_size: float = 1.0e-2
    growth: float = 0.2

    def __post_init__(self):
        checked = HemisphereMeshSpec(**asdict(self))
        for name in (f.name for f in fields(self)):      # numpy scalars become floats there
            object.__setattr__(self, name, getattr(checked, name))

    @classmethod
    def from_hemisphere(cls, spec: HemisphereMeshSpec) -> "SphereMeshSpec":
        """The sphere meshed with the sizes of a hemisphere spec (its lower half is that mesh's section)."""
        return cls(**asdict(spec))

    @property
    def contact_zone(self) -> HemisphereMeshSpec:
        """The hemisphere spec of the same sizes (the lower half of this mesh)."""
        return HemisphereMeshSpec(**asdict(self))

    def size_at(self, r, z):
        """Target element size h(r, z) [m] (meshes.hemisphere)."""
        return self.contact_zone.size_at(r, z)

    def estimate_dofs(self) -> int:
        """Degrees of freedom without meshing: the hemisphere's estimate plus the upper half at
        far_size (P2: about 2 nodes, 4 dofs per triangle of area sqrt(3)/4 far_size^2)."""
        upper = np.pi * self.radius ** 2 / 2 / (np.sqrt(3) / 4 * self.far_size ** 2)
        return int(estimate_dofs(self.contact_zone) + 4 * upper)

    def cache_key(self) -> str:
        """The mesh cache's key: a hash of the spec, the generator version and the domain."""
        return stable_key({"spec": asdict(self), "generator": GENERATOR_VERSION, "domain": "sphere"})

    def describe(self) -> dict:
        """A JSON-able description (for result stamps)."""
        return {**asdict(self), "domain": "whole sphere (half disc r-z section)",
                "element": "P2 triangle (6-node, isoparametric)", "key": self.cache_key()}


@dataclass(frozen=True)
class SphereMesh:
    """A loaded sphere mesh: ``mesh`` (skfem.MeshTri2, x[0] = r, x[1] = z) and ``boundaries``
    ('axis', 'surface': facet indices)."""

    spec: SphereMeshSpec | None
    path: Path | None
    mesh: object
    boundaries: dict = field(repr=False)
    build_time_s: float = 0.0

    @property
    def radius(self) -> float:
        return float(self.mesh.p[1].max()) / 2.0


def mesh_path(spec: SphereMeshSpec, cache_dir=None) -> Path:
    """Where the .msh file of ``spec`` is cached (the user's mesh cache by default)."""
    return (Path(cache_dir) if cache_dir is not None else default_cache_dir()) / f"sphere-{spec.cache_key()}.msh"


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


def identify_boundaries(mesh, radius: float) -> dict:
    """Facets of the axis (r = 0) and of the surface (|x - (0, R)| = R), geometrically (all three
    nodes of a facet on the line or circle, to 1e-9 R)."""
    tol = 1e-9 * radius
    boundary = mesh.boundary_facets()
    nodes = np.vstack([mesh.facets[:, boundary], mesh.dofs.facet_dofs[0, boundary][None, :]])
    r, z = mesh.doflocs[0][nodes], mesh.doflocs[1][nodes]
    on_axis = np.all(np.abs(r) <= tol, axis=0)
    on_circle = np.all(np.abs(np.hypot(r, z - radius) - radius) <= tol, axis=0) & ~on_axis
    found = {"axis": boundary[on_axis], "surface": boundary[on_circle]}
    unassigned = boundary.size - sum(v.size for v in found.values())
    if unassigned or any(v.size == 0 for v in found.values()):
        raise ValueError(f"mesh is not the sphere section of radius {radius}: {unassigned} boundary facets off the "
                         f"axis/surface, counts {{{', '.join(f'{k}: {v.size}' for k, v in found.items())}}}")
    return found


def load_msh(path, spec: SphereMeshSpec | None = None) -> SphereMesh:
    """Read a sphere .msh (FileNotFoundError if missing, ValueError if it is not this section)."""
    mesh = read_quadratic_triangles(path)
    radius = spec.radius if spec is not None else float(mesh.p[1].max()) / 2.0
    return SphereMesh(spec=spec, path=Path(path), mesh=mesh, boundaries=identify_boundaries(mesh, radius))


def sphere_mesh(spec: SphereMeshSpec | None = None, cache_dir=None, rebuild: bool = False) -> SphereMesh:
    """The mesh of ``spec`` (default ``SphereMeshSpec()``), from the cache or freshly built (a
    corrupt cached file is rebuilt); ``build_time_s``: time spent meshing and loading [s]."""
    spec = spec if spec is not None else SphereMeshSpec()
    started = time.perf_counter()
    path = mesh_path(spec, cache_dir)
    if path.is_file() and not rebuild:
        try:
            return replace(load_msh(path, spec), build_time_s=time.perf_counter() - started)
        except ValueError:
            pass                        # corrupt cache entry: rebuilt below
    build_msh(spec, path)
    return replace(load_msh(path, spec), build_time_s=time.perf_counter() - started)
