"""Where results are written (calib.output): only regular files are ever replaced, a symbolic
link is written through, errors name the path the user gave (never a temporary file), new files
follow the user's umask (results and the mesh cache alike), a set of results is swapped in as a
whole, a write killed midway leaves the old file, and no NaN reaches a result file."""
import os
import stat
from pathlib import Path

import numpy as np
import pytest

from calib import output
from calib.cli import main


def fifo(tmp_path):
    path = tmp_path / "pipe"
    os.mkfifo(path)
    return path


def folder(tmp_path):
    path = tmp_path / "folder"
    path.mkdir()
    return path


def link_to_device(tmp_path):
    path = tmp_path / "null"
    path.symlink_to("/dev/null")
    return path


def link_to_folder(tmp_path):
    path = tmp_path / "link"
    path.symlink_to(folder(tmp_path))
    return path


@pytest.mark.parametrize("make, kind", [(fifo, "a FIFO"), (folder, "a folder"),
                                        (link_to_device, "a device"), (link_to_folder, "a folder")],
                         ids=["fifo", "folder", "link to a device", "link to a folder"])
def test_anything_but_a_regular_file_is_refused_and_left_alone(tmp_path, make, kind):
    path = make(tmp_path)
    before = os.stat(path)
    with pytest.raises(OSError, match=f"^cannot write {path}.*it is {kind}") as caught:
        output.write_json(path, {"a": 1})
    assert ".tmp" not in str(caught.value)
    after = os.stat(path)
    assert stat.S_IFMT(after.st_mode) == stat.S_IFMT(before.st_mode) and after.st_ino == before.st_ino
    assert not [p for p in tmp_path.rglob(".*.tmp")]


def test_a_link_to_a_file_is_written_through(tmp_path):
    target = tmp_path / "real.json"
    target.write_text("{}")
    link = tmp_path / "link.json"
    link.symlink_to(target)
    output.write_json(link, {"a": 1})
    assert link.is_symlink() and '"a": 1' in target.read_text()


def test_an_unwritable_folder_names_the_given_path(tmp_path):
    blocker = tmp_path / "file"
    blocker.write_text("x")
    with pytest.raises(OSError, match=f"^cannot write {blocker / 'sub' / 'r.json'}") as caught:
        output.write_json(blocker / "sub" / "r.json", {})
    assert ".tmp" not in str(caught.value)


@pytest.mark.parametrize("umask, mode", [(0o022, 0o644), (0o027, 0o640), (0o077, 0o600)])
def test_new_files_follow_the_umask(tmp_path, umask, mode):
    old = os.umask(umask)
    try:
        path = output.write_json(tmp_path / "r.json", {})
    finally:
        os.umask(old)
    assert stat.S_IMODE(os.stat(path).st_mode) == mode


def test_mesh_cache_files_follow_the_umask(tmp_path):
    from meshes.hemisphere import HemisphereMeshSpec, build_msh

    old = os.umask(0o022)
    try:
        path = build_msh(HemisphereMeshSpec(contact_size=4e-4, refined_radius=2e-3, refined_depth=1e-3,
                                            far_size=2e-2, growth=0.5), tmp_path / "m.msh")
    finally:
        os.umask(old)
    assert stat.S_IMODE(os.stat(path).st_mode) == 0o644


