"""``nfdcal impact --counter-*``: dynamic FE impacts of the sphere on a deformable counter-body.

Per relative velocity v_in [m/s]: the two-body FE impact (calib.fe.impact_pair_run) gives e (the
relative normal velocity of separation over that of approach), P_max, the contact time, alpha_max
and the energy balance; each beside Hertz's elastic impact of the pair (E*, R*, reduced mass m*;
Johnson 1985, section 11.4), the limit the FE must reach below first yield.

Meshes: the sphere's is calib.studies.impact.impact_mesh's for the same v_in on the pair's contact
(PairImpactSetup.contact_setup: the largest contact radius estimated with the pair's E*, R*, m* and
first yield, nfdmodel.ContactPair; Hertz's P_max below first yield, the vz law of the master
table's dimensionless constants on the pair above it), and its contact element no finer than
1e-6 of the larger body meshed with it (the block or the counter-sphere; a slower impact is refused
naming the smallest v_in, as on the rigid flat); the counter-body's is calib.fit.counter.CounterBody.mesh_spec of it (a sphere of
radius R2, or a block of radius and height L = BLOCK_SIZE_OVER_R R1 with its far face held). The
counter-body's density is its own (CounterBody.rho: a counter-sphere needs it, ``nfdcal impact``
refuses one without --counter-rho), a flat's default the sphere's (the held block is not in m*).

Discretisation error: per velocity the variants of calib.studies.impact (VARIANTS: fine; coarse
mesh, the contact element doubled on both meshes by calib.studies.impact.coarse_mesh; coarse dt,
dt doubled) and its estimate Q_rel_error_estimate = |Q_2h / Q_h - 1| + |Q_2dt / Q_dt - 1| for Q
in COMPARED, with Q_mesh_change and Q_dt_change (the fine values ship, not extrapolated). The
functions below take ``variants`` (default FINE: the fine impact alone, as a scene's impact stage
asks; nfdcal impact passes calib.studies.impact.VARIANTS unless --no-error-estimate).

The runs go through the sweep runner (resumable: OUT/cases/<key>.json); writes impact_pair.csv
and impact_pair.json into OUT. Units: SI.
"""
from __future__ import annotations

import dataclasses
import math
import time
import warnings
from pathlib import Path
from typing import Callable

import numpy as np

from calib import output
from calib.fe.elastic import ElasticMaterial
from calib.fe.impact import ImpactNotConverged
from calib.fe.impact_pair import PairImpactSolver
from calib.fe.impact_pair_mesh import impact_pair_mesh
from calib.fe.impact_pair_run import hertz_pair_impact, run_pair_impact
from calib.fe.von_mises import VonMisesMaterial
from calib.fit.counter import BLOCK_SIZE_OVER_R, CounterBody, check_counter, check_counter_covers
from calib.fit.recipe import estimated_contact_radius
from calib.studies import impact
from calib.sweep.runner import run_sweep
from meshes.counter_body import BlockMeshSpec
from meshes.hemisphere import HemisphereMeshSpec
from meshes.keys import stable_key
from meshes.sphere import SphereMeshSpec
from nfdmodel import ContactPair
from nfdmodel.hertz_contact import hertz_impact_force
from nfdmodel.validation import bound_text

VERSION = 1                      # bump when the pair FE changes: invalidates finished cases
COMPARED = ("e", "P_max", "contact_time", "alpha_max")
FINE = ("fine",)
STUDY_VELOCITIES_OVER_V_Y = (0.5, 2.0, 10.0)    # the default velocities, multiples of the pair's v_Y


@dataclasses.dataclass(frozen=True)
class PairImpactSetup:
    """The sphere's impact setup (calib.studies.impact.ImpactSetup) and the counter-body; ``block_size``:
    the flat's block L [m] (None: BLOCK_SIZE_OVER_R R1)."""

    sphere: impact.ImpactSetup
    counter: CounterBody
    block_size: float | None = None

    @property
    def pair(self) -> ContactPair:
        """The Hertz pair (E*, R*, m* with the counter-body's density, CounterBody.pair)."""
        return self.counter.pair(self.sphere.material, self.sphere.radius)

    @property
    def contact_setup(self) -> impact.ImpactSetup:
        """The sphere's setup on the pair's contact (calib.studies.impact.ImpactSetup ``contact``,
        ``floor_radius``): what sizes the sphere's mesh and checks reach and resolution."""
        size = (self.block_size or BLOCK_SIZE_OVER_R * self.sphere.radius) if self.counter.is_flat else self.counter.R
        return dataclasses.replace(self.sphere, contact=self.pair, floor_radius=size)


