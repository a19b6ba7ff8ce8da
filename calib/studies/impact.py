"""Impacts of the whole sphere by the dynamic FE, against the quasi-static laws (``nfdcal impact``).

Each velocity runs three FE impacts (calib.fe.impact.run_impact) through the one sweep runner
(calib.sweep.runner: parallel, resumable, one file per finished impact in OUT/cases/):

  fine          the mesh of the impact (below) and dt = t_c / steps_per_contact: what ships;
  coarse mesh   the contact element doubled (the refined zone kept, as calib.fit.recipe.coarse_spec);
  coarse dt     dt doubled.

Discretisation error, shipped like the calibration's (calib/README.md, Mesh convergence): the
fine values ship, not extrapolated, with

    Q_rel_error_estimate = |Q_2h / Q_h - 1| + |Q_2dt / Q_dt - 1|

the change between the meshes and between the time steps, each the coarser run's error for a
first-order convergence and a bound of the finer's. First order in dt is what the time-step
ladder measures (results/impact/convergence.json: observed orders 0.7-0.9 for e, the contact time,
alpha_max and the dent at 24 v_Y), below the trapezoidal rule's second order on smooth motion:
the contact's onset and release at each node fall inside steps. The energy fractions ship as they
are (their balance residual says how well they close).

Mesh: one per velocity, the hemisphere recipe's mesh for that impact's largest contact radius
a_max (calib.fit.recipe.mesh_for, as the press sizes its mesh: the level's contact element
a_max / 37 by default), estimated from Hertz's P_max below first yield and from the vz law's at v_in
with the master table's constants above it (calib.fit.impact_window), the same sizes on the whole
sphere (meshes.sphere). The reference E, nu, R keep the reference mesh family (4e-5 m at the
contact) while a_max spans at least REFERENCE_ELEMENTS_PER_CONTACT_RADIUS = 6 of its elements (the
reference study's slowest impact, 0.5 v_Y, spans 6.2: P_max and contact time within 0.1 % of
Hertz's); a slower one gets the recipe's mesh. The FE vouches for P <= 1000 P_Y and a contact
radius <= 0.2 R (calib.fit.recipe): a faster impact is refused before meshing, naming the largest
v_in; so is a slower one whose contact the mesh cannot resolve, naming the smallest v_in: the
recipe's contact element below 1e-6 R (meshes.hemisphere), or, with a given contact_size, fewer
than MIN_ELEMENTS_PER_CONTACT_RADIUS = 1.5 elements across a_max. Measured on the reference
family's zone, elastic, against Hertz's P_max: 2 elements and more within 1.2 % (except 1.9 % at
1.7), 1.3 elements 4.2 % low, 0.67 elements 8.7 % high, 0.17 elements 19 % short, 0.03 elements
(a 1 um contact on 40 um elements) 2.6x.

Energy balance. Its residual (calib.fe.impact) is the time discretisation's: the trapezoidal
internal work against the return mapping's energy in the steps that yield (internal_work_error),
and the work of the contact reactions of nodes that touch or leave the flat inside a step (their
contact is found at the step's end; contact_work). Both shrink with dt: on the reference sphere
the residual falls from 3.4e-3 to 1.1e-3 of the kinetic energy in at 300 v_Y, and from 5.2e-4 to
1.5e-4 (to 6.3e-5 at 200 steps) at 24 v_Y, from 50 to 100 steps per contact, while the contact
element changes it by about 10 % (results/impact/convergence.json); each record carries it at
twice dt too (balance_residual_fraction_coarse_dt).

Quasi-static FE (calib.studies.impact_quasistatic): the hemisphere of the impact's mesh sizes
pressed to the impact's P_max and unloaded, its loop thrown as a collision of the sphere's mass:
e, contact time, alpha_max and dent at the same P_max, and the loading branch's force at the same
v_in. ``quasi_static_limit`` states from which v_in the dynamic FE differs from it by more than
the discretisation errors, with the vibration energy left.

The quasi-static laws at each v_in (exact by energy balance, nfdmodel.collision_reference): vz
with the two constants of the parameter file given (``params_file``: a calibration's
parameters.json, whichever law it ships, or a vz file), else the master table's (the paper's
outside the table); the vz-table law of the parameter file given as ``table_file`` (e.g. ``nfdcal
calibrate --v-max``'s); Thornton's law and its closed-form restitution (paper eq. 1.11); Hertz's
P_max and contact time 2.868 (m^2 / (R E*^2 v_in))^(1/5). And, for the reference sphere with the
CSV given as ``mdr_file`` (LAMMPS' restitution.csv, tests/benchmarks/bench_lammps.py), the
restitution of LAMMPS' ``granular mdr`` normal model (two aluminium spheres head-on) at the same
v_in / v_Y, interpolated linearly in log(v_in / v_Y) between its velocities: e depends on v_in / v_Y
alone for a given nu and E*/sigma_Y (nfdmodel/README.md, The reference case and the dimensionless
constants), so the pair's e is the sphere-on-flat one's. No file is read unless given: the summary
names each one compared with (vz_source, vz_table_source, mdr_source).
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
from calib.fe.impact import DEFAULT_STEPS_PER_CONTACT, ImpactNotConverged, run_impact
from calib.fe.kinematics import DEFAULT_KINEMATICS
from calib.fe.newmark import ImpactSolver
from calib.fe.von_mises import von_mises_material
from calib.fit import impact_window, recipe
from calib.studies.impact_files import law_parameters, mdr_table, table_parameters  # the study reads them
from calib.sweep.runner import run_sweep
from meshes.hemisphere import MIN_CONTACT_SIZE_OVER_RADIUS, hemisphere_mesh
from meshes.keys import stable_key
from meshes.sphere import SphereMeshSpec, sphere_mesh
from nfdmodel import (ContactPair, Material, RangeWarning, VZParams, collision_reference,
                      reference_case)
from nfdmodel.hertz_contact import hertz_force_at_radius, hertz_impact_approach, hertz_impact_force
from nfdmodel.reference_case import is_reference_sphere
from nfdmodel.thornton import thornton_closed_form
from nfdmodel.validation import SOLID_RANGES, bound_text

DEFAULT_OUT = output.RESULTS / "impact"
STUDY_VELOCITIES_OVER_V_Y = (0.5, 2.0, 10.0, 20.0, 40.0, 100.0, 300.0)   # to the FE's reach, 328 v_Y
CONVERGENCE_VELOCITY = 0.04      # m/s: the reference sphere at 24 v_Y, the benchmark's impact
VERSION = 2                       # bump when the FE or the recipe changes: invalidates finished cases
VARIANTS = ("fine", "coarse mesh", "coarse dt")
COMPARED = ("e", "P_max", "contact_time", "alpha_max", "dent")
HISTORY_POINTS = 400              # at most this many history samples per case file
SECONDS_PER_STEP_AT_13K_DOFS = 0.2     # an elastoplastic time step (tests/benchmarks/bench_impact.py: 18.5 s, 93 steps)
# Contact elements across the impact's contact radius (module docstring, Mesh): the reference mesh
# family's while it gives this many (the reference study's slowest impact spans 6.2), and the fewest
# a given contact_size may give (below, P_max is off by 4 % and more, beyond its error estimate).
REFERENCE_ELEMENTS_PER_CONTACT_RADIUS = 6.0
MIN_ELEMENTS_PER_CONTACT_RADIUS = 1.5


@dataclasses.dataclass(frozen=True)
class ImpactSetup:
    """What an impact run needs besides v_in: the sphere's material (calib's nfdmodel.Material; an
    elastic run ignores sigma_y), R [m], elastic (no yield: Hertz's limit), the mesh level or
    contact size [m], steps per contact, the sphere's isotropic hardening (a calib.fe.flow_curve
    FlowCurve; None: perfectly plastic), its strain-rate dependence (a calib.fe.rate_law RateLaw; None:
    rate-independent; the quasi-static FE paths take its rate-independent limit). ``contact``: the contact the impact makes (None: the
    sphere on the rigid flat; a pair impact's, calib.studies.impact_pair: E*, R*, m* and first yield
    of the two bodies, nfdmodel.ContactPair), which sizes the mesh and the checks;
    ``floor_radius``: the largest body meshed with the sphere's contact element [m] (None: the
    sphere), whose MIN_CONTACT_SIZE_OVER_RADIUS bounds that element from below; ``kinematics``: the
    FE's (calib.fe.kinematics.KINEMATICS), the impact's and its quasi-static path's."""

    material: Material
    radius: float
    elastic: bool = False
    level: str | None = None
    contact_size: float | None = None
    steps_per_contact: int = DEFAULT_STEPS_PER_CONTACT
    hardening: object = None
    rate_law: object = None
    contact: ContactPair | None = None
    floor_radius: float | None = None
    kinematics: str = DEFAULT_KINEMATICS

    @property
    def pair(self) -> ContactPair:
        return self.contact if self.contact is not None else ContactPair.sphere_flat(self.material, self.radius)


