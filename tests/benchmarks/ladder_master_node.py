"""Benchmark: a finite-strain node of the vz master table (calib/scenes/builtin/sweeps/vz_master_reach.toml) on
separate mesh and loading-step ladders, so each discretisation error is seen alone.

Not a timed test: prints one table. The node (default nu 0.3, E/sigma_Y 100, whose contact reaches a = 0.45 R) runs
as the scene's reference ladder runs it (calib.fit.vz_master_build.task, kind "refine": the scene's graded mesh
family at refinement r, 25 r elements across every contact radius, every size / r; force-controlled load-unload
paths with S loading steps per decade) for each pair r:S of ``--levels`` (default: the shipped node's 0.5:16, then
0.5:32, 0.5:64, 1:32 and 1:64). Per level: dofs,
wall time, and the FE's e and alpha_max [m] at each path's peak; then, at each peak, the step changes (the same
mesh, the steps doubled) and the mesh changes (the same steps, r doubled), relative.
The scene's [[refine]] ladders "mesh" and "steps" keep the same measurement for its node among the table's records
(calib.fit.vz_master_ladders); this runs any other node or levels, keeping nothing.
Usage: .venv/bin/python tests/benchmarks/ladder_master_node.py [--nu 0.3] [--E-over-sigma-y 100]
       [--levels 0.5:16 0.5:32 0.5:64 1:32 1:64]   (about 55 minutes on one core with the defaults)
"""
from __future__ import annotations

import argparse
import time

from calib.fit import vz_master_build, vz_master_scene
from calib.fit.vz_master_check import fe_paths

DEFAULT_LEVELS = ("0.5:16", "0.5:32", "0.5:64", "1:32", "1:64")
ELEMENTS = 25.0                 # the scene's elements across every contact radius at refinement 1


def level(text: str) -> tuple[float, float]:
    """"r:S" -> (the mesh family's refinement, loading steps per decade)."""
    try:
        refinement, steps = (float(part) for part in text.split(":"))
    except ValueError:
        raise argparse.ArgumentTypeError(f"--levels: need r:S (refinement:steps per decade), got {text!r}") from None
    if not (0.5 <= refinement <= 4.0 and steps >= 1):
        raise argparse.ArgumentTypeError(f"--levels: need 0.5 <= r <= 4 and S >= 1, got {text!r}")
    return refinement, steps


def run_level(scene: dict, nu: float, ratio: float, refinement: float, steps: float) -> dict:
    """The node on the mesh family's level r and S steps per decade (a refine task: the task scales the steps by r)."""
    refine = {"nu": nu, "E_over_sigma_y": ratio, "elements_per_contact_radius": ELEMENTS,
              "loading_steps_per_decade": steps / refinement, "refinement": refinement}
    item = vz_master_build.task(scene, nu, ratio, "refine", refine=refine, name=f"ladder_{refinement:g}_{steps:g}")
    started = time.perf_counter()
    row = vz_master_build.run_task(item)
    if row.get("status") != "ok":
        raise SystemExit(f"level {refinement:g}:{steps:g} failed: {row.get('error')}")
    peaks = {round(p["P_max"] / row["P_Y"], 1): (p["e"], p["alpha_max"]) for p in fe_paths(row)}
    return {"dofs": row["dofs"], "wall_s": time.perf_counter() - started, "peaks": peaks}


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--nu", type=float, default=0.3)
    parser.add_argument("--E-over-sigma-y", type=float, default=100.0)
    parser.add_argument("--levels", nargs="+", type=level, default=[level(t) for t in DEFAULT_LEVELS])
    ns = parser.parse_args(argv)
    scene = vz_master_scene.load_scene("vz_master_reach")
    runs = {lv: run_level(scene, ns.nu, ns.E_over_sigma_y, *lv) for lv in ns.levels}
    peaks = sorted(set.intersection(*(set(r["peaks"]) for r in runs.values())))
    print(f"node nu {ns.nu:g}, E/sigma_Y {ns.E_over_sigma_y:g}: e / alpha_max [mm] at each peak (P_max/P_Y)")
    print(f"{'r:S (N)':>14} {'dofs':>7} {'wall s':>7}  " + "  ".join(f"{x:>17g}" for x in peaks))
    for (refinement, steps), r in runs.items():
        print(f"{refinement:>4g}:{steps:<4g}({ELEMENTS * refinement:4.1f}) {r['dofs']:>7} {r['wall_s']:>7.0f}  "
              + "  ".join(f"{r['peaks'][x][0]:.4f} / {1e3 * r['peaks'][x][1]:7.3f}" for x in peaks))
    for kind, pairs in (("steps doubled", [(a, b) for a in runs for b in runs if a[0] == b[0] and b[1] == 2 * a[1]]),
                        ("mesh refined 2x", [(a, b) for a in runs for b in runs if a[1] == b[1] and b[0] == 2 * a[0]])):
        for a, b in pairs:
            print(f"{kind}, {a[0]:g}:{a[1]:g} -> {b[0]:g}:{b[1]:g}: e " + ", ".join(
                f"{x:g} {runs[b]['peaks'][x][0] / runs[a]['peaks'][x][0] - 1:+.2%}" for x in peaks)
                  + "; alpha_max " + ", ".join(
                f"{x:g} {runs[b]['peaks'][x][1] / runs[a]['peaks'][x][1] - 1:+.2%}" for x in peaks))


if __name__ == "__main__":
    main()
