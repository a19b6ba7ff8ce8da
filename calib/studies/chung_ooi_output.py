"""The files of calib.studies.chung_ooi: chung_ooi.csv (one row per impact), chung_ooi.json (per test
and material: the errors against the closed forms and the LAMMPS agreement, test 4 against the paper's
digitised curves; stamped), chung_ooi_paper.csv (one row per digitised point of test 4: the paper's value,
ours, the difference; calib.studies.chung_ooi_paper), chung_ooi.png.

Agreement of two runs of the same impacts (nfdmodel, the plugin, granular): the largest difference
of the final velocities (both bodies) over the case's largest speed, and of the final spins over
that speed / R_i.
"""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from calib import output
from calib.report.index_format import g, read_json, study_header, table



def agreement(a: np.ndarray, b: np.ndarray, case) -> float:
    """Largest difference of (impacts, 4, 3) velocities and spins, scaled (module doc)."""
    speed = float(np.max(case.speed))
    scale = np.array([speed, speed, speed / case.R, speed / case.R])[None, :, None]
    return float(np.max(np.abs(a - b) / scale))


def relative(a, b) -> float:
    a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    keep = np.isfinite(a) & np.isfinite(b)
    return float(np.max(np.abs(a[keep] / b[keep] - 1.0))) if keep.any() else math.nan


def largest(values) -> float | None:
    """The largest magnitude of the finite values, None when there is none."""
    values = np.asarray(values, dtype=float)
    values = values[np.isfinite(values)]
    return float(np.max(np.abs(values))) if values.size else None


def case_summary(entry: dict) -> dict:
    """Per test and material: the errors against the closed forms (module doc of chung_ooi_cases)."""
    case, model, ref = entry["case"], entry["nfdmodel"], entry["reference"]
    speed = float(np.max(case.speed))
    out = {"test": case.test, "material": case.material, "impacts": int(case.speed.size), "dt_s": entry["dt"],
           "mu": case.mu}
    if case.test in (1, 2):
        out |= {"delta_max_m": float(model["delta_max"][0]), "F_max_N": float(model["P_max"][0]),
                "t_c_s": float(model["contact_time"][0]), "e_n": float(model["e_n"][0]),
                "delta_max_error": relative(model["delta_max"], ref["delta_max"]),
                "F_max_error": relative(model["P_max"], ref["F_max"]),
                "t_c_error": relative(model["contact_time"], ref["t_c"]), "e_n_error": largest(model["e_n"] - 1.0)}
    if case.test == 3:
        out |= {"e_in": case.restitution.tolist(), "e_out": model["e_n"].tolist(),
                "e_out_minus_e_in": largest(model["e_n"] - case.restitution)}
    if case.test >= 4:
        slid, stuck = ref["slid_throughout"], ref["stuck"]
        out |= {"slid_throughout": int(slid.sum()), "stuck": int(stuck.sum()),
                "sliding_v_t_error": largest((model["v_t_out"] - ref["v_t_out_sliding"])[slid] / speed),
                "sliding_omega_error": largest((model["omega_out"] - ref["omega_out_sliding"])[slid] * case.R / speed),
                "no_slip_beta_error": largest((model["beta"] - ref["beta_no_slip"])[stuck]) if stuck.any() else None,
                "e_n_error": largest(model["e_n"] - 1.0), "largest_normal_turn_rad": largest(model["normal_turn"])}
    if case.test == 7:
        out |= {"v_t_out_largest": largest(model["v_t_out"]) / speed,
                "omega_change_largest": largest((model["omega_out"] - case.omega) / case.omega)}
    energy = model["kinetic_energy_lost"] - model["work_normal"] - model["work_friction"]
    out["energy_balance_error"] = largest(energy / (0.5 * case.pair().mass_star * case.speed ** 2))
    if "lammps" in entry:
        plugin, gran = entry["lammps"]["nfd/hertz"]["velocities"], entry["lammps"]["granular"]["velocities"]
        out |= {"plugin_vs_nfdmodel": agreement(plugin, model["velocities"], case),
                "plugin_vs_granular": agreement(plugin, gran, case),
                "granular_vs_nfdmodel": agreement(gran, model["velocities"], case)}
    return out


def plastic_summary(entry: dict) -> dict:
    case, model = entry["case"], entry["nfdmodel"]
    with np.errstate(divide="ignore"):
        psi = np.tan(np.radians(case.angle)) / (case.mu * (1.0 + model["e_n"]))
    slid = model["slid_throughout"]
    out = {"speed_m_s": float(case.speed[0]), "dt_s": entry["dt"], "mu": case.mu,
           "P_max_over_P_Y": [float(model["P_max_over_P_Y"].min()), float(model["P_max_over_P_Y"].max())],
           "e_n_head_on": float(model["e_n_head_on"][0]), "e_n_angle_spread": float(np.ptp(model["e_n"])),
           "e_n_minus_head_on": largest(model["e_n"] - model["e_n_head_on"]),
           "slid_throughout": int(slid.sum()),
           "sliding_e_t_error": largest((model["e_t"] - (1.0 - 1.0 / np.where(slid, psi, 1.0)))[slid])}
    if "lammps" in entry:
        out["plugin_vs_nfdmodel"] = agreement(entry["lammps"]["nfd/vz"]["velocities"], model["velocities"], case)
    return out


