"""The counter-body below the sphere, and the two r-z sections as one mesh of two bodies.

Body 1 is the hemisphere of meshes.hemisphere, pole at (0, 0), equatorial face z = R1. Body 2,
the counter-body, lies below the plane z = 0 and touches body 1 at the origin:

* a sphere of radius R2: the hemisphere section of radius R2 mirrored, z -> -z,

      {(r, z): r >= 0, -R2 <= z <= 0, r^2 + (z + R2)^2 <= R2^2}                  [m]

  (boundaries: axis r = 0, bottom face z = -R2, curved surface);
* a flat block: the cylinder of radius L and height L,

      {(r, z): 0 <= r <= L, -L <= z <= 0}                                        [m]

  (boundaries: axis r = 0, bottom face z = -L, side r = L, top face z = 0, candidate for
  contact). L is chosen large against the contact (a domain-size study shows where it stops
  mattering: tests/test_two_body.py and the report of calib.fe.two_body).

Both are meshed by meshes.hemisphere.mesh_section with the same graded size field
(HemisphereMeshSpec.size_at, refined around the origin: distance to the plane z = 0 enters
through |z|), 6-node isoparametric triangles, and cached under a hash of the spec.

``pair_mesh`` joins two sections into one scikit-fem MeshTri2 with two disconnected components,
so one P2 basis, one set of element arrays and one sparse pattern serve both bodies; every
element carries the index of its body (0: the sphere, 1: the counter-body) and the boundaries
are identified geometrically per body (exact for these domains, tolerance 1e-9 of the size).
"""
from __future__ import annotations

import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
from skfem import MeshTri2

from meshes.hemisphere import (HemisphereMeshSpec, default_cache_dir, hemisphere_mesh, mesh_section,
                               read_quadratic_triangles)
from meshes.keys import stable_key

BLOCK_GENERATOR_VERSION = 1  # bump when the block's meshing recipe changes: invalidates the cache


@dataclass(frozen=True)
class BlockMeshSpec(HemisphereMeshSpec):
    """The flat block's mesh: the fields of HemisphereMeshSpec [m] with ``radius`` = L, the block's
    radius and height (the size field is refined around the contact at the origin)."""

    EXTENT_OVER_R = float(np.sqrt(2.0))   # the far corner (L, L) of the section, |z| up

    def cache_key(self) -> str:
        return stable_key({"spec": self.key_fields(), "generator": BLOCK_GENERATOR_VERSION, "body": "block"})

    def contains(self, r, z):
        """True where (r, |z|) [m] lies in the block section [0, L] x [0, L]."""
        return (r <= self.radius) & (z <= self.radius)

    def describe(self) -> dict:
        return {**super().describe(), "body": "flat block (cylinder of radius and height L = radius)",
                "key": self.cache_key()}


def block_mesh(spec: BlockMeshSpec, cache_dir=None, rebuild: bool = False):
    """The block section [0, L] x [-L, 0] as a MeshTri2 (cached like the hemisphere's)."""

    def square(geo):
        corner = geo.addPoint(0.0, 0.0, 0.0)
        edge = geo.addPoint(1.0, 0.0, 0.0)
        foot = geo.addPoint(1.0, -1.0, 0.0)
        base = geo.addPoint(0.0, -1.0, 0.0)
        top = geo.addLine(corner, edge)
        side = geo.addLine(edge, foot)
        bottom = geo.addLine(foot, base)
        axis = geo.addLine(base, corner)
        body = geo.addPlaneSurface([geo.addCurveLoop([top, side, bottom, axis])])
        return (("top", 1, [top]), ("side", 1, [side]), ("bottom", 1, [bottom]), ("axis", 1, [axis]),
                ("body", 2, [body]))

    path = block_path(spec, cache_dir)
    if path.is_file() and not rebuild:
        try:
            return read_quadratic_triangles(path)
        except ValueError:
            pass  # corrupt cache entry: rebuild
    mesh_section(spec, path, "block", square)
    return read_quadratic_triangles(path)


def block_path(spec: BlockMeshSpec, cache_dir=None) -> Path:
    """Where the .msh file of the block ``spec`` is cached."""
    return (Path(cache_dir) if cache_dir is not None else default_cache_dir()) / f"block-{spec.cache_key()}.msh"


def six_node_cells(mesh) -> np.ndarray:
    """(6, n_elements) node indices of a MeshTri2 in gmsh's order (vertices, edges 01, 12, 20),
    nodes numbered as ``mesh.doflocs`` (vertices, then one node per facet)."""
    return np.vstack([mesh.t, mesh.nvertices + mesh.t2f])