def test_the_cli_says_one_line_naming_the_path(tmp_path, capsys):
    path = folder(tmp_path)
    assert main(["material", "--E", "205e9", "--nu", "0.29", "--sigma-y", "655e6", "--R", "0.005",
                 "--params-out", str(path)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and ".tmp" not in err[0]
    assert f"error: --params-out {path}: cannot write {path}: it is a folder" in err[0]


@pytest.mark.parametrize("argv", [["collide", "--report", "--v-in", "0.05", "--out"],
                                  ["hertz", "--steps", "2", "--P-min", "20", "--P-max", "40", "--out"]],
                         ids=["collide --report", "hertz"])
def test_an_output_folder_under_a_file_names_the_flag(tmp_path, capsys, argv):
    blocker = tmp_path / "file"
    blocker.write_text("x")
    out = blocker / "sub"
    assert main(argv + [str(out)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and f"--out {out}: cannot write" in err[0] and ".tmp" not in err[0], err


def test_a_report_is_written_all_or_nothing(tmp_path):
    """A failure part way through a set of results leaves the folder exactly as it was."""
    folder = tmp_path / "report"
    folder.mkdir()
    (folder / "old.csv").write_text("kept")
    with pytest.raises(RuntimeError, match="plot failed"):
        with output.all_or_nothing(folder) as staging:
            output.write_json(staging / "summary.json", {"a": 1})
            raise RuntimeError("plot failed")
    assert sorted(p.name for p in folder.iterdir()) == ["old.csv"]
    assert not list(tmp_path.glob(".report.*"))                      # no staging left behind
    with output.all_or_nothing(folder) as staging:
        output.write_json(staging / "summary.json", {"a": 1})
        output.write_json(staging / "sub" / "x.json", {})
    assert sorted(p.name for p in folder.iterdir()) == ["old.csv", "sub", "summary.json"]


@pytest.fixture
def calibration_folders(tmp_path, monkeypatch) -> list[Path]:
    """The folders nfdcal calibrate writes into, in call order (the FE and the writer stubbed)."""
    written = []
    import calib.fit.calibration as calibration
    import calib.report.calibration as report

    from types import SimpleNamespace

    from nfdmodel import CalibrationWindow

    window = CalibrationWindow(1.0, 41.2, None, "stub")
    result = SimpleNamespace(shipped_params=SimpleNamespace(window=window), load_paths=SimpleNamespace(paths=[]),
                             two_constant_window=lambda: window)
    monkeypatch.setattr(calibration, "calibrate", lambda spec, **options: result)
    monkeypatch.setattr(calibration, "summary", lambda result: {
        "Ca": 1.0, "Kc": 1.0, "Ca_hat": 1.0, "Kc_hat": 1.0, "P_Y": 1.0, "P_Y_fe": 1.0, "wall_time_s": 0.0,
        "paths": [], "window": {"P_min_over_P_Y": 1.0, "P_max_over_P_Y": 41.2},
        "shipped_window": {"P_min_over_P_Y": 1.0, "P_max_over_P_Y": 41.2}})
    monkeypatch.setattr(report, "write", lambda result, out, **options: written.append(Path(out)) or Path(out))
    monkeypatch.chdir(tmp_path)
    return written


def test_another_material_never_overwrites_the_reference_calibration(calibration_folders):
    """nfdcal calibrate with material flags writes to a folder of its own."""
    assert main(["calibrate", "--E", "210e9", "--nu", "0.29", "--sigma-y", "1.2e9", "--R", "0.005",
                 "--quiet"]) == 0
    assert main(["calibrate", "--quiet"]) == 0
    assert calibration_folders[0] == Path("results/calibration/E2.1e+11_nu0.29_sy1.2e+09_R0.005")
    assert calibration_folders[1] == Path("results/calibration")


def test_the_collision_report_honours_v_in_and_names_its_parameters(tmp_path, capsys):
    import csv

    assert main(["collide", "--report", "--v-in", "0.05", "0.1", "--out", str(tmp_path / "c")]) == 0
    assert "vz parameters:" in capsys.readouterr().out
    lines = [line for line in (tmp_path / "c" / "restitution.csv").read_text().splitlines()
             if not line.startswith("#")]
    rows = list(csv.DictReader(lines))
    assert sorted({float(r["v_in"]) for r in rows}) == [0.05, 0.1]


def test_a_report_swaps_in_as_a_whole_and_keeps_other_files(tmp_path):
    """The new set replaces the old one in one rename: files of the old set that the new one does
    not write stay (hard links), a file link is written through, permissions are kept."""
    folder = tmp_path / "report"
    (folder / "sub").mkdir(parents=True)
    (folder / "keep.csv").write_text("kept")
    (folder / "sub" / "deep.txt").write_text("deep")
    elsewhere = tmp_path / "elsewhere.json"
    elsewhere.write_text("{}")
    (folder / "linked.json").symlink_to(elsewhere)
    folder.chmod(0o750)
    inode_before = (folder / "keep.csv").stat().st_ino
    with output.all_or_nothing(folder) as staging:
        output.write_json(staging / "summary.json", {"a": 2})
        output.write_json(staging / "linked.json", {"b": 3})
        assert not (folder / "summary.json").exists()              # nothing visible before the swap
    assert (folder / "keep.csv").read_text() == "kept"
    assert (folder / "keep.csv").stat().st_ino == inode_before      # linked, not copied
    assert (folder / "sub" / "deep.txt").read_text() == "deep"
    assert (folder / "linked.json").is_symlink() and '"b": 3' in elsewhere.read_text()
    assert '"a": 2' in (folder / "summary.json").read_text()
    assert folder.stat().st_mode & 0o777 == 0o750
    assert sorted(p.name for p in tmp_path.iterdir()) == ["elsewhere.json", "report"]   # nothing left aside


def test_a_report_swap_without_renameat2_takes_the_two_rename_path(tmp_path, monkeypatch):
    folder = tmp_path / "report"
    folder.mkdir()
    (folder / "old.csv").write_text("kept")
    monkeypatch.setattr(output, "exchange_paths", lambda first, second: False)
    with output.all_or_nothing(folder) as staging:
        output.write_json(staging / "summary.json", {"a": 1})
    assert sorted(p.name for p in folder.iterdir()) == ["old.csv", "summary.json"]
    assert sorted(p.name for p in tmp_path.iterdir()) == ["report"]


def test_a_new_report_folder_is_created_with_the_umask(tmp_path):
    with output.all_or_nothing(tmp_path / "fresh") as staging:
        output.write_json(staging / "summary.json", {})
    assert (tmp_path / "fresh").stat().st_mode & 0o777 == 0o777 & ~output._umask()


def test_exchange_paths_swaps_two_folders(tmp_path):
    first, second = tmp_path / "a", tmp_path / "b"
    first.mkdir()
    second.mkdir()
    (first / "from_a").touch()
    if not output.exchange_paths(first, second):
        pytest.skip("no renameat2 RENAME_EXCHANGE here: all_or_nothing uses two renames")
    assert (second / "from_a").exists() and not list(first.iterdir())


@pytest.mark.parametrize("interrupt", [KeyboardInterrupt, OSError])
def test_a_write_killed_midway_leaves_the_old_file_and_no_partial_one(tmp_path, monkeypatch, interrupt):
    """calib.report writes to a temporary file and renames it: an exception (Ctrl-C, disk full)
    during the write leaves the previous result intact and no temporary file behind."""
    target = tmp_path / "result.json"
    output.write_json(target, {"P_max": 1.0})
    before = target.read_text()

    def dying_fsync(fd):
        raise interrupt("killed during the write")

    monkeypatch.setattr(os, "fsync", dying_fsync)
    with pytest.raises(interrupt):
        output.write_json(target, {"P_max": 2.0, "rows": list(range(10000))})
    with pytest.raises(interrupt):
        output.write_csv(tmp_path / "new.csv", [{"a": 1.0}])
    assert target.read_text() == before
    assert sorted(p.name for p in tmp_path.iterdir()) == ["result.json"]


def test_a_nan_row_never_reaches_a_result_file(tmp_path):
    with pytest.raises(ValueError, match="non-finite"):
        output.write_json(tmp_path / "r.json", {"rows": [{"e": np.float64("nan")}]})
    assert not any(tmp_path.iterdir())


def test_a_named_set_clears_its_own_stale_files_and_keeps_the_rest(tmp_path):
    """A calibration with other peaks leaves no path file of the previous one; a user's file and
    another set's files stay."""
    folder = tmp_path / "calibration"
    with output.all_or_nothing(folder, name="calibration") as staging:
        output.write_json(staging / "parameters.json", {"Ca": 1})
        output.write_csv(staging / "path_P500.csv", [{"a": 1.0}])
    with output.all_or_nothing(folder, name="ladder") as staging:
        output.write_json(staging / "ladder" / "rung.json", {})
    (folder / "notes.txt").write_text("mine")
    with output.all_or_nothing(folder, name="calibration") as staging:
        output.write_json(staging / "parameters.json", {"Ca": 2})
        output.write_csv(staging / "path_P40.csv", [{"a": 1.0}])
    names = sorted(p.relative_to(folder).as_posix() for p in folder.rglob("*") if p.is_file())
    assert names == [".calibration.files", ".ladder.files", "ladder/rung.json", "notes.txt", "parameters.json",
                     "path_P40.csv"]


def test_one_writer_per_results_folder(tmp_path):
    folder = tmp_path / "calibration"
    with output.one_writer(folder):
        with pytest.raises(OSError, match=rf"another nfdcal run \(process {os.getpid()}\) is writing there"):
            with output.one_writer(folder):
                pass
    with output.one_writer(folder):             # released at the end of the block
        pass
    assert not list(tmp_path.iterdir())          # the lock file goes with the run


def test_each_calibration_has_a_folder_of_its_own(calibration_folders):
    """Other peaks, mesh or shipped law than the reference calibration's: a folder of their own."""
    for flags in (["--peaks", "500", "1000"], ["--contact-size", "8e-5"], ["--ship", "force"], ["--ship", "radius"],
                  ["--ship", "table"]):
        assert main(["calibrate", "--quiet", *flags]) == 0
    assert [p.as_posix() for p in calibration_folders] == ["results/calibration/peaks500-1000", "results/calibration/h8e-05",
                                               "results/calibration/ship-force", "results/calibration/ship-radius",
                                               "results/calibration"]      # the default ships the table
