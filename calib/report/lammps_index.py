"""The LAMMPS folder's part of results/README.md (calib.report.results_index): the plugin's speed and
restitution against LAMMPS' granular styles, the Chung & Ooi tests and the heap, each read from its own
summary files."""
from __future__ import annotations

from pathlib import Path

from calib.report.index_format import g, num, read_json, section, study_header, table


def lammps(root: Path) -> list[str]:
    folder = root / "lammps"
    data = read_json(folder / "summary.json")
    if data is None:
        return []
    stamp = data["stamp"]
    lines = section("LAMMPS: the plugin against LAMMPS' granular styles (`lammps/`)", folder, root,
                    stamp.get("command", "python tests/benchmarks/bench_lammps.py"), stamp)
    lines += [f"LAMMPS {stamp.get('lammps', '?')}, {stamp['spheres']} spheres, best of {stamp['repeat']}. The pile: "
              f"{stamp['settle_steps']} settling steps ({num(stamp['settle_loop_s'])} s) to {stamp['settle_contacts_end']}"
              f" contacts, coordination {stamp['settle_coordination_end']:.3g}, kinetic energy "
              f"{stamp['settle_ke_end_J'] / stamp['settle_ke_peak_J']:.2g} of its peak; then {stamp['pile_steps']} "
              f"timed steps.", ""]
    pairs = {}
    for r in data["timing"]:
        pairs.setdefault((r["scene"], r["ranks"]), []).append(r)
    out = []
    for (scene, ranks), runs in pairs.items():
        nfd = next(r for r in runs if r["contact"].startswith("nfd"))
        ref = next(r for r in runs if not r["contact"].startswith("nfd"))
        cell = lambda r: (f"{num(r['us_per_step'])} us (pair {num(r['pair_us_per_step'])}, fixes "
                          f"{num(r['modify_us_per_step'])})")
        per_contact = lambda r: "-" if r["ns_per_contact_step"] is None else f"{r['ns_per_contact_step']:.0f} ns"
        contacts = lambda r: "-" if r["contacts_at_end"] is None else f"{r['contacts_at_end']}"
        out.append([scene, ranks, cell(nfd), cell(ref), f"{nfd['ratio_to_granular']:.2f}",
                    f"{per_contact(nfd)}, {per_contact(ref)}", f"{contacts(nfd)}, {contacts(ref)}"])
    lines += table(["scene", "ranks", "nfd/vz + nfd/wall/vz per step", "granular hertz/material + wall/gran",
                    f"ratio (target <= {data['target']:g})", "per contact: nfd, granular", "contacts at end"], out)
    rows = [[f"{r['v_in_over_v_Y']:g}", f"{r['P_max_over_P_Y']:.3g}", f"{r['e_reference_nfdmodel']:.4f}",
             f"{r['e_nfd_vz_lammps']:.4f}", f"{r['e_mdr_lammps']:.4f}", g(r["nfd_minus_reference"], 2),
             "yes" if r["in_calibrated_window"] else "no"] for r in data["restitution"]]
    lines += ["Restitution of two aluminium spheres head-on (`restitution.csv`): nfdmodel, the plugin and "
              "LAMMPS' `granular mdr`:", ""]
    lines += table(["v_in / v_Y", "P_max / P_Y", "e, nfdmodel", "e, nfd/vz", "e, mdr", "nfd/vz - nfdmodel",
                    "inside the window"], rows)
    return lines


def chung_ooi(root: Path) -> list[str]:
    data = read_json(root / "lammps" / "chung_ooi.json")
    if data is None:
        return []
    stamp, worst = data["stamp"], data["worst"]
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


def heap(root: Path) -> list[str]:
    data = read_json(root / "lammps" / "heap.json")
    if data is None:
        return []
    stamp = data["stamp"]
    lines = study_header("A heap in LAMMPS (`lammps/heap.*`)", stamp, "python -m calib.studies.heap") + [
             f"{data['spheres']} aluminium spheres (nfd/vz) collapse from a column onto a rough base; normal damping "
             f"`{data['damping'] or 'none'}` in both runs ({data['damping_note']}).", ""]
    rows = [[name, r["models"], f"{r['time_s']:.3g}", "yes" if r["settled"] else "no", g(r["ke_end_over_peak"], 2),
             f"{r['angle_of_repose_deg']:.1f}", f"{1e3 * r['height_m']:.1f}", f"{1e3 * r['radius_m']:.1f}"]
            for name, r in data["runs"].items()]
    lines += table(["run", "models", "time [s]", f"settled (KE < {data['settled_below']:g} peak)", "KE / peak",
                    "angle of repose [deg]", "height [mm]", "radius [mm]"], rows)
    return lines
