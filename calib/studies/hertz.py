"""Hertz-limit validation of the FE contact solver (the paper's figures 8 and 9).

An elastic sphere (R, E, nu) pressed on a rigid frictionless flat, force-controlled from P_min to
P_max; at every load the FE contact radius a, approach alpha and peak pressure p0 are compared
with Hertz (Johnson 1985, Contact Mechanics, eqs. 4.22-4.23; nfdmodel.ContactPair computes them):
    E* = E / (1 - nu^2),  a = (3 P R / (4 E*))^(1/3),  alpha = a^2 / R,
    p0 = 3 P / (2 pi a^2),  p(r) = p0 sqrt(1 - r^2 / a^2).

The FE body is a hemisphere whose top face z = R is held by a rigid plate, not a half-space:
its approach is smaller than Hertz's by about k P / (E* R) with k a constant of the geometry
(it does not shrink with the mesh; ``finite_size_coefficient`` measures it), i.e. a relative
deficit growing like a / R (0.3 % at 1500 N for the reference sphere).
"""
from __future__ import annotations

import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from calib import output
from calib.fe import ContactSolver, run_load_path
from calib.fe.elastic import ElasticMaterial
from calib.fit.recipe import contact_pair, hertz_mesh, mesh_for
from nfdmodel.reference_case import is_reference_sphere
from meshes.hemisphere import hemisphere_mesh
from nfdmodel import ContactPair, Material, reference_case


# --------------------------------------------------------------------------- run
@dataclass
class HertzRun:
    """Result of ``run_hertz``: per-load rows, the top-load pressure profile, timings [s]."""
    rows: list
    top_load: dict
    pressure_profile: dict = field(repr=False)
    mesh: dict = field(default_factory=dict)
    finite_size_coefficient: float = float("nan")
    time_mesh_s: float = 0.0
    time_setup_s: float = 0.0
    time_steps_s: float = 0.0
    wall_time_s: float = 0.0


def default_loads(P_min=1.0, P_max=1500.0, steps=25):
    """Geometrically spaced loads [N] (a ~ P^(1/3) is then evenly refined on a log scale)."""
    return np.geomspace(P_min, P_max, steps)


def hertz_spec(material: Material, radius: float, top_load: float,
               contact_size: float | None = None, counter=None):
    """The sphere's mesh of a Hertz run to ``top_load`` [N] (calib.fit.recipe.hertz_mesh; with a
    counter-body, calib.fit.counter.CounterBody, mesh_for at the pair's Hertz radius)."""
    if counter is not None:
        return mesh_for(radius, float(counter.pair(material, radius).hertz_radius(top_load)),
                        contact_size=contact_size)
    return hertz_mesh(ContactPair.sphere_flat(material, radius), top_load, contact_size=contact_size,
                      reference=is_reference_sphere(material.E, material.nu, radius))


