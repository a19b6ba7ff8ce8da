"""Each contact formula has one home (nfdmodel/README.md, Where each formula lives): the sources of
calib/, meshes/ and nfdmodel/ (Python, and the C kernel and the LAMMPS plugin in C/C++) are scanned
for the formulas written out again, as tests/test_limits.py scans them for the table's numbers.

A formula's home is one Python module, and for C/C++ the kernel (nfd_kernel.h/.c, nfd_rate.h), whose inline
functions the plugin calls."""
import io
import re
import tokenize
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parent.parent
SCANNED = ("calib", "meshes", "nfdmodel")
SUFFIXES = (".py", ".c", ".h", ".cpp")
C_KERNEL = {"nfdmodel/nfd_kernel.h", "nfdmodel/nfd_kernel.c"}
# The scalar transcription of every law, the specification to port from: it writes each law out in
# full (math only) by design, and the vectorised laws are tested against it.
SPECIFICATION = {"nfdmodel/reference.py"}

ONE = r"1(?:\.0*)?"
NUM = r"[\w.\[\]>-]+"              # a name, attribute or C member (a.b, p->c, x[i])
FORMULAS = {
    # formula: (regexes over code without comments or prose, its homes)
    "E* (1 - nu^2)": ([rf"{ONE}\s*-\s*[^\n;]{{0,60}}\bnu\w*\b[^\n;]{{0,20}}\*\*\s*2\b",
                       rf"{ONE}\s*-\s*{NUM}nu\w*\s*\*\s*{NUM}nu\w*\b"],
                      {"nfdmodel/materials.py"} | C_KERNEL),
    "E*, R* in series (1/(1/x + 1/y))": ([rf"{ONE}\s*/\s*\(\s*{ONE}\s*/\s*{NUM}\s*\+\s*{ONE}\s*/",
                                          rf"{ONE}\s*/\s*sum\("],
                                         {"nfdmodel/materials.py"} | C_KERNEL),
    "p_Y = A_Y sigma_Y and the body that yields first": (
        [r"yield_factor\([^()]*\)\s*\*\s*[\w.\[\]\"']*sigma",
         r"key\s*=\s*lambda[^:]*:\s*yield_factor",
         rf"\bp_Y\s*[<>]=?\s*{NUM}\.p_Y\b"],
        {"nfdmodel/materials.py"} | C_KERNEL),
    "P_Y = pi^3 R*^2 p_Y^3 / (6 E*^2)": ([r"\bpi\s*\*\*\s*3", r"NFD_PI\s*\*\s*NFD_PI\s*\*\s*NFD_PI"],
                                        {"nfdmodel/materials.py"} | C_KERNEL),
    "Hertz radius (3 P R* / (4 E*))^(1/3)": ([r"\b3(?:\.0*)?\s*\*\s*[^;\n]{1,60}?\*\s*[^;\n]{1,30}?/\s*\(\s*4(?:\.0*)?"
                                              rf"\s*\*\s*{NUM}"],
                                             {"nfdmodel/hertz_contact.py"} | C_KERNEL),
    "Hertz force at a radius 4 E* a^3 / (3 R*)": ([rf"\b4(?:\.0*)?\s*\*\s*{NUM}\s*\*\s*{NUM}\s*\*\*\s*3\s*/\s*\(\s*3"],
                                                  {"nfdmodel/hertz_contact.py"}),
    "Hertz peak pressure 3 P / (2 pi a^2)": ([r"\b3(?:\.0*)?\s*\*\s*[\w.]+\s*/\s*\(\s*2(?:\.0*)?\s*\*\s*(?:math\.|np\.)?pi"],
                                             {"nfdmodel/hertz_contact.py"}),
    "Hertz stiffness (4/3) E* sqrt(R*)": ([rf"\b4(?:\.0*)?\s*/\s*3(?:\.0*)?\s*\*\s*{NUM}\s*\*\s*(?:math\.|np\.)?sqrt\("],
                                          {"nfdmodel/hertz_contact.py", "nfdmodel/thornton.py"} | C_KERNEL),
    "Hertz impact (approach, force, duration 2.868)": ([r"\b2\.868", r"\*\*\s*0\.4\b(?!\s*\*)",
                                                        r"(?<![\w.])5(?:\.0*)?\s*\*\s*[\w.]*mass\w*\s*\*"],
                                                       {"nfdmodel/hertz_contact.py", "nfdmodel/nfd_limits.h"}
                                                       | C_KERNEL),
    "Thornton's closed-form restitution": ([r"\b6(?:\.0*)?\s*\*\s*(?:np\.|math\.)?sqrt\(\s*3"], {"nfdmodel/thornton.py"}),
    "Thornton's unloading radius a*^2 = (2 P* + P_Y) / (2 pi p_Y)": (
        [rf"\(\s*2(?:\.0*)?\s*\*\s*{NUM}\s*\+\s*{NUM}P_Y\s*\)\s*/\s*\(\s*2(?:\.0*)?\s*\*\s*(?:math\.|np\.|NFD_)?(?:pi|PI)"],
        {"nfdmodel/thornton.py"} | C_KERNEL),
    "the elastic energy of an unloading curve P <delta - delta_res> / (n + 1)": (
        [r"/\s*\(\s*(?:self\.)?(?:exponent|unloading_exponent|exponent_of)\w*(?:\([^()]*\))?\s*\+\s*1(?:\.0*)?\s*\)"],
        {"nfdmodel/turning_point.py"} | C_KERNEL),
    "the FE's reach (1000 P_Y, 0.2 R)": ([r"(?i)MAX_LOAD_OVER_YIELD\s*\*\s*[\w.]*P_Y\s*,\s*[\w.]*largest_admissible_load",
                                         r"(?i)\b\w*(?:limit|reach|over_yield|over_r)\w*\s*=\s*(?:1000|1e3|0\.2)\b"],
                                        {"calib/fit/recipe.py"}),
    "Johnson-Cook's factor 1 + C ln(rate / rate_0)": ([r"\b1(?:\.0*)?\s*\+\s*[\w.]*C\s*\*\s*(?:np\.|math\.)log\(",
                                                   rf"\b1(?:\.0*)?\s*\+\s*{NUM}\s*\*\s*log\("],
                                                  {"nfdmodel/strain_rate.py", "nfdmodel/nfd_rate.h"}),
    "Cowper-Symonds' factor 1 + (rate / D)^(1/q)": ([r"\b1(?:\.0*)?\s*\+\s*\([^\n;]{0,60}?/\s*[\w.]*\bD\s*\)\s*\*\*",
                                                     rf"\b1(?:\.0*)?\s*\+\s*pow\(\s*{NUM}\s*/"],
                                                    {"nfdmodel/strain_rate.py", "nfdmodel/nfd_rate.h"}),
}
# The FE's files that still derive a formula (file: the formulas), until each spot calls the home.