# ---------------------------------------------------------------- before any mesh
def estimated_force(setup: ImpactSetup, v_in: float) -> float:
    """P_max [N] the impact at v_in [m/s] is expected to reach: Hertz's for an elastic run, else the
    vz law's with the master table's constants (calib.fit.impact_window; on a pair's contact, its
    dimensionless constants on the pair's yield point, nfdmodel.unlike's substitution)."""
    pair = setup.pair
    hertz = float(hertz_impact_force(pair.mass_star, pair.hertz_stiffness, v_in))
    if setup.elastic or v_in <= pair.v_Y:
        return hertz
    params = estimating_law(setup)
    try:
        return impact_window.impact_force(params, v_in)
    except ValueError:                  # beyond the law's own domain: certainly beyond the FE's
        return math.inf


def estimating_law(setup: ImpactSetup) -> VZParams:
    """The vz law that estimates the impact's P_max (``estimated_force``): the master table's
    constants of the sphere's material (calib.fit.impact_window.estimating_constants), on the
    setup's contact."""
    params, _ = impact_window.estimating_constants(setup.material, setup.radius)
    if setup.contact is None:
        return params
    return VZParams.from_dimensionless(setup.contact, params.Ca_hat, params.Kc_hat, params.window)


def largest_load(setup: ImpactSetup) -> float:
    """The largest P_max [N] the FE vouches for: 1000 P_Y (unless elastic) and a contact radius of at
    most 0.2 R (calib.fit.recipe); Hertz's load at that radius when it is reached below first yield."""
    pair = setup.pair
    limit = recipe.CONTACT_RADIUS_LIMIT * pair.R_star
    if setup.elastic or recipe.estimated_contact_radius(pair, pair.P_Y) >= limit:
        hertz = hertz_force_at_radius(limit, pair.R_star, pair.E_star)
        return hertz if setup.elastic else min(hertz, pair.P_Y)
    return recipe.fe_reach(pair)


