"""The vz-unload law as a user reaches it: its parameter file (record -> file -> load gives the same
forces; a bad table refused naming it), ``nfdcal calibrate --ship unload`` on the coarse mesh (its
dent against an FE path held out of the fit, refitted here from the run's CSV files), ``nfdcal
collide --params`` against nfdmodel called directly, and the refusals (export lammps of a file on a
counter-body without --like-params-out, a law the file does not hold), one line, exit 2."""
import contextlib
import csv
import io
import json
import re

import numpy as np
import pytest

from calib.cli import main
from calib.fe.loadpath import contact_work
from calib.fit.unload_fit import fit_unload_law
from nfdmodel import ContactPair, Material, VZTableParams, VZUnloadParams, load_parameters, parameter_record

PAIR = ContactPair.sphere_flat(Material.reference(), 0.1)
BENT = VZTableParams(PAIR, (1.0, 3.0, 10.0, 41.0, 200.0, 1000.0), (0.0, 0.06, 0.25, 0.9, 3.0, 10.0),
                     (1.0, 1.02, 1.1, 1.4, 2.5, 6.0))
PARAMS = VZUnloadParams.from_table(BENT, (1.0, 2.2, 7.1, 41.0), (0.0, 0.05, 0.2, 0.45), (1.5, 1.46, 1.41, 1.36))
COARSE = "1.6e-4"      # contact element [m], as tests/test_calibration.py
HELD_OUT_PEAK = 500.0  # N (13.6 P_Y: the coarse contact resolves the dent from 10 P_Y up, tests/test_vz_unload.py)


def write_file(path, params=PARAMS, edit=None):
    record = json.loads(json.dumps(parameter_record(params, 0.1, Material.reference())))
    if edit is not None:
        edit(record)
    path.write_text(json.dumps(record), encoding="utf-8")
    return path


def one_line_refusal(argv, capsys, match):
    code = main(argv)
    err = capsys.readouterr().err.strip().splitlines()
    errors = [line for line in err if "warning" not in line]
    assert code == 2 and len(errors) == 1 and match in errors[0] and "Traceback" not in "".join(err), err
    return errors[0]


# ------------------------------------------------------------------------------ the parameter file
@pytest.mark.laws
def test_the_parameter_file_round_trip_gives_the_same_forces(tmp_path):
    """Load, unload, reload past the peak and unload again: the file's law and the law it was written
    from give the same forces to 1e-12 (relative to P_Y) at every step."""
    from nfdmodel import get_law

    loaded = load_parameters(write_file(tmp_path / "p.json"))
    assert type(loaded) is VZUnloadParams and loaded == PARAMS
    law = get_law("vz-unload")
    top = PAIR.delta_Y * np.array([0.7, 4.0, 40.0, 350.0])
    fractions = np.concatenate([np.linspace(0, 1, 60), np.linspace(1, 0.3, 30), np.linspace(0.3, 1.4, 50),
                                np.linspace(1.4, 0, 60)])
    a, b = law.initial_state(top.size), law.initial_state(top.size)
    for fraction in fractions:
        P_a, a = law.force_function(fraction * top, a, PARAMS)
        P_b, b = law.force_function(fraction * top, b, loaded)
        np.testing.assert_allclose(P_b, P_a, rtol=1e-12, atol=1e-12 * PAIR.P_Y)
    assert b.delta_res[0] == 0.0 and np.all(b.delta_res[1:] > 0)      # Hertz below first yield, dents above


def _set(key, index, value):
    def edit(record):
        record["unloading"][key][index] = value
    return edit


