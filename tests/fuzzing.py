"""A fuzzer of the command line: hypothesis-generated argument lists, scenes and parameter files.

Each case is a ``Case``: the argument list of one ``nfdcal`` command, and the text of the files
it reads (a scene, a parameter file, a master table), drawn from a grammar of every command's
flags whose values mix plausible numbers, edge values (0, negatives, NaN, inf, 1e308, subnormal
numbers, unit slips such as E = 70 typed in GPa), text where a number belongs and missing
values. ``run_case`` runs it in process, in a fresh sandbox folder (the working folder, the mesh
cache and every output inside it), and judges the outcome:

- success: exit code 0, stdout not empty, JSON output (``--json``) valid and free of NaN and
  inf, stderr only one-line warnings;
- clean error: exit code 2 and stderr one line "nfdcal ...: error: ..." (warnings aside);
- anything else is a failure: a traceback (an exception escaping ``cli.main``), another exit
  code, several error lines, NaN or inf in a written file, a file written or changed outside the
  output paths (``--out``, ``--params-out``, ``--master-out``, the default ``results/`` and the
  mesh cache), an input file changed, or a hang (more than ``timeout_s``).

The commands that run the FE (calibrate, hertz, impact, run, table) get ``--dry-run``: everything up to
the first mesh (validation, plausibility, the load plan, the memory check) runs, the FE does
not; the runtime commands (collide, material) run in full. Used by tests/test_fuzz.py (a few
hundred derandomized cases) and tests/benchmarks/fuzz_cli.py (thousands; table in
results/stability/).
"""
from __future__ import annotations

import contextlib
import importlib.util
import io
import json
import os
import re
import signal
import traceback
from dataclasses import dataclass, field
from pathlib import Path

from hypothesis import strategies as st

from calib import cli


# ----------------------------------------------------------------------------- values
def rarely(draw, one_in: int) -> bool:
    """True once in ``one_in`` draws. Not ``integers(0, n) == 0``: hypothesis favours the
    bounds of a range, so that event would fire far more often than 1/n."""
    return draw(st.sampled_from(range(one_in))) == one_in // 2
EDGE_NUMBERS = ("0", "-0", "-1", "1", "1e308", "1e400", "-1e400", "1e-320", "5e-324", "nan", "NaN", "inf",
                "-inf", "abc", "", " ", "1e", "0x10", "1_000", "1,5", "--", "70", "1e10", "1e-12", "0.5",
                "0.4999999999", "2", "1e4", "1e5", "1e-9", "3.0e+00")
PLAUSIBLE = {"--E": (70e9, 205e9, 117e9, 1e6, 1e12), "--nu": (0.0, 0.3, 0.49, 0.499), "--R": (0.1, 0.005, 1e-6, 10.0),
             "--sigma-y": (100e6, 655e6, 1e6, 5e9), "--rho": (2700.0, 7850.0, 1.0, 1e5),
             "--v-in": (0.02, 0.2, 1.0, 10.0, 1e-5), "--dt": (1e-6, 1e-7, 1e-9), "--Ca": (2.3e-7, 1e-9, 1e-4),
             "--Kc": (3e-4, 1e-6, 1e-1), "--K1": (1e8, 1e6), "--K2": (2e8, 1e7),
             "--peaks": (500.0, 1000.0, 1500.0, 10.0, 40.0), "--contact-size": (4e-5, 1e-4, 1e-3, 1e-9),
             "--P-min": (1.0, 10.0), "--P-max": (1500.0, 100.0), "--steps": (2, 25, 1000, 1001),
             "--workers": (1, 2, 64, 65), "--v-max": (0.05, 0.2, 1.0, 1e-3), "--type": (1, 2, 0, 1.5),
             "--steps-per-contact": (100, 20, 10, 9, 10000, 10001), "--counter-rho": (7850.0, 2700.0, 1.0, 1e5),
             "--angle": (30.0, 0.0, 10.0, 60.0, 89.0), "--mu": (0.3, 0.1, 1.0, 0.0), "--omega": (0.0, 20.0, -50.0, 500.0),
             "--x-gamma-t": (0.5, 0.0, 1.0, 30.0), "--damping": (0.5, 0.2, 0.9, 1.0), "--rolling": (1000.0, 0.01, 0.1),
             "--twisting": (0.01, 1e-4, 1e-3)}
# collide's contact models: LAMMPS's names, and a few it does not have
TANGENTIAL = ("mindlin", "mindlin_rescale", "mindlin/force", "mindlin_rescale/force", "none", "coulomb", "")
DAMPING = ("tsuji", "viscoelastic", "coeff_restitution", "none", "bogus")