@dataclass(frozen=True)
class PairMesh:
    """Two bodies in one MeshTri2 (module docstring).

    mesh          skfem.MeshTri2, x[0] = r, x[1] = z [m]
    body          body index of every element (0 upper body, the sphere; 1 the counter-body)
    boundaries    per body, facet indices: 'axis', 'surface' (the contact side), the far face
                  ('top' for body 0, 'bottom' for body 1) and 'side' for a block
    R1, R2        the bodies' radii of curvature at the contact [m] (inf for a block)
    block_sizes   L [m] of each body that is a block (None for a sphere)
    specs         the two mesh specs (for result stamps)
    """

    mesh: object
    body: np.ndarray = field(repr=False)
    boundaries: tuple = field(repr=False)
    R1: float
    R2: float
    block_sizes: tuple
    specs: tuple = field(repr=False)
    build_time_s: float = 0.0

    @property
    def block_size(self) -> float | None:
        """L [m] of a block counter-body (None for a counter-sphere)."""
        return self.block_sizes[1]

    @property
    def smallest_size(self) -> float:
        """The smallest radius or block size of the two bodies [m]."""
        return min(x for x in (self.R1, self.R2, *self.block_sizes) if x is not None)

    def describe(self) -> dict:
        return {"sphere": self.specs[0].describe(), "counter": self.specs[1].describe(),
                "counter_body": "flat block" if self.block_size is not None else "sphere",
                "elements": int(self.mesh.nelements), "nodes": int(self.mesh.doflocs.shape[1])}


def _section(spec, sign: float, cache_dir):
    """(points, 6-node cells, R, L) of one body: a hemisphere or a block, z scaled by ``sign``
    (+1: above the plane z = 0, pole or face at the origin; -1: below)."""
    if isinstance(spec, BlockMeshSpec):
        mesh, R, L = block_mesh(spec, cache_dir), float("inf"), float(spec.radius)
        flip = sign > 0                     # the block is meshed below z = 0
    else:
        mesh, R, L = hemisphere_mesh(spec, cache_dir).mesh, float(spec.radius), None
        flip = sign < 0                     # the hemisphere is meshed above z = 0
    points, cells = mesh.doflocs, six_node_cells(mesh)
    if flip:    # z -> -z reverses the orientation, so vertices 1, 2 and edges 01, 20 swap
        points, cells = points * np.array([[1.0], [-1.0]]), cells[[0, 2, 1, 5, 4, 3]]
    return points, cells, R, L


def pair_mesh(sphere: HemisphereMeshSpec, counter: HemisphereMeshSpec, cache_dir=None) -> PairMesh:
    """Body 1 over body 2: each a HemisphereMeshSpec (a sphere of that radius) or a BlockMeshSpec (a
    flat block of size L = its radius; body 1 a block only for the contact patch test)."""
    t0 = time.perf_counter()
    p1, c1, R1, L1 = _section(sphere, +1.0, cache_dir)
    p2, c2, R2, L2 = _section(counter, -1.0, cache_dir)
    points = np.hstack([p1, p2])
    cells = np.hstack([c1, c2 + p1.shape[1]])
    mesh = MeshTri2(np.ascontiguousarray(points), np.ascontiguousarray(cells))
    body = np.concatenate([np.zeros(c1.shape[1], dtype=int), np.ones(c2.shape[1], dtype=int)])
    boundaries = identify_pair_boundaries(mesh, body, (R1, R2), (L1, L2))
    return PairMesh(mesh=mesh, body=body, boundaries=boundaries, R1=R1, R2=R2, block_sizes=(L1, L2),
                    specs=(sphere, counter), build_time_s=time.perf_counter() - t0)


def identify_pair_boundaries(mesh, body, radii: tuple, blocks: tuple) -> tuple:
    """Per body, the boundary facets of each named boundary (see PairMesh); ValueError when a
    boundary facet fits none (not the sections this module builds)."""
    boundary = mesh.boundary_facets()
    owner = body[mesh.f2t[0, boundary]]
    nodes = np.vstack([mesh.facets[:, boundary], mesh.nvertices + boundary[None, :]])
    r, z = mesh.doflocs[0][nodes], mesh.doflocs[1][nodes]
    found = []
    for k, (sign, far_name) in enumerate(((1.0, "top"), (-1.0, "bottom"))):
        R, L = radii[k], blocks[k]
        tol = 1e-9 * (L if L is not None else R)
        axis = np.all(np.abs(r) <= tol, axis=0)
        if L is None:
            far = np.all(np.abs(z - sign * R) <= tol, axis=0)
            tests = {far_name: far, "surface": np.all(np.abs(np.hypot(r, z - sign * R) - R) <= tol, axis=0) & ~far}
        else:
            tests = {far_name: np.all(np.abs(z - sign * L) <= tol, axis=0),
                     "side": np.all(np.abs(r - L) <= tol, axis=0), "surface": np.all(np.abs(z) <= tol, axis=0)}
        mine = owner == k
        named = {"axis": boundary[mine & axis], **{name: boundary[mine & test & ~axis] for name, test in tests.items()}}
        count = sum(v.size for v in named.values())
        if count != mine.sum() or any(v.size == 0 for v in named.values()):
            raise ValueError(f"body {k} of the pair mesh has {mine.sum() - count} boundary facets off its named "
                             f"boundaries, counts {{{', '.join(f'{n}: {v.size}' for n, v in named.items())}}}")
        found.append(named)
    return tuple(found)