def run_hertz(spec=None, *, material: Material | None = None, radius: float = reference_case.R,
              loads=None, cache_dir=None, contact_radius_method="pressure",
              linear_solver=None, counter=None) -> HertzRun:
    """Force-controlled elastic FE run of ``material`` (E, nu; the reference aluminium by default)
    on a sphere of radius R [m], compared with Hertz at every load [N]. ``counter``: an elastic
    counter-body (calib.fit.counter.CounterBody, its sigma_Y unused) instead of the rigid flat, the
    two-body FE (calib.fe.two_body) compared with Hertz of the pair's E* and R*.

    ``spec``: meshes.hemisphere.HemisphereMeshSpec (default: ``hertz_spec``). Returns a HertzRun;
    raises ValueError on bad input and calib.fe.StepNotConverged if a step fails.
    """
    t_start = time.perf_counter()
    material = material or Material.reference()
    pair = contact_pair(material, radius, counter)
    loads = default_loads() if loads is None else np.asarray(loads, dtype=float)
    if loads.ndim != 1 or loads.size < 1 or not np.all(np.isfinite(loads)) or np.any(loads <= 0):
        raise ValueError("loads must be a non-empty list of finite forces > 0 [N]")
    if spec is None:
        spec = hertz_spec(material, radius, float(loads.max()), counter=counter)
    elif spec.radius != radius:
        raise ValueError(f"mesh radius {spec.radius} m differs from the sphere radius R = {radius} m")
    a_top = float(pair.hertz_radius(loads.max()))
    if a_top > spec.refined_radius:
        raise ValueError(f"P_max gives a Hertz contact radius {a_top:.3g} m beyond the mesh's "
                         f"refined_radius {spec.refined_radius:.3g} m: lower P_max")

    t0 = time.perf_counter()
    if counter is None:
        hemisphere = hemisphere_mesh(spec, cache_dir=cache_dir)
    else:
        from meshes.counter_body import pair_mesh

        hemisphere = pair_mesh(spec, counter.mesh_spec(spec), cache_dir=cache_dir)
    time_mesh = time.perf_counter() - t0
    t0 = time.perf_counter()
    if counter is None:
        solver = ContactSolver(hemisphere, ElasticMaterial(material.E, material.nu),
                               contact_radius_method=contact_radius_method, linear_solver=linear_solver)
    else:
        from calib.fe.two_body import TwoBodySolver

        solver = TwoBodySolver(hemisphere, ElasticMaterial(material.E, material.nu),
                               ElasticMaterial(counter.E, counter.nu), contact_radius_method=contact_radius_method,
                               linear_solver=linear_solver)
    time_setup = time.perf_counter() - t0
    t0 = time.perf_counter()
    results, _ = run_load_path(solver, loads, control="force")
    time_steps = time.perf_counter() - t0

    rows = []
    for res in results:
        rec = res.record
        a_h = float(pair.hertz_radius(rec.P))
        alpha_h = float(pair.hertz_approach(rec.P))
        p0_h = float(pair.hertz_peak_pressure(rec.P))
        row = rec.as_dict()
        row.update(contact_radius_hertz=a_h, alpha_hertz=alpha_h, peak_pressure_hertz=p0_h,
                   contact_radius_rel_error=rec.contact_radius / a_h - 1.0,
                   contact_radius_gap_rel_error=rec.contact_radius_gap / a_h - 1.0,
                   contact_radius_pressure_rel_error=rec.contact_radius_pressure / a_h - 1.0,
                   contact_radius_node_rel_error=rec.contact_radius_node / a_h - 1.0,
                   peak_pressure_rel_error=rec.peak_pressure / p0_h - 1.0,
                   alpha_rel_error=rec.alpha / alpha_h - 1.0,
                   force_rel_error=rec.P / rec.target - 1.0,
                   contact_force_rel_error=rec.contact_force / rec.P - 1.0)
        rows.append(row)

    # finite-size deficit of the approach: alpha_H - alpha = k P / (E* R)  (least squares)
    P = np.array([r["P"] for r in rows])
    deficit = np.array([r["alpha_hertz"] - r["alpha"] for r in rows])
    x = P / (pair.E_star * radius)
    k = float(x @ deficit / (x @ x))

    top = rows[-1]
    r = results[-1].pressure_r
    inside = r <= 1.5 * top["contact_radius_hertz"]
    profile = {"r": r[inside], "pressure": results[-1].pressure[inside],
               "pressure_hertz": pair.hertz_pressure(r[inside], top["P"])}
    wall = time.perf_counter() - t_start
    top_load = {"P": top["P"], "alpha": top["alpha"], "contact_radius": top["contact_radius"],
                "contact_radius_hertz": top["contact_radius_hertz"],
                "contact_radius_rel_error": top["contact_radius_rel_error"],
                "peak_pressure": top["peak_pressure"],
                "peak_pressure_hertz": top["peak_pressure_hertz"],
                "peak_pressure_rel_error": top["peak_pressure_rel_error"],
                "alpha_hertz": top["alpha_hertz"], "alpha_rel_error": top["alpha_rel_error"],
                "contact_force_rel_error": top["contact_force_rel_error"],
                "wall_time_s": wall}
    mesh = {**spec.describe(), **({"counter": counter.mesh_spec(spec).describe()} if counter is not None else {}),
            "n_elements": int(solver.n_elements), "n_dofs": int(solver.n_dofs),
            "n_contact_candidates": int(solver.candidate_r.size),
            "build_or_load_time_s": hemisphere.build_time_s}
    return HertzRun(rows=rows, top_load=top_load, pressure_profile=profile, mesh=mesh,
                    finite_size_coefficient=k, time_mesh_s=time_mesh, time_setup_s=time_setup,
                    time_steps_s=time_steps, wall_time_s=wall)


