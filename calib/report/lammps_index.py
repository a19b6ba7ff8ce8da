"""The LAMMPS benchmark's section of results/README.md (calib.report.results_index): the plugin's speed and
restitution against LAMMPS' granular styles, read from results/lammps/summary.json
(tests/benchmarks/bench_lammps.py). The Chung & Ooi tests and the heap in the same folder are their
studies' sections (calib.studies.chung_ooi_output, calib.studies.heap)."""
from __future__ import annotations

from pathlib import Path

from calib.report.index_format import g, num, read_json, section, table


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
