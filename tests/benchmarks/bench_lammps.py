"""Benchmark: the nfd laws inside LAMMPS against LAMMPS' own granular styles (results/lammps/).

Not a timed test: prints two tables and writes them, stamped (commit, wall time), with a picture:

1. Speed. Two scenes of a few thousand polydisperse spheres (tests/lammps_pour.py: aluminium and
   steel, R 1.6-2.4 mm, gravity, frictionless, a rigid floor, periodic in x and y), the same
   input but for the contact law: pair_style nfd/vz with fix nfd/wall/vz (the FE-calibrated
   elastoplastic law, its history per contact) against pair_style granular with hertz/material
   and damping coeff_restitution (e = 0.8) with fix wall/gran of the same model. Time per step
   from LAMMPS' own "Loop time", the two laws alternating, on 1 and 2 MPI ranks; the same
   neighbor settings for both (skin 0.2 mm, rebuilt when an atom moved half of it, newton off,
   comm_modify vel yes). Each row: the best of --repeat runs, and the ratio to granular both of
   the best runs and as the median of the --repeat ratios of a run of each law one after the
   other (on a shared machine the load changes between runs; the median of paired ratios follows
   it least), of the loop time and of the Pair section. Target: nfd/vz <= 1.5x granular.
   - The pour (--spheres, default 3000; --steps of 1e-7 s): dilute at its end (a few dozen pair
     contacts), so it times the per-pair and per-atom overhead.
   - With --friction, the pile again with friction and rolling resistance on both sides
     (FRICTION: tangential mindlin NULL 0 0.3 rolling sds 1000 0 0.1 after each law's constants;
     granular keeps its e = 0.8 damping): the target there is nfd/vz <= 1.1x granular.
   - With --region, that pile with friction again, its floor a region's face (region_floor: a block
     reaching beyond the box, side in) under fix nfd/wall/region/vz against fix wall/gran/region of
     the same models: the region wall's cost is in the Modify column (target: 1.1x wall/gran/region's).
     With --cylinder, the same with the floor the bottom cap of a cylinder about z (scene
     'pile+cylinder': region_floor's cylinder of radius 1 m about the box's corner, so that its side,
     beyond the periodic box, holds every sphere and touches none): the region style's own cost.
   - The dense pile (--pile-spheres, default 3000): lammps_pour.settle_input settles it once
     (granular, e = 0.1: a fall, then a drag quench; 95000 steps, about 70 s on 1 core) and
     writes it with write_data; from that same pile each law runs --pile-steps steps of 1e-7 s,
     gravity on. Each row has the pair contacts by geometry (compute contact/atom, both laws)
     and with history (compute nfd/contacts, nfd/vz) at the start and end of the timed run, the
     mean coordination (2 contacts / spheres) and the time per step per sphere and per contact.
2. Restitution. Two aluminium spheres (R = 1 cm) meeting head-on at v_in = 1..100 v_Y: e of
   pair_style nfd/vz (the two constants of the calibration of results/calibration/parameters.json,
   whichever law that file ships: calib.report.parameter_file.two_constant_law), of nfdmodel.collide
   with the same calibrated law (the FE-calibrated reference; the plugin equals it to 1e-8, see
   tests/test_lammps.py) and of pair_style granular normal mdr (LAMMPS' other elastoplastic
   normal model: E, nu, Y = sigma_y, gamma = 0 (no adhesion), psi_b = 0.5, damp = 0 (no viscous
   damping), damping mdr 1), all at dt = 1e-7 s.
3. results/lammps/pour.png: a 300-sphere pour (no drift) after 60 ms, side view coloured by
   material, next to the start.

Usage (about 3 minutes on 2 cores: the pour 30 s, the pile's settle 70 s and its timing 60 s):
    .venv/bin/python tests/benchmarks/bench_lammps.py [--spheres 3000] [--steps 10000] [--repeat 3]
        [--pile-spheres 3000] [--pile-steps 5000] [--friction] [--region] [--cylinder] [--plugin PATH]
Writes results/lammps/timing.csv, restitution.csv, pour.png and summary.json.
"""
from __future__ import annotations

import argparse
import json
import re
import sys
import tempfile
import time
import warnings
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "tests"))

import lammps_pour  # noqa: E402

from calib import output  # noqa: E402
from calib import lammps_plugin  # noqa: E402