# --------------------------------------------------------------------------- ladder
LADDER_CONTACT_SIZES = (1.6e-4, 8e-5, 4e-5, 2e-5, 1e-5)


def run_ladder(contact_sizes=LADDER_CONTACT_SIZES, *, cache_dir=None, loads=None,
               material: Material | None = None, radius: float = reference_case.R, **kwargs):
    """``run_hertz`` on a ladder of contact element sizes (other mesh parameters default).

    Returns rows: contact_size, n_dofs, errors at the top load for each contact-radius
    recovery, peak pressure and alpha errors, finite-size coefficient, wall times [s].
    The max-abs contact radius errors are over the loads above 36.45 N (the reference P_Y).
    """
    material = material or Material.reference()
    top_load = float(np.max(default_loads() if loads is None else loads))
    rows = []
    for h in contact_sizes:
        spec = hertz_spec(material, radius, top_load, contact_size=h * radius / reference_case.R)
        run = run_hertz(spec, material=material, loads=loads, cache_dir=cache_dir, radius=radius, **kwargs)
        top = run.rows[-1]
        rows.append({"contact_size": h, "n_elements": run.mesh["n_elements"],
                     "n_dofs": run.mesh["n_dofs"], "P": top["P"],
                     "contact_radius_gap_rel_error": top["contact_radius_gap_rel_error"],
                     "contact_radius_pressure_rel_error": top["contact_radius_pressure_rel_error"],
                     "contact_radius_node_rel_error": top["contact_radius_node_rel_error"],
                     "contact_radius_gap_max_abs_error_m": max(
                         abs(r["contact_radius_gap"] - r["contact_radius_hertz"])
                         for r in run.rows if r["P"] >= 36.45),
                     "contact_radius_pressure_max_abs_error_m": max(
                         abs(r["contact_radius_pressure"] - r["contact_radius_hertz"])
                         for r in run.rows if r["P"] >= 36.45),
                     "peak_pressure_rel_error": top["peak_pressure_rel_error"],
                     "alpha_rel_error": top["alpha_rel_error"],
                     "finite_size_coefficient": run.finite_size_coefficient,
                     "factorizations": sum(r["factorizations"] for r in run.rows),
                     "time_mesh_s": run.time_mesh_s, "time_setup_s": run.time_setup_s,
                     "time_steps_s": run.time_steps_s, "wall_time_s": run.wall_time_s})
    return rows