@pytest.mark.parametrize("edit, match", [
    (_set("dent", 2, 1.2), "table dent out of range"),
    (_set("exponent", 3, -1.0), "table exponent out of range"),
    (_set("exponent", 0, 1.4), "first unloading node is first yield"),
    (_set("P_max_over_P_Y", 2, 2.0), "table x_unload out of range"),
    (_set("dent", 1, "0.05"), "table dent[1] must be a number"),
    (lambda r: r["unloading"].pop("exponent"), "unloading: missing key(s) exponent"),
    (lambda r: r.pop("unloading"), "missing key(s) unloading"),
    (lambda r: r["unloading"].update(m=[1.5]), "unknown key(s) in 'unloading': 'm'"),
    (lambda r: r.update(law="vz-table"), "'unloading' belongs to law 'vz-unload'"),
])
def test_a_bad_unloading_table_is_refused_naming_it(tmp_path, capsys, edit, match):
    path = write_file(tmp_path / "bad.json", edit=edit)
    with pytest.raises(ValueError, match=re.escape(match)):
        load_parameters(path)
    line = one_line_refusal(["collide", "--params", str(path), "--v-in", "0.05"], capsys, match)
    assert str(path) in line


# ------------------------------------------------------------------------------ collide and the refusals
@pytest.mark.laws
def test_collide_with_the_file_is_nfdmodel_called_directly(tmp_path, capsys):
    from nfdmodel import collide

    path = write_file(tmp_path / "p.json")
    v_in = [0.005, 0.02, 0.1]
    assert main(["collide", "--params", str(path), "--v-in", *map(str, v_in), "--dt", "2e-7", "--json"]) == 0
    records = json.loads(capsys.readouterr().out)
    direct = collide("vz-unload", load_parameters(path), np.array(v_in), dt=2e-7)
    for key in ("e_velocity", "P_max", "contact_time"):
        np.testing.assert_allclose([r[key] for r in records], getattr(direct, key), rtol=1e-12)
    assert main(["collide", "--law", "vz-unload", "--params", str(path), "--v-in", "0.02", "--dt", "2e-7",
                 "--json"]) == 0
    assert json.loads(capsys.readouterr().out)[0]["e_velocity"] == pytest.approx(direct.e_velocity[1], rel=1e-12)


def test_export_of_a_vz_unload_file_on_a_counter_body_needs_the_like_type_folder(tmp_path, capsys):
    """A vz-unload file calibrated on a counter-body: export writes the like-type laws as files, so
    without --like-params-out it is one line naming the flag (its lines in LAMMPS:
    tests/test_export_counter_table.py)."""
    flat = {"shape": "flat", "E": 2.1e11, "nu": 0.3, "sigma_y": None, "R": None}

    def on_the_flat(record):        # the pair's quantities follow from the materials
        for key in ("P_Y", "a_Y", "delta_Y", "mass_star"):
            record.pop(key)
        record.update(counter_body=flat)

    path = write_file(tmp_path / "p.json", edit=on_the_flat)
    one_line_refusal(["export", "lammps", "--params", str(path), "--wall", "zlo", "0"], capsys,
                     "--like-params-out out of range: ")


@pytest.mark.parametrize("argv, match", [
    (["collide", "--law", "vz-table", "--params", "{file}", "--v-in", "0.05"], "the file holds the vz-unload law"),
    (["collide", "--law", "vz", "--params", "{file}", "--v-in", "0.05"], "the file holds the vz-unload law"),
    (["collide", "--law", "vz-unload", "--v-in", "0.05"], "--law vz-unload needs --params FILE"),
])
def test_what_cannot_take_a_vz_unload_file_says_so_in_one_line(tmp_path, capsys, argv, match):
    path = write_file(tmp_path / "p.json")
    one_line_refusal([a.replace("{file}", str(path)) for a in argv], capsys, match)


# ------------------------------------------------------------------------------ calibrate --ship unload
@pytest.fixture(scope="module")
def shipped(tmp_path_factory):
    """``nfdcal calibrate --ship unload`` on the coarse mesh, unloading from 260, 500 and 1000 N:
    (its output folder, its printed lines)."""
    out = tmp_path_factory.mktemp("ship_unload")
    printed = io.StringIO()
    with contextlib.redirect_stdout(printed):
        code = main(["calibrate", "--quiet", "--contact-size", COARSE, "--peaks", "260", str(HELD_OUT_PEAK), "1000",
                     "--ship", "unload", "--no-plots", "--out", str(out)])
    assert code == 0
    return out, printed.getvalue().splitlines()


def csv_rows(path) -> list[dict]:
    with open(path, encoding="utf-8") as stream:
        return list(csv.DictReader(line for line in stream if not line.startswith("#")))


