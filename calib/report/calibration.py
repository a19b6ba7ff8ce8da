"""Writes a calibration to disk: the parameter file nfdmodel loads, per-step CSVs, plots, a VTU.

Everything is stamped (git commit, mesh, wall time) and written atomically (calib.report).
Files in ``out`` (default results/calibration):
  parameters.json        the shipped runtime parameters (nfdmodel.load_parameters reads it)
  calibration.json       the summary (``nfdcal calibrate --json``) with both fits and the paths
  loading.csv            one row per FE step of the shared loading branch, with a_e, a_p, C_R
  path_P<Pmax>.csv       one row per FE step of each path (loading then unloading)
  fit_window.csv         Ca, Kc against the largest load used in the fit
  *.png                  P-alpha with all models, radii, C_R, pressure, fit residuals, window
  state_peak.vtu, state_final.vtu  equivalent plastic strain, von Mises stress, contact pressure
"""
from __future__ import annotations

import tempfile
from pathlib import Path

import meshio
import numpy as np

from calib import output
from calib.fe.von_mises import von_mises_stress
from calib.fit.calibration import CalibrationResult, summary
from calib.report.parameter_file import write_parameter_file
from nfdmodel import reference_case
from nfdmodel.parameter_file import ERROR_KEYS

DEFAULT_OUT = output.RESULTS / "calibration"


def _derived_columns(rows: list[dict], result: CalibrationResult) -> list[dict]:
    """Rows with the contact-radius decomposition: a_e (Hertz at P), a_p, C_R (paper 3.4-3.6)."""
    pair = result.spec.pair
    out = []
    for r in rows:
        force = max(r["P"], 0.0)
        a_e = float(pair.hertz_radius(force)) if force > 0 else 0.0
        a_ep = r["contact_radius"]
        out.append({**r, "a_ep": a_ep, "a_e": a_e, "a_p": a_ep - a_e,
                    "C_R": a_ep**2 / (pair.R_star * r["alpha"]) if r["alpha"] > 0 and a_ep > 0 else 0.0})
    return out


def write_calibration_parameters(path, result: CalibrationResult, stamp: dict, rate_law: dict | None = None) -> Path:
    """The parameter file of a calibration: the shipped fit, both fits' figures, the FE errors; ``rate_law``:
    the "rate_law" entry of a rate-dependent sphere (nfdmodel.parameter_file.rate_law_entry), None without."""
    s = summary(result)
    fit = {"shipped": result.shipped,
           "why": {"radius": "radius: the paper's definition (least squares of a_p and C_R - 1 against "
                             "P - P_Y on the FE loading points)",
                   "force": "force: minimises the runtime law's force error along the FE P-alpha paths",
                   "table": "table: the vz-table law, load-dependent a_p and C_R from the FE loading curve "
                            "and the work each FE unloading returned (meets the FE's restitution at every "
                            "path)",
                   "unload": "unload: the vz-unload law, the vz-table loading curve with a_p from the FE's contact "
                             "radius, and the dent delta_res/delta_max and unloading exponent m from the FE "
                             "unloading paths (meets the FE's dent, contact radius, unloading curve and e)"}[result.shipped],
           "radius_fit": s["radius_fit"], "force_fit": s["force_fit"], "loading_only": s["loading_only"]}
    fe_errors = {"P_Y_fe_rel_error": s["P_Y_fe_rel_error"],
                 "paths": [{k: p[k] for k in ("P_max", "alpha_max", "e", "alpha_residual", "models")}
                           for p in s["paths"]]}
    errors = {key: s[key] for key in ERROR_KEYS}
    counter = result.spec.counter.describe() if result.spec.counter is not None else None
    return write_parameter_file(path, result.shipped_params, result.spec.radius, result.spec.material, fit,
                                stamp, counter, **errors, discretisation=s["discretisation"], fe_errors=fe_errors,
                                mesh=result.mesh_info, **({"hardening": s["hardening"]} if "hardening" in s else {}),
                                **({} if rate_law is None else {"rate_law": rate_law}))