def number_text(flag: str, hostile: bool):
    """A value for ``flag``: plausible or scaled from plausible; ``hostile``: an edge case or any
    float's or integer's text."""
    plausible = PLAUSIBLE.get(flag, (1.0,))
    if not hostile:                        # the typical value half the time: deep runs, not only early errors
        return st.one_of(st.just(repr(plausible[0])), st.just(repr(plausible[0])), st.sampled_from(plausible).map(repr),
                         st.tuples(st.sampled_from(plausible), st.sampled_from((0.5, 0.9, 1.1, 2.0)))
                         .map(lambda t: repr(t[0] * t[1]) if isinstance(t[0], float) else str(t[0])))
    return st.one_of(
        st.tuples(st.sampled_from(plausible), st.sampled_from((1e-6, 1e-3, 1e3, 1e6))).map(lambda t: repr(t[0] * t[1])),
        st.sampled_from(EDGE_NUMBERS),
        st.floats(allow_nan=True, allow_infinity=True).map(repr),
        st.integers(-10**6, 10**13).map(str))


# ----------------------------------------------------------------------------- files
def toml_literal():
    return st.one_of(st.sampled_from(("1e9", "-1", "0", "nan", "inf", "-inf", "1e400", '"text"', '""', "true",
                                      "[1.0, 2.0]", "[]", "{a = 1}", "0.3", "5e-324", '"1e9"')),
                     st.floats(allow_nan=False, allow_infinity=False).map(repr))


SCENE_LINES = (  # (section, key, literal) of a valid scene that exercises every stage
    ("scene", "name", '"fuzz"'), ("mesh", "level", '"coarse"'),
    ("material", "name", '"m"'), ("material", "E", "70e9"), ("material", "nu", "0.3"),
    ("material", "sigma_y", "100e6"), ("material", "rho", "2700.0"), ("material", "R", "0.1"),
    ("hertz", "P_max", "300.0"), ("hertz", "steps", "3"),
    ("load_paths", "P_max_over_P_Y", "[13.7, 27.4]"), ("load_paths", "unload", "true"),
    ("calibration", "ship", '"radius"'),
    ("collision", "v_in_over_v_Y", "[2.0, 20.0]"), ("collision", "laws", '["vz", "thornton"]'),
    ("hertz.counter", "E", "210e9"), ("hertz.counter", "nu", "0.28"),
    ("impact", "v_in_over_v_Y", "[0.5, 20.0]"), ("impact", "error_estimate", "false"),
    ("impact.counter", "E", "70e9"), ("impact.counter", "R", "0.1"), ("impact.counter", "sigma_y", "100e6"),
    ("impact.counter", "rho", "2700.0"),
    ("outputs", "plots", "false"), ("outputs", "histories", "false"))
SCENE_SECTIONS = tuple(dict.fromkeys([s for s, _, _ in SCENE_LINES] + ["grid", "bogus"]))
SCENE_KEYS_EXTRA = ("contact_size", "E_over_sigma_y", "velocities", "bogus", "P_max", "unloading_steps",
                    "loading_steps", "out", "level", "v_in", "v_max", "v_max_from", "error_estimate", "quasi_static",
                    "steps_per_contact", "counter", "E", "nu", "sigma_y", "R", "rho")


@st.composite
def scene_text(draw) -> str:
    """A scene: the valid one with up to three lines dropped or given another value, keys added,
    or broken syntax now and then."""
    lines = list(SCENE_LINES)
    for k in draw(st.lists(st.integers(0, len(lines) - 1), max_size=3, unique=True)):
        lines[k] = None if draw(st.booleans()) else (lines[k][0], lines[k][1], draw(toml_literal()))
    lines = [line for line in lines if line is not None]
    for _ in range(draw(st.integers(0, 2)) if rarely(draw, 3) else 0):
        lines.append((draw(st.sampled_from(SCENE_SECTIONS)), draw(st.sampled_from(SCENE_KEYS_EXTRA)),
                      draw(toml_literal())))
    text, section = [], None
    for sec, key, literal in sorted(lines, key=lambda t: SCENE_SECTIONS.index(t[0])):
        if sec != section:
            text.append("[[material]]" if sec == "material" else f"[{sec}]")
            section = sec
        text.append(f"{key} = {literal}")
    body = "\n".join(text) + "\n"
    if rarely(draw, 10):                   # broken syntax now and then
        body = body[:draw(st.integers(0, len(body)))]
    return body


PARAMETERS = {"law": "vz", "Ca": 2.3155e-7, "Kc": 2.984e-4,
              "material": {"E": 70e9, "nu": 0.3, "sigma_y": 100e6, "rho": 2699.0, "R": 0.1}}
TABLE_PARAMETERS = {"law": "vz-table", "table": {"P_over_P_Y": [1.0, 10.0, 100.0], "a_p_over_a_Y": [0.0, 0.25, 1.4],
                                                 "C_R": [1.0, 1.1, 1.5]},
                    "material": {"E": 70e9, "nu": 0.3, "sigma_y": 100e6, "rho": 2699.0, "R": 0.1}}


