"""The Chung & Ooi impacts (calib.studies.chung_ooi) in LAMMPS: every impact of a case in one run.

Each impact is its own sphere on the wall z = 0 (``fix nfd/wall/hertz``, ``nfd/wall/vz`` or
``wall/gran granular hertz/material`` with E doubled: wall/gran mixes the sphere with itself), or
its own pair of spheres touching at z = 0 (``pair_style nfd/hertz`` or ``granular hertz/material``),
the impacts FAR apart along x, all starting at first touch with nfdmodel.oblique_collide's
velocities and spins (two spheres: in their centre-of-mass frame), integrated by ``fix
nve/sphere`` with the study's time step for ``steps`` steps; then ``write_dump`` of the final
velocities and spins. Test 3's restitutions differ per impact: one wall fix per sphere.
"""
from __future__ import annotations

import math
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

from calib import lammps_plugin
from calib.studies.chung_ooi_cases import hertz_closed_form, plastic_params

FAR = 4.0          # impacts this many (2 R_i + 2 R_j) apart


def num(value: float) -> str:
    return repr(float(value))


def models(case, restitution: float | None, plastic: bool = False) -> str:
    """The nfd styles' damping and tangential keywords of an impact (the study's Friction)."""
    words = []
    if restitution is not None and restitution < 1.0:
        words.append(f"damping coeff_restitution {num(restitution)}")
    if case.mu > 0.0:
        words.append(f"tangential {'mindlin_rescale/force' if plastic else 'mindlin'} NULL 0 {num(case.mu)}")
    return " ".join(words)


def granular(case, restitution: float | None, E: float) -> str:
    """granular's hertz/material E e|0 nu damping ... tangential ... of the same models."""
    damped = restitution is not None and restitution < 1.0
    normal = (f"hertz/material {num(E)} {num(restitution) if damped else 0} {num(case.solid.nu)} damping "
              f"{'coeff_restitution' if damped else 'viscoelastic'}")
    tangential = f"mindlin NULL 0 {num(case.mu)}" if case.mu > 0.0 else "linear_nohistory 0 0"
    return f"{normal} tangential {tangential}"


