"""No command writes over a file it reads (calib.commands.targets): every command that takes an output
path and an input file refuses, in one line naming the output flag (exit 2, before any work), an
output that names any of its inputs (the shipped master tables a flag's default stands for, a
table's metadata beside it, a file an output folder would get, through a symbolic link); the
input is left byte for byte. The shipped tables are copies here (calib/data is never written).
Beside them: material --params-out replaces a file only with --overwrite, a --plot name ends in
.png, the set of --peaks names the calibration's folder whatever their order, and hertz on a
counter-body writes a folder of its own."""
import argparse
import json
import shutil
from pathlib import Path

import pytest

from calib.cli import build_parser, main
from calib.commands import targets

DATA = Path(__file__).resolve().parent.parent / "calib" / "data"
MATERIAL = ["--E", "70e9", "--nu", "0.3", "--sigma-y", "100e6", "--R", "0.1"]
SPECIMEN = ["--E", "70e9", "--nu", "0.3", "--R", "0.1", "--rho", "2699"]
PARAMS = {"law": "vz", "Ca": 2.33e-7, "Kc": 2.69e-4,
          "material": {"E": 70e9, "nu": 0.3, "sigma_y": 100e6, "rho": 2699, "R": 0.1}}


@pytest.fixture
def place(tmp_path, monkeypatch):
    """{placeholder: path} of the inputs the cases name; the shipped tables are copies that the
    commands take as their defaults."""
    import calib.fit.master_table as master_table
    import calib.fit.vz_master_table as vz_master_table

    shipped = tmp_path / "data"
    shipped.mkdir()
    for name in ("master_table.csv", "master_table.json", "vz_master_table.csv", "vz_master_table.json"):
        shutil.copy(DATA / name, shipped / name)
    monkeypatch.setattr(master_table, "DEFAULT_TABLE", shipped / "master_table.csv")
    monkeypatch.setattr(vz_master_table, "DEFAULT_TABLE", shipped / "vz_master_table.csv")
    for name in ("master_table", "vz_master_table"):
        shutil.copy(DATA / f"{name}.csv", tmp_path / f"my_{name}.csv")
        shutil.copy(DATA / f"{name}.json", tmp_path / f"my_{name}.json")
    (tmp_path / "drops.csv").write_text("v_in,e\n0.02,0.8\n0.05,0.7\n0.1,0.65\n")
    (tmp_path / "params.json").write_text(json.dumps(PARAMS))
    (tmp_path / "report").mkdir()
    (tmp_path / "report" / "summary.json").write_text(json.dumps(PARAMS))
    (tmp_path / "impact").mkdir()
    (tmp_path / "impact" / "drops.csv").write_text("v_in,e\n0.02,0.8\n0.05,0.7\n")
    (tmp_path / "scene.toml").write_text('[scene]\nname = "x"\n[[material]]\nname = "a"\nE = 70e9\nnu = 0.3\n'
                                         'sigma_y = 100e6\nrho = 2700.0\nR = 0.1\n')
    (tmp_path / "link.json").symlink_to(shipped / "vz_master_table.csv")
    monkeypatch.chdir(tmp_path)
    return {"SHIPPED_MASTER": shipped / "master_table.csv", "SHIPPED_MASTER_JSON": shipped / "master_table.json",
            "SHIPPED_VZ": shipped / "vz_master_table.csv", "SHIPPED_VZ_JSON": shipped / "vz_master_table.json",
            "LINK_TO_SHIPPED_VZ": tmp_path / "link.json",
            "MASTER": tmp_path / "my_master_table.csv", "MASTER_JSON": tmp_path / "my_master_table.json",
            "VZ": tmp_path / "my_vz_master_table.csv", "DROPS": tmp_path / "drops.csv",
            "PARAMS": tmp_path / "params.json", "REPORT": tmp_path / "report",
            "REPORT_SUMMARY": tmp_path / "report" / "summary.json", "IMPACT": tmp_path / "impact",
            "IMPACT_DROPS": tmp_path / "impact" / "drops.csv", "SCENE": tmp_path / "scene.toml"}


