"""results/collision/: restitution, impact histories and time-step convergence of the runtime laws.

Regenerate with ``nfdcal collide --report [--out DIR]`` (default DIR = results/collision). Files:

* restitution.csv / .png   e (from velocities and from energies, paper eqs. 4.6, 4.7) against
                           v_in / v_Y for `vz` and `thornton`, 0.02 <= v_in <= 0.2 m/s, dt = 1e-6 s
                           (Vu-Quoc & Zhang 1999 fig. 20), with the exact energy-balance value and
                           Thornton's closed form (Thornton 1997, paper eq. 1.11); the impacts inside
                           the vz constants' calibrated window are shaded (in_calibrated_range);
* impact_v0.04.csv / .png  P-delta loop and P-t history at v_in = 0.04 m/s for both laws;
* dt_convergence.csv / .png  error of e and P_max (largest over the 10 velocities 0.02..0.2 m/s)
                           against the exact energy-balance reference, with wall time, for
                           dt = 1e-5 .. 1e-8 s (log-log);
* summary.json             stamp (commit, wall time), parameters and the headline numbers.
Reference case: nfdmodel.reference_case (aluminium sphere R = 0.1 m on a rigid flat), with Ca, Kc of the
reference calibration when it exists (else the paper's).
"""
from __future__ import annotations

import time
import warnings
from pathlib import Path

import numpy as np

from calib.output import (RESULTS, all_or_nothing, display_path, pyplot, save_figure, stamp, stamp_comment, write_csv,
                          write_json)
from nfdmodel import RangeWarning, VZParams, collide, collision_reference, limits
from nfdmodel.thornton import thornton_closed_form

DEFAULT_OUT = RESULTS / "collision"
LAWS = ("vz", "thornton")
SWEEP_VELOCITIES = np.round(np.linspace(0.02, 0.2, 19), 4)          # m/s
BENCH_VELOCITIES = np.linspace(0.02, 0.2, 10)                       # m/s
HISTORY_VELOCITY = 0.04                                             # m/s
PAPER_DT = 1e-6                                                     # s
DT_LADDER = (1e-5, 5e-6, 2e-6, 1e-6, 5e-7, 2e-7, 1e-7, 5e-8, 2e-8, 1e-8)


def _window_edge(x, over_window) -> float:
    """x where P_max / window's top crosses 1 (log-log interpolation between the sweep points);
    the last x when every impact stays inside, the first when none does."""
    inside = over_window <= 1.0
    if inside.all() or not inside.any():
        return float(x[-1] if inside.all() else x[0])
    k = int(np.argmin(inside))               # first impact beyond the window
    lx, ly = np.log(x[k - 1:k + 1]), np.log(over_window[k - 1:k + 1])
    return float(np.exp(lx[0] + (0.0 - ly[0]) * (lx[1] - lx[0]) / (ly[1] - ly[0])))




def generate(out_dir=DEFAULT_OUT, params_file=None, velocities=None) -> tuple[Path, str]:
    """Regenerate the collision results; returns (folder, the source of the vz parameters).

    The vz parameters are the two constants of ``params_file`` (a calibration's parameter file,
    whichever law it ships: calib.report.parameter_file.two_constant_law), else the paper's Ca, Kc;
    no other file is read. The source is named in summary.json and returned. ``velocities`` [m/s] replace the sweep of the paper's
    figure 20 (0.02 .. 0.2 m/s). The files are written all or nothing (calib.output.all_or_nothing)."""
    with all_or_nothing(out_dir, name="collision") as staging, warnings.catch_warnings():
        warnings.simplefilter("ignore", RangeWarning)   # the plots and CSVs show the window instead
        source = _generate(staging, params_file, velocities)
    return Path(out_dir), source


