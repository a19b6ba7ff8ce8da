"""The r-z section of the hemisphere pressed on the rigid flat, meshed by gmsh and cached.

Domain (Vu-Quoc & Zhang 1999, section 2): the quarter disc

    {(r, z): r >= 0, 0 <= z <= R, r^2 + (z - R)^2 <= R^2}        [m]

whose pole (0, 0) touches the flat z = 0. Boundaries: the axis r = 0, the top (equatorial) face
z = R that the rigid plate drives, and the curved surface, candidate for contact.

Elements: 6-node (quadratic, isoparametric) triangles, the paper's CAX6. The mid-side nodes of the
curved surface lie on the circle, so the initial gap of every surface node is exact
(z0 = R - sqrt(R^2 - r^2)) and the quarter-disc area pi R^2 / 4 is reproduced to O(h^4).

Mesh size (a gmsh size callback, evaluated by gmsh wherever it needs a size):

    h(r, z) = min(far_size, max(contact_size, grading * sqrt(r^2 + z^2)) + growth * d(r, z))
    d(r, z) = refined_depth * max(0, sqrt((r / refined_radius)^2 + (z / refined_depth)^2) - 1)

i.e. ``contact_size`` inside the quarter ellipse of semi-axes refined_radius (along the surface,
beyond the largest contact radius) and refined_depth (into the body, where the Hertz and plastic
zones live), then growing linearly with slope ``growth`` up to ``far_size``. With ``grading`` > 0
the element grows with the distance from the pole, h = grading x distance beyond contact_size:
a contact of any radius a >= contact_size / grading spans the same a / h = 1 / grading elements,
so load paths log-spaced over decades of load are resolved alike (grading 0: uniform).

The .msh file is cached under a hash of the spec (and of the generator version): a second
request reuses it, a corrupt file is rebuilt.

Loading: scikit-fem's meshio import drops gmsh's quadratic line groups ('line3' has no mapping in
skfem.io.meshio), so the boundaries are identified geometrically (r = 0, z = R, on the circle),
which is exact for this domain and independent of the file format.
"""
from __future__ import annotations

import contextlib
import dataclasses
import functools
import os
import signal
import tempfile
import threading
import time
from dataclasses import asdict, dataclass, field, replace
from pathlib import Path
from typing import ClassVar

import meshio
import numpy as np
from platformdirs import user_cache_dir
from skfem import MeshTri2

from calib.output import new_file_mode
from meshes.keys import stable_key

GENERATOR_VERSION = 2  # bump when the meshing recipe changes: invalidates the cache
_GMSH_LOCK = threading.Lock()  # gmsh is a process-wide singleton and not thread-safe


MIN_CONTACT_SIZE_OVER_RADIUS = 1e-6   # smallest contact element / sphere radius