DT = 1e-7                       # s
RADIUS = 0.01                   # m: the restitution sweep's spheres
SPEEDS_OVER_V_Y = (1.0, 2.0, 5.0, 10.0, 20.0, 40.0, 100.0)
TARGET_RATIO = 1.5
TARGET_FRICTION_RATIO = 1.1     # the pile with friction and rolling resistance, and its region wall
FRICTION = "tangential mindlin NULL 0 0.3 rolling sds 1000 0 0.1"   # --friction: both laws, both sides


def run_lammps(text: str, folder: Path, nprocs: int = 1) -> str:
    """The output of a LAMMPS run (lammps_pour.run_input); a RuntimeError when it failed."""
    code, text_out = lammps_pour.run_input(text, folder, nprocs, name=f"in.{time.perf_counter_ns()}")
    if code != 0 or "ERROR" in text_out:
        raise RuntimeError(f"LAMMPS failed: {text_out[-1500:]}")
    return text_out


def loop_time(log: str) -> tuple[float, int]:
    """(seconds, steps) of the last run's 'Loop time of T on P procs for S steps'."""
    found = re.findall(r"Loop time of ([\d.eE+-]+) on \d+ procs for (\d+) steps", log)
    return float(found[-1][0]), int(found[-1][1])


def section_time(log: str, name: str) -> float:
    """The average seconds of a section (Pair, Modify, ...) of the last run's timing breakdown."""
    found = re.findall(rf"^{name}\s*\|\s*[\d.eE+-]+\s*\|\s*([\d.eE+-]+)", log, flags=re.M)
    return float(found[-1]) if found else float("nan")


CONTACT_NAMES = {"nfd": "nfd/vz + nfd/wall/vz", "granular": "granular hertz/material coeff_restitution + wall/gran"}
REGION_NAMES = {"nfd": "nfd/vz + nfd/wall/region/vz",
                "granular": "granular hertz/material coeff_restitution + wall/gran/region"}