def test_calibrate_ship_unload_writes_the_law_and_states_its_figures(shipped):
    out, lines = shipped
    params = load_parameters(out / "parameters.json")
    summary = json.loads((out / "calibration.json").read_text(encoding="utf-8"))
    assert type(params) is VZUnloadParams and summary["shipped_fit"] == "unload"
    assert summary["accuracy"]["shipped"] == "vz-unload"
    assert [p["P_max"] for p in summary["vz_unload"]["held_out"]] == [HELD_OUT_PEAK]
    assert len(summary["vz_unload"]["fit"]) == 3 and all(r["within"] for r in summary["vz_unload"]["fit"])
    assert params.window.P_min_over_P_Y == pytest.approx(260.0 / params.pair.P_Y, rel=1e-12)
    assert any(line.startswith("vz-unload law against the FE paths it was fitted on") for line in lines)
    held = next(line for line in lines if line.startswith("vz-unload law against FE paths held out"))
    assert "dent " in held and "contact radius at the peak" in held and "unloading force" in held and " e " in held
    assert "vz-unload law against these FE paths" in "\n".join(lines) and "; shipped" in "\n".join(lines)


def test_the_dent_of_a_path_held_out_of_the_fit_is_the_fe_s(shipped):
    """Refitted here from the run's own FE files without the 500 N path (calib.fit.unload_fit on
    loading.csv, the other paths' unloading rows and calibration.json), the law driven along the
    FE's approach to 500 N leaves the FE's residual approach within the law's 3 % (or 0.5 % of
    alpha_max); the figure calibrate states for that path is this one."""
    out, _ = shipped
    summary = json.loads((out / "calibration.json").read_text(encoding="utf-8"))
    params = load_parameters(out / "parameters.json")
    pair = params.pair
    loading = csv_rows(out / "loading.csv")
    force, approach, radius = (np.array([float(r[k]) for r in loading]) for k in ("P", "alpha", "contact_radius"))
    kept = [p for p in summary["paths"] if p["P_max"] != HELD_OUT_PEAK]
    work = []
    for p in kept:
        unloading = [r for r in csv_rows(out / f"path_P{p['P_max']:g}.csv") if r["branch"] == "unloading"]
        work.append(contact_work(np.array([p["alpha_max"]] + [float(r["alpha"]) for r in unloading]),
                                 np.array([p["P_max"]] + [max(float(r["P"]), 0.0) for r in unloading])))
    law_params = fit_unload_law(force, approach, radius, pair, [p["P_max"] for p in kept],
                                [p["alpha_max"] for p in kept], [p["alpha_residual"] for p in kept], work)
    fe = next(p for p in summary["paths"] if p["P_max"] == HELD_OUT_PEAK)
    from nfdmodel import get_law

    law = get_law("vz-unload")
    state = law.initial_state(1)
    for delta in approach[force <= HELD_OUT_PEAK * (1 + 1e-6)]:
        _, state = law.force_function(np.array([delta]), state, law_params)
    dent = float(state.delta_res[0])
    dent_error, of_alpha_max = dent / fe["alpha_residual"] - 1.0, (dent - fe["alpha_residual"]) / fe["alpha_max"]
    assert abs(dent_error) <= 0.03 or abs(of_alpha_max) <= 0.005, (dent_error, of_alpha_max)
    stated = summary["vz_unload"]["held_out"][0]
    assert stated["dent_error"] == pytest.approx(dent_error, rel=1e-6, abs=1e-9)
    assert abs(stated["radius_error"]) <= 0.02 and stated["unloading_error"] <= 0.02 and abs(stated["e_error"]) <= 0.01


def test_without_an_interior_path_the_summary_says_none_was_held_out(shipped):
    """Two unloading paths (the lowest and the highest are never held out): said, not left blank."""
    from calib.fit import unload_ship

    out, _ = shipped
    record = json.loads((out / "calibration.json").read_text(encoding="utf-8"))["vz_unload"]
    lines = unload_ship.lines({**record, "held_out": []})
    assert lines[1] == ("vz-unload law against FE paths held out of its fit, one at a time: no interior path to "
                        "hold out (needs 3 or more unloading paths)")