# drop tests of the paper's aluminium sphere (e from the law's energy balance, rounded)
IMPACT_ROWS = (("0.002", "0.94"), ("0.01", "0.83"), ("0.05", "0.68"), ("0.2", "0.55"))
CSV_CELLS = ("", "nan", "-1", "0", "1.5", "1e400", "text", "inf", "0.5", "1e-9")


# a quasi-static load-unload cycle of the paper's sphere (approach [m], force [N]), two specimens
APPROACH_ROWS = (("0", "0", "a"), ("2e-6", "150", "a"), ("5e-6", "560", "a"), ("8e-6", "1050", "a"),
                 ("7e-6", "640", "a"), ("6.2e-6", "300", "a"), ("5.6e-6", "0", "a"),
                 ("0", "0", "b"), ("4e-6", "420", "b"), ("9e-6", "1250", "b"), ("8e-6", "700", "b"))
# the mistakes users make in a data file: units (mm/s, kN, mm), decimal commas, a second header
DATA_SLIPS = (lambda v: repr(float(v) * 1e3), lambda v: repr(float(v) * 1e-3), lambda v: v.replace(".", ","),
              lambda v: v + "_0", lambda v: "-" + v)


@st.composite
def approach_text(draw) -> str:
    """A force-approach CSV: the valid cycles with cells replaced, a unit slip on a column, the
    test column dropped, rows removed, or truncated now and then."""
    header = ["approach", "force", "test"]
    rows = [list(r) for r in APPROACH_ROWS]
    if rarely(draw, 4):
        column = draw(st.integers(0, 1))
        slip = draw(st.sampled_from(DATA_SLIPS))
        for row in rows:
            row[column] = slip(row[column])
    for _ in range(draw(st.integers(0, 2))):
        rows[draw(st.integers(0, len(rows) - 1))][draw(st.integers(0, 2))] = draw(st.sampled_from(CSV_CELLS))
    if rarely(draw, 5):
        header, rows = header[:2], [r[:2] for r in rows]
    if rarely(draw, 6):
        del rows[draw(st.integers(0, len(rows) - 1)):]
    text = "\n".join(",".join(r) for r in [header] + rows) + "\n"
    if rarely(draw, 10):
        text = text[:draw(st.integers(0, len(text)))]
    return text


@st.composite
def impacts_text(draw) -> str:
    """A drop-test CSV (or force-approach data under the same name): the valid one with cells
    replaced, a column renamed or dropped, rows removed, or truncated now and then."""
    header = ["v_in", "e"]
    rows = [list(r) for r in IMPACT_ROWS[:draw(st.integers(1, len(IMPACT_ROWS)))]]
    for _ in range(draw(st.integers(0, 2))):
        row = draw(st.integers(0, len(rows) - 1))
        rows[row][draw(st.integers(0, 1))] = draw(st.sampled_from(CSV_CELLS))
    if rarely(draw, 8):
        header[draw(st.integers(0, 1))] = draw(st.sampled_from(("V_in", "e ", "P_max", "approach", "")))
    if rarely(draw, 8):
        header, rows = ["approach", "force"], [["1e-6", "10"], ["2e-6", "30"], ["1e-6", "5"], ["5e-7", "0"]]
    if rarely(draw, 5):                          # a unit slip on a whole column (v_in in mm/s, ...)
        column = draw(st.integers(0, 1))
        slip = draw(st.sampled_from(DATA_SLIPS))
        for row in rows:
            if row[column] not in CSV_CELLS:
                row[column] = slip(row[column])
    text = "\n".join(",".join(r) for r in [header] + rows) + "\n"
    if rarely(draw, 10):
        text = text[:draw(st.integers(0, len(text)))]
    return text


def json_value():
    return st.one_of(st.sampled_from(("1e9", "-1", None, [], {}, True, "nan", 0, -1.0, 1e308, 5e-324)),
                     st.floats(allow_nan=True, allow_infinity=True), st.text(max_size=5))


@st.composite
def parameter_text(draw) -> str:
    """A parameter file: the valid one with up to two keys dropped or given another value, a key
    added, or truncated now and then."""
    data = json.loads(json.dumps(draw(st.sampled_from((PARAMETERS, TABLE_PARAMETERS)))))
    places = [(data, key) for key in data if key != "material"] + [(data["material"], key) for key in data["material"]]
    if "table" in data:
        places += [(data["table"], key) for key in data["table"]]
    places.append((data, "material"))
    for k in draw(st.lists(st.integers(0, len(places) - 1), max_size=2, unique=True)):
        where, key = places[k]
        if key not in where:
            continue
        if draw(st.booleans()):
            del where[key]
        else:
            where[key] = draw(json_value())
    if rarely(draw, 5):
        data[draw(st.sampled_from(("Ca_hat", "bogus", "law", "units", "window")))] = draw(json_value())
    text = json.dumps(data)           # NaN and Infinity as JavaScript spells them: must be refused
    if rarely(draw, 10):
        text = text[:draw(st.integers(0, len(text)))]
    return text


