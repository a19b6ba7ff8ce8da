"""The LAMMPS plugin's input fuzzer at scale (a script that prints a table; not collected by pytest).

    .venv/bin/python tests/benchmarks/fuzz_lammps.py [--cases 400] [--seed 0] [--out results/stability]

Draws ``--cases`` cases from tests/lammps_fuzzing.py (pair_coeff and nfd/wall/<law> argument lists
of every law: edge numbers, unit slips, the SI Ca and Kc typed as Ca_hat and Kc_hat, arguments
missing or added, window keywords), runs each impact in the wheel's lmp with the plugin and
counts per law and command: runs (finite, no energy created), refusals (an ERROR line naming the
command and what is out of range) and failures (a crash, NaN or inf, energy created, an error
that names nothing, a hang). Writes OUT/fuzz_lammps.csv (one row per law and command) and
OUT/fuzz_lammps.json (the counts, the failures with their inputs, the stamp). Exit code 1 if any
case failed.
"""
from __future__ import annotations

import argparse
import collections
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))   # tests/: the fuzzer's grammar

from hypothesis import HealthCheck, given, seed, settings  # noqa: E402
from lammps_fuzzing import plugin_case, plugin_input, run_plugin_case  # noqa: E402

from calib import output  # noqa: E402
from calib import lammps_plugin  # noqa: E402


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cases", type=int, default=400)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--timeout", type=float, default=60.0, help="seconds before a case counts as a hang")
    parser.add_argument("--out", default="results/stability")
    args = parser.parse_args(argv)

    plugin = lammps_plugin.build_plugin()["path"]
    counts = collections.defaultdict(collections.Counter)
    failures = []
    started = time.perf_counter()

    @seed(args.seed)
    @settings(max_examples=args.cases, deadline=None, database=None, phases=["generate"],
              suppress_health_check=list(HealthCheck))
    @given(case=plugin_case())
    def fuzz(case):
        with tempfile.TemporaryDirectory() as folder:
            outcome = run_plugin_case(plugin, case, Path(folder), timeout_s=args.timeout)
        kind = "failure" if outcome.failed else outcome.kind
        counts[(case.law, case.kind)][kind] += 1
        if outcome.failed:
            failures.append({"law": case.law, "command": case.kind, "args": case.args, "v_in": case.v_in,
                             "why": outcome.kind, "input": plugin_input("PLUGIN", case)})

    fuzz()
    wall = time.perf_counter() - started
    rows = [{"law": law, "command": "pair_coeff" if kind == "pair" else "fix nfd/wall", "cases": sum(c.values()),
             "ran": c["ran"], "refused": c["refused"], "failures": c["failure"]}
            for (law, kind), c in sorted(counts.items())]
    rows.append({"law": "all", "command": "all", **{k: sum(r[k] for r in rows) for k in ("cases", "ran", "refused",
                                                                                          "failures")}})
    print(f"{'law':<13} {'command':<13} {'cases':>6} {'ran':>5} {'refused':>8} {'failures':>9}")
    for r in rows:
        print(f"{r['law']:<13} {r['command']:<13} {r['cases']:>6} {r['ran']:>5} {r['refused']:>8} {r['failures']:>9}")
    print(f"{wall:.0f} s wall")
    for f in failures[:20]:
        print(f"FAIL {f['why']}: {f['command']} nfd/{f['law']} {' '.join(f['args'])}")
    stamp = output.stamp(wall, command=f"python tests/benchmarks/fuzz_lammps.py --cases {args.cases} --seed {args.seed}",
                         seed=args.seed, timeout_s=args.timeout)
    out = Path(args.out)
    output.write_csv(out / "fuzz_lammps.csv", rows, comment=output.stamp_comment(stamp))
    output.write_json(out / "fuzz_lammps.json", {"rows": rows, "failures": failures, "stamp": stamp})
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