@dataclass(frozen=True)
class SectionMeshSpec:
    """Sizes of an r-z section's mesh [m] (the hemisphere's here, the whole sphere's in
    meshes.sphere); validated on construction.

    radius          R, sphere radius
    contact_size    element size in the refined zone (the paper: 2.3e-5 m)
    refined_radius  the refined zone extends this far along the surface (> largest contact radius)
    refined_depth   ... and this deep under the contact (Hertz / plastic zone, a few contact radii)
    far_size        largest element size (far field)
    growth          slope of the size growth outside the refined zone (dimensionless)
    grading         h / distance from the pole where that exceeds contact_size (dimensionless,
                    in [0, 1); 0: a uniform refined zone)
    """

    radius: float = 0.1
    contact_size: float = 4.0e-5
    refined_radius: float = 1.6e-3
    refined_depth: float = 0.5e-3
    far_size: float = 1.0e-2
    growth: float = 0.2
    grading: float = 0.0

    def __post_init__(self):
        for name in ("radius", "contact_size", "refined_radius", "refined_depth", "far_size",
                     "growth"):
            value = getattr(self, name)
            if isinstance(value, np.number) and not isinstance(value, (bool, np.bool_)):
                # numpy scalars (float32 from arrays) become floats; Python numbers stay as given
                # so that the cache key of existing specs is unchanged
                value = float(value)
                object.__setattr__(self, name, value)
            if not (isinstance(value, (int, float)) and not isinstance(value, bool)
                    and np.isfinite(value) and value > 0):
                unit = "" if name == "growth" else " [m]"
                raise ValueError(f"{name} must be a finite number > 0{unit}, got {value!r}")
        grading = self.grading
        if isinstance(grading, np.number):
            grading = float(grading)
            object.__setattr__(self, "grading", grading)
        if not (isinstance(grading, (int, float)) and not isinstance(grading, bool) and 0.0 <= grading < 1.0):
            raise ValueError(f"grading must be a number in [0, 1), got {grading!r}")
        R = self.radius
        if not self.refined_radius < R:
            raise ValueError(f"refined_radius must be in (0, radius={R}), got {self.refined_radius}")
        if not self.refined_depth < R:
            raise ValueError(f"refined_depth must be in (0, radius={R}), got {self.refined_depth}")
        # below 1e-6 R no machine holds the mesh (and the dof estimate's quadrature, which
        # starts at 1e-7 R, would be meaningless): refused here, the memory check never sees it
        smallest = MIN_CONTACT_SIZE_OVER_RADIUS * R
        if not self.contact_size >= smallest:
            raise ValueError(f"contact_size out of range: need contact_size >= {smallest:g} m (1e-6 x the radius; "
                             f"a finer contact element would need ~1e9 dofs), got {self.contact_size:g}")
        if not self.contact_size <= min(self.refined_radius, self.refined_depth) / 2:
            raise ValueError("contact_size must be in [1e-6 radius, min(refined_radius, refined_depth)/2]"
                             f" = [{smallest:g}, {min(self.refined_radius, self.refined_depth) / 2:g}] m,"
                             f" got {self.contact_size:g}")
        if not self.contact_size <= self.far_size <= R:
            raise ValueError(f"far_size must be in [contact_size={self.contact_size}, radius={R}],"
                             f" got {self.far_size}")
        if not self.growth <= 1.0:
            raise ValueError(f"growth must be in (0, 1], got {self.growth}")

    def key_fields(self) -> dict:
        """The fields a cache key hashes: all of them, grading only when > 0 (so a uniform mesh's key
        does not depend on the field, and cached meshes stay valid)."""
        fields = asdict(self)
        if not fields["grading"]:
            del fields["grading"]
        return fields

    def size_at(self, r, z):
        """Target element size h(r, z) [m] (module docstring)."""
        rho = np.sqrt((np.asarray(r) / self.refined_radius) ** 2
                      + (np.asarray(z) / self.refined_depth) ** 2)
        distance_outside = self.refined_depth * np.maximum(rho - 1.0, 0.0)
        inner = (self.contact_size if not self.grading
                 else np.maximum(self.contact_size, self.grading * np.hypot(np.asarray(r), np.asarray(z))))
        return np.minimum(self.far_size, inner + self.growth * distance_outside)



@dataclass(frozen=True)
class HemisphereMeshSpec(SectionMeshSpec):
    """Parameters of the hemisphere mesh [m] (SectionMeshSpec: the fields and their ranges)."""

    def cache_key(self) -> str:
        """The mesh cache's key: a hash of the spec (floats to 12 digits, meshes.keys)."""
        return stable_key({"spec": self.key_fields(), "generator": GENERATOR_VERSION})

    def describe(self) -> dict:
        """A JSON-able description (for result stamps)."""
        return {**asdict(self), "element": "P2 triangle (6-node, isoparametric)",
                "key": self.cache_key()}

    # the section in the (r, |z|) quarter plane, for estimate_dofs: farthest point from the origin
    # over R, and the membership test
    EXTENT_OVER_R: ClassVar[float] = 1.0

    def contains(self, r, z):
        """True where (r, z) [m] lies in the hemisphere section r^2 + (z - R)^2 <= R^2."""
        return r**2 + (z - self.radius) ** 2 <= self.radius**2


@dataclass(frozen=True)
class SectionMesh:
    """A loaded r-z section mesh: the scikit-fem mesh and its boundaries.

    ``mesh`` is a ``skfem.MeshTri2`` (curved isoparametric 6-node triangles; x[0] = r, x[1] = z).
    ``boundaries`` maps the section's boundary names to facet indices of ``mesh``; HEIGHT: the
    section's height over R (its largest z is HEIGHT R).
    """

    HEIGHT: ClassVar[float] = 1.0
    spec: SectionMeshSpec | None
    path: Path | None
    mesh: object
    boundaries: dict = field(repr=False)
    build_time_s: float = 0.0

    @property
    def radius(self) -> float:
        return float(self.mesh.p[1].max()) / self.HEIGHT


@dataclass(frozen=True)
class HemisphereMesh(SectionMesh):
    """A loaded hemisphere mesh; ``boundaries``: 'axis', 'top', 'surface'."""


