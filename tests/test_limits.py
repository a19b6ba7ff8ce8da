"""nfdmodel/nfd_limits.h is the one table of the laws' codes, defaults, bounds and solver
tolerances: (a) every #define of it reaches nfdmodel.limits; (b) every Python consumer holds the
table's value (at the bound: accepted or refused as the table says); (c) no source file under
nfdmodel/ or calib/ writes one of the table's distinctive numbers again as a literal; (d) the four
lists of the laws (the table's NFD_LAW_* codes, nfdmodel.registry.LAWS, the kernel's nfd_step
switch, the LAMMPS plugin's all_laws()) name exactly the same laws."""
import io
import math
import re
import tokenize
import warnings
from pathlib import Path

import numpy as np
import pytest

from nfdmodel import (CalibrationWindow, ContactPair, Material, PlausibilityWarning, VZParams, limits, native,
                      reference_case, yield_factor)
from nfdmodel.materials import check_radius
from nfdmodel.validation import LARGEST_POSSIBLE_RADIUS, LARGEST_USUAL_RADIUS, SOLID_RANGES, check_solid

ROOT = Path(__file__).resolve().parent.parent
PAIR = ContactPair.reference()


# ------------------------------------------------------------------------ (a) the header
def test_every_define_of_the_header_is_in_the_table():
    defines = [line.split(None, 2)[1:] for line in limits.HEADER.read_text(encoding="utf-8").splitlines()
               if re.match(r"\s*#\s*define\b", line)]
    guard = [d for d in defines if len(d) == 1]
    assert guard == [["NFD_LIMITS_H"]]
    values = {name: text.split("/*")[0].strip() for name, text in (d for d in defines if len(d) == 2)}
    assert len(values) == len(limits.TABLE) >= 20
    for name, text in values.items():
        assert name.startswith("NFD_"), name
        key = name[len("NFD_"):]
        assert key in limits.TABLE, f"{name} {text} is not read by nfdmodel.limits"
        assert limits.TABLE[key] == float(text) and getattr(limits, key) == limits.TABLE[key], name
        assert isinstance(limits.TABLE[key], int) == bool(re.fullmatch(r"[-+]?\d+", text)), name


def test_the_law_codes_are_one_per_law_and_name_the_registry():
    from nfdmodel import LAWS
    codes = sorted(limits.LAW_NAMES)
    assert codes == list(range(limits.LAW_COUNT))
    assert set(limits.LAW_CODES) == set(LAWS)
    assert native.LAW_CODES is limits.LAW_CODES


# ------------------------------------------------------------------------ (b) the consumers
def test_vz_constants_are_admitted_up_to_the_table_s_bounds_and_not_beyond():
    """Ca_hat in [CA_HAT_MIN, CA_HAT_MAX], Kc_hat in [0, KC_HAT_MAX]: accepted at each bound,
    refused just beyond it with the bound in the message."""
    low, high, kc = limits.CA_HAT_MIN, limits.CA_HAT_MAX, limits.KC_HAT_MAX
    VZParams.from_dimensionless(PAIR, low, 0.0)
    VZParams.from_dimensionless(PAIR, high, 0.0)
    VZParams.from_dimensionless(PAIR, high, kc)
    for Ca_hat, Kc_hat, name in ((low * (1 - 1e-9), 0.0, "Ca"), (high * (1 + 1e-9), 0.0, "Ca"),
                                 (high, kc * (1 + 1e-9), "Kc")):
        with pytest.raises(ValueError, match=rf"^{name} out of range: .*{high if name == 'Ca' else kc:g}"):
            VZParams.from_dimensionless(PAIR, Ca_hat, Kc_hat)
    from nfdmodel import vz
    assert vz.CA_HAT_RANGE == (low, high) and vz.KC_HAT_MAX == kc


def test_the_default_window_is_the_recipe_s_largest_peak_and_the_assumed_window():
    from calib.fit import recipe
    from nfdmodel import window
    assert CalibrationWindow.assumed_default().P_max_over_P_Y == limits.DEFAULT_WINDOW
    assert window.DEFAULT_RECIPE_P_MAX_OVER_P_Y == limits.DEFAULT_WINDOW
    assert max(recipe.DEFAULT_PEAKS_OVER_YIELD) == recipe.DEFAULT_PEAKS_OVER_YIELD[-1] == limits.DEFAULT_WINDOW
    assert f"{limits.DEFAULT_WINDOW:g} P_Y" in CalibrationWindow.assumed_default().source