def pair_meshes(setup: PairImpactSetup, v_in: float) -> tuple[SphereMeshSpec, object]:
    """(sphere mesh, counter-body mesh) of the impact at v_in [m/s] (module docstring)."""
    sphere = impact.impact_mesh(setup.contact_setup, v_in)
    counter = setup.counter.mesh_spec(HemisphereMeshSpec(**dataclasses.asdict(sphere)))
    if isinstance(counter, BlockMeshSpec):
        if setup.block_size is not None:
            counter = dataclasses.replace(counter, radius=setup.block_size, far_size=min(counter.far_size, setup.block_size))
        return sphere, counter
    return sphere, SphereMeshSpec(**dataclasses.asdict(counter))


def check_pair(setup: PairImpactSetup, velocities, over_v_Y: bool = False) -> None:
    """ValueError naming the counter flag before any mesh: calib.fit.counter.check_counter with the
    impacts' contacts (Hertz's radius of the pair at the slowest impact's force, the estimated
    largest radius, calib.fit.recipe.estimated_contact_radius, at the fastest's; Johnson 1985
    eq. 11.24), and the counter-sphere wider than each sphere mesh's contact zone. ``over_v_Y``:
    the velocities are study_velocities, multiples of the pair's v_Y (they move with the counter)."""
    slowest, fastest = min(velocities), max(velocities)

    def contact(pair: ContactPair) -> tuple[float, float]:
        scale = pair.v_Y / setup.pair.v_Y if over_v_Y else 1.0

        def force(v):
            return hertz_impact_force(pair.mass_star, pair.hertz_stiffness, v * scale)
        return float(pair.hertz_radius(force(slowest))), estimated_contact_radius(pair, force(fastest))

    check_counter(setup.sphere.material, setup.sphere.radius, setup.counter, contact,
                  f"v_in {slowest:.4g} .. {fastest:.4g} m/s" + (" (multiples of the pair's v_Y)" if over_v_Y else ""))
    try:
        impact.check_resolution(setup.contact_setup, velocities)   # both meshes resolve each contact
    except ValueError as exc:
        if over_v_Y:        # no --v-in given: the input that makes the contact too small is named
            raise ValueError(default_velocities_refusal(setup, str(exc))) from None
        raise
    for v in velocities:
        check_counter_covers(setup.counter, pair_meshes(setup, v)[0])


def default_velocities_refusal(setup: PairImpactSetup, refusal: str) -> str:
    """The message when ``study_velocities`` make a contact too small for the meshes
    (calib.studies.impact.check_resolution's ``refusal``): on a counter-sphere the radius that
    decides it, --counter-R, and the smallest one whose study is resolved (by bisection in log R2;
    the contact at a multiple of the pair's v_Y grows with R*), and in every case --v-in instead."""
    given = refusal.split("need ", 1)[-1]
    head = (f"the default velocities ({', '.join(f'{f:g}' for f in STUDY_VELOCITIES_OVER_V_Y)} v_Y of the pair, "
            f"v_Y = {setup.pair.v_Y:.4g} m/s) make contacts too small for the meshes")

    def resolved(R2: float) -> bool:
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")         # a trial radius: not the user's news
                trial = dataclasses.replace(setup, counter=dataclasses.replace(setup.counter, R=R2))
                impact.check_resolution(trial.contact_setup, study_velocities(trial))
        except ValueError:
            return False
        return True

    largest = setup.sphere.radius       # beyond R1 the counter-sphere's own mesh floor grows with R2
    if setup.counter.is_flat or setup.counter.R >= largest or not resolved(largest):
        return f"--v-in out of range: {head}: give --v-in: need {given}"
    low, high = setup.counter.R, largest
    for _ in range(30):
        middle = math.sqrt(low * high)
        low, high = (low, middle) if resolved(middle) else (middle, high)
    return (f"--counter-R out of range for the default velocities: {head}: need --counter-R >= "
            f"{bound_text(high, '>=')} m here, or give --v-in: need {given}")


def solver_for(setup: PairImpactSetup, sphere: SphereMeshSpec, counter, cache_dir=None) -> PairImpactSolver:
    """The two-body impact solver on the meshes ``sphere``, ``counter`` (an elastic sphere when
    setup.sphere.elastic)."""
    material = setup.sphere.material
    first = (ElasticMaterial(material.E, material.nu) if setup.sphere.elastic
             else VonMisesMaterial(material.E, material.nu, material.sigma_y))
    second = setup.counter.fe_material()
    return PairImpactSolver(impact_pair_mesh(sphere, counter, cache_dir), first, second, material.rho,
                            setup.counter.density(material))