def _element_integral(spec: HemisphereMeshSpec) -> float:
    """Integral over the section of 1 / (area of an equilateral triangle of size h(r, z)): the
    number of elements a mesher filling the section at size h would make, up to a constant."""
    R = spec.radius
    # polar-like quadrature refined towards the pole, where h is smallest
    s = np.geomspace(1e-7, 1.0, 400) * R * spec.EXTENT_OVER_R  # distance from the pole [m]
    theta = np.linspace(0, np.pi / 2, 60)
    S, T = np.meshgrid(s, theta, indexing="ij")
    r, z = S * np.cos(T), S * np.sin(T)
    inside = spec.contains(r, z)
    h = spec.size_at(r, z)
    density = np.where(inside, 1.0 / (np.sqrt(3) / 4 * h**2), 0.0) * S  # Jacobian s
    return float(np.trapezoid(np.trapezoid(density, theta, axis=1), s))


@functools.cache
def _dofs_per_element_integral() -> float:
    """Calibrated once on the reference default mesh: 12,112 dofs (2,939 P2 triangles)."""
    return 12112.0 / _element_integral(HemisphereMeshSpec())


def estimate_dofs(spec: HemisphereMeshSpec) -> int:
    """Degrees of freedom of the P2 mesh of ``spec`` without meshing (within ~10 % on the meshes
    of the reference ladder): the element integral, scaled by the reference default mesh."""
    return int(_element_integral(spec) * _dofs_per_element_integral())


def default_cache_dir() -> Path:
    """The user's cache folder for meshes: ``$XDG_CACHE_HOME/nfdcal/meshes`` on Linux (platformdirs'
    ``user_cache_dir``), never a folder next to the installed package."""

    return Path(user_cache_dir("nfdcal", appauthor=False)) / "meshes"


def cache_path(spec, name: str, cache_dir=None) -> Path:
    """Where the .msh file of the section ``name`` of ``spec`` is cached (the user's mesh cache by
    default): ``<name>-<key>.msh``."""
    return (Path(cache_dir) if cache_dir is not None else default_cache_dir()) / f"{name}-{spec.cache_key()}.msh"


def mesh_path(spec: HemisphereMeshSpec, cache_dir=None) -> Path:
    """Where the .msh file of ``spec`` is cached."""
    return cache_path(spec, "hemisphere", cache_dir)


def build_msh(spec: HemisphereMeshSpec, path: str | os.PathLike) -> Path:
    """Mesh the hemisphere section with gmsh and write ``path`` (.msh 4.1), atomically."""

    def quarter_disc(geo):
        pole = geo.addPoint(0.0, 0.0, 0.0)
        centre = geo.addPoint(0.0, 1.0, 0.0)
        equator = geo.addPoint(1.0, 1.0, 0.0)
        axis = geo.addLine(pole, centre)
        top = geo.addLine(centre, equator)
        surface = geo.addCircleArc(equator, centre, pole)
        loop = geo.addCurveLoop([axis, top, surface])
        body = geo.addPlaneSurface([loop])
        return (("axis", 1, [axis]), ("top", 1, [top]), ("surface", 1, [surface]), ("body", 2, [body]))

    return mesh_section(spec, path, "hemisphere", quarter_disc)


