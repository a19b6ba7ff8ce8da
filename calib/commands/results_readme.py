"""``nfdcal results-readme``: write the index results/README.md from the summary files beside it.

    nfdcal results-readme                 # writes results/README.md
    nfdcal results-readme --check         # exit 1 when results/README.md is stale, writes nothing

Every number in the index is read from the results' own summaries, each section by the module next to
what writes its results (``sections``), assembled by ``calib.report.results_index``, so regenerating a
result and then this index keeps the two in step. Only ``OUT/README.md`` is
written, and only a regular file there is replaced.
"""
from __future__ import annotations

from pathlib import Path

from calib.commands.common import add_summary_arguments, print_summary

DEFAULT_OUT = "results"


def add_parser(subparsers) -> None:
    parser = subparsers.add_parser("results-readme", help="write results/README.md from the results' summaries",
                                   description=__doc__.split("\n\n")[0])
    parser.add_argument("--out", default=DEFAULT_OUT, metavar="DIR",
                        help=f"the results folder to index (default {DEFAULT_OUT}); its README.md is written")
    parser.add_argument("--check", action="store_true",
                        help="write nothing; exit 1 when DIR/README.md differs from what the summaries give")
    add_summary_arguments(parser, progress=False)
    parser.set_defaults(run=run)


def sections() -> tuple:
    """The sections of results/README.md in their order, each ``section(root) -> lines``."""
    from calib.report.calibration_index import calibration
    from calib.report.collision_index import collision
    from calib.report.fit_data_index import fit_data_benchmark
    from calib.report.lammps_index import lammps
    from calib.report.tables_index import hardening_sheet, master_table, pair_table, vz_master_table
    from calib.studies.below_nodes import below_nodes
    from calib.studies.between_nodes_index import between_nodes
    from calib.studies.chung_ooi_output import chung_ooi
    from calib.studies.heap import heap
    from calib.studies.hertz_index import hertz
    from calib.studies.identical_spheres_index import identical_spheres
    from calib.studies.impact_output import impact
    from calib.studies.mesh_ladder_index import mesh_ladder
    from calib.studies.pair_ratios import pair_ratios
    from calib.studies.pair_ratios_high import pair_ratios_high
    from calib.studies.pairs_output import pairs
    from calib.studies.stability_index import stability
    from calib.studies.wide_window_index import wide_window

    return (calibration, mesh_ladder, wide_window, between_nodes, identical_spheres, hertz, collision, impact,
            master_table, vz_master_table, below_nodes, hardening_sheet, fit_data_benchmark, pairs, pair_ratios, pair_ratios_high,
            pair_table, stability, lammps, chung_ooi, heap)


def run(ns) -> int:
    from calib import output
    from calib.report.results_index import README, render

    text = render(ns.out, sections())
    path = Path(ns.out) / README
    current = path.read_text(encoding="utf-8") if path.is_file() else None
    if ns.check:
        status = "up to date" if current == text else ("missing" if current is None else "stale")
    elif current == text:
        status = "up to date"
    else:
        output.atomic_write_text(path, text)
        status = "written"
    print_summary(ns, {"readme": str(path), "status": status, "lines": text.count("\n")},
                  [f"{path}: {status}" + (f" (run nfdcal results-readme --out {ns.out})"
                                          if status in ("stale", "missing") else "")])
    return 1 if ns.check and status != "up to date" else 0