def python_code(text: str) -> str:
    """``text`` without comments and prose: a string literal holding a space (a docstring, a
    message) is blanked; short names such as "nu" stay."""
    rows = [""] * (text.count("\n") + 2)
    for token in tokenize.generate_tokens(io.StringIO(text).readline):
        if token.type in (tokenize.COMMENT, tokenize.NL, tokenize.NEWLINE) or (
                token.type == tokenize.STRING and " " in token.string):
            continue
        row, column = token.start
        rows[row - 1] = rows[row - 1].ljust(column) + token.string.replace("\n", " ")
    return "\n".join(rows)


def c_code(text: str) -> str:
    """C/C++ ``text`` without comments and string literals."""
    text = re.sub(r"/\*.*?\*/", lambda m: "\n" * m.group().count("\n"), text, flags=re.S)
    text = re.sub(r"//[^\n]*", "", text)
    return re.sub(r'"(?:\\.|[^"\\])*"', '""', text)


def derivations(text: str, suffix: str) -> dict[str, list[str]]:
    """{formula: ['line: code', ...]} of the formulas written out in ``text``."""
    code = python_code(text) if suffix == ".py" else c_code(text)
    found = {}
    for name, (patterns, _) in FORMULAS.items():
        for pattern in patterns:
            for match in re.finditer(pattern, code):
                line = code.count("\n", 0, match.start()) + 1
                found.setdefault(name, []).append(f"{line}: {match.group().strip()}")
    return found


def scanned_files():
    for top in SCANNED:
        for path in sorted((ROOT / top).rglob("*")):
            relative = path.relative_to(ROOT).as_posix()
            if path.suffix in SUFFIXES and "__pycache__" not in relative:
                yield relative, path


def derivations_outside_homes() -> dict[str, dict[str, list[str]]]:
    out = {}
    for relative, path in scanned_files():
        if relative in SPECIFICATION:
            continue
        found = {name: hits for name, hits in derivations(path.read_text(encoding="utf-8"), path.suffix).items()
                 if relative not in FORMULAS[name][1]}
        if found:
            out[relative] = found
    return out