def mesh_section(spec, path: str | os.PathLike, name: str, geometry) -> Path:
    """Mesh an r-z section with gmsh at the size ``spec.size_at`` and write ``path`` (.msh 4.1),
    atomically. ``geometry(geo)`` adds the section in units of R to gmsh's built-in kernel ``geo``
    and returns its physical groups as (name, dim, tags); ``spec`` has the fields of
    HemisphereMeshSpec."""
    import gmsh  # here, not at the top: loading gmsh takes ~0.3 s and reading a cached mesh needs none

    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    # Mesh in units of R and scale the result: gmsh's tolerances are absolute, so meshing a
    # 1 um sphere in metres gives a (slightly) different mesh than a 10 m one. In units of R
    # every sphere of the same dimensionless spec gets the same mesh, up to a similarity.
    R = spec.radius
    unit = dataclasses.replace(spec, radius=1.0, contact_size=spec.contact_size / R,
                               refined_radius=spec.refined_radius / R,
                               refined_depth=spec.refined_depth / R, far_size=spec.far_size / R)
    with _GMSH_LOCK, _signals_after_gmsh():
        gmsh.initialize(readConfigFiles=False, interruptible=False)
        _signals_after_gmsh.take_back()
        try:
            gmsh.option.setNumber("General.Terminal", 0)
            gmsh.model.add(name)
            geo = gmsh.model.geo
            groups = geometry(geo)
            geo.synchronize()
            for group, dim, tags in groups:
                gmsh.model.addPhysicalGroup(dim, tags, name=group)
            # The size comes from the callback only (no size from points, boundary or curvature).
            for option in ("Mesh.MeshSizeFromPoints", "Mesh.MeshSizeFromCurvature",
                           "Mesh.MeshSizeExtendFromBoundary"):
                gmsh.option.setNumber(option, 0)
            gmsh.option.setNumber("Mesh.MeshSizeMin", unit.contact_size)
            gmsh.option.setNumber("Mesh.MeshSizeMax", unit.far_size)
            gmsh.model.mesh.setSizeCallback(    # interrupted: the coarsest size, to finish at once
                lambda dim, tag, x, y, z, lc: unit.far_size if _signals_after_gmsh._received else
                float(unit.size_at(x, y)))
            gmsh.option.setNumber("Mesh.Algorithm", 6)  # Frontal-Delaunay: well-shaped triangles
            gmsh.option.setNumber("Mesh.ElementOrder", 2)
            gmsh.option.setNumber("Mesh.SecondOrderLinear", 0)  # mid-side nodes on the circle
            gmsh.option.setNumber("Mesh.MshFileVersion", 4.1)
            gmsh.model.mesh.generate(2)
            if _signals_after_gmsh._received:
                return path                     # not written: the signal is raised again on leaving
            gmsh.model.mesh.affineTransform([R, 0, 0, 0, 0, R, 0, 0, 0, 0, R, 0])
            fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.stem}.", suffix=".msh")
            os.close(fd)
            try:
                gmsh.write(tmp)
                os.chmod(tmp, new_file_mode())  # mkstemp makes 0600: follow the user's umask
                os.replace(tmp, path)
            except BaseException:
                Path(tmp).unlink(missing_ok=True)
                raise
        finally:
            gmsh.finalize()
    return path


class _signals_after_gmsh(contextlib.ContextDecorator):
    """Ctrl-C and SIGTERM while gmsh meshes take effect once it is done: the library installs its
    own C handlers at initialize (SIGTERM then ends the process silently, and gmsh's own
    "interruptible" sets SIGINT to the default action), and a Python exception inside its size
    callback would be swallowed. Here a signal is recorded while gmsh runs (the size callback then
    answers the coarsest size, so gmsh finishes at once, and build_msh writes nothing), the
    process's handlers are put back after it, and the signal is raised again (nfdcal:
    "interrupted", exit 130; the default action where no handler was set). Main thread only
    (where handlers live)."""

    SIGNALS = (signal.SIGINT, signal.SIGTERM)
    _received: list = []

    def __enter__(self):
        self.active = threading.current_thread() is threading.main_thread()
        if self.active:
            type(self)._received = []
            self.previous = {sig: signal.signal(sig, self.record) for sig in self.SIGNALS}
        return self

    @staticmethod
    def record(signum, frame):
        _signals_after_gmsh._received.append(signum)

    @classmethod
    def take_back(cls):
        """After gmsh.initialize: the recording handlers again (gmsh replaced them in C)."""
        if threading.current_thread() is threading.main_thread():
            for sig in cls.SIGNALS:
                signal.signal(sig, cls.record)

    def __exit__(self, *exc):
        if self.active:
            for sig, handler in self.previous.items():
                if handler is not None:         # None: a handler not set from Python, left as it is
                    signal.signal(sig, handler)
            for sig in dict.fromkeys(type(self)._received):
                signal.raise_signal(sig)
        return False


def load_msh(path: str | os.PathLike, spec: HemisphereMeshSpec | None = None,
             radius: float | None = None) -> HemisphereMesh:
    """Read a hemisphere .msh into scikit-fem (MeshTri2) and identify its boundaries.

    The radius comes from ``spec`` or ``radius``, else from the mesh (max z). Raises
    FileNotFoundError for a missing file and ValueError for a file that is not a valid
    hemisphere mesh.
    """

    path = Path(path)
    mesh = read_quadratic_triangles(path)
    if radius is None:
        radius = spec.radius if spec is not None else float(mesh.p[1].max())
    boundaries = identify_boundaries(mesh, radius)
    return HemisphereMesh(spec=spec, path=path, mesh=mesh, boundaries=boundaries)