@pytest.mark.parametrize("name, low, high", [("E", limits.E_MIN, limits.E_MAX),
                                             ("sigma_y", limits.SIGMA_Y_MIN, limits.SIGMA_Y_MAX),
                                             ("rho", limits.RHO_MIN, limits.RHO_MAX),
                                             ("v_in", 0.0, limits.V_IN_MAX)])
def test_the_solid_ranges_are_the_table_s(name, low, high):
    assert SOLID_RANGES[name][:2] == (low, high)
    assert check_solid(name, high) == high and check_solid(name, low) == low
    for beyond in (high * (1 + 1e-9), low * (1 - 1e-9) if low else -1.0):
        with pytest.raises(ValueError, match=rf"^{name} out of range for an? (solid|impact): need "
                                             rf"{re.escape(f'{low:g} <= {name} <= {high:g}')} "):
            check_solid(name, beyond)


def test_a_material_at_the_table_s_bounds():
    base = dict(E=reference_case.E, nu=reference_case.NU, sigma_y=reference_case.SIGMA_Y, rho=reference_case.RHO)
    for key, value in (("E", limits.E_MAX), ("sigma_y", limits.SIGMA_Y_MIN), ("rho", limits.RHO_MAX)):
        Material(**{**base, key: value})
        with pytest.raises(ValueError, match=rf"^{key} out of range"):
            Material(**{**base, key: value * (1 + 1e-9) if value != limits.SIGMA_Y_MIN else value * (1 - 1e-9)})
    nu_below = math.nextafter(limits.NU_MAX, 0.0)
    Material(**{**base, "nu": nu_below})
    assert yield_factor(nu_below) > 0
    for call in (lambda: Material(**{**base, "nu": limits.NU_MAX}), lambda: yield_factor(limits.NU_MAX),
                 lambda: ContactPair(0.1, 7e10, 1e8, limits.NU_MAX, 1.0)):
        with pytest.raises(ValueError, match=rf"^nu out of range: need nu >= 0 and nu < {limits.NU_MAX:g}"):
            call()


def test_the_calibration_s_nu_ranges_are_the_table_s():
    from pydantic import TypeAdapter, ValidationError

    from calib.commands.common import MATERIAL_RANGES
    from calib.fe.material import elastic_constants
    from calib.scenes.schema import PoissonRatio
    scene_nu = TypeAdapter(PoissonRatio)
    assert scene_nu.validate_python(math.nextafter(limits.NU_MAX, 0.0)) < limits.NU_MAX
    with pytest.raises(ValidationError):
        scene_nu.validate_python(limits.NU_MAX)
    assert MATERIAL_RANGES["nu"]["high"] == limits.NU_MAX and not MATERIAL_RANGES["nu"].get("high_inclusive")
    assert elastic_constants(7e10, math.nextafter(limits.NU_MAX, 0.0))[1] < limits.NU_MAX
    with pytest.raises(ValueError, match=rf"^nu out of range: need nu >= 0 and nu < {limits.NU_MAX:g}"):
        elastic_constants(7e10, limits.NU_MAX)


def test_the_radius_bounds_are_the_table_s():
    assert (LARGEST_USUAL_RADIUS, LARGEST_POSSIBLE_RADIUS) == (limits.RADIUS_USUAL_MAX, limits.RADIUS_MAX)
    with warnings.catch_warnings():
        warnings.simplefilter("error", PlausibilityWarning)
        assert check_radius("R", limits.RADIUS_USUAL_MAX) == limits.RADIUS_USUAL_MAX
        with pytest.raises(PlausibilityWarning):
            check_radius("R", limits.RADIUS_USUAL_MAX * (1 + 1e-9))
    with pytest.warns(PlausibilityWarning):
        assert check_radius("R", limits.RADIUS_MAX) == limits.RADIUS_MAX
    with pytest.raises(ValueError, match=rf"^R out of range for a particle: need 0 < R <= {limits.RADIUS_MAX:g} m"):
        check_radius("R", limits.RADIUS_MAX * (1 + 1e-9))