# (argv with placeholders, the input that must be left alone, the output flag the line names)
CASES = {
    "material --params-out the shipped master table": (
        ["material", *MATERIAL, "--params-out", "SHIPPED_MASTER"], "SHIPPED_MASTER", "--params-out"),
    "material --params-out the shipped master table's metadata": (
        ["material", *MATERIAL, "--params-out", "SHIPPED_MASTER_JSON"], "SHIPPED_MASTER_JSON", "--params-out"),
    "material --v-max --params-out the shipped vz master table": (
        ["material", *MATERIAL, "--v-max", "0.1", "--params-out", "SHIPPED_VZ"], "SHIPPED_VZ", "--params-out"),
    "material --params-out a link to the shipped vz master table": (
        ["material", *MATERIAL, "--params-out", "LINK_TO_SHIPPED_VZ", "--overwrite"], "SHIPPED_VZ", "--params-out"),
    "material --vz-table X --params-out X": (
        ["material", *MATERIAL, "--v-max", "0.1", "--vz-table", "VZ", "--params-out", "VZ"], "VZ", "--params-out"),
    "material --table X --params-out X's metadata": (
        ["material", *MATERIAL, "--table", "MASTER", "--params-out", "MASTER_JSON", "--overwrite"], "MASTER_JSON",
        "--params-out"),
    "fit-data --vz-table X --params-out X --overwrite": (
        ["fit-data", "--impacts", "DROPS", *SPECIMEN, "--vz-table", "VZ", "--params-out", "VZ", "--overwrite"], "VZ",
        "--params-out"),
    "fit-data --params-out the shipped vz master table": (
        ["fit-data", "--impacts", "DROPS", *SPECIMEN, "--params-out", "SHIPPED_VZ", "--overwrite"], "SHIPPED_VZ",
        "--params-out"),
    "fit-data --law vz --params-out the shipped master table": (
        ["fit-data", "--impacts", "DROPS", *SPECIMEN, "--law", "vz", "--params-out", "SHIPPED_MASTER", "--overwrite"],
        "SHIPPED_MASTER", "--params-out"),
    "fit-data --params-out the data": (
        ["fit-data", "--impacts", "DROPS", *SPECIMEN, "--params-out", "DROPS", "--overwrite"], "DROPS", "--params-out"),
    "export lammps --like-params-out the parameter file": (
        ["export", "lammps", "--params", "PARAMS", "--like-params-out", "PARAMS"], "PARAMS", "--like-params-out"),
    "impact --drops X --out X": (["impact", "--drops", "DROPS", "--out", "DROPS", "--dry-run"], "DROPS", "--out"),
    "impact --drops OUT/drops.csv --out OUT": (
        ["impact", "--drops", "IMPACT_DROPS", "--out", "IMPACT", "--dry-run"], "IMPACT_DROPS", "--out"),
    "impact --repeat --unload-params X --out X": (
        ["impact", "--v-in", "0.0168", "--repeat", "2", "--unload-params", "PARAMS", "--out", "PARAMS"], "PARAMS",
        "--out"),
    "collide --report --params X --out X": (
        ["collide", "--report", "--params", "PARAMS", "--out", "PARAMS"], "PARAMS", "--out"),
    "collide --report --params OUT/summary.json --out OUT": (
        ["collide", "--report", "--params", "REPORT_SUMMARY", "--out", "REPORT"], "REPORT_SUMMARY", "--out"),
    "table SCENE --master-out SCENE": (["table", "SCENE", "--master-out", "SCENE", "--dry-run"], "SCENE", "--master-out"),
    "table --check-master --master-out the shipped master table": (
        ["table", "master_validation", "--check-master", "--master-out", "SHIPPED_MASTER", "--dry-run"],
        "SHIPPED_MASTER", "--master-out"),
    "run SCENE --out SCENE": (["run", "SCENE", "--out", "SCENE"], "SCENE", "--out"),
}


@pytest.mark.parametrize("argv, kept, out_flag", CASES.values(), ids=CASES.keys())
def test_an_output_naming_an_input_is_refused_and_the_input_kept(place, capsys, argv, kept, out_flag):
    before = {key: path.read_bytes() for key, path in place.items() if path.is_file()}
    code = main([str(place.get(token, token)) for token in argv])
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 2 and len(err) == 1, err
    assert f"error: {out_flag} " in err[0] and "out of range: it is " in err[0], err[0]
    assert "never overwritten" in err[0]
    after = {key: path.read_bytes() for key, path in place.items() if path.is_file()}
    assert after == before and kept in before                       # the input, and every other, unchanged