# ----------------------------------------------------------------------------- argument lists
MATERIAL_FLAGS = ("--R", "--E", "--nu", "--sigma-y", "--rho")
COUNTER_FLAGS = ("--counter-E", "--counter-nu", "--counter-sigma-y", "--counter-R", "--counter-rho")
# a command's flags: value-taking flags map to how many values they take (1, or "+" for one or more)
COMMANDS = {
    "collide": {"--law": 1, "--v-in": "+", "--dt": 1, "--Ca": 1, "--Kc": 1, "--K1": 1, "--K2": 1,
                "--params": 1, "--json": 0, "--angle": "+", "--mu": 1, "--omega": 1, "--tangential": 1,
                "--damping": 2, "--x-gamma-t": 1, "--rolling": "+", "--twisting": "+", "--plot": 1, "--overwrite": 0,
                **{f: 1 for f in MATERIAL_FLAGS}},
    "material": {"--table": 1, "--vz-table": 1, "--v-max": 1, "--params-out": 1, "--overwrite": 0, "--json": 0,
                 **{f: 1 for f in MATERIAL_FLAGS}},
    "calibrate": {"--peaks": "+", "--v-max": 1, "--contact-size": 1, "--ship": 1, "--out": 1, "--no-plots": 0, "--json": 0,
                  "--ladder": 0, "--quiet": 0, **{f: 1 for f in MATERIAL_FLAGS}},
    "hertz": {"--P-min": 1, "--P-max": 1, "--steps": 1, "--contact-size": 1, "--ladder": 0, "--out": 1,
              "--json": 0, **{f: 1 for f in MATERIAL_FLAGS}},
    "impact": {"--v-in": "+", "--steps-per-contact": 1, "--contact-size": 1, "--params": 1, "--drops": 1,
               "--no-error-estimate": 0, "--no-quasi-static": 0, "--convergence": 0, "--workers": 1, "--out": 1,
               "--no-plots": 0, "--json": 0, "--quiet": 0, **{f: 1 for f in MATERIAL_FLAGS + COUNTER_FLAGS}},
    "run": {"SCENE": 1, "--out": 1, "--v-max": 1, "--json": 0, "--quiet": 0, "--list": 0},
    "table": {"SCENE": 1, "--out": 1, "--v-max": 1, "--workers": 1, "--master-out": 1, "--accuracy": 1, "--check-master": 0,
              "--json": 0, "--quiet": 0},
    "fit-data": {"--impacts": 1, "--force-approach": 1, "--law": 1, "--noise": 1, "--free": 0, "--pair": 0, "--table": 1,
                 "--vz-table": 1,
                 "--params-out": 1, "--plot": 1, "--overwrite": 0, "--force": 0, "--json": 0,
                 **{f: 1 for f in MATERIAL_FLAGS}},
    "export": {"ENGINE": 1, "--params": 1, "--type": 1, "--wall": 2, "--wall-E": 1, "--wall-nu": 1,
               "--like-params-out": 1, "--overwrite": 0, "--json": 0},
    # build and path: the plugin comes from a cache seeded with one build (--force would compile each case)
    "lammps": {"ACTION": 1, "--out": 1, "--json": 0},
    "results-readme": {"--out": 1, "--check": 0, "--json": 0},
}
REQUIRED = {"collide": ("--v-in",), "run": ("SCENE",), "table": ("SCENE",),
            "fit-data": ("--impacts", "--E", "--nu", "--R", "--rho"), "export": ("ENGINE", "--params"),
            "lammps": ("ACTION",)}
POSITIONAL = ("SCENE", "ENGINE", "ACTION")   # a command's positional argument, first after its name
FE_COMMANDS = ("calibrate", "hertz", "impact", "run", "table")
LAWS = ("vz", "vz-table", "thornton", "hertz", "walton-braun", "VZ", "bogus", "")
OUTPUT_FLAGS = ("--out", "--params-out", "--master-out", "--plot", "--like-params-out")
INPUT_FLAGS = ("--params", "--table", "--vz-table", "--impacts", "--drops", "--force-approach")


@dataclass
class Case:
    """One command line and the files it reads (text by sandbox-relative name)."""
    argv: list[str]
    files: dict[str, str] = field(default_factory=dict)

    @property
    def command(self) -> str:
        return self.argv[0] if self.argv else ""