def _generate(out: Path, params_file, velocities) -> str:
    started = time.perf_counter()
    sweep = SWEEP_VELOCITIES if velocities is None else np.sort(np.asarray(velocities, dtype=float))
    if params_file is not None:
        from calib.report.parameter_file import two_constant_law

        params = two_constant_law(params_file)
    else:
        params = VZParams.reference()
    if params_file is None:
        params_source = "paper (Vu-Quoc & Zhang 1999)"
    else:  # repo-relative when inside the repo: results must not name local absolute paths
        resolved = Path(params_file).resolve()
        params_source = display_path(resolved)
    pair = params.pair
    v_Y = pair.v_Y
    summary: dict = {"case": {"R": pair.R_star, "E_star": pair.E_star, "nu": pair.nu,
                              "sigma_y": pair.sigma_y, "mass": pair.mass_star, "Ca": params.Ca,
                              "Kc": params.Kc, "A_Y": pair.A_Y, "P_Y": pair.P_Y, "a_Y": pair.a_Y,
                              "delta_Y": pair.delta_Y, "v_Y": v_Y},
                     "params_source": params_source, "newton_tolerance": limits.VZ_TOLERANCE}

    # 1. Restitution against v_in / v_Y (paper fig. 20).
    rows = []
    window_edge = None                   # v_in / v_Y where vz leaves its calibrated window
    for law in LAWS:
        result = collide(law, params, sweep, dt=PAPER_DT)
        if law == "vz" and result.in_calibrated_range is not None:
            summary["vz_window"] = {**params.window.record(), "in_calibrated_range": result.in_calibrated_range,
                                    "P_max_over_window": result.P_max_over_window}
            window_edge = _window_edge(sweep / v_Y, result.P_max_over_window)
        exact = collision_reference(law, params, sweep)
        closed = thornton_closed_form(sweep, v_Y) if law == "thornton" else None
        for i, v in enumerate(sweep):
            rows.append({"law": law, "v_in": v, "v_in_over_v_Y": v / v_Y,
                         "e_velocity": result.e_velocity[i], "e_energy": result.e_energy[i],
                         "e_exact": exact.restitution[i],
                         "e_thornton_closed_form": closed[i] if closed is not None else "",
                         "P_max": result.P_max[i], "delta_max": result.delta_max[i],
                         "in_calibrated_range": ("" if result.in_calibrated_range is None
                                                 else bool(result.in_calibrated_range[i])),
                         "delta_res": result.delta_res[i], "contact_time": result.contact_time[i],
                         "dt": result.dt})
        agreement = np.abs(result.e_velocity - result.e_energy) / result.e_energy
        summary[f"restitution_{law}"] = {
            "v_in": sweep, "e_velocity": result.e_velocity, "e_energy": result.e_energy,
            "e_exact": exact.restitution, "max_relative_difference_e_velocity_e_energy": agreement.max(),
            "max_relative_error_vs_exact": np.abs(result.e_velocity / exact.restitution - 1).max(),
            "dt": PAPER_DT}
    st = stamp(time.perf_counter() - started, dt=PAPER_DT)
    write_csv(out / "restitution.csv", rows, comment=stamp_comment(st))
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(6.4, 4.4))
    colors = {"vz": "C0", "thornton": "C3"}
    for law in LAWS:
        sel = [r for r in rows if r["law"] == law]
        x = np.array([r["v_in_over_v_Y"] for r in sel])
        ax.plot(x, [r["e_exact"] for r in sel], "-", color=colors[law], lw=1.2,
                label=f"{law}: exact (energy balance)")
        ax.plot(x, [r["e_velocity"] for r in sel], "o", color=colors[law], ms=4, mfc="none",
                label=f"{law}: -v_out/v_in (leap-frog, dt = 1e-6 s)")
        ax.plot(x, [r["e_energy"] for r in sel], "x", color=colors[law], ms=4,
                label=f"{law}: sqrt(unloading/loading area)")
    xs = np.linspace(sweep[0], sweep[-1], 200)
    ax.plot(xs / v_Y, thornton_closed_form(xs, v_Y), "k--", lw=0.8, label="Thornton closed form (eq. 1.11)")
    if window_edge is not None:
        ax.axvspan(min(sweep[0] / v_Y, window_edge), window_edge, color="C2", alpha=0.12, lw=0,
                   label=f"vz constants' calibrated window (P <= {params.window.P_max_over_P_Y:.3g} P_Y)")
    ax.set_xlabel("v_in / v_Y  (v_Y = %.3g m/s)" % v_Y)
    ax.set_ylabel("coefficient of restitution e")
    ax.set_title("Sphere on rigid flat, reference case (cf. Vu-Quoc & Zhang 1999 fig. 20)", fontsize=9)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7)
    save_figure(fig, out / "restitution.png")

    # Thornton's closed form over 2 <= v_in/v_Y <= 200 (the required agreement: 0.5 %).
    ratios = np.geomspace(2.0, 200.0, 12)
    thornton = collide("thornton", params, ratios * v_Y, dt=PAPER_DT)
    closed = thornton_closed_form(ratios * v_Y, v_Y)
    summary["thornton_closed_form_check"] = {
        "v_in_over_v_Y": ratios, "e_velocity": thornton.e_velocity, "e_closed_form": closed,
        "max_relative_error": np.abs(thornton.e_velocity / closed - 1).max(), "dt": PAPER_DT}

    # 2. P-delta loop and P-t history at 0.04 m/s.
    history_rows = []
    fig, (ax_loop, ax_time) = plt.subplots(1, 2, figsize=(10, 4))
    for law in LAWS:
        result = collide(law, params, [HISTORY_VELOCITY], dt=PAPER_DT, history=True)
        h = result.history
        for t, d, f in zip(h.time, h.delta[:, 0], h.force[:, 0]):
            history_rows.append({"law": law, "time": t, "delta": d, "force": f})
        contact = h.force[:, 0] > 0
        last = np.flatnonzero(contact)[-1] + 2
        ax_loop.plot(1e6 * h.delta[:last, 0], h.force[:last, 0], color=colors[law],
                     label=f"{law}: e = {result.e_velocity[0]:.4f}")
        ax_time.plot(1e3 * h.time[:last], h.force[:last, 0], color=colors[law],
                     label=f"{law}: P_max = {result.P_max[0]:.1f} N, t_c = {1e3 * result.contact_time[0]:.3f} ms")
        summary[f"impact_{law}_v0.04"] = {"e_velocity": result.e_velocity[0],
                                          "e_energy": result.e_energy[0], "P_max": result.P_max[0],
                                          "delta_max": result.delta_max[0],
                                          "delta_res": result.delta_res[0],
                                          "contact_time": result.contact_time[0]}
    ax_loop.set_xlabel("approach delta [um]")
    ax_loop.set_ylabel("contact force P [N]")
    ax_loop.set_title("P-delta loop, v_in = 0.04 m/s", fontsize=9)
    ax_time.set_xlabel("time [ms]")
    ax_time.set_ylabel("contact force P [N]")
    ax_time.set_title("P-t history, v_in = 0.04 m/s, dt = 1e-6 s", fontsize=9)
    for ax, where in ((ax_loop, "upper left"), (ax_time, "upper right")):
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7, loc=where)
    st = stamp(time.perf_counter() - started, dt=PAPER_DT, v_in=HISTORY_VELOCITY)
    write_csv(out / "impact_v0.04.csv", history_rows, comment=stamp_comment(st))
    save_figure(fig, out / "impact_v0.04.png")

    # 3. Error against run time for the 10-velocity sweep.
    convergence_rows = []
    for law in LAWS:
        exact = collision_reference(law, params, BENCH_VELOCITIES)
        for dt in DT_LADDER:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", RuntimeWarning)
                result = collide(law, params, BENCH_VELOCITIES, dt=dt)
            convergence_rows.append({
                "law": law, "dt": dt, "steps": result.steps, "wall_time_s": result.wall_time_s,
                "error_e_velocity": np.abs(result.e_velocity / exact.restitution - 1).max(),
                "error_e_energy": np.abs(result.e_energy / exact.restitution - 1).max(),
                "error_P_max": np.abs(result.P_max / exact.P_max - 1).max(),
                "max_newton_iterations": result.max_newton_iterations})
    summary["dt_convergence"] = convergence_rows
    st = stamp(time.perf_counter() - started, reference="exact energy balance (collision_reference)",
               velocities=BENCH_VELOCITIES)
    write_csv(out / "dt_convergence.csv", convergence_rows, comment=stamp_comment(st))
    fig, (ax_dt, ax_wall) = plt.subplots(1, 2, figsize=(10, 4))
    for law in LAWS:
        sel = [r for r in convergence_rows if r["law"] == law]
        dts = np.array([r["dt"] for r in sel])
        wall = np.array([r["wall_time_s"] for r in sel])
        for key, marker, name in (("error_e_velocity", "o", "e (velocity)"),
                                  ("error_e_energy", "x", "e (energy)"), ("error_P_max", "s", "P_max")):
            err = np.maximum([r[key] for r in sel], 1e-16)
            ax_dt.loglog(dts, err, marker + "-", color=colors[law], ms=4, mfc="none", lw=0.8,
                         label=f"{law}: {name}")
            ax_wall.loglog(wall, err, marker + "-", color=colors[law], ms=4, mfc="none", lw=0.8,
                           label=f"{law}: {name}")
    ax_dt.loglog(np.array(DT_LADDER), 2e-6 * (np.array(DT_LADDER) / 1e-6) ** 2, "k:", lw=0.8, label="slope 2")
    ax_dt.set_xlabel("time step dt [s]")
    ax_wall.set_xlabel("wall time of the 10-velocity sweep [s]")
    for ax in (ax_dt, ax_wall):
        ax.set_ylabel("max relative error vs exact reference")
        ax.grid(alpha=0.3, which="both")
        ax.legend(fontsize=6)
    ax_dt.set_title("Leap-frog convergence, v_in = 0.02..0.2 m/s", fontsize=9)
    ax_wall.set_title("Error against run time", fontsize=9)
    save_figure(fig, out / "dt_convergence.png")

    summary["stamp"] = stamp(time.perf_counter() - started, command="nfdcal collide --report")
    write_json(out / "summary.json", summary)
    return params_source
