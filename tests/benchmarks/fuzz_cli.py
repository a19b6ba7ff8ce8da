"""The command-line fuzzer at scale (a script that prints a table; not collected by pytest).

    .venv/bin/python tests/benchmarks/fuzz_cli.py [--cases 3000] [--seed 0] [--out results/stability]
    .venv/bin/python tests/benchmarks/fuzz_cli.py --fit-data    # fit-data's unit factors, every case

Draws ``--cases`` cases from tests/fuzzing.py (argument lists of every command, fuzzed scenes and
parameter files; the FE commands with --dry-run), runs each in a fresh sandbox and counts the
outcomes per command: successes, clean errors (one line, exit code 2) and failures (a traceback,
another exit code, NaN or inf in a written file, a file touched outside the output paths, a
hang). ``--fit-data`` runs instead every case of fit-data's unit-factor fuzzer (tests/fuzzing.py:
each column of each data kind multiplied by 1e-3..1e3; the kinds: drop tests with P_max, contact
time, dent, dent and imprint radius, and force curves; a success must hold the truth in its
interval, a refusal must name the column) and prints one line per case (the dent and radius kinds'
44 cases: the data as made fitted, every other factor refused naming its column). Writes OUT/fuzz.csv (one row per command) and OUT/fuzz.json (the counts, the failures
with their argument lists, the stamp). Exit code 1 if any case failed.
"""
from __future__ import annotations

import argparse
import collections
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))   # tests/: the fuzzer's grammar

from fuzzing import command_case, fit_data_cases, run_case, run_fit_data_case  # noqa: E402
from hypothesis import HealthCheck, given, seed, settings  # noqa: E402

from calib import output  # noqa: E402


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cases", type=int, default=3000)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--timeout", type=float, default=60.0, help="seconds before a case counts as a hang")
    parser.add_argument("--out", default="results/stability")
    parser.add_argument("--fit-data", action="store_true", help="fit-data's unit-factor cases instead")
    args = parser.parse_args(argv)
    if args.fit_data:
        return fit_data(args.timeout)

    counts = collections.defaultdict(collections.Counter)
    failures, slowest = [], (0.0, None)
    started = time.perf_counter()

    @seed(args.seed)
    @settings(max_examples=args.cases, deadline=None, database=None, phases=["generate"],
              suppress_health_check=list(HealthCheck))
    @given(case=command_case())
    def fuzz(case):
        nonlocal slowest
        t0 = time.perf_counter()
        with tempfile.TemporaryDirectory() as sandbox:
            outcome = run_case(case, Path(sandbox), timeout_s=args.timeout)
        elapsed = time.perf_counter() - t0
        slowest = max(slowest, (elapsed, " ".join(case.argv)), key=lambda t: t[0])
        kind = "failure" if outcome.failed else outcome.kind
        counts[case.command][kind] += 1
        if outcome.failed:
            failures.append({"command": case.command, "argv": case.argv, "why": outcome.kind,
                             "stderr": outcome.stderr[-600:], "files": case.files})

    fuzz()
    wall = time.perf_counter() - started
    rows = [{"command": command, "cases": sum(c.values()), "successes": c["success"],
             "clean_errors": c["clean error"], "failures": c["failure"]} for command, c in sorted(counts.items())]
    rows.append({"command": "all", **{k: sum(r[k] for r in rows) for k in ("cases", "successes", "clean_errors",
                                                                             "failures")}})
    print(f"{'command':<10} {'cases':>6} {'successes':>10} {'clean errors':>13} {'failures':>9}")
    for r in rows:
        print(f"{r['command']:<10} {r['cases']:>6} {r['successes']:>10} {r['clean_errors']:>13} {r['failures']:>9}")
    print(f"{wall:.0f} s wall, slowest case {slowest[0]:.1f} s: {slowest[1]}")
    for f in failures[:20]:
        print(f"FAIL {f['why']}: nfdcal {' '.join(f['argv'])}")
    stamp = output.stamp(wall, command=f"python tests/benchmarks/fuzz_cli.py --cases {args.cases} --seed {args.seed}",
                         seed=args.seed, timeout_s=args.timeout)
    out = Path(args.out)
    output.write_csv(out / "fuzz.csv", rows, comment=output.stamp_comment(stamp))
    output.write_json(out / "fuzz.json", {"rows": rows, "failures": failures, "slowest_case_s": slowest[0],
                                          "stamp": stamp})
    return 1 if failures else 0


def fit_data(timeout_s: float) -> int:
    """Every case of fit-data's unit-factor fuzzer, one line each; 1 if any failed."""
    failed = 0
    for case in fit_data_cases():
        t0 = time.perf_counter()
        with tempfile.TemporaryDirectory() as sandbox:
            verdict, outcome = run_fit_data_case(case, Path(sandbox), timeout_s)
        failed += verdict.startswith("FAIL")
        print(f"{case.name:<32} {verdict:<10} {time.perf_counter() - t0:5.1f} s", flush=True)
    print(f"{len(fit_data_cases())} cases, {failed} failures")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