def read_quadratic_triangles(path: str | os.PathLike):
    """The 6-node triangles of a gmsh .msh file as a scikit-fem ``MeshTri2`` (counter-clockwise).

    Raises FileNotFoundError for a missing file and ValueError for a file that holds no readable
    quadratic triangle mesh.
    """
    path = Path(path)
    if not path.is_file():
        raise FileNotFoundError(f"mesh file not found: {path}")
    try:
        raw = meshio.read(path, file_format="gmsh")
        if "triangle6" not in raw.cells_dict:
            raise ValueError("no 6-node triangles")
        # Same node order as gmsh's 6-node triangle (vertices, then edges 01, 12, 20); MeshTri2
        # moves the vertices first. Only the triangles are used: boundaries are found below.
        points, cells = raw.points[:, :2], raw.cells_dict["triangle6"]
        # counter-clockwise vertices (positive Jacobian): swap vertices 1, 2 and edges 01, 20
        v0, v1, v2 = (points[cells[:, k]] for k in range(3))
        e1, e2 = v1 - v0, v2 - v0
        clockwise = e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0] < 0
        cells = np.where(clockwise[:, None], cells[:, [0, 2, 1, 5, 4, 3]], cells)
        mesh = MeshTri2(np.ascontiguousarray(points.T), np.ascontiguousarray(cells.T))
    except (Exception, SystemExit) as exc:  # meshio raises many kinds of errors on a corrupt
        # file, and calls sys.exit(1) on an empty one: never let it end the caller's process
        raise ValueError(f"mesh file {path} is not a readable quadratic triangle mesh: {exc}") from exc
    return mesh


def identify_boundaries(mesh, radius: float, top: bool = True) -> dict:
    """Facets of the axis (r = 0), the top face (z = R; the hemisphere's, ``top``) and the curved
    surface (|x - (0, R)| = R).

    Geometric and exact for these domains: a boundary facet's three nodes (two vertices and the
    mid-side node) all lie on the line/circle of its boundary. Tolerance 1e-9 R (round-off of
    the stored coordinates, far below any element size).
    """
    R = float(radius)
    tol = 1e-9 * R
    boundary = mesh.boundary_facets()
    # all three nodes of each boundary facet: vertices from mesh.facets, mid-node from the dofs
    nodes = np.vstack([mesh.facets[:, boundary],
                       mesh.dofs.facet_dofs[0, boundary][None, :]])
    r, z = mesh.doflocs[0][nodes], mesh.doflocs[1][nodes]
    on_axis = np.all(np.abs(r) <= tol, axis=0)
    on_top = np.all(np.abs(z - R) <= tol, axis=0) if top else np.zeros_like(on_axis)
    on_circle = np.all(np.abs(np.hypot(r, z - R) - R) <= tol, axis=0) & ~on_top & ~on_axis
    found = {"axis": boundary[on_axis], "top": boundary[on_top], "surface": boundary[on_circle]}
    if not top:
        del found["top"]
    unassigned = boundary.size - sum(v.size for v in found.values())
    if unassigned or any(v.size == 0 for v in found.values()):
        raise ValueError(f"mesh is not the {'hemisphere' if top else 'sphere'} section of radius {R}: "
                         f"{unassigned} boundary facets off the {'/'.join(found)}, "
                         f"counts {{{', '.join(f'{k}: {v.size}' for k, v in found.items())}}}")
    return found


def cached_mesh(path: Path, build, load, rebuild: bool = False):
    """``load(path)`` of the cached .msh file, or of the one ``build(path)`` writes when there is
    none, when ``rebuild``, or when the cached one cannot be read (corrupt, truncated, wrong
    content); ``build_time_s`` of the result: the time spent meshing and loading [s]."""
    started = time.perf_counter()
    if path.is_file() and not rebuild:
        try:
            return replace(load(path), build_time_s=time.perf_counter() - started)
        except ValueError:
            pass  # corrupt cache entry: rebuilt below
    build(path)
    return replace(load(path), build_time_s=time.perf_counter() - started)


def hemisphere_mesh(spec: HemisphereMeshSpec | None = None, cache_dir=None,
                    rebuild: bool = False) -> HemisphereMesh:
    """The mesh of ``spec`` (default: ``HemisphereMeshSpec()``), from the cache or freshly built
    (``cached_mesh``)."""

    spec = spec if spec is not None else HemisphereMeshSpec()
    return cached_mesh(mesh_path(spec, cache_dir), lambda path: build_msh(spec, path),
                       lambda path: load_msh(path, spec), rebuild)