def path_value(flag: str):
    """A path for ``flag``: inside the sandbox, existing or not, a folder, or a fuzzed input."""
    if flag in OUTPUT_FLAGS:
        return st.sampled_from(("out", "out/deeper/p.json", "existing.json", "folder", "link.json",
                                "/dev/null", "out/p.json", "input.json", "impacts.csv", "scene.toml"))
    if flag == "--params":
        return st.sampled_from(("input.json",) * 6 + ("missing.json", "folder", "scene.toml"))
    if flag in ("--table", "--vz-table"):
        return st.sampled_from(("missing.csv", "folder", "input.json", "scene.toml"))
    if flag in ("--impacts", "--drops"):
        return st.sampled_from(("impacts.csv",) * 6 + ("missing.csv", "folder", "input.json", "approach.csv"))
    if flag == "--force-approach":
        return st.sampled_from(("approach.csv",) * 6 + ("missing.csv", "folder", "impacts.csv"))
    return st.sampled_from(("scene.toml",) * 6 + ("reference", "steel", "master_grid", "missing.toml",
                                                  "folder", "bogus"))


def flag_values(flag: str, count, hostile: bool):
    if flag in ("--law",):
        return st.lists(st.sampled_from(LAWS), min_size=1, max_size=1)
    if flag == "--ship":
        return st.lists(st.sampled_from(("radius", "force", "table", "both", "")), min_size=1, max_size=1)
    if flag == "ACTION":
        return st.lists(st.sampled_from(("build", "path", "path", "bogus", "")), min_size=1, max_size=1)
    if flag == "ENGINE":
        return st.lists(st.sampled_from(("lammps",) * 4 + ("LAMMPS", "liggghts", "")), min_size=1, max_size=1)
    if flag == "--wall":                     # FACE COORD
        return st.tuples(st.sampled_from(("zlo", "xhi", "ylo", "top", "", "zlo ")), number_text("--wall", hostile)
                         ).map(list)
    if flag == "--tangential":
        return st.lists(st.sampled_from(TANGENTIAL), min_size=1, max_size=1)
    if flag == "--damping":                  # MODEL VALUE (now and then the value left off)
        return st.tuples(st.sampled_from(DAMPING), number_text(flag, hostile)).map(
            lambda t: list(t) if not t[1].startswith("3") else [t[0]])
    if flag in ("--rolling", "--twisting"):  # sds K GAMMA MU, marshall, none, or a count that is wrong
        models = ("sds", "sds", "none", "marshall" if flag == "--twisting" else "bogus")
        return st.tuples(st.sampled_from(models), st.lists(number_text(flag, hostile), min_size=0, max_size=4)).map(
            lambda t: [t[0], *(t[1][:3] if t[0] == "sds" and len(t[1]) >= 3 else t[1][:1] if t[0] == "sds" else [])])
    if flag in ("--accuracy",):
        return st.lists(st.text(max_size=20), min_size=1, max_size=1)
    if flag in OUTPUT_FLAGS or flag in INPUT_FLAGS + ("SCENE",):
        return st.lists(path_value(flag), min_size=1, max_size=1)
    if flag == "--dt":
        return st.lists(st.one_of(st.just("auto"), number_text(flag, hostile)), min_size=1, max_size=1)
    size = (1, 4) if count == "+" else (1, 1)
    return st.lists(number_text(flag, hostile), min_size=size[0], max_size=size[1])


@st.composite
def command_case(draw, commands: tuple[str, ...] | None = None) -> Case:
    """An argument list of one command (of ``commands``, default any; FE commands with --dry-run) and
    its input files."""
    command = draw(st.sampled_from(sorted(commands or COMMANDS)))
    flags = COMMANDS[command]
    chosen = draw(st.lists(st.sampled_from(sorted(flags)), max_size=6, unique=True))
    if not rarely(draw, 10):                     # mostly all given, so the fuzzer gets past the first check
        chosen += [needed for needed in REQUIRED.get(command, ()) if needed not in chosen and "--list" not in chosen]
    hostile = set(draw(st.lists(st.sampled_from(chosen), max_size=2, unique=True))) if chosen else set()
    argv = [command]
    # now and then one flag loses its value (once per case: deep runs stay common)
    bare = draw(st.sampled_from(chosen)) if chosen and rarely(draw, 10) else None
    for flag in chosen:
        count = flags[flag]
        values = draw(flag_values(flag, count, flag in hostile)) if count else []
        if flag in POSITIONAL:
            argv[1:1] = values
            continue
        if count and flag == bare:
            values = []                          # a flag without its value
        argv += [flag, *values]
    if command in FE_COMMANDS:
        argv.append("--dry-run")
    if rarely(draw, 15):                         # an unknown flag or a stray token
        argv.insert(draw(st.integers(1, len(argv))), draw(st.sampled_from(("--bogus", "-x", "extra", "--", "-1e-3"))))
    files = {"input.json": draw(parameter_text()), "scene.toml": draw(scene_text()),
             "existing.json": "{}\n", "impacts.csv": draw(impacts_text()), "approach.csv": draw(approach_text())}
    return Case(argv=argv, files=files)


