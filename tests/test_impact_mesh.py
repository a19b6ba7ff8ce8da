"""nfdcal impact: each velocity's mesh resolves its own contact (calib.studies.impact, Mesh), or the
impact is refused before any FE work; and the law files it is compared with are of its own sphere.

Checked against what the code did not produce: Hertz's closed form (nfdmodel.hertz_contact) for a
slow impact, the contact radius over the contact element, the shipped study's mesh keys
(results/impact/impact.json: its figures stay bit for bit), and one-line refusals with exit 2."""
import json
import math
import re
from pathlib import Path

import pytest

from calib.cli import main
from calib.studies import impact, impact_files
from nfdmodel import ContactPair, Material, VZParams, load_parameters, parameter_record, reference_case
from nfdmodel.hertz_contact import hertz_impact_force, hertz_impact_time

RESULTS = Path(__file__).resolve().parent.parent / "results"
REFERENCE = Material.reference()


def refused(argv, capsys) -> str:
    """The one-line refusal (exit 2) of ``nfdcal impact argv``."""
    assert main(["impact", *argv]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "Traceback" not in err, err
    return err


# ---------------------------------------------------------------- item: the mesh follows the contact
@pytest.mark.parametrize("material, radius, v_over_v_Y", [
    (REFERENCE, reference_case.R, 1.5e-5),                  # the slowest the recipe resolves on R = 0.1 m
    (REFERENCE, reference_case.R, 6e-5),                    # 1e-7 m/s: 0.17 reference elements
    (REFERENCE, reference_case.R, 0.5),                     # the study's slowest: the reference family
    (Material(7e10, 0.3, 1e6, 2699.0), reference_case.R, 2.0),     # reference E, nu, R, soft: 2 v_Y
    (Material(7e10, 0.3, 1e6, 2699.0), reference_case.R, 100.0),
    (Material(2e11, 0.3, 5e8, 7850.0), 0.01, 0.5),         # another sphere: the recipe's level
], ids=["slowest", "1e-7 m/s", "0.5 v_Y", "soft 2 v_Y", "soft 100 v_Y", "steel"])
def test_every_impact_mesh_spans_its_contact(material, radius, v_over_v_Y):
    """The contact radius the impact reaches spans at least 6 of its mesh's contact elements and
    lies inside the refined zone (the reference E, nu, R included, whatever sigma_Y)."""
    setup = impact.ImpactSetup(material=material, radius=radius)
    v_in = v_over_v_Y * setup.pair.v_Y
    impact.check_reach(setup, [v_in])
    mesh = impact.impact_mesh(setup, v_in)
    a = impact.contact_radius(setup, v_in)
    assert a / mesh.contact_size >= impact.REFERENCE_ELEMENTS_PER_CONTACT_RADIUS
    assert mesh.refined_radius >= a


def test_the_shipped_study_keeps_its_meshes():
    """The reference study (results/impact) and its elastic limit keep their meshes: the same keys,
    so their figures stay bit for bit."""
    for name in ("impact.json", "hertz_limit/impact.json"):
        summary = json.loads((RESULTS / "impact" / name).read_text())
        case = summary["case"]
        setup = impact.ImpactSetup(Material(case["E"], case["nu"], case["sigma_y"], case["rho"]), case["R"],
                                   elastic=case["elastic"])
        for record in summary["impacts"]:
            assert impact.impact_mesh(setup, record["v_in"]).describe()["key"] == record["mesh_key"], (name, record["v_in"])
    convergence = json.loads((RESULTS / "impact" / "convergence.json").read_text())
    assert impact.impact_mesh(impact.reference_setup(), convergence["v_in"]).contact_size == convergence["contact_size"]


@pytest.mark.parametrize("base, size, velocities", [
    ([], None, ["1e-9"]),                                   # finer than a mesh of the sphere holds
    (["--sigma-y", "1e6"], None, ["1e-9"]),
    ([], "4e-5", ["1e-7"]),                                 # 0.17 elements of the given size
    ([], "1.6e-4", ["1e-4", "0.04"]),
    (["--counter-E", "2.1e11", "--counter-nu", "0.28"], None, ["1e-9"]),
], ids=["recipe", "recipe soft", "given size", "given size, two velocities", "pair"])
@pytest.mark.parametrize("dry", [True, False], ids=["dry run", "run"])
def test_an_unresolved_contact_is_refused_before_work(base, size, velocities, dry, tmp_path, monkeypatch, capsys):
    """One line, exit 2, no output folder: the smallest v_in the mesh resolves (and the
    --contact-size that would do) named, and each suggestion is accepted."""
    monkeypatch.chdir(tmp_path)
    out = tmp_path / "out"
    sized = ["--contact-size", size] if size else []
    err = refused([*base, *sized, "--v-in", *velocities, "--out", str(out), "--no-error-estimate"]
                  + (["--dry-run"] if dry else []), capsys)
    assert "--v-in out of range" in err and f"{min(map(float, velocities)):g} m/s" in err and not out.exists()
    v_min = re.search(r"need v_in >= ([0-9.e+-]+) m/s", err).group(1)
    if "--counter-E" not in base:     # a pair's block mesh is twice the sphere's: its own floor is not named yet
        assert main(["impact", *base, *sized, "--v-in", v_min, "--dry-run"]) == 0
    if size:
        smaller = re.search(r"or --contact-size <= ([0-9.e+-]+) m", err).group(1)
        assert main(["impact", *base, "--contact-size", smaller, "--v-in", *velocities, "--dry-run"]) == 0
    capsys.readouterr()


def test_a_slow_impact_is_hertzs(tmp_path, monkeypatch, capsys):
    """At 1e-7 m/s (6e-5 v_Y: a contact radius of 6.7 um on R = 0.1 m, 0.17 of the reference
    mesh's elements) the FE on the mesh the command sizes gives Hertz's P_max and contact time
    (nfdmodel.hertz_contact) within 1 % and e within 1e-3 of 1; on the reference mesh it read
    P_max 19 % short."""
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "cache"))
    monkeypatch.chdir(tmp_path)
    v_in = 1e-7
    assert main(["impact", "--v-in", str(v_in), "--steps-per-contact", "20", "--no-error-estimate", "--no-quasi-static",
                 "--no-plots", "--workers", "1", "--out", str(tmp_path / "out"), "--json", "--quiet"]) == 0
    (record,) = json.loads(capsys.readouterr().out)
    pair = impact.reference_setup().pair
    assert record["P_max"] == pytest.approx(float(hertz_impact_force(pair.mass_star, pair.hertz_stiffness, v_in)), rel=0.01)
    assert record["contact_time"] == pytest.approx(
        float(hertz_impact_time(pair.mass_star, pair.R_star, pair.E_star, v_in)), rel=0.01)
    assert abs(record["e"] - 1.0) < 1e-3
    assert record["contact_radius_max"] / record["contact_size"] > impact.REFERENCE_ELEMENTS_PER_CONTACT_RADIUS