def coarse_meshes(sphere: SphereMeshSpec, counter) -> tuple[SphereMeshSpec, object]:
    """Both meshes with the contact element doubled (calib.studies.impact.coarse_mesh on each)."""
    return impact.coarse_mesh(sphere), impact.coarse_mesh(counter)


def tasks_for(setup: PairImpactSetup, velocities, variants=FINE) -> list[dict]:
    """One sweep task per velocity and variant (module docstring); its key hashes everything the
    result depends on, not the variant's label."""
    tasks = []
    for v in velocities:
        fine_meshes = pair_meshes(setup, v)
        for variant in variants:
            sphere, counter = coarse_meshes(*fine_meshes) if variant == "coarse mesh" else fine_meshes
            steps = setup.sphere.steps_per_contact // (2 if variant == "coarse dt" else 1)
            task = task_of(setup, v, sphere, counter, steps)
            tasks.append({**task, "variant": variant})
    return tasks


def task_of(setup: PairImpactSetup, v, sphere: SphereMeshSpec, counter, steps_per_contact: int) -> dict:
    """One sweep task: the impact at v [m/s] on the meshes ``sphere``, ``counter``."""
    task = {"v_in": float(v), "material": dataclasses.asdict(setup.sphere.material), "radius": setup.sphere.radius,
            "elastic": setup.sphere.elastic, "counter": setup.counter.describe(),
            "block_size": setup.block_size, "sphere_mesh": dataclasses.asdict(sphere),
            "counter_mesh": dataclasses.asdict(counter), "counter_block": isinstance(counter, BlockMeshSpec),
            "steps_per_contact": int(steps_per_contact), "version": VERSION}
    return {**task, "key": stable_key(task)}


def run_task(task: dict) -> dict:
    """One pair impact as a row (never raises: a failure is a row with status "failed")."""
    from threadpoolctl import threadpool_limits    # one BLAS thread per FE process (calib/README.md)

    from nfdmodel import Material

    started = time.perf_counter()
    base = {"key": task["key"], "v_in": task["v_in"]}
    try:
        with threadpool_limits(1):
            counter = CounterBody(**{k: task["counter"].get(k) for k in ("E", "nu", "sigma_y", "R", "rho")})
            setup = PairImpactSetup(impact.ImpactSetup(Material(**task["material"]), task["radius"],
                                                       elastic=task["elastic"],
                                                       steps_per_contact=task["steps_per_contact"]),
                                    counter, task["block_size"])
            sphere = SphereMeshSpec(**task["sphere_mesh"])
            counter_mesh = (BlockMeshSpec if task["counter_block"] else SphereMeshSpec)(**task["counter_mesh"])
            solver = solver_for(setup, sphere, counter_mesh)
            result = run_pair_impact(solver, task["v_in"], steps_per_contact=task["steps_per_contact"])
    except (ImpactNotConverged, ValueError, np.linalg.LinAlgError) as exc:
        return {**base, "status": "failed", "error": str(exc), "wall_time_s": time.perf_counter() - started}
    hertz = hertz_pair_impact(result.E_star, result.R_star, result.reduced_mass, task["v_in"])
    return {**base, **result.record(), "hertz": hertz, "status": "ok", "error": "",
            "mesh": solver.pair_mesh.describe(), "git_commit": output.git_commit()}


def run_impacts(setup: PairImpactSetup, velocities, cases: Path, *, workers: int = 1,
                progress: Callable[[str], None] | None = None, variants=FINE) -> tuple[list[dict], dict]:
    """Every task of ``tasks_for`` through the sweep runner: (rows, each with its variant, counts
    {computed, reused}); ValueError naming the first that failed."""
    check_pair(setup, velocities)
    impact.check_reach(setup.contact_setup, velocities)
    tasks = tasks_for(setup, velocities, variants)
    meshes = {stable_key([task["sphere_mesh"], task["counter_mesh"]]): task for task in tasks}
    for task in meshes.values():        # meshed here, one at a time (gmsh is one per process)
        impact_pair_mesh(SphereMeshSpec(**task["sphere_mesh"]),
                         (BlockMeshSpec if task["counter_block"] else SphereMeshSpec)(**task["counter_mesh"]))
    describe = (lambda row: f"v_in = {row['v_in']:g} m/s: "
                + (f"e = {row['e']:.4f}, {row['wall_time_s']:.1f} s" if row["status"] == "ok" else row["error"]))
    swept = run_sweep(tasks, run_task, cases, keep=lambda row: row.get("status") == "ok", workers=workers,
                      progress=progress, describe=describe)
    rows = [{**row, "variant": task["variant"]} for task, row in zip(tasks, swept.rows)]
    failed = [row for row in rows if row["status"] != "ok"]
    if failed:
        raise ValueError(f"the pair FE impact at v_in = {failed[0]['v_in']:g} m/s ({failed[0]['variant']}) failed: "
                         f"{failed[0]['error']}")
    return rows, {"computed": swept.computed, "reused": swept.reused}


