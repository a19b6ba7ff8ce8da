"""The DEM benchmark of Chung & Ooi (2011, Granular Matter 13:643), tests 1-8, in the elastic limit and
with the plastic vz law: results/lammps/chung_ooi.{csv,json,png}.

Each case (calib.studies.chung_ooi_cases: the tests, their closed forms and the plastic trends) runs
through nfdmodel, the LAMMPS plugin and LAMMPS's own granular styles (calib.studies.chung_ooi_lammps),
test 4 also against the paper's digitised curves (calib.studies.chung_ooi_paper); the files are
written by calib.studies.chung_ooi_output.

    python -m calib.studies.chung_ooi [--out results/lammps] [--no-lammps]
"""
from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

from calib.studies.chung_ooi_cases import (cases, plastic_cases, plastic_params, references, run_nfdmodel,
                                           run_plastic, time_step)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--out", default="results/lammps")
    parser.add_argument("--no-lammps", action="store_true", help="nfdmodel and the closed forms only")
    ns = parser.parse_args(argv)
    from calib.studies import chung_ooi_output as report
    started = time.perf_counter()
    runner = None
    if not ns.no_lammps:
        from calib.studies import chung_ooi_lammps as runner
    elastic = []
    for case in cases():
        dt = time_step(case)
        model = run_nfdmodel(case, dt)
        entry = {"case": case, "dt": dt, "nfdmodel": model, "reference": references(case, model)}
        if runner is not None:
            entry["lammps"] = {contact: runner.run_case(case, dt, contact) for contact in ("nfd/hertz", "granular")}
        elastic.append(entry)
        print(report.case_line(entry), flush=True)
    plastic = []
    for case in plastic_cases():
        params, _ = plastic_params()
        dt = time_step(case) / 2.0
        entry = {"case": case, "dt": dt, "nfdmodel": run_plastic(case, dt)}
        if runner is not None:
            entry["lammps"] = {"nfd/vz": runner.run_case(case, dt, "nfd/vz", plastic=True)}
        plastic.append(entry)
        print(report.plastic_line(entry), flush=True)
    from calib.studies import chung_ooi_paper
    paper = chung_ooi_paper.compare([entry["case"] for entry in elastic if entry["case"].test == 4])
    print("test 4 against the paper's curves, worst: " + ", ".join(
        f"{k} {v:.3g}" for k, v in chung_ooi_paper.worst(paper).items()), flush=True)
    written = report.write(Path(ns.out), elastic, plastic, paper, time.perf_counter() - started, ns.no_lammps)
    print("wrote " + ", ".join(str(p) for p in written))
    return 0


if __name__ == "__main__":
    sys.exit(main())