@pytest.mark.laws      # the numpy solve meets its tolerance too (.ci/run)
def test_the_solvers_use_the_table_s_tolerances():
    import nfdmodel
    from calib.report import collision as report
    from nfdmodel import vz_curve, vz_table
    assert (vz_curve.NEWTON_TOLERANCE, vz_curve.NEWTON_MAX_ITERATIONS) == (limits.VZ_TOLERANCE,
                                                                         limits.VZ_MAX_ITERATIONS)
    assert (nfdmodel.NEWTON_TOLERANCE, nfdmodel.NEWTON_MAX_ITERATIONS) == (limits.VZ_TOLERANCE,
                                                                         limits.VZ_MAX_ITERATIONS)
    assert (vz_table.NEWTON_TOLERANCE, vz_table.NEWTON_MAX_ITERATIONS) == (limits.TABLE_TOLERANCE,
                                                                         limits.TABLE_MAX_ITERATIONS)
    assert "limits.VZ_TOLERANCE" in Path(report.__file__).read_text(encoding="utf-8")
    # the vz solve meets its tolerance: the force reproduces the explicit loading curve delta(P)
    params = VZParams.reference()
    P = PAIR.P_Y * np.geomspace(1.5, 200.0, 50)
    from nfdmodel import get_law
    law = get_law("vz")
    force, _ = law.force_function(params.loading_approach(P), law.initial_state(P.size), params)
    np.testing.assert_allclose(force, P, rtol=limits.VZ_TOLERANCE)


# ------------------------------------------------------------------------ (c) the scan
# A number of the table written again as a literal is a second source of truth. "Distinctive":
# the value, and (for common values such as 1e4) an identifier of the same statement naming the
# quantity (a dict key given as a string counts). 0.5 (nu's bound) and the law codes 0..4 are too
# common to be told apart from other uses: their consumers are checked above.
def _word(name: str) -> str:
    """``name`` as a part of an identifier between underscores (sigma_y in largest_sigma_y), not
    after "over_" (E_OVER_SIGMA_Y_RANGE is a ratio, another quantity)."""
    return rf"(?:^|(?<!over)_){name}(?:_|$)"


DISTINCTIVE = {                      # table name: regex over the statement's identifiers, or None: anywhere
    "DEFAULT_WINDOW": None,
    "E_MAX": None,
    "E_MIN": _word("e"),
    "SIGMA_Y_MIN": _word("sigma_?y"), "SIGMA_Y_MAX": _word("sigma_?y"),
    "RHO_MIN": _word("rho"), "RHO_MAX": _word("rho"),
    "V_IN_MAX": _word("v_in"),
    "RADIUS_USUAL_MAX": r"usual|radius_max", "RADIUS_MAX": r"possible|radius_max",
    "CA_HAT_MIN": _word("ca_hat"), "CA_HAT_MAX": _word("ca_hat"), "KC_HAT_MAX": _word("kc_hat"),
    "VZ_TOLERANCE": r"newton", "VZ_MAX_ITERATIONS": r"newton",
    "TABLE_TOLERANCE": r"newton", "TABLE_MAX_ITERATIONS": r"newton", "TABLE_MAX_NODES": r"node",
    "MONOTONE_LOAD_MAX": r"monoton", "MONOTONE_POINTS": r"monoton", "DISSIPATION_LOAD_MIN": r"dissipat",
    "DISSIPATION_LOAD_MAX": r"dissipat", "DISSIPATION_POINTS": r"dissipat", "DISSIPATION_SLACK": r"dissipat|slack",
    "STEPS_PER_CONTACT_MIN": r"steps_per_contact", "STEPS_PER_UNLOADING_MIN": r"steps_per_unloading",
    "HERTZ_IMPACT_TIME": None,
    "RATE_LENGTH_FACTOR": r"rate|length",
}
SCANNED = ("nfdmodel", "calib")
SUFFIXES = (".py", ".c", ".h", ".cpp")
NOT_SCANNED = ("nfdmodel/nfd_limits.h",)     # the LAMMPS plugin (nfdmodel/lammps/*.h, *.cpp) is scanned too
_IDENTIFIER = re.compile(r"[A-Za-z_]\w*")
_C_NUMBER = re.compile(r"(?<![\w.])(\d+\.?\d*(?:[eE][-+]?\d+)?|\.\d+(?:[eE][-+]?\d+)?)[fFlLuU]*(?![\w.])")


def python_statements(text: str):
    """(line, identifiers, [(line, number literal)]) per logical line of Python source: names,
    and string literals that are bare identifiers (dict keys such as "sigma_y"); numbers inside
    other strings and comments are text, not code."""
    words, numbers, first = [], [], None
    for token in tokenize.generate_tokens(io.StringIO(text).readline):
        if token.type in (tokenize.NEWLINE, tokenize.ENDMARKER):
            if numbers:
                yield first, words, numbers
            words, numbers, first = [], [], None
            continue
        first = token.start[0] if first is None else first
        if token.type == tokenize.NAME:
            words.append(token.string)
        elif token.type == tokenize.STRING:
            inner = token.string.strip("'\"")
            if _IDENTIFIER.fullmatch(inner):
                words.append(inner)
        elif token.type == tokenize.NUMBER:
            numbers.append((token.start[0], token.string))