def case_line(entry: dict) -> str:
    s = case_summary(entry)
    keys = [k for k in s if k.endswith(("_error", "_vs_nfdmodel", "_vs_granular")) and s[k] is not None]
    keys += ["e_out_minus_e_in"] if "e_out_minus_e_in" in s else []
    return f"test {s['test']} {s['material']}: " + ", ".join(f"{k} {s[k]:.2e}" for k in keys)


def plastic_line(entry: dict) -> str:
    s = plastic_summary(entry)
    keys = [k for k in s if k.endswith(("_error", "_vs_nfdmodel", "_head_on")) and s[k] is not None]
    return f"plastic {s['speed_m_s']:g} m/s: " + ", ".join(f"{k} {s[k]:.3g}" for k in keys)


COLUMNS = ["test", "material", "variable", "value", "speed", "angle", "omega", "omega_partner", "e_n", "e_t", "beta",
           "angle_out", "v_t_out", "omega_out", "omega_partner_out", "P_max", "delta_max", "contact_time",
           "slid_throughout", "stuck", "ref_e_n", "ref_delta_max", "ref_F_max", "ref_t_c", "ref_v_t_out_sliding",
           "ref_omega_out_sliding", "ref_beta_no_slip", "plugin_vs_nfdmodel", "plugin_vs_granular"]


def rows(elastic: list[dict], plastic: list[dict]) -> list[dict]:
    out = []
    for entry in elastic + plastic:
        case, model = entry["case"], entry["nfdmodel"]
        ref = entry.get("reference", {})
        for k in range(case.speed.size):
            row = {"test": case.test if "reference" in entry else f"{case.test} plastic {case.speed[0]:g} m/s",
                   "material": case.material, "variable": case.variable, "value": float(case.values[k]),
                   "speed": float(case.speed[k]), "angle": float(case.angle[k]), "omega": float(case.omega[k]),
                   "omega_partner": float(case.omega_partner[k])}
            for name in ("e_n", "e_t", "beta", "angle_out", "v_t_out", "omega_out", "omega_partner_out", "P_max",
                         "delta_max", "contact_time", "slid_throughout", "stuck"):
                if name in model:
                    row[name] = model[name][k].item()
                elif name in ref:
                    row[name] = bool(ref[name][k])
            for name in ("e_n", "delta_max", "F_max", "t_c", "v_t_out_sliding", "omega_out_sliding", "beta_no_slip"):
                if name in ref and np.isfinite(ref[name][k]):
                    row["ref_" + name] = float(ref[name][k])
            for label, contact in (("plugin_vs_nfdmodel", None), ("plugin_vs_granular", "granular")):
                lammps = entry.get("lammps")
                if not lammps:
                    continue
                mine = next(iter(lammps.values()))["velocities"][k:k + 1]
                other = model["velocities"][k:k + 1] if contact is None else lammps.get(contact, {}).get("velocities")
                if other is not None:
                    row[label] = agreement(mine, other if contact is None else other[k:k + 1], case)
            out.append(row)
    return out


def write(out: Path, elastic: list[dict], plastic: list[dict], paper: list[dict], wall_time: float,
          no_lammps: bool) -> list[Path]:
    from calib.studies import chung_ooi_paper
    out.mkdir(parents=True, exist_ok=True)
    command = "python -m calib.studies.chung_ooi --out " + str(out) + (" --no-lammps" if no_lammps else "")
    stamp = output.stamp(wall_time, command=command, lammps=_lammps_version())
    summary = {"stamp": stamp, "tests": [case_summary(e) for e in elastic],
               "plastic": [plastic_summary(e) for e in plastic],
               "paper_test4": {"source": "calib/data/chung_ooi_test4.csv", "points": len(paper),
                               "worst": chung_ooi_paper.worst(paper), "tolerance": chung_ooi_paper.TOLERANCE,
                               "spin_scale_rad_s": chung_ooi_paper.spin_scale()},
               "worst": _worst(elastic, plastic)}
    summary["worst"] |= {"paper_" + k: v for k, v in summary["paper_test4"]["worst"].items()}
    paths = [output.write_json(out / "chung_ooi.json", summary),
             output.write_csv(out / "chung_ooi.csv", rows(elastic, plastic), COLUMNS,
                              comment=output.stamp_comment(stamp)),
             output.write_csv(out / "chung_ooi_paper.csv", paper, chung_ooi_paper.COLUMNS,
                              comment=output.stamp_comment(stamp))]
    from calib.studies import chung_ooi_plot
    paths.append(chung_ooi_plot.plot(out / "chung_ooi.png", elastic, plastic, paper))
    return paths