def test_the_default_tables_are_read_from_the_package(place):
    """What the check compares with is where the tables are loaded from (here the copies)."""
    assert targets.shipped_table("table") == place["SHIPPED_MASTER"].resolve()
    assert targets.shipped_table("vz_table") == place["SHIPPED_VZ"].resolve()


def test_every_file_flag_is_declared():
    """A flag that names a file is an input or an output of calib.commands.targets, so the check sees it."""
    files = {"FILE", "CSV", "JSON", "PNG", "DIR"}
    parser = build_parser()
    commands = next(a for a in parser._actions if a.choices and "material" in a.choices).choices
    undeclared = []
    for name, sub in commands.items():
        subs = [a for a in sub._actions if a.choices and isinstance(a.choices, dict)]
        for command in [sub] + [p for a in subs for p in a.choices.values() if isinstance(p, argparse.ArgumentParser)]:
            for action in command._actions:
                if (action.metavar in files or action.dest == "scene") and \
                        action.dest not in targets.INPUT_FLAGS + targets.OUTPUT_FLAGS:
                    undeclared.append(f"{name} {action.dest}")
    assert not undeclared


def test_material_replaces_a_parameter_file_only_with_overwrite(tmp_path, capsys):
    target = tmp_path / "steel.json"
    assert main(["material", *MATERIAL, "--params-out", str(target), "--json"]) == 0
    first = target.read_bytes()
    capsys.readouterr()
    assert main(["material", *MATERIAL, "--R", "0.2", "--params-out", str(target)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and f"--params-out {target} exists: give --overwrite" in err[0], err
    assert target.read_bytes() == first
    assert main(["material", *MATERIAL, "--R", "0.2", "--params-out", str(target), "--overwrite", "--json"]) == 0
    assert json.loads(target.read_text())["material"]["R"] == 0.2


@pytest.mark.parametrize("argv", [["collide", "--v-in", "0.1", "--angle", "30"],
                                  ["fit-data", "--impacts", "DROPS", *SPECIMEN, "--law", "vz"]],
                         ids=["collide", "fit-data"])
@pytest.mark.parametrize("name", ["plot.txt", "plot.pdf", "plot"])
def test_a_plot_is_named_png(place, capsys, argv, name):
    assert main([str(place.get(t, t)) for t in argv] + ["--plot", name]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and f"--plot {name} out of range: the plot is a PNG image" in err[0], err
    assert not Path(name).exists()


def test_the_set_of_peaks_names_the_folder():
    from types import SimpleNamespace

    from calib.commands.calibrate import folder_name
    from nfdmodel import Material

    ns = SimpleNamespace(peaks=["x"], E=None, nu=None, sigma_y=None, rho=None, R=None)
    material = Material(70e9, 0.3, 100e6, 2699.0)
    names = {folder_name(ns, material, 0.1, peaks, None, "table", None) for peaks in
             [(500.0, 1000.0, 1500.0), (1500.0, 500.0, 1000.0), (1000.0, 1500.0, 500.0)]}
    assert names == {"peaks500-1000-1500"}


def test_hertz_on_a_counter_body_keeps_the_rigid_flat_validation(capsys):
    """results/hertz is the rigid flat's; a counter-body run writes below it, named as calibrate names it."""
    assert main(["hertz", "--dry-run", "--json"]) == 0
    rigid = json.loads(capsys.readouterr().out)
    assert main(["hertz", "--counter-E", "2e11", "--counter-nu", "0.28", "--dry-run", "--json"]) == 0
    pair = json.loads(capsys.readouterr().out)
    folder = next(v for k, v in pair.items() if k in ("out", "folder", "outputs"))
    assert Path(next(v for k, v in rigid.items() if k in ("out", "folder", "outputs"))) == Path("results/hertz")
    assert Path(folder) == Path("results/hertz/E7e+10_nu0.3_sy1e+08_R0.1_on_E2e+11_nu0.28_sy-elastic_flat")