# ---------------------------------------------------------------- items: the law files are the impact's
def vz_file(path: Path, material: Material, radius: float) -> Path:
    """A vz parameter file of ``material`` on a sphere of ``radius`` (the reference constants)."""
    ref = VZParams.reference()
    params = VZParams(impact.ImpactSetup(material, radius).pair, ref.Ca, ref.Kc, ref.window)
    path.write_text(json.dumps(parameter_record(params, radius, material)))
    return path


def table_file(path: Path, material: Material, radius: float) -> Path:
    """A vz-table parameter file of ``material`` (the shipped calibration's nodes), nothing beside it."""
    from nfdmodel import VZTableParams

    shipped = load_parameters(RESULTS / "calibration" / "parameters.json")
    params = VZTableParams(impact.ImpactSetup(material, radius).pair, shipped.x, shipped.f, shipped.g, shipped.window)
    path.write_text(json.dumps(parameter_record(params, radius, material)))
    return path


OTHERS = {"E": (Material(2e11, 0.3, 1e8, 2699.0), 0.1), "nu": (Material(7e10, 0.33, 1e8, 2699.0), 0.1),
          "sigma_y": (Material(7e10, 0.3, 2e8, 2699.0), 0.1), "rho": (Material(7e10, 0.3, 1e8, 7850.0), 0.1),
          "R": (Material(7e10, 0.3, 1e8, 2699.0), 0.05)}