@pytest.mark.parametrize("code, suffix, formula", [
    ("E_star = material.E / (1.0 - material.nu ** 2)\n", ".py", "E* (1 - nu^2)"),
    ("E = float(E) / (1.0 - float(getattr(m, 'nu', 0.0)) ** 2)\n", ".py", "E* (1 - nu^2)"),
    ("m.E_star = m.E / (1.0 - m.nu * m.nu);\n", ".cpp", "E* (1 - nu^2)"),
    ("E = 1.0 / sum((1.0 - m.nu ** 2) / m.E for m in materials)\n", ".py", "E*, R* in series (1/(1/x + 1/y))"),
    ("c.E_star = 1.0 / (1.0 / a.E_star + 1.0 / b.E_star);\n", ".cpp", "E*, R* in series (1/(1/x + 1/y))"),
    ("R = 1.0 / (1.0 / R1 + 1.0 / R2)\n", ".py", "E*, R* in series (1/(1/x + 1/y))"),
    ("first = yield_factor(a.nu) * a.sigma_y <= yield_factor(b.nu) * b.sigma_y\n", ".py",
     "p_Y = A_Y sigma_Y and the body that yields first"),
    ("s = min(bodies, key=lambda s: yield_factor(s[1]) * s[0])\n", ".py", "p_Y = A_Y sigma_Y and the body that yields first"),
    ("NfdMaterial c = a.p_Y <= b.p_Y ? a : b;\n", ".cpp", "p_Y = A_Y sigma_Y and the body that yields first"),
    ("P_Y = math.pi ** 3 * R ** 2 * p ** 3 / (6.0 * E ** 2)\n", ".py", "P_Y = pi^3 R*^2 p_Y^3 / (6 E*^2)"),
    ("a = np.cbrt(3.0 * P * pair.R_star / (4.0 * pair.E_star))\n", ".py", "Hertz radius (3 P R* / (4 E*))^(1/3)"),
    ("a = ((3.0 * target * sphere_radius / (4.0 * E_star)) ** (1.0 / 3.0))\n", ".py",
     "Hertz radius (3 P R* / (4 E*))^(1/3)"),
    ("a = cbrt(3.0 * P * (R_p * R_p) / (4.0 * p->E_star));\n", ".c", "Hertz radius (3 P R* / (4 E*))^(1/3)"),
    ("P = 4.0 * pair.E_star * limit ** 3 / (3.0 * pair.R_star)\n", ".py", "Hertz force at a radius 4 E* a^3 / (3 R*)"),
    ("p0 = 3.0 * force / (2.0 * math.pi * a ** 2)\n", ".py", "Hertz peak pressure 3 P / (2 pi a^2)"),
    ("k = 4.0 / 3.0 * E * math.sqrt(R)\n", ".py", "Hertz stiffness (4/3) E* sqrt(R*)"),
    ("t = 2.868 * (m ** 2 / (R * E ** 2 * v)) ** 0.2\n", ".py", "Hertz impact (approach, force, duration 2.868)"),
    ("d = (15.0 * m * v * v / (16.0 * E * math.sqrt(R))) ** 0.4\n", ".py", "Hertz impact (approach, force, duration 2.868)"),
    ("d = (5.0 * pair.mass_star * v_in ** 2 / (4.0 * k)) ** 0.4\n", ".py", "Hertz impact (approach, force, duration 2.868)"),
    ("e = np.sqrt(6.0 * np.sqrt(3.0) / 5.0) * x\n", ".py", "Thornton's closed-form restitution"),
    ("a_sq = (2.0 * P_max + pair.P_Y) / (2.0 * math.pi * pair.p_Y)\n", ".py",
     "Thornton's unloading radius a*^2 = (2 P* + P_Y) / (2 pi p_Y)"),
    ("reach = min(recipe.MAX_LOAD_OVER_YIELD * pair.P_Y, recipe.largest_admissible_load(pair))\n", ".py",
     "the FE's reach (1000 P_Y, 0.2 R)"),
    ("X_LIMIT = 1000.0\n", ".py", "the FE's reach (1000 P_Y, 0.2 R)"),
    ("R = 1.0 + self.C * np.log(ratio)\n", ".py", "Johnson-Cook's factor 1 + C ln(rate / rate_0)"),
    ("R = 1.0 + (np.asarray(rate, dtype=float) / self.D) ** (1.0 / self.q)\n", ".py",
     "Cowper-Symonds' factor 1 + (rate / D)^(1/q)"),
    ("double R = 1.0 + C * log(rate / rate_0);\n", ".c", "Johnson-Cook's factor 1 + C ln(rate / rate_0)"),
    ("R = 1.0 + m.C * log(ratio > 1.0 ? ratio : 1.0);\n", ".cpp", "Johnson-Cook's factor 1 + C ln(rate / rate_0)"),
    ("double R = 1.0 + pow(rate / r->first, 1.0 / r->second);\n", ".c", "Cowper-Symonds' factor 1 + (rate / D)^(1/q)"),
])
def test_the_scan_finds_a_formula_written_out(code, suffix, formula):
    assert formula in derivations(code, suffix)