def write_vtu(path: Path, solver, state, pressure_r=None, pressure=None) -> None:
    """Equivalent plastic strain and von Mises stress (element means), displacement and contact
    pressure (nodes) of one FE state, as a VTU of 6-node triangles that ParaView opens."""

    mesh = solver.hemisphere.mesh
    n_points = mesh.p.shape[1]
    u = state.displacement
    displacement = np.zeros((n_points, 3))
    displacement[:, 0] = u[solver.r_dof]
    displacement[:, 1] = u[solver.z_dof]
    contact_pressure = np.zeros(n_points)
    if pressure is not None:
        contact_pressure[solver.candidate_nodes] = np.interp(solver.candidate_r, pressure_r, pressure)
    stress = solver.stress(state)
    eps_p = getattr(state.material_state, "equivalent_plastic_strain", np.zeros(stress.shape[:2]))
    cells = np.vstack([mesh.t, mesh.t2f + mesh.nvertices]).T  # 3 vertices then 3 edge nodes
    points = np.column_stack([mesh.p.T, np.zeros(n_points)])
    out = meshio.Mesh(points, [("triangle6", cells)],
                      point_data={"displacement": displacement, "contact_pressure": contact_pressure},
                      cell_data={"equivalent_plastic_strain": [eps_p.mean(axis=1)],
                                 "von_mises_stress": [von_mises_stress(stress).mean(axis=1)]})
    with tempfile.TemporaryDirectory() as scratch:  # meshio writes a named file; the bytes go
        meshio.write(Path(scratch) / "state.vtu", out)  # through the one atomic writer
        output.atomic_write_bytes(path, (Path(scratch) / "state.vtu").read_bytes())


def _plots(result: CalibrationResult, out: Path, loading: list[dict]) -> None:
    plt = output.pyplot()
    pair = result.spec.pair
    colors = {"vz": "C3", "vz (force fit)": "C4", "vz (radius fit)": "C4", "vz-table": "C1", "thornton": "C2", "hertz": "C7"}

    fig, ax = plt.subplots(figsize=(7, 5))
    for k, path in enumerate(result.load_paths.paths):
        alpha = np.array([r["alpha"] for r in path.rows])
        force = np.array([r["P"] for r in path.rows])
        ax.plot(alpha * 1e6, force, "o", ms=3, color=f"C{k}", label=f"FE, P_max = {path.peak:g} N (e = {path.restitution:.3f})")
        for comparison in result.comparisons[path.peak]:
            ax.plot(alpha * 1e6, comparison.force, "-" if comparison.law == "vz" else "--", lw=1,
                    color=colors[comparison.law],
                    label=f"{comparison.law} (e = {comparison.restitution:.3f})" if k == len(result.load_paths.paths) - 1 else None)
    ax.set_xlabel("approach alpha [um]"); ax.set_ylabel("force P [N]")
    ax.set_title("Force-approach: FE against the runtime laws driven by the FE's alpha")
    ax.legend(fontsize=7); ax.grid(alpha=0.3)
    output.save_figure(fig, out / "force_approach.png")

    fig, ax = plt.subplots(figsize=(7, 5))
    P = np.array([r["P"] for r in loading])
    for key, label in (("a_ep", "a_ep (FE)"), ("a_e", "a_e (Hertz at P)"), ("a_p", "a_p = a_ep - a_e")):
        ax.plot(P, [r[key] * 1e3 for r in loading], "o-", ms=3, label=label)
    for k, path in enumerate(result.load_paths.paths):
        rows = _derived_columns([r for r in path.rows if r["branch"] == "unloading"], result)
        ax.plot([r["P"] for r in rows], [r["a_p"] * 1e3 for r in rows], "x--", ms=3, color=f"C{k + 3}",
                label=f"a_p on unloading from {path.peak:g} N")
    x = np.linspace(pair.P_Y, P.max(), 50)
    ax.plot(x, result.params.Ca * (x - pair.P_Y) * 1e3, "k-", lw=1, label=f"Ca (P - P_Y), Ca = {result.params.Ca:.3e} m/N")
    ax.set_xlabel("P [N]"); ax.set_ylabel("radius [mm]"); ax.legend(fontsize=7); ax.grid(alpha=0.3)
    ax.set_title("Contact radius decomposition (loading)")
    output.save_figure(fig, out / "contact_radii.png")

    fig, ax = plt.subplots(figsize=(7, 5))
    ax.plot(P, [r["C_R"] for r in loading], "o", ms=3, label="C_R = a_ep^2 / (R alpha), FE")
    ax.plot(x, 1 + result.params.Kc * (x - pair.P_Y), "k-", lw=1, label=f"1 + Kc (P - P_Y), Kc = {result.params.Kc:.3e} 1/N")
    ax.plot(x, 1 + reference_case.KC * (x - pair.P_Y), "k:", lw=1, label=f"paper, Kc = {reference_case.KC:.3g} 1/N")
    ax.set_xlabel("P [N]"); ax.set_ylabel("C_R [-]"); ax.legend(fontsize=8); ax.grid(alpha=0.3)
    output.save_figure(fig, out / "curvature_factor.png")

    fig, ax = plt.subplots(figsize=(7, 5))
    for k, (peak, (r, p)) in enumerate(sorted(result.load_paths.pressure_profiles.items())):
        ax.plot(r * 1e3, p / 1e6, "o-", ms=2, color=f"C{k}", label=f"FE, P = {peak:g} N")
        a = float(pair.hertz_radius(peak))
        rr = np.linspace(0, a, 100)
        ax.plot(rr * 1e3, pair.hertz_pressure(rr, peak) / 1e6, "--", color=f"C{k}", lw=1,
                label=f"Hertz, P = {peak:g} N")
    ax.axhline(pair.p_Y / 1e6, color="k", lw=0.8, ls=":", label="A_Y sigma_Y")
    ax.set_xlim(0, 1.2 * max(result.radius_data.contact_radius) * 1e3)
    ax.set_xlabel("r [mm]"); ax.set_ylabel("contact pressure [MPa]"); ax.legend(fontsize=7); ax.grid(alpha=0.3)
    output.save_figure(fig, out / "pressure.png")

    data, fit = result.radius_data, result.radius_fit
    mask = data.excess_force > 0
    fig, axes = plt.subplots(1, 2, figsize=(10, 4))
    axes[0].plot(data.force[mask], (data.plastic_radius[mask] - fit.Ca.slope * data.excess_force[mask]) * 1e6, "o", ms=3)
    axes[0].set_title(f"a_p residual, Ca fit (R^2 = {fit.Ca.r_squared:.4f})"); axes[0].set_ylabel("[um]")
    axes[1].plot(data.force[mask], data.curvature_factor[mask] - 1 - fit.Kc.slope * data.excess_force[mask], "o", ms=3)
    axes[1].set_title(f"C_R residual, Kc fit (R^2 = {fit.Kc.r_squared:.4f})")
    for a in axes:
        a.set_xlabel("P [N]"); a.axhline(0, color="k", lw=0.8); a.grid(alpha=0.3)
    output.save_figure(fig, out / "fit_residuals.png")

    fig, axes = plt.subplots(1, 2, figsize=(10, 4))
    w = result.window
    axes[0].errorbar([r["P_fit_max"] for r in w], [r["Ca"] for r in w], yerr=[r["Ca_se"] for r in w], fmt="o-", ms=3)
    axes[0].axhline(reference_case.CA, color="k", ls=":", label="paper"); axes[0].set_ylabel("Ca [m/N]")
    axes[1].errorbar([r["P_fit_max"] for r in w], [r["Kc"] for r in w], yerr=[r["Kc_se"] for r in w], fmt="o-", ms=3)
    axes[1].axhline(reference_case.KC, color="k", ls=":", label="paper"); axes[1].set_ylabel("Kc [1/N]")
    for a in axes:
        a.set_xlabel("largest load in the fit [N]"); a.legend(); a.grid(alpha=0.3)
    output.save_figure(fig, out / "fit_window.png")