# --------------------------------------------------------------------------- results/
def write_hertz_results(out, *, material: Material | None = None, radius: float = reference_case.R,
                        P_min=1.0, P_max=1500.0, steps=25, contact_size=None, cache_dir=None, counter=None):
    """Run the validation and write JSON + CSV + PNG into ``out``; returns the JSON summary.
    ``counter``: an elastic counter-body instead of the rigid flat (run_hertz)."""

    out = Path(out)
    material = material or Material.reference()
    E, nu = material.E, material.nu
    spec = hertz_spec(material, radius, P_max, contact_size, counter=counter)
    run = run_hertz(spec, material=material, radius=radius, loads=default_loads(P_min, P_max, steps),
                    cache_dir=cache_dir, counter=counter)
    run_pair = contact_pair(material, radius, counter)
    stamp = output.stamp(run.wall_time_s, mesh=run.mesh, time_mesh_s=run.time_mesh_s,
                         time_setup_s=run.time_setup_s, time_steps_s=run.time_steps_s,
                         time_assembly_s=sum(r["time_assembly_s"] for r in run.rows),
                         time_solve_s=sum(r["time_solve_s"] for r in run.rows))
    summary = {"case": {"radius": radius, "E": E, "nu": nu, "P_min": P_min, "P_max": P_max,
                        "steps": steps, "material": "linear elastic", "control": "force",
                        **({"counter_body": counter.describe(), "E_star": run_pair.E_star, "R_star": run_pair.R_star}
                           if counter is not None else {})},
               "top_load": run.top_load,
               "alpha_finite_size": {
                   "coefficient_k": run.finite_size_coefficient,
                   "model": "alpha_hertz - alpha_fe = k P / (E* R) (hemisphere with rigid top "
                            "is stiffer than a half-space; mesh-independent, see mesh_ladder.csv)"},
               "max_abs_contact_radius_error_m_above_36N": max(
                   (abs(r["contact_radius"] - r["contact_radius_hertz"]) for r in run.rows
                    if r["P"] >= 36.45), default=None),      # None: no load reaches 36.45 N
               "residual_tolerance": run.rows[-1]["residual_tolerance"],
               "factorizations": sum(r["factorizations"] for r in run.rows),
               "steps": run.rows, "stamp": stamp}
    output.write_json(out / "hertz.json", summary)
    output.write_csv(out / "hertz_steps.csv", run.rows, comment=output.stamp_comment(stamp))
    profile_rows = [dict(r=float(r), pressure=float(p), pressure_hertz=float(ph))
                    for r, p, ph in zip(run.pressure_profile["r"], run.pressure_profile["pressure"],
                                        run.pressure_profile["pressure_hertz"])]
    output.write_csv(out / "pressure_profile.csv", profile_rows,
                     comment=output.stamp_comment(stamp))
    plot_hertz(out, run, material, radius, counter)
    return summary


def plot_hertz(out, run, material: Material, radius: float, counter=None):
    """contact_radius.png, approach.png, peak_pressure.png (FE and Hertz against P, and the
    relative error) and pressure_profile.png (at the top load) into ``out``."""

    pair = contact_pair(material, radius, counter)
    E, nu = material.E, material.nu
    plt = output.pyplot()
    P = np.array([r["P"] for r in run.rows])
    Pf = np.geomspace(P.min(), P.max(), 200)
    h = run.mesh["contact_size"]
    label = f"FE (P2, h = {h:.2g} m)"
    for name, key, fn, ylabel in (
            ("contact_radius", "contact_radius", pair.hertz_radius, "contact radius a [m]"),
            ("approach", "alpha", pair.hertz_approach, "approach alpha [m]"),
            ("peak_pressure", "peak_pressure", pair.hertz_peak_pressure, "peak pressure p0 [Pa]")):
        fig, (ax, ax_err) = plt.subplots(2, 1, figsize=(6, 6), sharex=True,
                                         gridspec_kw={"height_ratios": [3, 1]})
        ax.plot(Pf, fn(Pf), "k-", label="Hertz")
        ax.plot(P, [r[key] for r in run.rows], "o", mfc="none", label=label)
        ax.set_xscale("log"), ax.set_yscale("log"), ax.set_ylabel(ylabel), ax.legend()
        ax.set_title(f"Sphere on rigid flat, R = {radius} m, E = {E:.3g} Pa, nu = {nu}" if counter is None else
                     f"Sphere R = {radius} m, E = {E:.3g} Pa, nu = {nu}; E* = {pair.E_star:.3g} Pa, "
                     f"R* = {pair.R_star:.3g} m", fontsize=9)
        ax_err.semilogx(P, [100 * r[f"{key}_rel_error"] for r in run.rows], "o-", ms=3)
        ax_err.axhline(0, color="k", lw=0.5)
        ax_err.set_xlabel("P [N]"), ax_err.set_ylabel("FE / Hertz - 1 [%]")
        output.save_figure(fig, out / f"{name}.png")
    prof = run.pressure_profile
    top = run.top_load
    fig, ax = plt.subplots(figsize=(6, 4))
    rr = np.linspace(0, prof["r"].max(), 400)
    ax.plot(rr * 1e3, pair.hertz_pressure(rr, top["P"]) / 1e6, "k-", label="Hertz")
    ax.plot(prof["r"] * 1e3, prof["pressure"] / 1e6, "o", ms=3, mfc="none",
            label=f"FE nodal pressure (lumped), {label}")
    ax.axvline(top["contact_radius"] * 1e3, color="C1", ls="--", lw=1,
               label=f"FE contact radius ({100 * top['contact_radius_rel_error']:+.3f} %)")
    ax.set_xlabel("r [mm]"), ax.set_ylabel("contact pressure p [MPa]")
    ax.set_title(f"Pressure at P = {top['P']:.0f} N")
    ax.legend(fontsize=8)
    output.save_figure(fig, out / "pressure_profile.png")