# ----------------------------------------------------------------------------- judging
@dataclass
class Outcome:
    kind: str          # "success", "clean error" or "FAIL: <why>"
    code: int | None
    stdout: str
    stderr: str

    @property
    def failed(self) -> bool:
        return self.kind.startswith("FAIL")


class Hang(Exception):
    pass


@contextlib.contextmanager
def time_limit(seconds: float):
    def alarm(signum, frame):
        raise Hang(f"no answer after {seconds:g} s")

    previous = signal.signal(signal.SIGALRM, alarm)
    signal.setitimer(signal.ITIMER_REAL, seconds)
    try:
        yield
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, previous)


def snapshot(root: Path) -> dict[str, tuple[int, int, int]]:
    """Every file under ``root`` (symlinks as such): (size, mtime_ns, mode), by relative path."""
    files = {}
    for path in root.rglob("*"):
        stat = path.lstat()
        if not path.is_dir() or path.is_symlink():
            files[str(path.relative_to(root))] = (stat.st_size, stat.st_mtime_ns, stat.st_mode)
    return files


NON_FINITE = re.compile(r"(?i)(?<![\w.])(nan|-?inf(inity)?)(?![\w.])")


def output_paths(argv: list[str], sandbox: Path) -> list[str]:
    """Sandbox-relative paths a command may write: its output flags (and what a symlink among
    them points to), results/, the mesh cache."""
    allowed = ["results", "cache"]
    for k, token in enumerate(argv[:-1]):
        if token in OUTPUT_FLAGS:
            allowed.append(os.path.normpath(argv[k + 1]))
            target = (sandbox / argv[k + 1]).resolve()
            if target.is_relative_to(sandbox.resolve()):
                allowed.append(str(target.relative_to(sandbox.resolve())))
    return allowed


def read_paths(argv: list[str]) -> set[str]:
    """Sandbox-relative paths the command reads: its input flags' and a scene argument's."""
    read = {os.path.normpath(argv[k + 1]) for k, token in enumerate(argv[:-1]) if token in INPUT_FLAGS}
    if argv and argv[0] in ("run", "table") and len(argv) > 1 and not argv[1].startswith("-"):
        read.add(os.path.normpath(argv[1]))
    return read


def judge(case: Case, sandbox: Path, code, stdout: str, stderr: str, before: dict, after: dict) -> str:
    lines = [line for line in stderr.splitlines() if line.strip()]
    warnings = [line for line in lines if re.match(r"nfdcal( \S+){0,2}: warning: ", line)]
    others = [line for line in lines if line not in warnings]
    if "Traceback" in stderr or "Traceback" in stdout:
        return "FAIL: traceback printed"
    allowed = output_paths(case.argv, sandbox)
    for name in sorted(set(after) | set(before)):
        if before.get(name) == after.get(name):
            continue
        if not any(name == a or name.startswith(a + os.sep) for a in allowed):
            return f"FAIL: touched {name} (outside the output paths {allowed})"
        path = sandbox / name
        if name in after and name.endswith((".json", ".csv")) and path.is_file() and \
                NON_FINITE.search(path.read_text(encoding="utf-8", errors="replace")):
            return f"FAIL: NaN or inf written to {name}"
    if code == 1 and case.command == "results-readme" and "--check" in case.argv and stdout.strip() and not others:
        code = 0                                  # --check's answer "stale or missing" is its exit code 1
    if code == 0:
        if others:
            return f"FAIL: exit 0 with stderr {others[0][:120]!r}"
        if not stdout.strip():
            return "FAIL: exit 0 and nothing on stdout"
        if "--json" in case.argv:
            try:
                json.loads(stdout, parse_constant=lambda c: (_ for _ in ()).throw(ValueError(c)))
            except ValueError as exc:
                return f"FAIL: --json output is not finite JSON ({str(exc)[:80]})"
        return "success"
    if code == 2:
        if len(others) != 1:
            return f"FAIL: exit 2 with {len(others)} error lines"
        if not re.match(r"nfdcal( \S+){0,2}: error: \S", others[0]):      # nfdcal lammps build: error: ...
            return f"FAIL: error line {others[0][:120]!r}"
        return "clean error"
    return f"FAIL: exit code {code}"


def materialize(case: Case, sandbox: Path) -> None:
    for name, text in case.files.items():
        (sandbox / name).write_text(text, encoding="utf-8")
    (sandbox / "folder").mkdir(exist_ok=True)
    if not (sandbox / "link.json").is_symlink():
        (sandbox / "link.json").symlink_to("existing.json")


PLUGIN_CACHE = {}