def write(result: CalibrationResult, out: str | Path = DEFAULT_OUT, plots: bool = True,
          vtu: bool = True, rate_law: dict | None = None) -> Path:
    """Write the calibration outputs to ``out`` (see the module docstring), all or nothing: a
    failure part way (a plot, a full disk) leaves the folder as it was. The files of a previous
    calibration in ``out`` that this one does not write are removed; other files stay. ``rate_law``:
    the parameter file's "rate_law" entry (write_calibration_parameters)."""
    with output.all_or_nothing(out, name="calibration") as staging:
        _write(result, staging, plots, vtu, rate_law)
    return Path(out)


def _write(result: CalibrationResult, out: Path, plots: bool, vtu: bool, rate_law: dict | None = None) -> None:
    stamp = output.stamp(result.wall_time_s, mesh=result.mesh_info, timings=result.timings)
    comment = output.stamp_comment(stamp)
    write_calibration_parameters(out / "parameters.json", result, stamp, rate_law)
    output.write_json(out / "calibration.json", {**summary(result), "stamp": stamp})
    loading = _derived_columns(result.load_paths.loading_rows, result)
    output.write_csv(out / "loading.csv", loading, comment=comment)
    for path in result.load_paths.paths:
        output.write_csv(out / f"path_P{path.peak:g}.csv", _derived_columns(path.rows, result), comment=comment)
    output.write_csv(out / "fit_window.csv", result.window, comment=comment)
    if plots:
        _plots(result, out, loading)
    solver = result.solver
    if vtu and solver is not None:
        last = result.load_paths.paths[-1]
        r, p = result.load_paths.pressure_profiles[last.peak]
        write_vtu(out / "state_peak.vtu", solver, last.peak_state, r, p)
        write_vtu(out / "state_final.vtu", solver, result.load_paths.final_state)
