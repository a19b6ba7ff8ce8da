"""One command language: every command answers with a readable summary by default and with one
JSON object (or list) under --json, takes the same flag names for the same things, and a dry run
names the folder it would really write."""
import argparse
import json

import pytest

from calib import cli

REFERENCE_SCENE = "reference"


def subparsers() -> dict[str, argparse.ArgumentParser]:
    parser = cli.build_parser()
    action = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    return dict(action.choices)


def flags(parser) -> set[str]:
    return {option for action in parser._actions for option in action.option_strings}


def actions(parser) -> dict[str, argparse.ArgumentParser]:
    """A command's own sub-commands (nfdcal lammps build / path), or {} when it has none."""
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            return dict(action.choices)
    return {}


@pytest.mark.parametrize("command", cli.COMMAND_MODULES)
def test_every_command_has_json_and_writes_to_out(command):
    parser = subparsers()[command.replace("_", "-")]     # module fit_data: command fit-data
    for name, each in (actions(parser) or {command: parser}).items():
        options = flags(each)
        assert "--json" in options, name
        # material and fit-data write only the files --params-out (--plot) name; lammps path prints a path,
        # export prints input lines
        if name not in ("material", "fit_data", "path", "export"):
            assert "--out" in options, name


def test_one_name_per_meaning_across_commands():
    """A flag spelled two ways for one quantity (--radius and --R, --output and --out) is refused."""
    synonyms = {"--radius": "--R", "--output": "--out", "--young": "--E", "--poisson": "--nu",
                "--sigma-Y": "--sigma-y", "--yield-stress": "--sigma-y", "--density": "--rho",
                "--params-file": "--params", "--quiet-mode": "--quiet", "--dryrun": "--dry-run"}
    for name, parser in subparsers().items():
        wrong = flags(parser) & set(synonyms)
        assert not wrong, f"{name}: {', '.join(f'{w} (use {synonyms[w]})' for w in wrong)}"
    material_flags = {"--R", "--E", "--nu", "--sigma-y", "--rho"}
    for name in ("collide", "hertz", "calibrate", "material"):
        assert material_flags <= flags(subparsers()[name]), name


CHEAP_CALLS = {
    "material": ["material", "--E", "205e9", "--nu", "0.29", "--sigma-y", "655e6", "--R", "0.005"],
    "collide": ["collide", "--v-in", "0.02", "0.1"],
    "run --list": ["run", "--list"],
    "run --dry-run": ["run", REFERENCE_SCENE, "--dry-run"],
}


@pytest.mark.parametrize("name", CHEAP_CALLS)
def test_readable_by_default_json_on_request(name, capsys):
    assert cli.main(CHEAP_CALLS[name]) == 0
    text = capsys.readouterr().out
    with pytest.raises(json.JSONDecodeError):
        json.loads(text)
    assert text.strip() and max(len(line) for line in text.splitlines()) < 300   # no paragraph per call
    assert cli.main(CHEAP_CALLS[name] + ["--json"]) == 0
    assert json.loads(capsys.readouterr().out)


def test_material_prints_first_yield_and_a_one_line_accuracy(capsys):
    assert cli.main(CHEAP_CALLS["material"]) == 0
    text = capsys.readouterr().out
    assert "delta_Y = 2.708e-07 m" in text and "P_Y = 2.973 N" in text
    accuracy = next(line for line in text.splitlines() if line.startswith("accuracy:"))
    assert "off-grid" in accuracy and len(accuracy) < 250
    assert cli.main(CHEAP_CALLS["material"] + ["--json"]) == 0
    values = json.loads(capsys.readouterr().out)
    assert values["accuracy_details"].endswith("master_table.json: master_table.accuracy_details")


def test_dry_run_names_the_folder_it_would_write(tmp_path, capsys):
    assert cli.main(["run", REFERENCE_SCENE, "--dry-run", "--out", str(tmp_path / "here"), "--json"]) == 0
    plan = json.loads(capsys.readouterr().out)
    assert plan["out"] == str(tmp_path / "here") and plan["stages"] and plan["estimated_total_s"] > 0
    assert not (tmp_path / "here").exists()          # a dry run writes nothing


def test_a_ladder_dry_run_lists_its_rungs_and_builds_nothing(tmp_path, capsys, monkeypatch):
    import meshes.hemisphere

    monkeypatch.setattr(meshes.hemisphere, "build_msh", lambda *a, **k: pytest.fail("meshed"))
    assert cli.main(["calibrate", "--ladder", "--dry-run", "--out", str(tmp_path / "here"), "--json"]) == 0
    plan = json.loads(capsys.readouterr().out)
    assert len(plan["stages"]) == 5 and plan["rungs_done"] == [] and plan["estimated_total_s"] > 0
    assert all("second mesh" not in stage["detail"] for stage in plan["stages"])     # a rung is one mesh
    assert not (tmp_path / "here").exists()
