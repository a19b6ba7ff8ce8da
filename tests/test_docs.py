"""The READMEs name what exists and each topic has one home: every test file and benchmark in
tests/README.md, every study in calib/README.md, whose commands table is what the argument parsers
give (calib.cli_readme); the model's equations, the test commands, the commands table and
"adding a law" each in exactly one README (the others link to it)."""
import re
from pathlib import Path

import pytest

from calib import cli_readme

REPO = Path(__file__).resolve().parent.parent
READMES = ("README.md", "calib/README.md", "calib/fit/README.md", "nfdmodel/README.md", "nfdmodel/lammps/README.md",
           "tests/README.md")


def text(path: str) -> str:
    return (REPO / path).read_text(encoding="utf-8")


def named(readme: str, files) -> list[str]:
    """The files whose name does not appear in ``readme`` as a code span (`name.py`, or with arguments)."""
    body = text(readme)
    return [p.name for p in files if not re.search(rf"`(?:[\w/]*/)?{re.escape(p.name)}[` ]", body)]


def test_tests_readme_names_every_test_file_and_helper():
    files = sorted(REPO.glob("tests/*.py"))
    assert any(p.name == "test_docs.py" for p in files)
    missing = named("tests/README.md", files)
    assert not missing, f"tests/README.md does not name {missing}: add each to its subject's row"


def test_tests_readme_names_every_benchmark():
    missing = named("tests/README.md", sorted(REPO.glob("tests/benchmarks/*.py")))
    assert not missing, f"tests/README.md does not name the benchmarks {missing}"


def test_calib_readme_names_every_study():
    studies = [p for p in sorted(REPO.glob("calib/studies/*.py")) if p.name != "__init__.py"]
    missing = named("calib/README.md", studies)
    assert not missing, f"calib/README.md (Studies) does not name {missing}"


def test_the_commands_table_is_what_the_parsers_give():
    table = cli_readme.render()
    assert cli_readme.section(text("calib/README.md")) == table, \
        "calib/README.md's commands table is stale: run python -m calib.cli_readme"
    rows = [line for line in table.splitlines() if line.startswith("| `nfdcal ")]
    assert len(rows) >= 12 and "| `nfdcal calibrate` |" in table and "| `nfdcal lammps build` |" in table
    assert cli_readme.main(["--check"]) == 0


def test_the_regenerator_rewrites_only_the_table(tmp_path, capsys):
    readme = tmp_path / "README.md"
    original = text("calib/README.md")
    stale = original.replace("| `nfdcal hertz` |", "| `nfdcal hertz` | stale |", 1)
    readme.write_text(stale, encoding="utf-8")
    assert cli_readme.main(["--readme", str(readme), "--check"]) == 1
    assert readme.read_text(encoding="utf-8") == stale
    assert cli_readme.main(["--readme", str(readme)]) == 0
    assert readme.read_text(encoding="utf-8") == original
    (tmp_path / "bare.md").write_text("# no table\n", encoding="utf-8")
    with pytest.raises(ValueError, match="no commands table"):
        cli_readme.main(["--readme", str(tmp_path / "bare.md")])
    capsys.readouterr()


# one line that only the topic's home holds
HOMES = {
    "the loading equation F(P)": (r"F\(P\) += \(P - P_Y\) \+ c1 P\^\(1/3\)", "nfdmodel/README.md"),
    "first yield P_Y": (r"P_Y += pi\^3 R\*\^2 \(A_Y sigma_Y\)\^3", "nfdmodel/README.md"),
    "the test commands": (r"python -m pytest", "tests/README.md"),
    "adding a law": (r"^#+ Adding a law", "nfdmodel/README.md"),
    "the commands table": (re.escape(cli_readme.BEGIN), "calib/README.md"),
}


@pytest.mark.parametrize("topic", HOMES)
def test_each_topic_has_one_home(topic):
    pattern, home = HOMES[topic]
    holders = [r for r in READMES if re.search(pattern, text(r), re.M)]
    assert holders == [home], f"{topic}: in {holders}, its home is {home} (link to it from the others)"