@pytest.mark.parametrize("code, suffix", [
    ('"""E* = E / (1 - nu^2), t_c = 2.868 (m^2 / (R E^2 v))^(1/5)"""\n', ".py"),     # prose
    ("x = 1.0  # 1.0 - nu ** 2 of the wall\n", ".py"),                               # a comment
    ("E_star = plane_strain_modulus(m.E, m.nu)\n", ".py"),
    ("c_L = math.sqrt(E * (1 - nu) / (rho * (1 + nu) * (1 - 2 * nu)))\n", ".py"),     # a wave speed
    ("R_j = 1.0 / (1.0 / R - 1.0 / R_i)\n", ".py"),                                  # R* undone
    ("/* a = (3 P R / (4 E))^(1/3) */ double a = nfd_hertz_radius(P, R, E);\n", ".c"),
    ("lowest = yield_pressure(s.sigma_y, s.nu) / yield_factor(nu)\n", ".py"),
])
def test_the_scan_leaves_other_code_alone(code, suffix):
    assert not derivations(code, suffix)


def test_each_formula_is_written_only_in_its_home():
    """Outside its home no file derives a formula again."""
    assert sum(1 for _ in scanned_files()) > 50
    found = {relative: names for relative, names in derivations_outside_homes().items() if names}
    assert not found, f"formulas written out again (call their home, nfdmodel/README.md): {found}"


def test_every_home_holds_its_formula():
    for name, (_, homes) in FORMULAS.items():
        python_homes = [home for home in homes if home.endswith(".py")]
        assert len(python_homes) <= 2, name
        assert any(name in derivations((ROOT / home).read_text(encoding="utf-8"), Path(home).suffix)
                   for home in homes), f"{name}: not in its home {sorted(homes)}"


# ---------------------------------------------------------------- the homes compute the callers' numbers
def test_the_contact_modulus_keeps_each_caller_s_rounding():
    """E* of a pair: the home adds the compliances in the caller's order and form, so each caller's
    number is unchanged bit for bit (1/(1/E'_i + 1/E'_j), 1/((1-nu_i^2)/E_i + (1-nu_j^2)/E_j), ...)."""
    from nfdmodel.materials import contact_modulus, effective_radius, plane_strain_compliance, plane_strain_modulus
    rng = np.random.default_rng(3)
    for E_i, nu_i, E_j, nu_j, R_i, R_j in zip(*(rng.uniform(lo, hi, 2000) for lo, hi in
                                                ((1e9, 3e11), (0.0, 0.49), (1e9, 3e11), (0.0, 0.49), (1e-3, 1.0),
                                                 (1e-3, 1.0)))):
        E_i, nu_i, E_j, nu_j, R_i, R_j = map(float, (E_i, nu_i, E_j, nu_j, R_i, R_j))
        assert plane_strain_modulus(E_i, nu_i) == E_i / (1.0 - nu_i ** 2)
        assert contact_modulus(plane_strain_compliance(E_i, nu_i), plane_strain_compliance(E_j, nu_j)) == \
            1.0 / sum((1.0 - nu ** 2) / E for E, nu in ((E_i, nu_i), (E_j, nu_j)))
        Ep_i, Ep_j = E_i / (1.0 - nu_i ** 2), E_j / (1.0 - nu_j ** 2)
        assert contact_modulus(1.0 / Ep_i, 1.0 / Ep_j) == 1.0 / (1.0 / Ep_i + 1.0 / Ep_j)
        assert contact_modulus(1.0 / Ep_i, (1.0 - nu_j ** 2) / E_j) == 1.0 / (1.0 / Ep_i + (1.0 - nu_j ** 2) / E_j)
        assert effective_radius(R_i, R_j) == 1.0 / (1.0 / R_i + 1.0 / R_j)


def test_the_body_that_yields_first_is_the_lower_yield_pressure_the_first_on_a_tie():
    from nfdmodel.materials import first_to_yield, yield_factor
    assert first_to_yield((1e8, 0.3), (1e8, 0.3)) == 0
    assert first_to_yield((1e8, 0.3), (0.99e8, 0.3)) == 1
    # a lower sigma_y does not decide alone: A_Y grows with nu
    assert yield_factor(0.0) * 1e8 < yield_factor(0.45) * 0.9e8
    assert first_to_yield((1e8, 0.0), (0.9e8, 0.45)) == 0
