"""Drop tests against the dynamic FE impact, both ways between ``nfdcal fit-data`` and ``nfdcal impact``.

    nfdcal impact --drops drops.csv --E ... --R ...     # the FE at the tests' velocities, each test against it
    nfdcal fit-data --impacts results/impact/drop_tests.csv --E ... --R ...   # fit the law to the FE's impacts

``drops.csv`` is fit-data's impacts file (v_in [m/s], e [-], optional P_max [N], contact_time [s];
read by calib.fit.measured.data.read_impacts, with its one-line errors). The FE runs at the tests'
distinct velocities, or, when there are more than MOST_VELOCITIES, at that many spread evenly in
log v_in over their range; each test is compared with the FE at its v_in, interpolated linearly in
log v_in between the FE's velocities (e), log-log (P_max, contact time); a test whose v_in is not
one of the FE's is marked ``interpolated`` (OUT/drops.csv) and the summary counts them and names the
rule (``summary``: interpolated, interpolation), as ``nfdcal impact --drops`` prints:

    e_change = e_test - e_FE,   P_max_ratio = P_max,test / P_max,FE - 1,   contact_time_ratio likewise

written to OUT/drops.csv, one row per test. drop_tests.csv (written by every ``nfdcal impact``
run) holds the FE's v_in, e, P_max, contact_time in fit-data's columns. Units: SI.
"""
from __future__ import annotations

from pathlib import Path

import numpy as np

from calib import output

MOST_VELOCITIES = 6
INTERPOLATION = (f"more than {MOST_VELOCITIES} distinct velocities: the FE at {MOST_VELOCITIES} spread evenly in log "
                 f"v_in, each test against it interpolated (e linearly in log v_in, P_max and contact time log-log)")
FIT_DATA_COLUMNS = ("v_in", "e", "P_max", "contact_time")


def read(path):
    """The drop tests of ``path`` (calib.fit.measured.data.read_impacts)."""
    from calib.fit.measured.data import read_impacts

    return read_impacts(path)


def velocities(tests) -> tuple[float, ...]:
    """The FE's velocities [m/s] for the tests (module docstring)."""
    distinct = np.unique(tests.v_in)
    if distinct.size <= MOST_VELOCITIES:
        return tuple(float(v) for v in distinct)
    return tuple(float(v) for v in np.geomspace(distinct[0], distinct[-1], MOST_VELOCITIES))


def compare(tests, records: list[dict]) -> list[dict]:
    """One row per test: its values, the FE's at its v_in and the differences (module docstring)."""
    records = sorted(records, key=lambda r: r["v_in"])
    log_v = np.log([r["v_in"] for r in records])

    def at(key, v, log_scale):
        values = np.array([r[key] for r in records], dtype=float)
        if len(records) == 1:
            return float(values[0])
        if log_scale:
            return float(np.exp(np.interp(np.log(v), log_v, np.log(values))))
        return float(np.interp(np.log(v), log_v, values))

    rows = []
    for k, v in enumerate(tests.v_in):
        row = {"row": int(tests.rows[k]), "v_in": float(v), "e": float(tests.e[k]), "e_fe": at("e", v, False),
               "interpolated": bool(not np.any(np.isclose(np.log(v), log_v, rtol=0.0, atol=1e-12)))}
        row["e_change"] = row["e"] - row["e_fe"]
        for key, measured in (("P_max", tests.P_max), ("contact_time", tests.contact_time)):
            if measured is not None and np.isfinite(measured[k]):
                row[key] = float(measured[k])
                row[f"{key}_fe"] = at(key, v, True)
                row[f"{key}_ratio"] = row[key] / row[f"{key}_fe"] - 1.0
        rows.append(row)
    return rows


def summary(rows: list[dict]) -> dict:
    """The root-mean-square e_change and the mean P_max / contact time ratios (where measured); how
    many tests were compared with the FE interpolated between its velocities, and the rule."""
    out = {"tests": len(rows), "e_change_rms": float(np.sqrt(np.mean([r["e_change"] ** 2 for r in rows]))),
           "e_change_mean": float(np.mean([r["e_change"] for r in rows])),
           "interpolated": sum(bool(r.get("interpolated")) for r in rows)}
    if out["interpolated"]:
        out["interpolation"] = INTERPOLATION
    for key in ("P_max", "contact_time"):
        ratios = [r[f"{key}_ratio"] for r in rows if f"{key}_ratio" in r]
        if ratios:
            out[f"{key}_ratio_mean"] = float(np.mean(ratios))
    return out


def write_comparison(path: Path, rows: list[dict], stamp: dict) -> Path:
    columns = ["row", "v_in", "e", "e_fe", "e_change", "P_max", "P_max_fe", "P_max_ratio", "contact_time",
               "contact_time_fe", "contact_time_ratio", "interpolated"]
    columns = [c for c in columns if any(c in r for r in rows)]
    return Path(output.write_csv(path, rows, columns, comment=output.stamp_comment(stamp)))


def write_fit_data_file(path: Path, records: list[dict], stamp: dict) -> Path:
    """drop_tests.csv: the FE impacts in fit-data's impacts columns (module docstring)."""
    return Path(output.write_csv(path, [{k: r[k] for k in FIT_DATA_COLUMNS} for r in records], list(FIT_DATA_COLUMNS),
                                 comment=output.stamp_comment(stamp)))
