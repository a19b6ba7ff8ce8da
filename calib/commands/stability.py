"""``nfdcal stability``: the runtime laws, collisions and FE calibration on extreme cases.

    nfdcal stability [--out results/stability] [--runtime | --fe] [--workers 2]

Runs the grid of :mod:`calib.studies.runtime_stability` (overlaps 1e-15 R .. 0.5 R, P/P_Y up to 1e6,
v_in/v_Y 0.1 .. 1e4, dt 1e-9 s .. beyond the stability limit, Ca and Kc at 1e-3 .. 1e3 x, R 1e-6 ..
10 m, nu up to 0.49, E/sigma_Y 50 .. 5000, float32 inputs) and writes runtime_stability.csv and
.json; then the FE cases of :mod:`calib.studies.fe_stability` (E/sigma_Y 50 .. 5000, nu 0 .. 0.49,
P/P_Y up to 1000, R 1e-6 .. 10 m, each on two meshes for an error estimate; resumable) into
fe_stability.csv and .json. Prints the outcome counts (``--json``: the summaries as one object,
keys ``runtime`` and ``fe``); exit code 1 if a case FAILED (NaN, an unexpected exception, energy
created, or a silently inaccurate collision).
"""
from __future__ import annotations

from calib.commands.common import add_summary_arguments, number, print_summary


def add_parser(subparsers) -> None:
    parser = subparsers.add_parser("stability",
                                   help="the runtime laws (--runtime) and the FE calibration (--fe) on extreme inputs",
                                   description=__doc__.split("\n\n")[0])
    parser.add_argument("--out", default=None, help="output folder (default results/stability)")
    only = parser.add_mutually_exclusive_group()
    only.add_argument("--runtime", action="store_true", help="only the runtime laws and collisions (~30 s)")
    only.add_argument("--fe", action="store_true", help="only the FE calibrations (minutes; resumable)")
    parser.add_argument("--workers", default="2", help="local processes for the FE runs (default 2)")
    add_summary_arguments(parser)
    parser.set_defaults(run=run)


def run(ns) -> int:
    from pathlib import Path

    from calib.commands.progress import progress_reporter
    from calib.studies.runtime_stability import CSV_NAME, DEFAULT_OUT, JSON_NAME, generate

    out = Path(ns.out or DEFAULT_OUT)
    try:            # fail at once, not after the 30 s run (the dispatcher reports ValueError in one line)
        out.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise ValueError(f"--out: cannot create the output folder {out}: {exc.strerror or exc}") from None
    workers = number("--workers", ns.workers)
    if workers != int(workers) or not 1 <= workers <= 64:
        raise ValueError(f"--workers out of range: need an integer in [1, 64], got {ns.workers}")
    summaries, lines = {}, []
    if not ns.fe:
        summaries["runtime"] = summary = generate(out)
        lines.append(f"runtime laws: {summary['cases']} cases, {outcome_counts(summary)}; worst Newton"
                     f" iterations {summary['newton_max']}; written to {out}/{CSV_NAME} and {JSON_NAME}")
    if not ns.runtime:
        from calib.studies import fe_stability

        with progress_reporter(ns.quiet) as progress:
            summaries["fe"] = summary = fe_stability.generate(out, workers=int(workers), progress=progress)
        lines.append(f"FE calibrations: {summary['runs']} runs, {outcome_counts(summary)}; written to "
                     f"{out}/{fe_stability.CSV_NAME} and {fe_stability.JSON_NAME}")
    failures = [f for summary in summaries.values() for f in summary["failures"]]
    print_summary(ns, summaries, lines + [f"FAIL {failure}" for failure in failures])
    return 1 if failures else 0


def outcome_counts(summary: dict) -> str:
    """'1179 ok, 202 clear error, 11 warned'"""
    return ", ".join(f"{count} {outcome}" for outcome, count in summary["outcomes"].items())