def c_statements(text: str):
    """(line, identifiers, [(line, number literal)]) per line of C/C++ source, comments and
    string literals removed."""
    text = re.sub(r"/\*.*?\*/", lambda m: "\n" * m.group().count("\n"), text, flags=re.S)
    text = re.sub(r"//[^\n]*", "", text)
    text = re.sub(r'"(?:\\.|[^"\\])*"', '""', text)
    for number, line in enumerate(text.splitlines(), 1):
        found = [(number, m.group(1)) for m in _C_NUMBER.finditer(line)]
        if found and not line.lstrip().startswith("#include"):
            yield number, _IDENTIFIER.findall(line), found


def restated_numbers(text: str, suffix: str) -> list[str]:
    """'line: literal (TABLE_NAME)' for each distinctive number of the table in ``text``."""
    hits = []
    statements = python_statements(text) if suffix == ".py" else c_statements(text)
    for _, words, numbers in statements:
        for line, literal in numbers:
            try:
                value = float(literal.rstrip("fFlLuU").replace("_", ""))
            except ValueError:                       # 0x.., 1j: not one of the table's numbers
                continue
            for name, context in DISTINCTIVE.items():
                if float(limits.TABLE[name]) == value and (
                        context is None or any(re.search(context, word, re.IGNORECASE) for word in words)):
                    hits.append(f"{line}: {literal} ({name})")
    return hits


def scanned_files():
    for top in SCANNED:
        for path in sorted((ROOT / top).rglob("*")):
            relative = path.relative_to(ROOT).as_posix()
            if path.suffix in SUFFIXES and not relative.startswith(NOT_SCANNED) and "__pycache__" not in relative:
                yield relative, path


@pytest.mark.parametrize("text, suffix", [
    ("P_MAX_OVER_P_Y = 41.2\n", ".py"),
    ("window = CalibrationWindow(1.0, 41.2)\n", ".py"),
    ("E_LIMIT = 2e12\n", ".py"),
    ('RANGES = {"sigma_y": (1e4, 1e11)}\n', ".py"),
    ("largest_sigma_y = 1e11\n", ".py"),
    ("rho_max = 3e4\n", ".py"),
    ("check_real('Ca_hat', Ca_hat, low=1e-8)\n", ".py"),
    ("if (Kc_hat > 1e4) return -1;\n", ".c"),
    ("#define NFD_WINDOW 41.2\n", ".h"),
    ("  const double sigma_y_max = 1e11;  // whiskers\n", ".cpp"),
    ("NEWTON_TOLERANCE = 1e-10\n", ".py"),
])
def test_the_scan_finds_a_restated_number(text, suffix):
    assert restated_numbers(text, suffix)


@pytest.mark.parametrize("text, suffix", [
    ("n_fit = 10\n", ".py"),                                        # 10: not next to a radius bound
    ("E_OVER_SIGMA_Y_RANGE = (20.0, 1e4)\n", ".py"),               # another quantity's 1e4
    ("xtol = 1e-12  # 41.2\n", ".py"),                             # a comment
    ("message = f'window 41.2, sigma_y <= 1e11'\n", ".py"),         # text
    ("/* 41.2 P_Y */ double x = 2.0 * sigma_y;\n", ".c"),
    ('printf("window 41.2, sigma_y %g", sigma_y);\n', ".c"),
])
def test_the_scan_leaves_other_numbers_alone(text, suffix):
    assert not restated_numbers(text, suffix)


def test_no_source_file_restates_a_number_of_the_table():
    found = {relative: hits for relative, path in scanned_files()
             if (hits := restated_numbers(path.read_text(encoding="utf-8"), path.suffix))}
    assert sum(1 for _ in scanned_files()) > 50
    assert not found, "numbers of nfdmodel/nfd_limits.h written again (read them from nfdmodel.limits or " \
                      f"include nfd_limits.h): {found}"