def study_velocities(setup: PairImpactSetup) -> tuple[float, ...]:
    """0.5, 2 and 10 v_Y of the pair (nfdmodel.ContactPair.v_Y: the body that yields first) [m/s]."""
    return tuple(f * setup.pair.v_Y for f in STUDY_VELOCITIES_OVER_V_Y)


def study(setup: PairImpactSetup, velocities, out: Path, *, workers: int = 1,
          progress: Callable[[str], None] | None = None, variants=FINE) -> list[dict]:
    """The impacts (``variants``: FINE, or calib.studies.impact.VARIANTS with the error estimate),
    written to OUT/impact_pair.csv and .json; returns one record per velocity."""
    started = time.perf_counter()
    rows, counts = run_impacts(setup, velocities, out / "cases", workers=workers, progress=progress, variants=variants)
    pair = setup.pair
    records = []
    for _, runs in impact.runs_by_velocity(rows):
        row = runs["fine"]
        record = {k: row[k] for k in ("v_in", "v1_in", "v2_in", "e", "v_sep", "P_max", "contact_time", "alpha_max",
                                      "contact_radius_max", "momentum_change", "kinetic_in", "plastic_work",
                                      "energy_left", "balance_residual", "contact_work", "dt", "steps", "dofs",
                                      "wall_time_s", "cpu_time_s")}
        record["v_in_over_v_Y"] = row["v_in"] / pair.v_Y
        record["hertz"] = row["hertz"]
        record["balance_residual_fraction"] = row["balance_residual"] / row["kinetic_in"]
        record["energy_left_fraction"] = row["energy_left"] / row["kinetic_in"]
        record["mesh"] = row["mesh"]
        record.update(impact.error_estimates(runs, COMPARED))
        record["wall_time_s_all_runs"] = sum(run["wall_time_s"] for run in runs.values())
        record["cpu_time_s_all_runs"] = sum(run["cpu_time_s"] for run in runs.values())
        records.append(record)
    stamp = output.stamp(time.perf_counter() - started, counter=setup.counter.describe(),
                         material=dataclasses.asdict(setup.sphere.material), radius=setup.sphere.radius,
                         variants=list(variants), **counts)
    output.write_json(out / "impact_pair.json", {"stamp": stamp, "impacts": records})
    flat = [{k: v for k, v in r.items() if not isinstance(v, dict)}
            | {f"hertz_{k}": v for k, v in r["hertz"].items()} for r in records]
    output.write_csv(out / "impact_pair.csv", flat)
    return records


def block_size_effect(setup: PairImpactSetup, v_in: float, sizes, *, cache_dir=None) -> list[dict]:
    """e, P_max, contact time and alpha_max of the impact at v_in [m/s] on blocks of the ``sizes``
    L [m] (a flat counter-body; calib.fe.impact_pair states what the finite block means)."""
    if not setup.counter.is_flat:
        raise ValueError("block_size_effect needs a flat counter-body (no counter R)")
    rows = []
    for L in sizes:
        sized = dataclasses.replace(setup, block_size=float(L))
        sphere, counter = pair_meshes(sized, v_in)
        result = run_pair_impact(solver_for(sized, sphere, counter, cache_dir), v_in,
                                 steps_per_contact=setup.sphere.steps_per_contact)
        rows.append({"block_size": float(L), **{k: getattr(result, k) for k in COMPARED}, "wall_time_s": result.wall_time_s})
    return rows


def wave_return_time(counter: CounterBody, rho: float, block_size: float) -> float:
    """2 L / c_L [s]: the time a longitudinal wave takes to the held face and back, c_L =
    sqrt(E (1 - nu) / (rho (1 + nu)(1 - 2 nu))) [m/s]."""
    nu = counter.nu
    return 2.0 * block_size / math.sqrt(counter.E * (1 - nu) / (rho * (1 + nu) * (1 - 2 * nu)))


def block_size_default(radius: float) -> float:
    """The flat's block L [m] for a sphere of radius R [m]: BLOCK_SIZE_OVER_R R."""
    return BLOCK_SIZE_OVER_R * radius