def check_reach(setup: ImpactSetup, velocities) -> None:
    """ValueError before any FE when an impact goes beyond what the FE vouches for (``largest_load``),
    naming the largest v_in it can, or makes a contact its mesh cannot resolve (``check_resolution``)."""
    pair = setup.pair
    reach = largest_load(setup)
    for v in velocities:
        if estimated_force(setup, v) > reach:
            if setup.elastic or reach <= pair.P_Y:              # Hertz: (1/2) m v^2 = (2/5) P alpha
                v_reach = math.sqrt(0.8 * reach * float(pair.hertz_approach(reach)) / pair.mass_star)
            else:
                v_reach = impact_window.reach_velocity(estimating_law(setup), reach)
            raise ValueError(f"--v-in out of range: the impact at {v:g} m/s goes beyond what this FE vouches for "
                             f"(P <= {recipe.MAX_LOAD_OVER_YIELD:g} P_Y and contact radius <= "
                             f"{recipe.CONTACT_RADIUS_LIMIT:g} R): need v_in <= {bound_text(v_reach, '<=')} m/s "
                             f"({v_reach / pair.v_Y:.4g} v_Y) for this material and R")
    check_resolution(setup, velocities)


def contact_radius(setup: ImpactSetup, v_in: float) -> float:
    """The largest contact radius [m] the impact at v_in [m/s] is expected to reach (sizes its mesh):
    calib.fit.recipe.estimated_contact_radius at ``estimated_force``."""
    return recipe.estimated_contact_radius(setup.pair, estimated_force(setup, v_in))


def velocity_for_radius(setup: ImpactSetup, radius: float, start: float) -> float:
    """The smallest v_in [m/s] whose ``contact_radius`` reaches ``radius`` [m] (it grows with v_in),
    from ``start`` [m/s], a velocity below it; by bisection in log v_in."""
    low, high = start, 2.0 * start
    while contact_radius(setup, high) < radius:
        low, high = high, 2.0 * high
    for _ in range(60):
        middle = math.sqrt(low * high)
        low, high = (middle, high) if contact_radius(setup, middle) < radius else (low, middle)
    return high * (1.0 + 1e-3)          # printed to 4 digits, still reaching the radius


def smallest_resolved_radius(setup: ImpactSetup) -> float:
    """The smallest contact radius [m] the impact's mesh resolves: MIN_ELEMENTS_PER_CONTACT_RADIUS
    elements of the given contact_size, else the recipe's contact element no finer than 1e-6 R (R:
    the largest body meshed with it, ``floor_radius``)."""
    if setup.contact_size is not None:
        return MIN_ELEMENTS_PER_CONTACT_RADIUS * setup.contact_size
    return (MIN_CONTACT_SIZE_OVER_RADIUS * max(setup.radius, setup.floor_radius or 0.0)
            / recipe.MESH_LEVELS[setup.level or "default"])