def case_input(case, dt: float, steps: int, contact: str, plugin: str, plastic: bool = False) -> str:
    """The LAMMPS input of every impact of the case (module doc)."""
    R_i, m_i, R_j, m_j = case.bodies()
    spacing = FAR * 2.0 * (R_i + max(R_j, R_i))
    n = case.speed.size
    E, nu, rho = case.solid.E, case.solid.nu, case.solid.rho
    v_n = case.speed * np.cos(np.radians(case.angle))
    v_t = case.speed * np.sin(np.radians(case.angle))
    lines = ["units si", "atom_style sphere", "atom_modify map array", "newton off", "comm_modify vel yes",
             "boundary f f f",
             f"region box block {num(-spacing)} {num(n * spacing)} {num(-spacing)} {num(spacing)} "
             f"{num(-2.5 * max(R_j, R_i) - spacing)} {num(2.5 * R_i + spacing)}", "create_box 1 box"]
    atom = 0
    for k in range(n):
        x = k * spacing
        share = 0.0 if case.partner is None else m_i / (m_i + m_j)
        atom += 1
        lines += [f"create_atoms 1 single {num(x)} 0 {num(R_i)}",
                  f"set atom {atom} diameter {num(2 * R_i)} density {num(rho)} vx {num(v_t[k] * (1 - share))} "
                  f"vz {num(-v_n[k] * (1 - share))} omega 0 {num(case.omega[k])} 0"]
        if case.partner is not None:
            atom += 1
            density = rho * case.partner[1]
            lines += [f"create_atoms 1 single {num(x)} 0 {num(-R_j)}",
                      f"set atom {atom} diameter {num(2 * R_j)} density {num(density)} vx {num(-v_t[k] * share)} "
                      f"vz {num(v_n[k] * share)} omega 0 {num(case.omega_partner[k])} 0"]
    lines.append(f"plugin load {plugin}")
    restitutions = [None] * n if case.restitution is None else list(case.restitution)
    if case.partner is None:
        lines += [f"pair_style zero {num(2.0 * R_i)}", "pair_coeff * *"]     # bins of the size of the spheres
        for k, e in enumerate(restitutions):
            group = "all" if case.restitution is None else f"g{k}"
            if group != "all":
                lines.append(f"group g{k} id {k + 1}")
            if contact == "granular":
                lines.append(f"fix w{k} {group} wall/gran granular {granular(case, e, 2.0 * E)} zplane 0.0 NULL")
            elif contact == "nfd/vz":
                params, material = plastic_params()
                lines.append(f"fix w{k} {group} nfd/wall/vz zlo 0.0 {num(material.E)} {num(material.nu)} "
                             f"{num(material.sigma_y)} 0.026 0.0098 window inf {models(case, e, plastic)}")
            else:
                lines.append(f"fix w{k} {group} nfd/wall/hertz zlo 0.0 {num(E)} {num(nu)} {models(case, e)}")
            if group == "all":
                break
    elif contact == "granular":
        lines += ["pair_style granular", f"pair_coeff * * {granular(case, restitutions[0], E)}"]
    elif contact == "nfd/vz":
        params, material = plastic_params()
        lines += ["pair_style nfd/vz", f"pair_coeff 1 1 {num(material.E)} {num(material.nu)} {num(material.sigma_y)} "
                                       f"0.026 0.0098 window inf {models(case, restitutions[0], plastic)}"]
    else:
        lines += ["pair_style nfd/hertz", f"pair_coeff 1 1 {num(E)} {num(nu)} {models(case, restitutions[0])}"]
    lines += [f"neighbor {num(0.1 * R_i)} bin", "neigh_modify every 1 delay 0 check no", "fix 1 all nve/sphere",
              f"timestep {num(dt)}", "thermo 0", f"run {steps}",
              "write_dump all custom final.txt id vx vy vz omegax omegay omegaz modify sort id format float %.17g"]
    return "\n".join(lines) + "\n"


def lmp() -> str:
    found = Path(sys.executable).parent / "lmp"
    path = str(found) if found.is_file() else shutil.which("lmp")
    if not path:
        raise FileNotFoundError(f"lmp not found next to {sys.executable} nor on PATH: pip install 'nfdcal[lammps]'")
    return path


def run_case(case, dt: float, contact: str, plastic: bool = False, steps: int | None = None) -> dict:
    """velocities (impacts, 4, 3): v_i, v_j, omega_i, omega_j after the run (a flat: v_j = omega_j = 0)."""
    plugin = lammps_plugin.build_plugin()["path"]
    if steps is None:
        v_n = case.speed * np.cos(np.radians(case.angle))
        slowest = hertz_closed_form(case.pair(), float(max(v_n.min(), 1e-12)))["t_c"]
        steps = int(math.ceil((3.0 if plastic else 1.3) * slowest / dt)) + 20
    with tempfile.TemporaryDirectory() as folder:
        script = Path(folder) / "in.chung_ooi"
        script.write_text(case_input(case, dt, steps, contact, plugin, plastic))
        done = subprocess.run([lmp(), "-in", str(script), "-log", "none", "-screen", "none"], capture_output=True,
                              text=True, cwd=folder, timeout=1800)
        final = Path(folder) / "final.txt"
        if done.returncode != 0 or not final.is_file():
            raise RuntimeError(f"LAMMPS failed on test {case.test} ({case.material}, {contact}): "
                               f"{(done.stdout + done.stderr)[-1500:]}")
        rows = np.array([[float(t) for t in line.split()] for line in final.read_text().splitlines()[9:]])
    per = 1 if case.partner is None else 2
    rows = rows.reshape(case.speed.size, per, 7)
    out = np.zeros((case.speed.size, 4, 3))
    out[:, 0], out[:, 2] = rows[:, 0, 1:4], rows[:, 0, 4:7]
    if per == 2:
        out[:, 1], out[:, 3] = rows[:, 1, 1:4], rows[:, 1, 4:7]
    return {"velocities": out, "steps": steps}
