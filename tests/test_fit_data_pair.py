"""``nfdcal fit-data --counter-E ...``: sigma_Y from drop tests and force curves of a sphere on an elastic flat or sphere.

The data are the two-body FE's, never the law's: the quasi-static drop tests (v_in from the FE's loading work, its
e and P_max) and loading curves of the pair table build's held-out pairs, off every node of the table
(results/pairs/pair_fe_drops.json, written by python -m calib.fit.pair_table_build; calib.fit.pair_fit_check).
On the pair law sigma_Y comes back within 3 % for every pair, its 95 % interval covering the truth
for all
but at most one; the same data fitted as
if the floor were rigid miss it by more than 10 %. A yielding counter-body, --pair, --law vz, a dent column and
--pair-table without --counter-E are refused in one line (exit 2); --params-out writes the pair law with its
counter-body, which nfdmodel reads back.
"""
import json
import math
from pathlib import Path

import pytest
from test_fit_data_refusals import assert_refused, fit_data as run  # noqa: E402  (tests/ on the path)

from nfdmodel import load_parameters


ROOT = Path(__file__).resolve().parent.parent
FE_DATA = ROOT / "results" / "pairs" / "pair_fe_drops.json"
SIGMA_Y_BOUND = 0.03


def rows() -> list[dict]:
    return [r for r in json.loads(FE_DATA.read_text(encoding="utf-8"))["rows"]]


def flags(row: dict, counter: bool = True) -> list[str]:
    out = ["--E", repr(row["E"]), "--nu", repr(row["nu"]), "--R", repr(row["R"]), "--rho", repr(row["rho"]), "--json"]
    if counter:
        body = row["counter"]
        out += ["--counter-E", repr(body["E"]), "--counter-nu", repr(body["nu"])]
        if body["R"] is not None:
            out += ["--counter-R", repr(body["R"]), "--counter-rho", repr(body["rho"])]
    return out


def drops_csv(tmp_path, row: dict, columns=("v_in", "e", "P_max")) -> Path:
    path = tmp_path / "drops.csv"
    drops = row["drops"]
    path.write_text(",".join(columns) + "\n" + "".join(",".join(repr(drops[c][k]) for c in columns) + "\n"
                                                       for k in range(len(drops["e"]))), encoding="utf-8")
    return path


def force_csv(tmp_path, row: dict) -> Path:
    path = tmp_path / "press.csv"
    loading = row["loading"]
    path.write_text("approach,force\n" + "".join(f"{a!r},{p!r}\n" for a, p in zip(loading["alpha"], loading["P"])),
                    encoding="utf-8")
    return path


@pytest.mark.parametrize("data", ["drops e", "drops e+P", "force"])
def test_sigma_y_from_the_two_body_fe(data, tmp_path, capsys):
    errors, covered = [], []
    for row in rows():
        given = (["--force-approach", str(force_csv(tmp_path, row))] if data == "force" else
                 ["--impacts", str(drops_csv(tmp_path, row, ("v_in", "e") if data == "drops e" else
                                             ("v_in", "e", "P_max")))])
        code, out, err = run([*given, *flags(row)], capsys)
        assert code == 0, err
        found = json.loads(out)
        assert found["counter"]["E"] == row["counter"]["E"]
        errors.append(math.log(found["sigma_y"] / row["sigma_y"]))
        low, high = found["sigma_y_interval95"]
        covered.append(low <= row["sigma_y"] <= high)
    assert len(errors) >= 4 and max(map(abs, errors)) < SIGMA_Y_BOUND, errors
    assert sum(covered) >= len(covered) - 1, (errors, covered)     # 95 % intervals: at most one of five misses


def test_a_rigid_flat_fit_of_the_same_drops_misses(tmp_path, capsys):
    row = next(r for r in rows() if r["counter"]["R"] is None)
    code, out, err = run(["--impacts", str(drops_csv(tmp_path, row)), *flags(row, counter=False), "--law",
                          "vz-table"], capsys)
    if code == 0:                       # fitted: far from the truth
        assert abs(math.log(json.loads(out)["sigma_y"] / row["sigma_y"])) > 0.1
    else:                               # or refused as a law that does not describe the data
        assert code == 2 and "Traceback" not in err


def test_params_out_holds_the_pair_law(tmp_path, capsys):
    row = rows()[0]
    target = tmp_path / "pair.json"
    code, out, err = run(["--impacts", str(drops_csv(tmp_path, row)), *flags(row), "--params-out", str(target)],
                         capsys)
    assert code == 0, err
    params = load_parameters(target)
    assert params.pair.E_star < row["E"] / (1 - row["nu"] ** 2)           # the pair's E*, not the sphere's
    record = json.loads(target.read_text(encoding="utf-8"))
    assert record["counter_body"]["E"] == row["counter"]["E"]


@pytest.mark.parametrize("extra, named", [
    (["--counter-sigma-y", "1e9"], ["--counter-sigma-y", "elastic"]),
    (["--pair"], ["--pair", "two identical spheres"]),
    (["--law", "vz"], ["--law", "vz-table"]),
    (["--counter-E", "2e8"], ["--counter-E"]),                             # E1'/E2' beyond the pair table's nodes
])
def test_what_the_pair_table_does_not_cover_is_refused(extra, named, tmp_path, capsys):
    row = next(r for r in rows() if r["counter"]["R"] is None)
    argv = ["--impacts", str(drops_csv(tmp_path, row)), *flags(row)]
    if "--counter-E" in extra:
        argv = argv[:argv.index("--counter-E")] + argv[argv.index("--counter-E") + 2:]
    assert_refused(*run([*argv, *extra], capsys), *named)


def test_a_dent_column_and_a_lone_pair_table_are_refused(tmp_path, capsys):
    row = next(r for r in rows() if r["counter"]["R"] is None)
    path = tmp_path / "dents.csv"
    drops = row["drops"]
    path.write_text("v_in,e,dent\n" + "".join(f"{v!r},{e!r},1e-6\n" for v, e in zip(drops["v_in"], drops["e"])),
                    encoding="utf-8")
    assert_refused(*run(["--impacts", str(path), *flags(row)], capsys), "dent", "--counter-E")
    assert_refused(*run(["--impacts", str(drops_csv(tmp_path, row)), *flags(row, counter=False), "--pair-table",
                         str(tmp_path / "x.csv")], capsys), "--pair-table", "--counter-E")