def check_resolution(setup: ImpactSetup, velocities) -> None:
    """ValueError before any FE when an impact's contact is too small for its mesh (module docstring,
    Mesh), naming the smallest v_in the mesh resolves and, with a given contact_size, the one that
    would do."""
    need = smallest_resolved_radius(setup)
    slowest = min(velocities, default=None)
    if slowest is None or contact_radius(setup, slowest) >= need:
        return
    a = contact_radius(setup, slowest)
    v_min = velocity_for_radius(setup, need, slowest)
    body = ("a mesh of the sphere" if setup.floor_radius is None or setup.floor_radius <= setup.radius else
            f"the counter-body's mesh (size {setup.floor_radius:g} m)")
    where = (f"spans {a / setup.contact_size:.2g} elements of --contact-size {setup.contact_size:g} m; the FE needs "
             f">= {MIN_ELEMENTS_PER_CONTACT_RADIUS:g}: need v_in >= {bound_text(v_min, '>=')} m/s on this mesh, or --contact-size <= "
             f"{bound_text(a / MIN_ELEMENTS_PER_CONTACT_RADIUS, '<=', 3)} m" if setup.contact_size is not None else
             f"needs a contact element below {MIN_CONTACT_SIZE_OVER_RADIUS:g} of the body's size, finer than {body} "
             f"can hold: need v_in >= {bound_text(v_min, '>=')} m/s ({v_min / setup.pair.v_Y:.4g} v_Y) for this material and R")
    raise ValueError(f"--v-in out of range: the contact of the impact at {slowest:g} m/s (radius about {a:.3g} m) "
                     + where)


def impact_mesh(setup: ImpactSetup, v_in: float) -> SphereMeshSpec:
    """The sphere mesh of the impact at v_in [m/s] (module docstring, Mesh)."""
    a_max = contact_radius(setup, v_in)
    resolved = (setup.contact_size is not None or a_max >= REFERENCE_ELEMENTS_PER_CONTACT_RADIUS
                * recipe.REFERENCE_CONTACT_SIZES[setup.level or "default"])
    reference = resolved and is_reference_sphere(setup.material.E, setup.material.nu, setup.radius)
    hemisphere = recipe.mesh_for(setup.radius, a_max, reference=reference, level=setup.level,
                                 contact_size=setup.contact_size)
    return SphereMeshSpec.from_hemisphere(hemisphere)


def coarse_mesh(spec: SphereMeshSpec) -> SphereMeshSpec:
    """The contact element doubled, the refined zone at least two elements wide and deep."""
    h = 2.0 * spec.contact_size
    return dataclasses.replace(spec, contact_size=h, refined_radius=max(spec.refined_radius, 2 * h),
                               refined_depth=max(spec.refined_depth, 2 * h), far_size=max(spec.far_size, h))


def tasks_for(setup: ImpactSetup, velocities, variants=VARIANTS) -> list[dict]:
    """The sweep tasks: one per velocity and variant (module docstring), keyed by what decides them."""
    tasks = []
    for v in velocities:
        fine = impact_mesh(setup, v)
        for variant in variants:
            mesh = coarse_mesh(fine) if variant == "coarse mesh" else fine
            steps = setup.steps_per_contact // 2 if variant == "coarse dt" else setup.steps_per_contact
            tasks.append(task_of(setup, v, variant, mesh, steps))
    return tasks


def task_of(setup: ImpactSetup, v_in: float, variant: str, mesh: SphereMeshSpec, steps_per_contact: int) -> dict:
    """One sweep task; its key hashes what decides the run (not the variant's label, so the
    study and the convergence ladders share a run they both need)."""
    material = setup.material
    task = {"v_in": float(v_in), "E": material.E, "nu": material.nu,
            "sigma_y": None if setup.elastic else material.sigma_y, "rho": material.rho, "R": setup.radius,
            "mesh": dataclasses.asdict(mesh), "steps_per_contact": int(steps_per_contact)}
    if setup.hardening is not None and not setup.elastic:      # absent for perfect plasticity: its keys stay
        task["hardening"] = setup.hardening.record()
    if setup.rate_law is not None and not setup.elastic:       # absent when rate-independent: its keys stay
        task["rate_law"] = setup.rate_law.record()
    if setup.kinematics != DEFAULT_KINEMATICS:                   # absent for small strain: its keys stay
        task["kinematics"] = setup.kinematics
    return {**task, "variant": variant, "key": stable_key({**task, "version": VERSION})}


def planned_runs(tasks: list[dict], cases: Path) -> list[dict]:
    """Per task, what a dry run shows: v_in, variant, contact element [m], estimated dofs and time
    steps, whether ``cases`` holds it finished, and the estimated wall time [s] on one process."""
    runs = []
    for task in tasks:
        spec = SphereMeshSpec(**task["mesh"])
        dofs = spec.estimate_dofs()
        steps = int(1.1 * task["steps_per_contact"]) + 10
        runs.append({"v_in": task["v_in"], "variant": task["variant"], "contact_size": spec.contact_size,
                     "dofs_estimate": dofs, "steps_estimate": steps, "finished": (Path(cases) / f"{task['key']}.json").is_file(),
                     "estimate_s": steps * SECONDS_PER_STEP_AT_13K_DOFS * dofs / 13000})
    return runs


