"""``nfdcal collide`` oblique impacts: the models of the flags against nfdmodel called directly, and
collide's refusals (one line naming the flag and its range, exit code 2).

- k_t of a --params file with a counter-body is 8 G* of the two materials the file states
  (nfdmodel.friction.Friction.mindlin with both), not of a pseudo-material of the pair's E* and
  nu; --damping, --x-gamma-t, --rolling and --twisting give nfdmodel's Friction of the same models.
- The messages: a speed, spin or law out of range names the flag, its range and the value typed;
  e_t and beta are printed only where they are defined; an existing --plot file is replaced only
  with --overwrite.
"""
from __future__ import annotations

import json

import numpy as np
import pytest

from calib.cli import main
from nfdmodel import ContactPair, Material, VZParams, parameter_record
from nfdmodel.friction import Friction
from nfdmodel.oblique import oblique_collide

pytestmark = pytest.mark.laws

STEEL = Material(2.1e11, 0.29, 5e8, 7850.0)
ALUMINIUM = Material.reference()
R, R2, DT = 0.01, 0.02, 1e-7


@pytest.fixture(scope="module")
def pair_file(tmp_path_factory):
    """A steel sphere (R 1 cm) calibrated against an aluminium counter-sphere (R 2 cm)."""
    pair = ContactPair.sphere_counter(STEEL, R, ALUMINIUM.E, ALUMINIUM.nu, ALUMINIUM.sigma_y, R2, ALUMINIUM.rho)
    counter = {"shape": "sphere", "E": ALUMINIUM.E, "nu": ALUMINIUM.nu, "sigma_y": ALUMINIUM.sigma_y, "R": R2,
               "rho": ALUMINIUM.rho}
    path = tmp_path_factory.mktemp("pair") / "pair.json"
    record = parameter_record(VZParams.from_dimensionless(pair, 0.026, 0.0098), R, STEEL, counter)
    path.write_text(json.dumps(record))
    return path


def collide_json(capsys, *argv) -> list[dict]:
    assert main(["collide", *argv, "--json"]) == 0
    return json.loads(capsys.readouterr().out)


@pytest.mark.parametrize("flags, friction", [
    ([], {}),
    (["--damping", "tsuji", "0.5", "--x-gamma-t", "0.5"], {"damping": "tsuji", "damping_value": 0.5, "x_gamma_t": 0.5}),
    (["--rolling", "sds", "1000", "0.01", "0.1", "--twisting", "marshall"],
     {"rolling": "sds", "k_roll": 1000.0, "gamma_roll": 0.01, "mu_roll": 0.1, "twisting": "marshall"}),
    (["--twisting", "sds", "0.01", "1e-4", "1e-3"],
     {"twisting": "sds", "k_twist": 0.01, "gamma_twist": 1e-4, "mu_twist": 1e-3}),
])
def test_a_pair_file_takes_k_t_of_its_two_materials(capsys, pair_file, flags, friction):
    """collide --params (a counter-body) --angle --mu with the models of the flags: e_n, e_t, the spin
    out of nfdmodel.oblique_collide with Friction.mindlin(mu, sphere, counter-body) to 1e-12. The
    pseudo-material of the pair's E* and nu (k_t 8 G/(2 - nu) of E = E* (1 - nu^2): 9.4869e10 Pa against
    the two materials' 9.5067e10 Pa) gives at 30 deg without the other models e_t 0.453547 and spin
    31.2300 rad/s against the two materials' 0.453754 and 31.2106 (measured)."""
    from nfdmodel import load_parameters

    records = collide_json(capsys, "--params", str(pair_file), "--v-in", "0.5", "--angle", "30", "60",
                           "--mu", "0.3", "--omega", "-20", "--dt", str(DT), *flags)
    model = Friction.mindlin(0.3, STEEL, ALUMINIUM, variant="mindlin_rescale/force", **friction)
    reference = oblique_collide("vz", load_parameters(pair_file), model, 0.5, [30.0, 60.0], -20.0, dt=DT)
    for record, e_n, e_t, spin in zip(records, reference.e_n, reference.e_t, reference.omega_out):
        assert record["e_n"] == pytest.approx(e_n, rel=1e-12)
        assert record["e_t"] == pytest.approx(e_t, rel=1e-12)
        assert record["omega_out"] == pytest.approx(spin, rel=1e-12)


def test_e_t_and_beta_are_not_printed_where_undefined(capsys):
    """At normal incidence without spin, e_t = v_t'/v_t and beta = -V'/V divide by zero: JSON null,
    the table '-' and a line saying why (not 'nan')."""
    records = collide_json(capsys, "--v-in", "0.1", "--angle", "0", "10", "--mu", "0.3")
    assert records[0]["e_t"] is None and records[0]["beta"] is None
    assert records[1]["e_t"] == pytest.approx(0.91, abs=0.05) and records[1]["beta"] is not None
    assert main(["collide", "--v-in", "0.1", "--angle", "0", "--mu", "0.3"]) == 0
    out = capsys.readouterr().out
    assert "nan" not in out and "e_t = v_t'/v_t is not defined at normal incidence" in out


@pytest.mark.parametrize("argv, message", [
    # a zero speed: "0 J at v_in = 1e-300 m/s" named a speed never typed
    (["--v-in", "0", "--angle", "30"], "--v-in out of range: need 0 < v_in <= 10000 m/s"),
    # the speed typed, not its normal part 86602.5 with "did you give mm/s?"
    (["--v-in", "1e5", "--angle", "30"], "got 100000"),
    (["--v-in", "0.1", "--angle", "10", "--mu", "0.3", "--omega", "1e300"],    # accepted with an overflow warning
     "--omega out of range: need |omega| <= 100000 rad/s"),
    (["--v-in", "0.1", "--law", "vz-table"], "--law vz-table needs --params FILE"),   # "must be VZTableParams"
    (["--v-in", "0.1", "--angle", "10", "--damping", "tsuji"], "--damping out of range: need MODEL VALUE"),
    (["--v-in", "0.1", "--angle", "10", "--damping", "tsuji", "2"], "--damping: e out of range"),
    (["--v-in", "0.1", "--angle", "10", "--rolling", "sds", "1"], "--rolling out of range"),
    (["--v-in", "0.1", "--angle", "10", "--twisting", "marshall"], "--mu out of range"),
    (["--v-in", "0.1", "--angle", "10", "--mu", "0.3", "--tangential", "coulomb"], "--tangential: tangential out"),
    (["--v-in", "0.1", "--overwrite"], "--overwrite applies to --plot only"),
])
def test_collide_refusals_name_the_flag(capsys, argv, message):
    assert main(["collide", *argv]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and message in err, err


def test_an_existing_plot_is_replaced_only_with_overwrite(capsys, tmp_path):
    plot = tmp_path / "e_t.png"
    plot.write_bytes(b"the user's own picture")
    argv = ["collide", "--v-in", "0.1", "--angle", "10", "--mu", "0.3", "--plot", str(plot)]
    assert main(argv) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "exists: give --overwrite" in err
    assert plot.read_bytes() == b"the user's own picture"
    assert main(argv + ["--overwrite"]) == 0
    assert plot.read_bytes()[:4] == b"\x89PNG"