def test_the_plugin_names_each_law_as_the_table_does():
    """Each NfdLaw of the LAMMPS plugin is built with an NFD_LAW_* code and the name nfdmodel
    gives that code (pair_style nfd/<name>); every law of the table is there once."""
    source = (ROOT / "nfdmodel" / "lammps" / "nfd_law.cpp").read_text(encoding="utf-8")
    declared = {code: name for code, name in re.findall(r"\(\s*NFD_(LAW_\w+)\s*,\s*\"([\w-]+)\"", source)}
    assert {limits.TABLE[code]: name for code, name in declared.items()} == limits.LAW_NAMES


# ------------------------------------------------------------------------ (d) the four law lists
def kernel_switch_laws(source: str) -> list[str]:
    """The NFD_LAW_* case labels of ``nfd_step``'s switch in nfd_kernel.c (C text), in order."""
    body = re.search(r"\bint\s+nfd_step\s*\([^)]*\)\s*\{(.*?)\n\}", source, re.S)
    assert body, "nfd_kernel.c has no nfd_step"
    return re.findall(r"\bcase\s+NFD_(LAW_\w+)\s*:", body.group(1))


def plugin_all_laws(source: str) -> list[str]:
    """The NFD_LAW_* codes of the laws ``all_laws()`` of nfd_law.cpp (C++ text) returns, in order:
    each entry &variable of its array, the variable's class, that class's NFD_LAW_* constructor code."""
    body = re.search(r"\ball_laws\s*\(\s*\)\s*\{(.*?)\n\}", source, re.S)
    assert body, "nfd_law.cpp has no all_laws()"
    classes = dict((variable, cls) for cls, variable in re.findall(r"static\s+const\s+(\w+)\s+(\w+)\s*;",
                                                                    body.group(1)))
    array = re.search(r"laws\[\]\s*=\s*\{([^}]*)\}", body.group(1))
    assert array, "all_laws() has no laws[] array"
    entries = [name for name in re.findall(r"&\s*(\w+)", array.group(1))]
    codes = dict(re.findall(r"\b(\w+)\s*\(\s*\)\s*:\s*\w*\s*\w+\s*\(\s*NFD_(LAW_\w+)\s*,", source))
    return [codes.get(classes.get(entry, "?"), f"?{entry}") for entry in entries]


def law_lists() -> dict[str, list[str]]:
    """{list: the law names it holds, as the table names them (limits.LAW_NAMES)}."""
    from nfdmodel import LAWS
    named = {f"LAW_{name.upper().replace('-', '_')}": name for name in limits.LAW_CODES}
    kernel = (ROOT / "nfdmodel" / "nfd_kernel.c").read_text(encoding="utf-8")
    plugin = (ROOT / "nfdmodel" / "lammps" / "nfd_law.cpp").read_text(encoding="utf-8")
    return {"nfd_limits.h": [limits.LAW_NAMES[code] for code in sorted(limits.LAW_NAMES)],
            "registry.LAWS": list(LAWS),
            "nfd_kernel.c nfd_step": [named.get(code, code) for code in kernel_switch_laws(kernel)],
            "nfd_law.cpp all_laws()": [named.get(code, code) for code in plugin_all_laws(plugin)]}


def test_the_four_law_lists_name_the_same_laws():
    lists = law_lists()
    table = lists["nfd_limits.h"]
    assert len(table) == limits.LAW_COUNT == 6
    for where, names in lists.items():
        assert len(names) == len(set(names)), f"{where} names a law twice: {names}"
        assert set(names) == set(table), f"{where} names {sorted(names)}, nfd_limits.h {sorted(table)}"


def test_the_law_list_parsers_see_a_missing_law():
    kernel = ("int nfd_step(int law, double delta)\n{\n    switch (law) {\n"
              "    case NFD_LAW_HERTZ: return 0;\n    case NFD_LAW_VZ: return 1;\n    default: return 2;\n    }\n}\n")
    assert kernel_switch_laws(kernel) == ["LAW_HERTZ", "LAW_VZ"]
    plugin = ("class HertzLaw : public SolidLaw {\n    HertzLaw() : SolidLaw(NFD_LAW_HERTZ, \"hertz\") {}\n};\n"
              "class VzLaw : public SolidLaw {\n    VzLaw() :\n        SolidLaw(NFD_LAW_VZ, \"vz\") {}\n};\n"
              "static const NfdLaw *const *all_laws()\n{\n    static const HertzLaw hertz;\n"
              "    static const VzLaw vz;\n    static const NfdLaw *const laws[] = {&hertz, nullptr};\n"
              "    return laws;\n}\n")
    assert plugin_all_laws(plugin) == ["LAW_HERTZ"]