# ---------------------------------------------------------------- one impact (a sweep worker)
def run_task(task: dict) -> dict:
    """One FE impact as a row (never raises: a failure is a row with status "failed")."""
    from threadpoolctl import threadpool_limits    # one BLAS thread per FE process (calib/README.md)

    started = time.perf_counter()
    base = {"key": task["key"], "v_in": task["v_in"], "variant": task["variant"]}
    try:
        with threadpool_limits(1):
            spec = SphereMeshSpec(**task["mesh"])
            mesh = sphere_mesh(spec)
            material = (ElasticMaterial(task["E"], task["nu"]) if task["sigma_y"] is None
                        else von_mises_material(task["E"], task["nu"], task["sigma_y"], task.get("hardening"),
                                               task.get("rate_law")))
            solver = ImpactSolver(mesh, material, task["rho"], kinematics=task.get("kinematics", DEFAULT_KINEMATICS))
            result = run_impact(solver, task["v_in"], steps_per_contact=task["steps_per_contact"])
    except (ImpactNotConverged, ValueError, np.linalg.LinAlgError) as exc:
        return {**base, "status": "failed", "error": str(exc), "wall_time_s": time.perf_counter() - started}
    history = result.history
    every = max(1, math.ceil(history["time"].size / HISTORY_POINTS))
    return {**base, **result.record(), "status": "ok", "error": "", "mesh": spec.describe(),
            "git_commit": output.git_commit(), "history": {k: v[::every] for k, v in history.items()}}


def run_impacts(setup: ImpactSetup, velocities, cases: Path, *, workers: int = 1,
                progress: Callable[[str], None] | None = None, variants=VARIANTS) -> tuple[list[dict], dict]:
    """Every task of ``tasks_for`` through the sweep runner (finished cases in ``cases``); returns
    (rows, counts {computed, reused}). Raises ValueError naming the first impact that failed."""
    check_reach(setup, velocities)
    tasks = tasks_for(setup, velocities, variants)
    for spec in {task["mesh"]["contact_size"]: task["mesh"] for task in tasks}.values():
        sphere_mesh(SphereMeshSpec(**spec))           # built here, one at a time (gmsh is one per process)
    describe = (lambda row: f"v_in = {row['v_in']:g} m/s ({row['variant']}): "
                + (f"e = {row['e']:.4f}, {row['wall_time_s']:.1f} s" if row["status"] == "ok" else row["error"]))
    swept = run_sweep(tasks, run_task, cases, keep=lambda row: row.get("status") == "ok", workers=workers,
                      progress=progress, describe=describe)
    rows = [{**row, "variant": task["variant"]} for task, row in zip(tasks, swept.rows)]   # a shared run's label
    failed = [row for row in rows if row["status"] != "ok"]
    if failed:
        raise ValueError(f"the FE impact at v_in = {failed[0]['v_in']:g} m/s ({failed[0]['variant']}) failed: "
                         f"{failed[0]['error']}")
    return rows, {"computed": swept.computed, "reused": swept.reused}


# ---------------------------------------------------------------- the comparison
def law_predictions(setup: ImpactSetup, v_in: float, params, table=None, mdr=None) -> dict:
    """The quasi-static laws' impact at v_in [m/s] (module docstring): per law e, P_max [N],
    contact_time [s], delta_max, delta_res [m]; Thornton's closed-form e; the vz-table law's
    (``table``: its parameters) and LAMMPS' mdr e (``mdr``: :func:`mdr_table`) where given. Below first yield (v_in <= v_Y) every law is Hertz's,
    and an elastic run is compared with Hertz alone."""
    pair = setup.pair
    hertz_delta = hertz_impact_approach(pair.mass_star, pair.hertz_stiffness, v_in)
    hertz = {"e": 1.0, "P_max": float(pair.hertz_stiffness * hertz_delta ** 1.5),
             "contact_time": float(pair.hertz_contact_time(v_in)), "delta_max": float(hertz_delta), "delta_res": 0.0}
    if setup.elastic:
        return {"hertz": hertz}
    out = {"vz": dict(hertz), "thornton": {**hertz, "e_closed_form": 1.0}}
    if table is not None:
        out["vz_table"] = dict(hertz)
    if v_in > pair.v_Y:
        laws = (("vz", "vz", params), ("thornton", "thornton", pair)) + \
            ((("vz_table", "vz-table", table),) if table is not None else ())
        for name, law, law_params in laws:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", RangeWarning)        # the window is reported, not warned
                ref = collision_reference(law, law_params, [v_in])
            out[name] = {"e": float(ref.restitution[0]), "P_max": float(ref.P_max[0]),
                         "contact_time": float(ref.contact_time_estimate[0]), "delta_max": float(ref.delta_max[0]),
                         "delta_res": float(ref.delta_res[0])}
        out["thornton"]["e_closed_form"] = float(thornton_closed_form(v_in, pair.v_Y))
    out["hertz"] = hertz
    if mdr is not None and mdr[0][0] <= math.log(v_in / pair.v_Y) <= mdr[0][-1]:
        out["mdr"] = {"e": float(np.interp(math.log(v_in / pair.v_Y), *mdr))}
    return out