@pytest.mark.parametrize("flag, write", [("--params", vz_file), ("--table-params", table_file)], ids=["vz", "vz-table"])
@pytest.mark.parametrize("differs", list(OTHERS))
def test_a_law_file_of_another_material_is_refused(flag, write, differs, tmp_path, monkeypatch, capsys):
    """The impact's sphere (the reference one) against a file of another E, nu, sigma_y, rho or R:
    one line naming the flag and both values, before any work."""
    monkeypatch.chdir(tmp_path)
    material, radius = OTHERS[differs]
    path = write(tmp_path / "other.json", material, radius)
    err = refused(["--v-in", "0.04", flag, str(path), "--out", str(tmp_path / "out")], capsys)
    assert flag in err and not (tmp_path / "out").exists()
    stated, ours = err.split("this impact's sphere has")
    assert f"{differs} = " in stated and f"{differs} = " in ours
    assert main(["impact", "--v-in", "0.04", flag, str(write(tmp_path / "own.json", REFERENCE, 0.1)),
                 "--dry-run"]) == 0            # the file of the impact's own sphere is taken
    capsys.readouterr()


def test_a_counter_body_file_is_refused(tmp_path, monkeypatch, capsys):
    """A law calibrated against a counter-body is another contact's than the rigid flat's."""
    monkeypatch.chdir(tmp_path)
    counter = {"shape": "flat", "E": 2.1e11, "nu": 0.28, "sigma_y": None, "R": None}
    pair = ContactPair.sphere_counter(REFERENCE, 0.1, 2.1e11, 0.28, None, None)
    ref = VZParams.reference()
    record = parameter_record(VZParams(pair, ref.Ca, ref.Kc, ref.window), 0.1, REFERENCE, counter)
    (tmp_path / "pair.json").write_text(json.dumps(record))
    err = refused(["--v-in", "0.04", "--params", "pair.json", "--dry-run"], capsys)
    assert "--params pair.json" in err and "counter-body" in err


@pytest.mark.parametrize("flags, flag, named", [
    (["--params", "TABLE"], "--params", "--table-params"),      # a vz-table file, no calibration.json beside it
    (["--table-params", "VZ"], "--table-params", "--params"),   # a vz file where the vz-table law is compared
], ids=["vz-table as --params", "vz as --table-params"])
@pytest.mark.parametrize("dry", [True, False], ids=["dry run", "run"])
def test_a_law_file_of_the_other_law_is_refused_before_work(flags, flag, named, dry, tmp_path, monkeypatch, capsys):
    """Refused in one line naming the flag and the one to use, before the FE runs."""
    monkeypatch.chdir(tmp_path)
    files = {"TABLE": str(table_file(tmp_path / "table.json", REFERENCE, 0.1)),
             "VZ": str(vz_file(tmp_path / "vz.json", REFERENCE, 0.1))}
    out = tmp_path / "out"
    err = refused(["--v-in", "0.04", *[files.get(f, f) for f in flags], "--out", str(out)]
                  + (["--dry-run"] if dry else []), capsys)
    assert err.count(flag) >= 1 and named in err.split(flag, 1)[1] and not out.exists()


def test_calibrates_default_output_is_taken_as_params(tmp_path, monkeypatch, capsys):
    """calibrate's default output (a vz-table parameters.json with its calibration.json) gives
    --params its two constants: taken."""
    monkeypatch.chdir(tmp_path)
    assert main(["impact", "--v-in", "0.04", "--params", str(RESULTS / "calibration" / "parameters.json"),
                 "--dry-run"]) == 0
    assert "vz constants of" in capsys.readouterr().out
    assert math.isfinite(impact_files.law_parameters(impact.reference_setup(),
                                               RESULTS / "calibration" / "parameters.json")[0].Ca)
