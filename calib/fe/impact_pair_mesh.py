"""The two bodies of a pair impact as one r-z mesh: the whole sphere over a whole counter-sphere or a block.

Body 1 is the whole sphere of meshes.sphere (bottom pole at the origin, centre (0, R1)); body 2,
below the plane z = 0, touches it at the origin:

* a counter-sphere of radius R2: the whole-sphere section of meshes.sphere mirrored, z -> -z,

      {(r, z): r >= 0, r^2 + (z + R2)^2 <= R2^2}                                  [m]

  (boundaries: axis r = 0, surface); free, like the sphere;
* a flat: the block section [0, L] x [-L, 0] of meshes.counter_body (a cylinder of radius and
  height L), its far face z = -L held (u_z = 0), its side r = L free.

Both are meshed by gmsh with the graded size field of meshes.hemisphere refined about the
origin, and joined into one scikit-fem MeshTri2 of two disconnected components (one P2 basis,
one sparse pattern), each element carrying its body's index (0 the sphere, 1 the counter-body).
Boundaries are identified geometrically (tolerance 1e-9 of the body's size). The contact sides
are body 1's lower half surface (z < R1) and body 2's upper half (z > -R2) or the block's top
face z = 0: along each, r grows monotonically, as calib.fe.contact_pair requires.
"""
from __future__ import annotations

import time
from dataclasses import dataclass, field

import numpy as np
from skfem import MeshTri2

from meshes.counter_body import BlockMeshSpec, block_mesh, six_node_cells
from meshes.sphere import SphereMeshSpec, sphere_mesh


@dataclass(frozen=True)
class ImpactPairMesh:
    """Two free bodies, or a sphere over a held block, in one MeshTri2 (module docstring).

    mesh: skfem.MeshTri2 (x[0] = r, x[1] = z [m]); body: the body index of every element;
    boundaries: per body, facet indices of 'axis', 'contact' (the side facing the other body),
    'other' (the rest of the free surface) and, for a block, 'held' (the far face z = -L);
    R1, R2 [m] (R2 = inf for a block); block_size: L [m] (None for a counter-sphere); specs: the
    two mesh specs (for result stamps).
    """

    mesh: object
    body: np.ndarray = field(repr=False)
    boundaries: tuple = field(repr=False)
    R1: float
    R2: float
    block_size: float | None
    specs: tuple = field(repr=False)
    build_time_s: float = 0.0

    @property
    def is_block(self) -> bool:
        return self.block_size is not None

    def describe(self) -> dict:
        return {"sphere": self.specs[0].describe(), "counter": self.specs[1].describe(),
                "counter_body": "flat block, far face held" if self.is_block else "free sphere",
                "elements": int(self.mesh.nelements), "nodes": int(self.mesh.doflocs.shape[1])}


def impact_pair_mesh(sphere: SphereMeshSpec, counter, cache_dir=None) -> ImpactPairMesh:
    """The sphere ``sphere`` over ``counter``: a SphereMeshSpec (a free counter-sphere of its
    radius) or a BlockMeshSpec (a block of size L = its radius, far face held)."""
    t0 = time.perf_counter()
    m1 = sphere_mesh(sphere, cache_dir).mesh
    p1, c1 = m1.doflocs, six_node_cells(m1)
    if isinstance(counter, BlockMeshSpec):
        m2 = block_mesh(counter, cache_dir)
        p2, c2 = m2.doflocs, six_node_cells(m2)
        R2, L = float("inf"), float(counter.radius)
    elif isinstance(counter, SphereMeshSpec):
        m2 = sphere_mesh(counter, cache_dir).mesh
        # z -> -z reverses the orientation: vertices 1, 2 and edges 01, 20 swap
        p2, c2 = m2.doflocs * np.array([[1.0], [-1.0]]), six_node_cells(m2)[[0, 2, 1, 5, 4, 3]]
        R2, L = float(counter.radius), None
    else:
        raise ValueError(f"counter must be a SphereMeshSpec or a BlockMeshSpec, got {type(counter).__name__}")
    mesh = MeshTri2(np.ascontiguousarray(np.hstack([p1, p2])), np.ascontiguousarray(np.hstack([c1, c2 + p1.shape[1]])))
    body = np.concatenate([np.zeros(c1.shape[1], dtype=int), np.ones(c2.shape[1], dtype=int)])
    R1 = float(sphere.radius)
    boundaries = _boundaries(mesh, body, R1, R2, L)
    return ImpactPairMesh(mesh=mesh, body=body, boundaries=boundaries, R1=R1, R2=R2, block_size=L,
                          specs=(sphere, counter), build_time_s=time.perf_counter() - t0)


def _boundaries(mesh, body, R1: float, R2: float, L: float | None) -> tuple:
    facets = mesh.boundary_facets()
    owner = body[mesh.f2t[0, facets]]
    nodes = np.vstack([mesh.facets[:, facets], mesh.nvertices + facets[None, :]])
    r, z = mesh.doflocs[0][nodes], mesh.doflocs[1][nodes]
    found = []
    for k, size in ((0, R1), (1, L if L is not None else R2)):
        tol = 1e-9 * size
        mine = owner == k
        axis = mine & np.all(r <= tol, axis=0)
        rest = mine & ~axis
        if k == 0:
            contact = rest & np.all(z < R1 + tol, axis=0)
            named = {"axis": facets[axis], "contact": facets[contact], "other": facets[rest & ~contact]}
        elif L is None:
            contact = rest & np.all(z > -R2 - tol, axis=0)
            named = {"axis": facets[axis], "contact": facets[contact], "other": facets[rest & ~contact]}
        else:
            contact = rest & np.all(np.abs(z) <= tol, axis=0)
            held = rest & np.all(np.abs(z + L) <= tol, axis=0)
            side = rest & np.all(np.abs(r - L) <= tol, axis=0)
            if np.any(rest & ~(contact | held | side)):
                raise ValueError("the block's boundary has facets off its faces")
            named = {"axis": facets[axis], "contact": facets[contact], "other": facets[side], "held": facets[held]}
        if named["axis"].size == 0 or named["contact"].size == 0:
            raise ValueError(f"body {k} of the impact pair mesh has no axis or no contact side")
        found.append(named)
    return tuple(found)
