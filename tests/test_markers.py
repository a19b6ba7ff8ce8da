"""The `laws` marker: .ci/run runs the tests it marks a second time on nfdmodel's numpy kernels
(``NFDCAL_BACKEND=numpy pytest -m laws``), so a test of the laws cannot miss that rerun.

The rule: a test file that imports from nfdmodel a name through which a law runs (``get_law``,
``LAWS``, ``collide``, ``collision_reference``, ``oblique_collide``, any ``*_force*`` or ``*_step*``
function such as ``vz_force`` or ``contact_step``) or a module that runs one (one module per law, as
``LAWS`` names them, and ``collision``, ``oblique``, ``friction``, ``reference``, ``registry``,
``native``, ``turning_point``, ``vz_curve``), as ``from nfdmodel[.module] import ...``, ``import
nfdmodel.module`` or ``nfdmodel.NAME``, carries ``pytest.mark.laws``: on the module
(``pytestmark``) or on the tests that exercise the laws. The files that use the laws only as a
fixed reference for something else are listed in NOT_RERUN with the reason.
"""
import ast
import re
from pathlib import Path

import pytest

import nfdmodel

pytestmark = pytest.mark.laws

TESTS = Path(__file__).resolve().parent

FE = "the FE and the fits: a law is their reference, not their subject (numpy = native: test_native.py)"
PLUGIN = "the LAMMPS plugin against nfdmodel: the plugin is the subject (numpy = native: test_native.py)"
NOT_RERUN = {
    "test_native.py": "pins each backend itself (native.use_backend): a rerun repeats the same comparisons",
    "test_collide_material.py": "nfdcal collide's constants from the material flags: the command is the subject",
    "test_calibration.py": FE,
    "test_fe_impact.py": FE,
    "test_fit.py": FE,
    "test_reach.py": FE,
    "test_fit_data.py": FE,
    "test_scenes.py": FE,
    "test_vz_hardening.py": "the hardening sheet's tables and commands against the FE: the tables are the subject, "
                            "not the kernel (numpy = native: test_native.py)",
    "test_export_counter_table.py": PLUGIN,
    "test_lammps.py": PLUGIN,
    "test_lammps_friction.py": PLUGIN,
    "test_lammps_guards.py": PLUGIN,
    "test_lammps_energy.py": PLUGIN,
    "test_lammps_rate.py": PLUGIN,
    "test_lammps_pair_constants.py": PLUGIN,
    "test_lammps_wall_material.py": PLUGIN,
}

LAW_MODULES = {name.replace("-", "_") for name in nfdmodel.LAWS} | {
    "collision", "oblique", "friction", "reference", "registry", "native", "turning_point", "vz_curve"}
LAW_NAMES = {"get_law", "LAWS", "collide", "collision_reference", "oblique_collide"} | {
    name for name in nfdmodel.__all__ if re.search(r"_(force|step)", name)}


def law_api_used(source: str) -> set[str]:
    """The names and modules of nfdmodel's law API that a test file's source imports or uses."""
    used = set()
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, ast.ImportFrom) and (node.module or "").split(".")[0] == "nfdmodel":
            parts = node.module.split(".")
            if len(parts) > 1 and parts[1] in LAW_MODULES:
                used.add(node.module)
            used |= {alias.name for alias in node.names
                     if alias.name in LAW_NAMES or (len(parts) == 1 and alias.name in LAW_MODULES)}
        elif isinstance(node, ast.Import):
            used |= {alias.name for alias in node.names
                     if alias.name.split(".")[0] == "nfdmodel" and alias.name.split(".")[1:2] in
                     [[module] for module in LAW_MODULES]}
        elif (isinstance(node, ast.Attribute) and isinstance(node.value, ast.Name) and node.value.id == "nfdmodel"
              and (node.attr in LAW_NAMES or node.attr in LAW_MODULES)):
            used.add(f"nfdmodel.{node.attr}")
    return used


def marked(source: str) -> bool:
    return re.search(r"\bpytest\.mark\.laws\b", source) is not None


def test_the_law_api_names_exist():
    assert {"vz_force", "vz_step", "contact_step", "vz_table_step"} <= LAW_NAMES
    assert all(hasattr(nfdmodel, name) for name in LAW_NAMES)
    assert {"vz", "vz_table", "walton_braun"} <= LAW_MODULES


@pytest.mark.parametrize("source, expected", [
    ("from nfdmodel import collide, Material", {"collide"}),
    ("from nfdmodel.oblique import oblique_collide", {"nfdmodel.oblique", "oblique_collide"}),
    ("from nfdmodel import vz_table", {"vz_table"}),
    ("import nfdmodel.friction", {"nfdmodel.friction"}),
    ("import nfdmodel\nnfdmodel.get_law('vz')", {"nfdmodel.get_law"}),
    ("from nfdmodel import Material, ContactPair\nimport nfdmodel\nnfdmodel.backend()", set()),
])
def test_the_rule_finds_the_law_api(source, expected):
    assert law_api_used(source) == expected


def test_every_test_file_using_the_laws_carries_the_marker():
    missing, stale = [], []
    for path in sorted(TESTS.glob("test_*.py")):
        source = path.read_text(encoding="utf-8")
        uses, has = law_api_used(source), marked(source)
        if path.name in NOT_RERUN:
            if has or not uses:
                stale.append(f"{path.name}: {'marked' if has else 'uses no law'}; drop it from NOT_RERUN")
        elif uses and not has:
            missing.append(f"{path.name} uses {sorted(uses)}: mark it pytest.mark.laws (or list it in NOT_RERUN)")
    assert not missing and not stale, "\n".join(missing + stale)


def test_ci_reruns_the_marked_tests_on_numpy():
    ci = (TESTS.parent / ".ci" / "run").read_text(encoding="utf-8")
    assert "NFDCAL_BACKEND=numpy .venv/bin/python -m pytest -q -n auto -m laws" in ci
    pyproject = (TESTS.parent / "pyproject.toml").read_text(encoding="utf-8")
    assert '"laws: ' in pyproject
