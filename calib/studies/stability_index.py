"""The stability section of results/README.md (calib.report.results_index): the runtime and FE stability
studies (calib.studies.runtime_stability, fe_stability; ``nfdcal stability``), the fuzzers' summaries and the
mesh ladders at high nu, read from results/stability/.
"""
from __future__ import annotations

from pathlib import Path

from calib.report.index_format import files_line, g, pct, provenance, read_csv, read_json, table


def stability(root: Path) -> list[str]:
    folder = root / "stability"
    runtime, fe, fuzz, plugin = (read_json(folder / n) for n in ("runtime_stability.json", "fe_stability.json",
                                                                 "fuzz.json", "fuzz_lammps.json"))
    if runtime is None and fe is None and fuzz is None and plugin is None:
        return []
    lines = ["## Stability (`stability/`)", "", files_line(root, folder), ""]
    if runtime:
        s = runtime["summary"]
        lines += [f"**Runtime** (`{runtime['stamp'].get('command', 'nfdcal stability')} --runtime`): {s['cases']} "
                  f"cases, " + ", ".join(f"{n} {k}" for k, n in s["outcomes"].items())
                  + f", {len(s['failures'])} failures; the backends disagree on {len(s.get('backends_disagree', []))}; "
                  f"at most {s['newton_max']} Newton iterations. " + provenance(runtime["stamp"]), ""]
        lines += table(["backend", "cases", "outcomes"],
                       [[name, b["cases"], ", ".join(f"{n} {k}" for k, n in b["outcomes"].items())]
                        for name, b in s.get("backends", {}).items()])
        worst = [[group, ", ".join(f"{k} {g(v, 2)}" for k, v in errs.items())]
                 for group, errs in s["worst_errors_of_ok_rows"].items()]
        lines += table(["group", "largest error of the cases that ran"], worst)
    if fe:
        s = fe["summary"]
        lines += [f"**FE** (`nfdcal stability --fe`): {s['runs']} runs, "
                  + ", ".join(f"{n} {k}" for k, n in s["outcomes"].items()) + f", {len(s['failures'])} failures; "
                  f"at most {s['newton_max']} Newton iterations. " + provenance(fe["stamp"]), ""]
        cases = {}
        for r in fe["rows"]:
            cases.setdefault(r["case"], []).append(r)
        out = []
        for name, runs in cases.items():
            fine = min(runs, key=lambda r: r["mesh_ratio"])
            if fine["outcome"] != "ok":
                out.append([name, fine["outcome"].split(":")[0], "", "", "", ""])
                continue
            out.append([name, "ok", f"{fine['Ca_hat']:.4g}, {fine['Kc_hat']:.4g}", f"{fine['e']:.3f}",
                        ", ".join(pct(fine[k] or 0.0, 1) for k in ("Ca_hat_mesh_change", "Kc_hat_mesh_change")),
                        fine["newton_max"]])
        lines += table(["case", "outcome", "Ca_hat, Kc_hat", "e", "mesh change Ca_hat, Kc_hat", "Newton max"], out)
    if fuzz:
        lines += [f"**Command-line fuzzer** (`{fuzz['stamp']['command']}`): slowest case "
                  f"{fuzz['slowest_case_s']:.2g} s. " + provenance(fuzz["stamp"]), ""]
        lines += table(["command", "cases", "successes", "clean errors", "failures"],
                       [[r["command"], r["cases"], r["successes"], r["clean_errors"], r["failures"]]
                        for r in fuzz["rows"]])
    if plugin:
        lines += [f"**LAMMPS plugin input fuzzer** (`{plugin['stamp']['command']}`): pair_coeff and wall-fix lines "
                  "of every law, each an impact that runs without creating energy or an ERROR line naming the "
                  "command and what is out of range. " + provenance(plugin["stamp"]), ""]
        lines += table(["law", "command", "cases", "ran", "refused", "failures"],
                       [[r["law"], r["command"], r["cases"], r["ran"], r["refused"], r["failures"]]
                        for r in plugin["rows"]])
    for path in sorted(folder.glob("mesh_ladder_nu*.csv")):
        stamp, rows = read_csv(path)
        rows = sorted(rows, key=lambda r: -r["contact_size"])
        lines += [f"**Mesh ladder at nu = {rows[0]['nu']:g}** (`{path.name}`, `nfdcal calibrate --ladder --nu "
                  f"{rows[0]['nu']:g} --out results/stability`): no volumetric locking if the coarse meshes are not "
                  "stiffer. " + provenance(stamp), ""]
        lines += table(["h [um]", "dofs", "Ca [1e-7 m/N]", "Kc [1e-4 1/N]", "e at 1500 N",
                        "change vs finest: alpha, contact radius, Ca, Kc"],
                       [[f"{r['contact_size'] * 1e6:g}", r["dofs"], f"{r['Ca'] * 1e7:.4f}", f"{r['Kc'] * 1e4:.4f}",
                         f"{r['e_1500']:.4f}", ", ".join(pct(r[f"{q}_rel_change_vs_finest"]) for q in
                                                         ("alpha_max_1500", "contact_radius_1500", "Ca", "Kc"))]
                        for r in rows])
    return lines