def write_ladder_results(out, *, contact_sizes=LADDER_CONTACT_SIZES, material: Material | None = None,
                         radius: float = reference_case.R, P_min=1.0, P_max=1500.0, steps=25,
                         cache_dir=None):
    """Mesh ladder: CSV + log-log PNG of |error| against wall time; returns a summary."""

    out = Path(out)
    t0 = time.perf_counter()
    material = material or Material.reference()
    rows = run_ladder(contact_sizes, cache_dir=cache_dir, radius=radius, material=material,
                      loads=default_loads(P_min, P_max, steps))
    default_h = hertz_spec(material, radius, P_max).contact_size
    stamp = output.stamp(time.perf_counter() - t0, mesh={"ladder_contact_sizes": list(contact_sizes),
                                                         "default_contact_size": default_h})
    output.write_csv(out / "mesh_ladder.csv", rows, comment=output.stamp_comment(stamp))
    plt = output.pyplot()
    fig, (ax, ax_abs) = plt.subplots(1, 2, figsize=(12, 4.5))
    t = np.array([r["wall_time_s"] for r in rows])
    default_t = [r["wall_time_s"] for r in rows if r["contact_size"] == default_h]
    for key, lab, mk in (("contact_radius_pressure_rel_error", "a, pressure-fit edge (default)", "o"),
                         ("contact_radius_gap_rel_error", "a, gap-fit edge", "s"),
                         ("contact_radius_node_rel_error", "a, outermost contact node", "x"),
                         ("peak_pressure_rel_error", "p0 (finite-size physics)", "^"),
                         ("alpha_rel_error", "alpha (finite-size physics)", "v")):
        ax.loglog(t, [abs(r[key]) for r in rows], marker=mk, label=lab)
    for r in rows:
        ax.annotate(f"h={r['contact_size']:.1e}\n{r['n_dofs']} dofs", (r["wall_time_s"], 2e-6),
                    fontsize=6, ha="center")
    ax.set_xlabel("wall time of the run (mesh + 25 force steps) [s]")
    ax.set_ylabel(f"|FE / Hertz - 1| at P = {P_max:g} N")
    ax.set_ylim(1e-6, 1e-1)
    for key, lab, mk in (("contact_radius_pressure_max_abs_error_m", "pressure-fit edge (default)", "o"),
                         ("contact_radius_gap_max_abs_error_m", "gap-fit edge", "s")):
        ax_abs.loglog(t, [r[key] for r in rows], marker=mk, label=lab)
    ax_abs.axhline(1e-6, color="r", ls="--", lw=1, label="1e-6 m (needed by the Ca/Kc fit)")
    ax_abs.set_xlabel("wall time of the run [s]")
    ax_abs.set_ylabel("max |a_FE - a_Hertz| over P >= 36.45 N [m]")
    for a_ in (ax, ax_abs):
        if default_t:
            a_.axvline(default_t[0], color="k", ls=":", lw=1, label="default mesh")
        a_.legend(fontsize=7)
    output.save_figure(fig, out / "mesh_ladder.png")
    return {"rows": rows, "default_choice": {"contact_size": default_h}, "stamp": stamp}
