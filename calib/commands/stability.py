"""``nfdcal stability``: the runtime laws and collisions on extreme cases (issue 6).

    nfdcal stability [--out results/stability]

Runs the grid of :mod:`calib.stability_report` (overlaps 1e-15 R .. 0.5 R, P/P_Y up to 1e6,
v_in/v_Y 0.1 .. 1e4, dt 1e-9 s .. beyond the stability limit, Ca and Kc at 1e-3 .. 1e3 x, R 1e-6 ..
10 m, nu up to 0.49, E/sigma_Y 50 .. 5000, float32 inputs) and writes runtime_stability.csv and
.json. Prints the summary; exit code 1 if a case FAILED (NaN, an unexpected exception, energy
created, or a silently inaccurate collision).
"""
from __future__ import annotations


def add_parser(subparsers) -> None:
    parser = subparsers.add_parser("stability", help="stability table of the runtime laws on extreme cases",
                                   description=__doc__.split("\n\n")[0])
    parser.add_argument("--out", default=None, help="output folder (default results/stability)")
    parser.set_defaults(run=run)


def run(ns) -> int:
    import json

    from calib.stability_report import CSV_NAME, DEFAULT_OUT, JSON_NAME, generate

    from pathlib import Path

    out = Path(ns.out or DEFAULT_OUT)
    try:            # fail now, not after the 30 s run (the dispatcher reports ValueError in one line)
        out.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise ValueError(f"--out: cannot create the output folder {out}: {exc.strerror or exc}") from None
    summary = generate(out)
    print(json.dumps({k: v for k, v in summary.items() if k != "failures"}, indent=2))
    for failure in summary["failures"]:
        print(f"FAIL {failure}")
    print(f"stability table written to {out}/{CSV_NAME} and {JSON_NAME}")
    return 1 if summary["failures"] else 0