def impact_records(setup: ImpactSetup, rows: list[dict], params, table=None, quasi_static=(), mdr=None) -> list[dict]:
    """One record per velocity: the fine run's values, the error estimates from the other
    variants (module docstring), the energy fractions, the laws' predictions (``table``: the
    vz-table law's parameters; ``mdr``: LAMMPS' restitution, :func:`mdr_table`) and the quasi-static FE at the same P_max (``quasi_static``: rows of
    calib.studies.impact_quasistatic, with the dynamic FE's relative difference to each)."""
    from calib.studies import impact_quasistatic

    pair = setup.pair
    # the path's values from its stored points (cheap): a finished case gets the current recipe
    static = {row["v_in"]: {**row, **impact_quasistatic.thrown(row["path"], pair.mass_star, row["v_in"])}
              for row in quasi_static}
    records = []
    for v_in, runs in runs_by_velocity(rows):
        fine = runs["fine"]
        kinetic = fine["kinetic_in"]
        record = {"v_in": v_in, "v_in_over_v_Y": v_in / pair.v_Y, "P_max_over_P_Y": fine["P_max"] / pair.P_Y,
                  **{k: fine[k] for k in ("e", "v_out", "P_max", "time_P_max", "contact_time", "alpha_max", "dent",
                                          "contact_radius_max", "kinetic_in", "kinetic_out", "plastic_work",
                                          "residual_stress_energy", "vibration_energy", "balance_residual",
                                          "internal_work_error", "contact_work", "solver_residual_work",
                                          "recontacts", "dt", "steps", "newton_iterations", "dofs", "mass",
                                          "wall_time_s")},
                  "cpu_time_s": fine.get("cpu_time_s"),
                  "plastic_fraction": fine["plastic_work"] / kinetic,
                  "residual_stress_fraction": fine["residual_stress_energy"] / kinetic,
                  "vibration_fraction": fine["vibration_energy"] / kinetic,
                  "balance_residual_fraction": fine["balance_residual"] / kinetic,
                  "contact_size": fine["mesh"]["contact_size"], "mesh_key": fine["mesh"]["key"]}
        record.update(error_estimates(runs, COMPARED))
        coarse_dt = runs.get("coarse dt")
        # the balance residual is the time discretisation's (module docstring): it shrinks with dt
        record["balance_residual_fraction_coarse_dt"] = (coarse_dt["balance_residual"] / coarse_dt["kinetic_in"]
                                                        if coarse_dt else None)
        record["wall_time_s_all_runs"] = sum(run["wall_time_s"] for run in runs.values())
        record["models"] = law_predictions(setup, v_in, params, table, mdr)
        if v_in in static:
            record["quasi_static"] = {k: v for k, v in static[v_in].items() if k not in ("path", "key", "status", "error")}
            record["dynamic_over_quasi_static"] = impact_quasistatic.compared(record, static[v_in])
        records.append(record)
    return records


def runs_by_velocity(rows) -> list[tuple[float, dict]]:
    """The sweep's rows grouped per v_in [m/s], in increasing order: (v_in, {variant: row})."""
    grouped: dict[float, dict] = {}
    for row in rows:
        grouped.setdefault(row["v_in"], {})[row["variant"]] = row
    return sorted(grouped.items())


def error_estimates(runs: dict, quantities) -> dict:
    """Per quantity Q of ``quantities`` from the runs of one velocity ({variant: row}): Q_mesh_change
    = Q_2h / Q_h - 1, Q_dt_change = Q_2dt / Q_dt - 1 and Q_rel_error_estimate, their absolute sum
    (module docstring; None without both coarse runs)."""
    fine, out = runs["fine"], {}
    for quantity in quantities:
        mesh_change = _relative_change(runs.get("coarse mesh", {}).get(quantity), fine[quantity])
        dt_change = _relative_change(runs.get("coarse dt", {}).get(quantity), fine[quantity])
        out[f"{quantity}_mesh_change"], out[f"{quantity}_dt_change"] = mesh_change, dt_change
        out[f"{quantity}_rel_error_estimate"] = (None if mesh_change is None or dt_change is None
                                                 else abs(mesh_change) + abs(dt_change))
    return out


def _relative_change(other, value):
    if other is None:
        return None
    if value == 0.0:
        return 0.0 if other == 0.0 else None
    return float(other / value - 1.0)


def largest_vibration(records: list[dict]) -> dict:
    """Where the sphere keeps the most vibration energy after it separates (the measure of the
    quasi-static assumption: the laws have no vibration): its fraction of the kinetic energy in, at
    which v_in / v_Y, and the fraction the restitution's square loses to it there."""
    worst = max(records, key=lambda r: r["vibration_fraction"])
    return {"largest_fraction": worst["vibration_fraction"], "v_in_over_v_Y": worst["v_in_over_v_Y"],
            "e_change_if_returned": math.sqrt(worst["e"] ** 2 + worst["vibration_fraction"]) / worst["e"] - 1.0}


