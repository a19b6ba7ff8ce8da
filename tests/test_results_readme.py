"""The documentation: results/README.md is what ``nfdcal results-readme`` makes of the committed summaries
(never stale), the command writes only README.md and ``--check`` fails on a stale one, and every relative
link in the repository's README files reaches a file (and, inside Markdown, a heading)."""
import json
import re
import shutil
from pathlib import Path

import pytest

from calib.cli import main
from calib.commands.results_readme import sections
from calib.report.index_format import g
from calib.report.results_index import render

REPO = Path(__file__).resolve().parent.parent
RESULTS = REPO / "results"
# READMEs other branches of the same change write; a link to them is checked once they exist
WRITTEN_ELSEWHERE = ("nfdmodel/lammps/README.md", "calib/fit/README.md")


def test_results_readme_is_what_the_summaries_give(capsys):
    assert render(RESULTS, sections()) == (RESULTS / "README.md").read_text(encoding="utf-8"), \
        "results/README.md is stale: run nfdcal results-readme"
    assert main(["results-readme", "--check", "--out", str(RESULTS)]) == 0
    assert "up to date" in capsys.readouterr().out


def test_results_readme_states_the_reference_calibration():
    text = (RESULTS / "README.md").read_text(encoding="utf-8")
    cal = json.loads((RESULTS / "calibration" / "calibration.json").read_text(encoding="utf-8"))
    assert f"| Ca [m/N], two meshes extrapolated | {g(cal['Ca'])}, " in text
    assert f"| Kc [1/N], the same | {g(cal['Kc'])}, " in text
    assert f"| {cal['Ca_hat']:.4f}, {cal['Kc_hat']:.4f} |" in text
    assert "2.365e-07" in text and "3.091e-04" in text and "0.0263, 0.0113" in text   # the shipped figures
    assert cal["stamp"]["git_commit"] in text                                          # its provenance


def test_command_writes_only_the_readme_and_check_finds_it_stale(tmp_path, capsys):
    out = tmp_path / "results"
    shutil.copytree(RESULTS / "collision", out / "collision")
    before = sorted(p.relative_to(out) for p in out.rglob("*"))
    assert main(["results-readme", "--check", "--out", str(out)]) == 1                  # missing
    assert main(["results-readme", "--out", str(out)]) == 0
    assert sorted(p.relative_to(out) for p in out.rglob("*")) == sorted(before + [Path("README.md")])
    readme = (out / "README.md").read_text(encoding="utf-8")
    assert "## Collisions of the runtime laws" in readme and "## Reference calibration" not in readme
    assert main(["results-readme", "--check", "--out", str(out)]) == 0
    (out / "README.md").write_text(readme + "edited by hand\n", encoding="utf-8")
    assert main(["results-readme", "--check", "--out", str(out)]) == 1
    assert (out / "README.md").read_text(encoding="utf-8").endswith("edited by hand\n")  # --check writes nothing
    capsys.readouterr()


def test_command_refuses_what_is_not_a_results_folder_or_a_file(tmp_path, capsys):
    assert main(["results-readme", "--out", str(tmp_path / "none")]) == 2
    (tmp_path / "README.md").mkdir()
    assert main(["results-readme", "--out", str(tmp_path)]) == 2
    (tmp_path / "collision").mkdir()
    (tmp_path / "collision" / "summary.json").write_text('{"case": {}}', encoding="utf-8")     # another version's
    assert main(["results-readme", "--out", str(tmp_path)]) == 2
    (tmp_path / "collision" / "summary.json").write_text("{", encoding="utf-8")               # damaged
    assert main(["results-readme", "--out", str(tmp_path)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 4 and "no results folder" in err[0] and "it is a folder" in err[1]
    assert "section 'collision'" in err[2] and "summary.json: not a JSON summary" in err[3]


def readmes() -> list[Path]:
    # build/ holds copies setuptools makes (a non-editable install from the checkout: .ci/check-wheel)
    return sorted(p for p in REPO.rglob("README.md")
                  if not any(part.startswith(".") or part == "build" for part in p.relative_to(REPO).parts))


LINK = re.compile(r"\[[^\]]*\]\(([^)\s]+)\)")
FENCE = re.compile(r"^```.*?^```", re.S | re.M)


def anchors(markdown: str) -> set[str]:
    """GitHub's anchors of the headings of a Markdown text."""
    headings = re.findall(r"^#+ +(.+?) *$", FENCE.sub("", markdown), re.M)
    return {re.sub(r"[^\w\- ]", "", h.lower()).replace(" ", "-") for h in headings}


def test_readme_links_resolve():
    files = readmes()
    assert REPO / "README.md" in files and RESULTS / "README.md" in files
    broken = []
    for readme in files:
        text = readme.read_text(encoding="utf-8")
        for target in LINK.findall(FENCE.sub("", text)):
            if re.match(r"[a-z]+:", target):
                continue                                            # http(s), mailto: not checked here
            path, _, anchor = target.partition("#")
            dest = (readme.parent / path).resolve() if path else readme
            rel = dest.relative_to(REPO).as_posix() if dest.is_relative_to(REPO) else str(dest)
            if not dest.exists():
                if rel not in WRITTEN_ELSEWHERE:
                    broken.append(f"{readme.relative_to(REPO)}: {target}")
            elif anchor and dest.suffix == ".md" and anchor not in anchors(dest.read_text(encoding="utf-8")):
                broken.append(f"{readme.relative_to(REPO)}: {target} (no such heading)")
    assert not broken, "\n".join(broken)


def test_readme_opens_with_the_two_setup_commands_and_stays_short():
    text = (REPO / "README.md").read_text(encoding="utf-8")
    lines = text.splitlines()
    assert lines[2:6] == [
        "```bash",
        "bash .ci/install && .venv/bin/nfdcal calibrate     # install, then run the reference calibration",
        "bash .ci/run                                       # install, then run the test suite",
        "```"]
    assert len(lines) <= 300


GUIDES = ("README.md", "nfdmodel/README.md", "calib/README.md", "tests/README.md", "results/README.md",
          "results/linear_solvers.md")


@pytest.mark.parametrize("guide", GUIDES)
def test_readme_prose_lines_are_short(guide):
    """Prose wraps at 120 characters; tables and code may not."""
    text = FENCE.sub("", (REPO / guide).read_text(encoding="utf-8"))
    long = [line[:60] for line in text.splitlines() if len(line) > 120 and not line.startswith("|")]
    assert not long, long