def seed_plugin_cache(sandbox: Path) -> None:
    """The sandbox's cache holds a build of the LAMMPS plugin (hard links to one build made once
    in the user's cache), so `nfdcal lammps build | path` cases do not compile each time."""
    if "folder" not in PLUGIN_CACHE:
        from calib import lammps_plugin

        PLUGIN_CACHE["folder"] = Path(lammps_plugin.build_plugin()["path"]).parent
    built = PLUGIN_CACHE["folder"]
    target = sandbox / "cache" / "nfdcal" / "lammps" / built.name
    target.mkdir(parents=True, exist_ok=True)
    for path in built.iterdir():
        if path.is_file() and not (target / path.name).exists():
            os.link(path, target / path.name)


def run_case(case: Case, sandbox: Path, timeout_s: float = 60.0) -> Outcome:
    """Run ``case`` in ``sandbox`` (its working folder and mesh cache) and judge the outcome."""
    sandbox = Path(sandbox)
    materialize(case, sandbox)
    if case.command == "lammps" and importlib.util.find_spec("lammps") is not None:
        seed_plugin_cache(sandbox)
    before = snapshot(sandbox)
    stdout, stderr = io.StringIO(), io.StringIO()
    cwd, cache = os.getcwd(), os.environ.get("XDG_CACHE_HOME")
    code = None
    try:
        os.chdir(sandbox)
        os.environ["XDG_CACHE_HOME"] = str(sandbox / "cache")
        with contextlib.redirect_stdout(stdout), contextlib.redirect_stderr(stderr), time_limit(timeout_s):
            try:
                code = cli.main(list(case.argv))
            except SystemExit as exc:          # argparse's usage errors and --help
                code = exc.code if isinstance(exc.code, int) else 2
    except Hang as exc:
        return Outcome(f"FAIL: hang ({exc})", None, stdout.getvalue(), stderr.getvalue())
    except BaseException as exc:               # noqa: BLE001 - anything escaping main is a traceback
        detail = traceback.format_exception_only(type(exc), exc)[-1].strip()
        return Outcome(f"FAIL: {detail[:200]}", None, stdout.getvalue(), stderr.getvalue())
    finally:
        os.chdir(cwd)
        if cache is None:
            os.environ.pop("XDG_CACHE_HOME", None)
        else:
            os.environ["XDG_CACHE_HOME"] = cache
    after = snapshot(sandbox)
    written, read = output_paths(case.argv, sandbox), read_paths(case.argv)
    for name in case.files:     # a file the command reads never changes; another only when named as an output
        if before.get(name) != after.get(name) and (name not in written or name in read):
            return Outcome(f"FAIL: input {name} changed", code, stdout.getvalue(), stderr.getvalue())
    kind = judge(case, sandbox, code, stdout.getvalue(), stderr.getvalue(), before, after)
    return Outcome(kind, code, stdout.getvalue(), stderr.getvalue())



# ----------------------------------------------------------------------------- fit-data: unit factors
# Every column of each data kind multiplied by a factor 1e-3..1e3 (1: the data as made). FE data the
# law never made: the FE's drop tests of results/impact/drop_tests.csv (v_in, e, P_max, contact_time;
# aluminium, sigma_Y 1e8 Pa), the FE drop tests and force-approach curve of an off-grid material
# (tests/data/vz_master_fe.json); for the two-constant law (--law vz, biased against the FE) drop
# tests of that law itself with 2 % noise. Expected: sigma_Y inside its reported 95 % interval,
# which contains the truth, or one line (exit 2) naming the column.
UNIT_FACTORS = (1e-3, 1e-2, 1e-1, 1.0, 1e1, 1e2, 1e3)
FIT_DATA_KINDS = {"drops e+P+t": ("v_in", "e", "P_max", "contact_time"), "drops e+P": ("v_in", "e", "P_max"),
                  "force": ("approach", "force"), "vz drops e+P": ("v_in", "e", "P_max"),
                  "drops e+dent": ("v_in", "e", "dent"), "drops e+dent+radius": ("v_in", "e", "dent", "radius")}
FIT_DATA_TRUTH = 1e8             # sigma_Y [Pa] of every data kind's material


@dataclass
class FitDataCase:
    kind: str
    column: str
    factor: float

    @property
    def name(self) -> str:
        return f"{self.kind}: {self.column} x {self.factor:g}"


def fit_data_cases() -> list[FitDataCase]:
    """Every (data kind, column, factor) once; factor 1 once per kind."""
    return [FitDataCase(kind, column, factor) for kind, columns in FIT_DATA_KINDS.items()
            for column in columns for factor in UNIT_FACTORS if factor != 1.0 or column == columns[0]]


FIT_DATA_SOURCES = {}