def quasi_static_limit(records: list[dict]) -> dict:
    """Where the quasi-static assumption fails: for e, the contact time (both at the same P_max) and
    P_max (at the same v_in), the smallest v_in / v_Y at which the dynamic FE differs from the quasi-static FE at the same P_max by more than the
    estimated errors (twice the dynamic FE's, its mesh and time step, as the quasi-static path shares
    the mesh sizes, plus the path's sampling error; None: nowhere), the largest differences and the
    vibration energy left."""
    compared = [r for r in records if "dynamic_over_quasi_static" in r]
    if not compared:
        return {}
    estimated = all(r.get("e_rel_error_estimate") is not None for r in compared)
    out = {"error_estimated": estimated, "vibration": largest_vibration(records)}
    for key in ("e", "contact_time", "P_max"):         # P_max: at the same v_in
        beyond = [r["v_in_over_v_Y"] for r in compared if estimated and abs(r["dynamic_over_quasi_static"][key]) >
                  2.0 * r[f"{key}_rel_error_estimate"] + r["quasi_static"].get(f"{key}_rel_error_estimate", 0.0)]
        worst = max(compared, key=lambda r: abs(r["dynamic_over_quasi_static"][key]))
        out[f"{key}_fails_from_v_in_over_v_Y"] = min(beyond) if beyond else None
        out[f"largest_{key}_change"] = worst["dynamic_over_quasi_static"][key]
        out[f"largest_{key}_change_at_v_in_over_v_Y"] = worst["v_in_over_v_Y"]
    return out


def run_quasi_static(setup: ImpactSetup, rows: list[dict], cases: Path, *, workers: int = 1,
                     progress: Callable[[str], None] | None = None) -> tuple[list[dict], dict]:
    """The quasi-static FE path to each yielding fine impact's P_max (calib.studies.impact_quasistatic)
    through the sweep runner (finished ones in ``cases``); (rows, counts {computed, reused})."""
    from calib.studies import impact_quasistatic

    fine = [row for row in rows if row["variant"] == "fine" and row["P_max"] > setup.pair.P_Y]
    if setup.elastic or not fine:
        return [], {"computed": 0, "reused": 0}
    tasks = [impact_quasistatic.task_of(setup.material, setup.radius, row, setup.hardening, setup.kinematics)
             for row in fine]
    for task in tasks:
        hemisphere_mesh(SphereMeshSpec(**task["mesh"]).contact_zone)     # gmsh is one per process
    describe = (lambda row: f"v_in = {row['v_in']:g} m/s (quasi-static FE path): "
                + (f"e = {row['e']:.4f}, {row['wall_time_s']:.1f} s" if row["status"] == "ok" else row["error"]))
    swept = run_sweep(tasks, impact_quasistatic.run_task, cases, keep=lambda row: row.get("status") == "ok",
                      workers=workers, progress=progress, describe=describe)
    failed = [row for row in swept.rows if row["status"] != "ok"]
    if failed:
        raise ValueError(f"the quasi-static FE path of the impact at v_in = {failed[0]['v_in']:g} m/s failed: "
                         f"{failed[0]['error']}")
    return swept.rows, {"computed": swept.computed, "reused": swept.reused}


def reference_setup(**options) -> ImpactSetup:
    """The paper's aluminium sphere (nfdmodel.reference_case)."""
    return ImpactSetup(material=Material.reference(), radius=reference_case.R, **options)


def study_velocities(setup: ImpactSetup) -> tuple[float, ...]:
    """The study's velocities [m/s]: STUDY_VELOCITIES_OVER_V_Y x v_Y."""
    return tuple(k * setup.pair.v_Y for k in STUDY_VELOCITIES_OVER_V_Y)