def _worst(elastic, plastic) -> dict:
    tests = [case_summary(e) for e in elastic]
    worst = {}
    for key in ("delta_max_error", "F_max_error", "t_c_error", "e_out_minus_e_in", "sliding_v_t_error",
                "sliding_omega_error", "no_slip_beta_error", "energy_balance_error", "plugin_vs_nfdmodel",
                "plugin_vs_granular", "granular_vs_nfdmodel"):
        values = [t[key] for t in tests if t.get(key) is not None and np.isfinite(t[key])]
        if values:
            worst[key] = float(max(np.abs(values)))
    plastic_rows = [plastic_summary(e) for e in plastic]
    for key in ("e_n_minus_head_on", "sliding_e_t_error", "plugin_vs_nfdmodel"):
        values = [t[key] for t in plastic_rows if t.get(key) is not None]
        if values:
            worst["plastic_" + key] = float(max(values))
    return worst


def _lammps_version() -> str | None:
    try:
        from calib import lammps_plugin
        return lammps_plugin.lammps_location()[1]
    except Exception:           # noqa: BLE001  (the stamp only names it)
        return None


def chung_ooi(root: Path) -> list[str]:
    data = read_json(root / "lammps" / "chung_ooi.json")
    if data is None:
        return []
    stamp = data["stamp"]
    lines = study_header("Chung & Ooi (2011) benchmark tests 1-8 (`lammps/chung_ooi.*`)", stamp,
                         "python -m calib.studies.chung_ooi") + [
             "Elastic limit (Hertz, Mindlin, no damping but test 3's) through nfdmodel, the plugin and LAMMPS "
             f"{stamp.get('lammps') or '?'}'s granular, against the closed forms the paper's curves are built on "
             "(and, for test 4, the paper's digitised curves, below). Errors: Hertz's overlap, force, contact "
             "time (tests 1, 2), the restitution asked (3), the Coulomb rebound and spin where the contact slides "
             "throughout (4-8; two spheres: the line of centres turns), the no-slip Mindlin spring (scipy) where "
             "it hardly slips; agreement: final velocities and spins over the speed (and speed / R).", ""]
    paper = data.get("paper_test4")
    if paper:
        worst_paper, tolerance = paper["worst"], paper["tolerance"]
        lines += ["Test 4 against the paper's own curves, as the PySPH authors digitised them "
                  f"(`{paper['source']}`: source and licence in its header; `lammps/chung_ooi_paper.csv`, "
                  f"{paper['points']} points, both materials): largest |ours - paper| "
                  f"e_t {worst_paper['e_t']:.3f} (tolerance {tolerance['e_t']:g}), contact-point rebound angle "
                  f"{worst_paper['rebound_angle_deg']:.2f} deg ({tolerance['rebound_angle_deg']:g}), spin "
                  f"{worst_paper['spin_rad_s']:.3f} of {paper['spin_scale_rad_s']:.0f} rad/s "
                  f"({tolerance['spin_rad_s']:g}); the paper's runs have e_n = 0.98, these are elastic, and the "
                  "digitised angles sit up to 0.3 deg off (calib/studies/chung_ooi_paper.py).", ""]
    rows = []
    for t in data["tests"]:
        closed = [f"{k.replace('_error', '')} {g(t[k], 2)}" for k in ("delta_max_error", "F_max_error", "t_c_error",
                                                                       "sliding_v_t_error", "sliding_omega_error",
                                                                       "no_slip_beta_error") if t.get(k) is not None]
        if "e_out_minus_e_in" in t:
            closed.append(f"e - e asked {g(t['e_out_minus_e_in'], 2)}")
        rows.append([t["test"], t["material"], t["impacts"], ", ".join(closed) or "-",
                     g(t.get("plugin_vs_nfdmodel"), 2), g(t.get("plugin_vs_granular"), 2)])
    lines += table(["test", "material", "impacts", "against the closed forms", "plugin vs nfdmodel",
                    "plugin vs granular"], rows)
    prow = [[f"{p['speed_m_s']:g}", f"{p['P_max_over_P_Y'][0]:.3g}..{p['P_max_over_P_Y'][1]:.3g}",
             f"{p['e_n_head_on']:.4f}", g(p["e_n_minus_head_on"], 2), p["slid_throughout"],
             g(p.get("sliding_e_t_error"), 2), g(p.get("plugin_vs_nfdmodel"), 2)] for p in data["plastic"]]
    lines += ["Plastic (vz, the paper's aluminium, R = 2.5 mm on a flat, mu = 0.3, mindlin_rescale/force): e_n "
              "does not depend on the angle, e_t = 1 - 1/Psi, Psi = tan / (mu (1 + e_n)), where it slides "
              "(Wu, Thornton & Li 2009):", ""]
    lines += table(["v [m/s]", "P_max / P_Y", "e_n head-on at v", "e_n - head-on at the same v_n", "sliding impacts",
                    "e_t - (1 - 1/Psi)", "nfd/wall/vz vs nfdmodel"], prow)
    return lines