def fit_data_source(kind: str) -> tuple[dict, list[str]]:
    """The unscaled columns of ``kind`` and its specimen's flags (made once)."""
    if kind in FIT_DATA_SOURCES:
        return FIT_DATA_SOURCES[kind]
    import numpy as np

    root = Path(__file__).resolve().parent
    if kind == "drops e+P+t":
        lines = [line for line in (root.parent / "results" / "impact" / "drop_tests.csv").read_text().splitlines()
                 if line and not line.startswith("#")]
        header = lines[0].split(",")
        values = {name: np.array([float(line.split(",")[k]) for line in lines[1:]]) for k, name in enumerate(header)}
        flags = ["--E", "7e10", "--nu", "0.3", "--R", "0.1", "--rho", "2699"]
    elif kind == "vz drops e+P":
        from calib.fit.master_table import MasterTable
        from calib.fit.measured.specimen import Specimen, law_parameters, predict_impacts

        truth = law_parameters(Specimen(70e9, 0.3, 0.1, 2699.0), {"sigma_y": FIT_DATA_TRUTH}, MasterTable.load())
        v = truth.pair.v_Y * np.geomspace(2.0, 100.0, 12)
        rng = np.random.default_rng(7)
        exact = predict_impacts(truth, v)
        values = {"v_in": v, "e": np.minimum(exact["e"] * (1 + 0.02 * rng.standard_normal(v.size)), 1.0),
                  "P_max": exact["P_max"] * (1 + 0.02 * rng.standard_normal(v.size))}
        flags = ["--law", "vz", "--E", "7e10", "--nu", "0.3", "--R", "0.1", "--rho", "2699"]
    elif kind == "drops e+dent+radius":         # the FE's drop tests with its contact radius at the peak
        row = json.loads((root / "data" / "vz_master_radius_fe.json").read_text(encoding="utf-8"))["rows"][0]
        assert row["sigma_y"] == FIT_DATA_TRUTH
        values = {name: np.array([t[name] for t in row["tests"]]) for name in FIT_DATA_KINDS[kind]}
        flags = ["--E", repr(row["E_over_sigma_y"] * row["sigma_y"]), "--nu", repr(row["nu"]), "--R", repr(row["R"]),
                 "--rho", repr(row["rho"])]
    else:
        from calib.fit.vz_master_check import fe_datasets
        from calib.fit.vz_master_table import VZMasterTable

        row = json.loads((root / "data" / "vz_master_fe.json").read_text(encoding="utf-8"))["rows"][0]
        sets = fe_datasets(row, VZMasterTable.load())
        assert sets["sigma_y"] == FIT_DATA_TRUTH
        values = dict(sets["drops"]) if kind != "force" else dict(zip(("approach", "force"), sets["force"]))
        s = sets["specimen"]
        flags = ["--E", repr(s.E), "--nu", repr(s.nu), "--R", repr(s.R), "--rho", repr(s.rho)]
    FIT_DATA_SOURCES[kind] = (values, flags)
    return FIT_DATA_SOURCES[kind]


def fit_data_argv(case: FitDataCase) -> Case:
    """The command line and its data file, ``case.column`` multiplied by ``case.factor``."""
    values, flags = fit_data_source(case.kind)
    columns = FIT_DATA_KINDS[case.kind]
    rows = [",".join(columns)] + [",".join(repr(float(values[c][i]) * (case.factor if c == case.column else 1.0))
                                           for c in columns) for i in range(len(values[columns[0]]))]
    name = "approach.csv" if case.kind == "force" else "impacts.csv"
    flag = "--force-approach" if case.kind == "force" else "--impacts"
    return Case([("fit-data"), flag, name, *flags, "--json", "--params-out", "out/p.json"],
                {name: "\n".join(rows) + "\n"})


def judge_fit_data(case: FitDataCase, outcome: Outcome) -> str:
    """"success" (sigma_Y inside its 95 % interval, which holds the truth), "refused" (one line naming
    the column) or "FAIL: <why>"."""
    if outcome.failed:
        return outcome.kind
    if outcome.kind == "clean error":
        line = [x for x in outcome.stderr.splitlines() if ": error: " in x][0]
        if case.factor == 1.0:
            return f"FAIL: data as made refused: {line[:300]}"
        if not re.search(rf"column '?{case.column}\b", line):
            return f"FAIL: refused without naming the column {case.column}: {line[:300]}"
        return "refused"
    out = json.loads(outcome.stdout)
    if "sigma_y_interval95" in out:
        low, high = out["sigma_y_interval95"]
    else:
        low, high = out["sigma_y"] - 1.96 * out["sigma_y_se"], out["sigma_y"] + 1.96 * out["sigma_y_se"]
    if not (low <= out["sigma_y"] <= high and low <= FIT_DATA_TRUTH <= high):
        return f"FAIL: exit 0, sigma_Y {out['sigma_y']:.4g} Pa, interval {low:.4g}..{high:.4g} (truth {FIT_DATA_TRUTH:g})"
    return "success"


def run_fit_data_case(case: FitDataCase, sandbox: Path, timeout_s: float = 120.0) -> tuple[str, Outcome]:
    outcome = run_case(fit_data_argv(case), sandbox, timeout_s)
    return judge_fit_data(case, outcome), outcome