def timing(folder: Path, scene: str, spheres: int, steps: int, repeat: int, make_input) -> list[dict]:
    """Time per step of both contact laws on one scene, 1 and 2 ranks, best of ``repeat``, the two
    laws alternating. make_input(contact, processors) -> the input (pour_input or pile_input:
    the pile's thermo ends with the sum of compute contact/atom, twice the pair contacts). The
    contacts: by geometry on the pile (both laws), with history (nfd/vz's census, column 3; an
    orphan history, column 4, is an error; column 5, unpaired or differing copies, is kept: on
    the pile it is 1, the two copies of a contact across the periodic boundary seeing the other
    atom's image shifted by the box length, rounded, their overlaps differing by ~1e-9 relative)."""
    rows = []
    for nprocs in (1, 2):
        runs = {"nfd": [], "granular": []}
        for _ in range(repeat):
            for contact in runs:
                log = run_lammps(make_input(contact, "2 1 1" if nprocs == 2 else ""), folder, nprocs)
                seconds, done = loop_time(log)
                columns = len(lammps_pour.thermo_columns(contact)) + (1 if scene.startswith("pile") else 0)
                thermo = lammps_pour.thermo_rows(log, columns)
                first, last = thermo[0], thermo[-1]
                run = {"per_step": seconds / done, "pair": section_time(log, "Pair") / done,
                       "modify": section_time(log, "Modify") / done}
                if scene.startswith("pile"):
                    run.update(contacts_at_start=int(first[-1]) // 2, contacts_at_end=int(last[-1]) // 2)
                if contact == "nfd":
                    if thermo[:, 3].any():
                        raise RuntimeError(f"{scene}: nfd/vz lost {int(thermo[:, 3].max())} contact histories")
                    run.update(history_contacts_at_start=int(first[2]), history_contacts_at_end=int(last[2]),
                               unpaired_copies_at_end=int(last[4]), on_floor_at_end=int(last[5]))
                runs[contact].append(run)
        best = {contact: min(found, key=lambda run: run["per_step"]) for contact, found in runs.items()}
        paired = {key: float(np.median([mine[key] / theirs[key] for mine, theirs in zip(runs["nfd"], runs["granular"])]))
                  for key in ("per_step", "pair")}
        for contact, run in best.items():
            contacts = (0.5 * (run["contacts_at_start"] + run["contacts_at_end"]) if scene.startswith("pile")
                        else None)
            rows.append({
                "scene": scene, "ranks": nprocs, "spheres": spheres, "steps": steps,
                "contact": (REGION_NAMES if scene in ("pile+region", "pile+cylinder") else CONTACT_NAMES)[contact],
                "us_per_step": 1e6 * run["per_step"], "ns_per_sphere_step": 1e9 * run["per_step"] / spheres,
                "ns_per_contact_step": None if contacts is None else 1e9 * run["per_step"] / contacts,
                "pair_ns_per_contact_step": None if contacts is None else 1e9 * run["pair"] / contacts,
                "pair_us_per_step": 1e6 * run["pair"], "modify_us_per_step": 1e6 * run["modify"],
                **{key: run.get(key) for key in ("contacts_at_start", "contacts_at_end", "history_contacts_at_start",
                                                 "history_contacts_at_end")},
                "coordination_at_start": None if contacts is None else 2.0 * run["contacts_at_start"] / spheres,
                "coordination_at_end": None if contacts is None else 2.0 * run["contacts_at_end"] / spheres,
                **{key: run.get(key) for key in ("on_floor_at_end", "unpaired_copies_at_end")},
                "ratio_to_granular": run["per_step"] / best["granular"]["per_step"],
                "median_paired_ratio": paired["per_step"] if contact == "nfd" else 1.0,
                "median_paired_pair_ratio": paired["pair"] if contact == "nfd" else 1.0})
    return rows


REGION_FLOORS = {"block": "region floor block -1 1 -1 1 0.0 1 side in",
                 "cylinder": "region floor cylinder z 0 0 1 0.0 1 side in"}


def region_floor(text: str, style: str = "block") -> str:
    """A pile input (lammps_pour.pile_input) with its floor z = 0 as the zlo face of a block region that
    reaches beyond the periodic box, or the bottom cap of a cylinder about z whose side lies beyond it
    (REGION_FLOORS[style]): fix nfd/wall/region/vz, or fix wall/gran/region, of the same constants and
    models."""
    lines = []
    for line in text.splitlines():
        if line.startswith("read_data"):
            line += "\n" + REGION_FLOORS[style]
        elif line.startswith("fix floor"):
            line = re.sub(r" nfd/wall/vz zlo 0\.0 ", " nfd/wall/region/vz floor ", line)
            line = re.sub(r" wall/gran granular (.*) zplane 0\.0 NULL$", r" wall/gran/region granular \1 region floor",
                          line)
            if "region" not in line:
                raise ValueError(f"region_floor: no floor wall to replace in {line!r}")
        lines.append(line)
    return "\n".join(lines) + "\n"


def settle_pile(folder: Path, spheres: int) -> tuple[Path, dict]:
    """The dense pile (lammps_pour.settle_input) in ``folder``/pile.data, settled on 1 rank.
    Returns the file and the settle's record: loop time [s] (its runs summed), steps, simulated
    time [s], the kinetic energy's peak and end [J], pair contacts and coordination at the end."""
    data = folder / "pile.data"
    log = run_lammps(lammps_pour.settle_input(spheres, str(data)), folder)
    found = re.findall(r"Loop time of ([\d.eE+-]+) on \d+ procs for (\d+) steps", log)
    thermo = lammps_pour.thermo_rows(log, 3)
    contacts = int(thermo[-1, 2]) // 2
    phases = [lammps_pour.SETTLE_FALL[:2]] + [stage[:2] for stage in lammps_pour.SETTLE_QUENCH]
    return data, {"settle_loop_s": sum(float(seconds) for seconds, _ in found),
                  "settle_steps": sum(int(steps) for _, steps in found),
                  "settle_simulated_s": sum(steps * dt for steps, dt in phases),
                  "settle_ke_peak_J": float(thermo[:, 1].max()), "settle_ke_end_J": float(thermo[-1, 1]),
                  "settle_contacts_end": contacts, "settle_coordination_end": 2.0 * contacts / spheres}


def impact_input(plugin: str, v_in: float, style: str, coeff: str, steps: int) -> str:
    lines = ["units si", "atom_style sphere 1" if "mdr" in coeff else "atom_style sphere", "atom_modify map array",
             "newton off", "comm_modify vel yes", "boundary f f f",
             "region box block -0.1 0.1 -0.05 0.05 -0.05 0.05", "create_box 1 box",
             f"create_atoms 1 single {-RADIUS!r} 0 0", f"create_atoms 1 single {RADIUS!r} 0 0",
             f"set type 1 diameter {2 * RADIUS!r}", "set type 1 density 2699.0",
             f"set atom 1 vx {0.5 * v_in!r}", f"set atom 2 vx {-0.5 * v_in!r}"]
    if style.startswith("nfd"):
        lines.append(f"plugin load {plugin}")
    lines += [f"pair_style {style}", f"pair_coeff 1 1 {coeff}", "neighbor 0.001 bin",
              "neigh_modify every 1 delay 0 check no", "fix 1 all nve/sphere", f"timestep {DT!r}",
              "variable vr equal vx[1]-vx[2]", "thermo_style custom step v_vr", "thermo_modify format float %.17g",
              f"thermo {steps}", f"run {steps}"]
    return "\n".join(lines) + "\n"


def restitution(plugin: str, folder: Path, parameters: Path = ROOT / "results" / "calibration" / "parameters.json",
                speeds=SPEEDS_OVER_V_Y) -> list[dict]:
    """Part 2 (module docstring) at ``speeds`` (multiples of v_Y) with the two constants of the
    calibration whose parameter file is ``parameters``."""
    import nfdmodel
    from calib.report.parameter_file import two_constant_law
    from nfdmodel import ContactPair, Material, VZParams

    calibrated = two_constant_law(parameters)
    record = json.loads(Path(parameters).read_text())["material"]
    material = Material(record["E"], record["nu"], record["sigma_y"], 2699.0)
    pair = ContactPair.sphere_sphere(material, RADIUS, material, RADIUS)
    params = VZParams.from_dimensionless(pair, calibrated.Ca_hat, calibrated.Kc_hat, calibrated.window)
    nfd_coeff = (f"{material.E!r} {material.nu!r} {material.sigma_y!r} {float(calibrated.Ca_hat)!r} {float(calibrated.Kc_hat)!r} "
                 f"window inf")
    mdr_coeff = (f"mdr {material.E!r} {material.nu!r} {material.sigma_y!r} 0.0 0.5 0.0 damping mdr 1 "
                 f"tangential linear_nohistory 0.0 0.0")
    rows = []
    for ratio in speeds:
        v_in = ratio * pair.v_Y
        estimate = nfdmodel.collision_reference("vz", params, [v_in]).contact_time_estimate[0]
        steps = int(2.0 * estimate / DT) + 100
        with warnings.catch_warnings():          # beyond the window: said in the column in_calibrated_window
            warnings.simplefilter("ignore", nfdmodel.RangeWarning)
            reference = nfdmodel.collide("vz", params, [v_in], dt=DT)
        e = {}
        for name, style, coeff in (("nfd", "nfd/vz", nfd_coeff), ("mdr", "granular", mdr_coeff)):
            log = run_lammps(impact_input(plugin, v_in, style, coeff, steps), folder)
            rows_out = [line.split() for line in log.splitlines() if re.fullmatch(r"\s*\d+\s+[-+.\deE]+\s*", line)]
            e[name] = -float(rows_out[-1][1]) / v_in
        rows.append({"v_in_over_v_Y": ratio, "v_in_m_s": v_in, "P_max_over_P_Y": reference.P_max[0] / pair.P_Y,
                     "e_reference_nfdmodel": reference.e_velocity[0], "e_nfd_vz_lammps": e["nfd"],
                     "e_mdr_lammps": e["mdr"],
                     "nfd_minus_reference": e["nfd"] - reference.e_velocity[0],
                     "mdr_minus_reference": e["mdr"] - reference.e_velocity[0],
                     "in_calibrated_window": bool(reference.P_max[0] <= params.window.P_max_over_P_Y * pair.P_Y)})
    return rows


def picture(plugin: str, folder: Path, path: Path, steps: int) -> dict:
    dump = folder / "pour.final"
    text = lammps_pour.pour_input(plugin, n=300, steps=steps, thermo=steps, drift=0.0, rebuild_every_step=False,
                                  dump=str(dump))
    log = run_lammps(text, folder)
    final = np.loadtxt(dump, skiprows=9)
    _, side, rows = lammps_pour.spheres(300, drift=0.0)
    start = np.array([(kind, R, x, z) for kind, R, x, _, z, *_ in rows])
    plt = output.pyplot()
    from matplotlib.collections import PatchCollection
    from matplotlib.patches import Circle

    fig, axes = plt.subplots(1, 2, figsize=(9.0, 3.0), sharey=True)
    colours = {1: "tab:grey", 2: "tab:blue"}
    for ax, (title, points) in zip(axes, (("start", [(k, R, x, z) for k, R, x, z in start]),
                                          (f"after {steps * lammps_pour.DT * 1e3:.0f} ms",
                                           [(k, R, x, z) for _, k, R, x, _, z in final]))):
        circles = [Circle((1e3 * x, 1e3 * z), 1e3 * R) for _, R, x, z in points]
        ax.add_collection(PatchCollection(circles, facecolors=[colours[int(k)] for k, *_ in points],
                                          edgecolors="none", alpha=0.85))
        ax.set_xlim(0.0, 1e3 * side)
        ax.set_title(f"{title} (grey: aluminium, blue: steel)", fontsize=9)
        ax.set_xlabel("x [mm] (side view)")
        ax.set_aspect("equal")
    ax = axes[0]
    ax.set_ylabel("z [mm]")
    ax.set_ylim(-1.0, 1e3 * float(max(start[:, 3].max(), final[:, 5].max())) + 3.0)
    for ax in axes:
        ax.axhline(0.0, color="k", lw=1)
    fig.suptitle("300 spheres poured onto a rigid floor: pair_style nfd/vz + fix nfd/wall/vz", fontsize=10)
    output.save_figure(fig, path)
    return {"picture_steps": steps, "picture_loop_s": loop_time(log)[0]}


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--spheres", type=int, default=3000, help="the pour's spheres")
    parser.add_argument("--steps", type=int, default=10000, help="timed steps of the pour (1e-7 s)")
    parser.add_argument("--repeat", type=int, default=3, help="runs per law, scene and rank count (the best kept)")
    parser.add_argument("--picture-steps", type=int, default=600000, help="the picture's pour (1e-7 s steps)")
    parser.add_argument("--pile-spheres", type=int, default=3000, help="the dense pile's spheres")
    parser.add_argument("--pile-steps", type=int, default=5000, help="timed steps on the pile (1e-7 s)")
    parser.add_argument("--friction", action="store_true", help="also the pile with friction and rolling "
                        "resistance (scene 'pile+friction')")
    parser.add_argument("--region", action="store_true", help="also the pile with friction on a region wall "
                        "(scene 'pile+region': fix nfd/wall/region/vz against fix wall/gran/region)")
    parser.add_argument("--cylinder", action="store_true", help="also that pile on a cylinder's bottom cap "
                        "(scene 'pile+cylinder': the region style's cost)")
    parser.add_argument("--plugin", default=None, help="time this plugin build (a path) in place of the sources'")
    parser.add_argument("--out", default=str(ROOT / "results" / "lammps"))
    ns = parser.parse_args(argv)
    started = time.perf_counter()
    parts = {}                                  # wall time [s] of each part

    def clock(name: str, since: float) -> float:
        parts[f"{name}_wall_s"] = round(time.perf_counter() - since, 1)
        return time.perf_counter()

    plugin = ns.plugin or lammps_plugin.build_plugin()["path"]
    out = Path(ns.out)
    with tempfile.TemporaryDirectory() as scratch:
        folder = Path(scratch)
        now = time.perf_counter()
        speed = timing(folder, "pour", ns.spheres, ns.steps, ns.repeat, lambda contact, processors:
                       lammps_pour.pour_input(plugin, n=ns.spheres, steps=ns.steps, thermo=ns.steps, contact=contact,
                                              rebuild_every_step=False, processors=processors))
        now = clock("pour", now)
        pile, settled = settle_pile(folder, ns.pile_spheres)
        now = clock("settle", now)
        print(f"pile settled: {settled['settle_steps']} steps ({settled['settle_simulated_s']:.3f} s simulated) in "
              f"{settled['settle_loop_s']:.0f} s; kinetic energy {settled['settle_ke_end_J']:.2e} J "
              f"(peak {settled['settle_ke_peak_J']:.2e} J), {settled['settle_contacts_end']} pair contacts, "
              f"coordination {settled['settle_coordination_end']:.2f}")
        speed += timing(folder, "pile", ns.pile_spheres, ns.pile_steps, ns.repeat, lambda contact, processors:
                        lammps_pour.pile_input(plugin, str(pile), ns.pile_steps, contact=contact,
                                               processors=processors))
        now = clock("pile", now)
        if ns.friction:
            speed += timing(folder, "pile+friction", ns.pile_spheres, ns.pile_steps, ns.repeat,
                            lambda contact, processors: lammps_pour.pile_input(
                                plugin, str(pile), ns.pile_steps, contact=contact, processors=processors,
                                models=FRICTION))
            now = clock("pile_friction", now)
        if ns.region:
            speed += timing(folder, "pile+region", ns.pile_spheres, ns.pile_steps, ns.repeat,
                            lambda contact, processors: region_floor(lammps_pour.pile_input(
                                plugin, str(pile), ns.pile_steps, contact=contact, processors=processors,
                                models=FRICTION)))
            now = clock("region", now)
        if ns.cylinder:
            speed += timing(folder, "pile+cylinder", ns.pile_spheres, ns.pile_steps, ns.repeat,
                            lambda contact, processors: region_floor(lammps_pour.pile_input(
                                plugin, str(pile), ns.pile_steps, contact=contact, processors=processors,
                                models=FRICTION), "cylinder"))
            now = clock("cylinder", now)
        print(f"{'scene':>5} {'ranks':>5} {'contact':<55} {'us/step':>8} {'ns/sph.':>7} {'ns/con.':>7} {'pair':>7} "
              f"{'modify':>7} {'contacts':>11} {'history':>11} {'coord.':>11} {'ratio':>6} {'median':>6} "
              f"{'pair':>6}")

        def pair(row, key, fmt):
            first, last = row[f"{key}_at_start"], row[f"{key}_at_end"]
            return "" if first is None else f"{first:{fmt}}->{last:{fmt}}"

        for r in speed:
            per_contact = "" if r["ns_per_contact_step"] is None else f"{r['ns_per_contact_step']:.0f}"
            print(f"{r['scene']:>5} {r['ranks']:>5} {r['contact']:<55} {r['us_per_step']:>8.1f} "
                  f"{r['ns_per_sphere_step']:>7.1f} {per_contact:>7} {r['pair_us_per_step']:>7.1f} "
                  f"{r['modify_us_per_step']:>7.1f} {pair(r, 'contacts', 'd'):>11} "
                  f"{pair(r, 'history_contacts', 'd'):>11} {pair(r, 'coordination', '.2f'):>11} "
                  f"{r['ratio_to_granular']:>6.2f} {r['median_paired_ratio']:>6.2f} {r['median_paired_pair_ratio']:>6.2f}")
        sweep = restitution(plugin, folder)
        now = clock("restitution", now)
        print(f"\n{'v/v_Y':>6} {'P_max/P_Y':>9} {'e ref':>8} {'e nfd/vz':>9} {'e mdr':>8}")
        for r in sweep:
            print(f"{r['v_in_over_v_Y']:>6g} {r['P_max_over_P_Y']:>9.1f} {r['e_reference_nfdmodel']:>8.4f} "
                  f"{r['e_nfd_vz_lammps']:>9.4f} {r['e_mdr_lammps']:>8.4f}")
        shot = picture(plugin, folder, out / "pour.png", ns.picture_steps)
        clock("picture", now)
    wall = time.perf_counter() - started
    command = "python tests/benchmarks/bench_lammps.py " + " ".join(argv if argv is not None else sys.argv[1:])
    stamp = output.stamp(wall, command=command.strip(), spheres=ns.spheres, steps=ns.steps, repeat=ns.repeat,
                         dt_s=DT, lammps=lammps_plugin.lammps_location()[1], pile_spheres=ns.pile_spheres,
                         pile_steps=ns.pile_steps, **settled, **shot, **parts)
    output.write_csv(out / "timing.csv", speed, comment=output.stamp_comment(stamp))
    output.write_csv(out / "restitution.csv", sweep, comment=output.stamp_comment(stamp))
    nfd_rows = [r for r in speed if r["contact"].startswith("nfd")]
    ratios = {f"{r['scene']}, {r['ranks']} rank(s)": r["ratio_to_granular"] for r in nfd_rows}
    medians = {f"{r['scene']}, {r['ranks']} rank(s)": r["median_paired_ratio"] for r in nfd_rows}
    output.write_json(out / "summary.json", {"ratio_nfd_to_granular": ratios, "median_paired_ratio": medians,
                                             "target": TARGET_RATIO, "target_friction": TARGET_FRICTION_RATIO,
                                             "timing": speed, "restitution": sweep, "stamp": stamp})
    print(f"\nnfd/vz vs granular, median of paired runs: {', '.join(f'{k} {v:.2f}x' for k, v in medians.items())} "
          f"(target <= {TARGET_RATIO}x, pile+friction <= {TARGET_FRICTION_RATIO}x); {wall:.0f} s "
          f"({', '.join(f'{k} {v:.0f}' for k, v in parts.items())}); written to {output.display_path(out)}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