def check_study_velocities(setup: ImpactSetup) -> None:
    """ValueError before any FE when ``study_velocities`` (the default of ``nfdcal impact``, multiples
    of the material's v_Y) are beyond the FE (``check_reach``): the input that decides it is the
    yield stress (whether they fit depends on E / sigma_Y, nu alone), so the refusal names --sigma-y
    and the range of it whose study fits, with E, nu, R as given, and the velocities the FE takes
    for this material (--v-in)."""
    try:
        with warnings.catch_warnings(record=True) as noted:    # a refusal is one line: noted, shown if it passes
            check_reach(setup, study_velocities(setup))
    except ValueError as exc:
        given = str(exc).split("need ", 1)[-1].rstrip(".")
    else:
        for note in noted:
            warnings.warn_explicit(note.message, note.category, note.filename, note.lineno)
        return

    def fits(sigma_y: float) -> bool:
        trial = dataclasses.replace(setup, material=dataclasses.replace(setup.material, sigma_y=sigma_y))
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")     # a trial material's estimate: not the user's news
                check_reach(trial, study_velocities(trial))
        except ValueError:
            return False
        return True

    sigma, E = setup.material.sigma_y, setup.material.E
    # a grid over the calibrated E / sigma_Y (calib.fit.recipe) inside the range of real solids
    ratio_low, ratio_high = recipe.E_OVER_SIGMA_Y_RANGE
    low, high = max(E / ratio_high, SOLID_RANGES["sigma_y"][0]), min(E / ratio_low, SOLID_RANGES["sigma_y"][1])
    grid = [low * (high / low) ** (k / 24) for k in range(25)] if high > low else []
    fitting = [s for s in grid if fits(s)]
    words = (f"--sigma-y out of range for the default velocities ({STUDY_VELOCITIES_OVER_V_Y[0]:g} .. "
             f"{STUDY_VELOCITIES_OVER_V_Y[-1]:g} v_Y, v_Y = {setup.pair.v_Y:.4g} m/s): at sigma_Y = {sigma:g} Pa")
    if not fitting:
        raise ValueError(f"{words} they go beyond the FE, and so they do at every --sigma-y the FE is calibrated for (E/sigma_Y {ratio_low:g} .. "
                         f"{ratio_high:g}) with E = {E:g} Pa, nu = "
                         f"{setup.material.nu:g}, R = {setup.radius:g} m: give --v-in: need {given}")
    side = ">=" if sigma < fitting[0] else "<="
    inside, outside = (fitting[0], sigma) if side == ">=" else (fitting[-1], sigma)
    for _ in range(20):                 # bisection in log sigma_Y to the edge of the fitting range
        middle = math.sqrt(inside * outside)
        inside, outside = (middle, outside) if fits(middle) else (inside, middle)
    raise ValueError(f"{words} they go beyond the FE: need --sigma-y {side} {bound_text(inside, side)} Pa for E = "
                     f"{E:g} Pa, nu = {setup.material.nu:g}, R = {setup.radius:g} m, or give --v-in: need {given}")


def study(setup: ImpactSetup, velocities, out: Path, *, workers: int = 1, progress: Callable[[str], None] | None = None,
          variants=VARIANTS, params_file=None, table_file=None, mdr_file=None, plots: bool = True,
          quasi_static: bool = True) -> list[dict]:
    """Run the impacts (finished ones reused from OUT/cases/) and, with ``quasi_static``, the
    quasi-static FE paths at their peak forces (OUT/quasi_static_cases/), and write the study's
    files into ``out`` as one set (calib.studies.impact_output); returns the per-velocity records.
    The laws are compared with the files given alone (module docstring: ``params_file``,
    ``table_file``, ``mdr_file``)."""
    from calib.studies import impact_output

    started = time.perf_counter()
    params, source = law_parameters(setup, params_file)      # a bad file is refused before any FE
    table, mdr = table_parameters(setup, table_file), mdr_table(setup, mdr_file)
    out = Path(out)
    rows, counts = run_impacts(setup, velocities, out / "cases", workers=workers, progress=progress, variants=variants)
    static, static_counts = (run_quasi_static(setup, rows, out / "quasi_static_cases", workers=workers,
                                              progress=progress) if quasi_static else ([], None))
    records = impact_records(setup, rows, params, table, static, mdr)
    pair = setup.pair
    fine = [row for row in rows if row["variant"] == "fine"]
    summary = {"case": {"E": setup.material.E, "nu": setup.material.nu,
                        "sigma_y": None if setup.elastic else setup.material.sigma_y, "rho": setup.material.rho,
                        "R": setup.radius, "mass": pair.mass_star, "P_Y": pair.P_Y, "v_Y": pair.v_Y,
                        "elastic": setup.elastic, "steps_per_contact": setup.steps_per_contact,
                        **({} if setup.hardening is None else {"hardening": setup.hardening.record()}),
                        **({} if setup.rate_law is None else {"rate_law": setup.rate_law.record()})},
               "vz_source": source, "vz_table_source": output.display_path(table_file) if table else None,
               "mdr_source": output.display_path(mdr_file) if mdr is not None else None,
               "variants": list(variants),
               "vibration": largest_vibration(records), "quasi_static": quasi_static_limit(records),
               "stamp": output.stamp(time.perf_counter() - started, mesh=fine[-1]["mesh"], **counts,
                                     fe_wall_time_s=sum(row["wall_time_s"] for row in rows),
                                     **({"quasi_static_" + k: v for k, v in static_counts.items()} if static_counts else {}))}
    with output.all_or_nothing(out, name="impact") as staging:
        impact_output.write(staging, records, rows, summary, plots)
    return records
