"""The files an impact's laws are read from (nfdcal impact --params, --table-params,
--lammps-restitution), each checked against the impact's sphere before any FE runs.

``setup`` is the impact's calib.studies.impact.ImpactSetup (its material, R, hardening). A file
whose law is of another sphere, of a counter-body, of another law or of another flow curve is
refused in one line naming its flag (a ValueError: nfdcal's exit 2).
"""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from calib import output
from calib.fit import impact_window
from nfdmodel import load_parameters
from nfdmodel.reference_case import is_reference_sphere


def law_parameters(setup, params_file=None) -> tuple[object, str]:
    """(vz parameters, their source): the two constants of the file given (a calibration's
    parameter file, whichever law it ships: calib.report.parameter_file.two_constant_law), else the
    master table's (the paper's outside it). A ValueError naming --params for a file that gives
    no two constants or states another material than the impact's (``check_material``)."""
    if params_file is not None:
        from calib.report.parameter_file import two_constant_law

        try:
            params = two_constant_law(params_file)
        except (ValueError, KeyError, TypeError, OSError) as exc:   # calibration.json beside it: a bad one too
            hint = ("; or give it as --table-params (its vz-table law)"
                    if "not the vz law" in str(exc) else "")
            raise ValueError(f"--params {_named(exc, params_file)}{hint}") from None
        check_material(setup, params_file, "--params")
        return params, output.display_path(params_file)
    params, source = impact_window.estimating_constants(setup.material, setup.radius)
    if setup.hardening is not None:     # the master table is of perfectly plastic spheres
        source += " (of the perfectly plastic sphere: give --params of this hardening sphere's calibration)"
    return params, source


def table_parameters(setup, table_file=None):
    """The vz-table law's parameters from the file given, else None; a ValueError naming
    --table-params for a file of another law or material (``check_material``)."""
    if table_file is None:
        return None
    from nfdmodel import VZTableParams
    from nfdmodel.parameter_file import law_of

    try:
        table = load_parameters(table_file)
    except (ValueError, OSError) as exc:
        raise ValueError(f"--table-params {_named(exc, table_file)}") from None
    if not isinstance(table, VZTableParams):
        raise ValueError(f"--table-params {table_file}: holds the vz law, not the vz-table law: give it as --params")
    if type(table) is not VZTableParams:      # a subclass unloads otherwise (vz-unload)
        raise ValueError(f"--table-params {table_file}: holds the {law_of(table)} law, not the vz-table law: give a "
                         f"vz-table file (nfdcal calibrate --ship table)")
    check_material(setup, table_file, "--table-params")
    return table


def _named(exc: Exception, path) -> str:
    """The error's message, starting with the file it is about."""
    text = str(exc).strip("'\"")
    return text if str(path) in text else f"{path}: {text}"


def check_material(setup, path, flag: str) -> None:
    """ValueError naming ``flag`` and both materials when the parameter file at ``path`` (already
    read by nfdmodel.load_parameters) states another sphere than the impact's (E, nu, sigma_y, rho,
    R of its "material", nfdmodel/parameter_file.py; relative 1e-6) or a counter-body: its law is
    another contact's (rho too: the law's impact is of the file's mass)."""
    import json

    data = json.loads(Path(path).read_text(encoding="utf-8"))
    stated = data["material"]
    material = setup.material
    ours = {"E": material.E, "nu": material.nu, "sigma_y": material.sigma_y, "rho": material.rho, "R": setup.radius}
    differ = [key for key, value in ours.items() if not math.isclose(stated[key], value, rel_tol=1e-6)]
    hardening = None if setup.hardening is None else setup.hardening.record()

    def curve(record):      # the flow curve itself, not the name of the file it was read from
        return None if record is None else {k: v for k, v in record.items() if k != "source"}

    if curve(data.get("hardening")) != curve(hardening):
        def named(record):
            if record is None:
                return "perfectly plastic"
            if record["flow_curve"] == "linear":
                return f"hardening linearly, H = {record['hardening_modulus']:g} Pa"
            return f"hardening by the {record['flow_curve']} flow curve" + (
                f" of {record['source']}" if "source" in record else "")
        raise ValueError(f"{flag} {path}: the file's law is of a sphere {named(data.get('hardening'))}; this impact's "
                         f"sphere is {named(hardening)}: give the file of this sphere, or its flags")
    if differ or data.get("counter_body") is not None:
        words = lambda m: ", ".join(f"{key} = {m[key]:g}" for key in ours)  # noqa: E731
        against = " against a counter-body" if data.get("counter_body") is not None else ""
        raise ValueError(f"{flag} {path}: the file's law is of {words(stated)}{against}; this impact's sphere has "
                         f"{words(ours)} on a rigid flat (SI units): give the file of this material, or its flags")


def mdr_table(setup, mdr_file=None) -> tuple[np.ndarray, np.ndarray] | None:
    """(log(v_in / v_Y), e) of LAMMPS' mdr restitution from the CSV given (module docstring), None
    without one; a ValueError for another sphere than the reference one (the CSV is of its material)
    or a file without the columns v_in_over_v_Y, e_mdr_lammps."""
    if mdr_file is None:
        return None
    if not is_reference_sphere(setup.material.E, setup.material.nu, setup.radius, setup.material.sigma_y):
        raise ValueError(f"{mdr_file}: LAMMPS' mdr restitution is the reference sphere's; this sphere is another")
    import csv

    with open(mdr_file, encoding="utf-8") as handle:
        rows = list(csv.DictReader(line for line in handle if not line.startswith("#")))
    try:
        x = np.log([float(row["v_in_over_v_Y"]) for row in rows])
        e = np.array([float(row["e_mdr_lammps"]) for row in rows])
        if not x.size or np.any(np.diff(x) <= 0.0):
            raise ValueError("no rows, or velocities not increasing")
    except (KeyError, ValueError, TypeError):
        raise ValueError(f"{mdr_file}: not a restitution CSV (columns v_in_over_v_Y, e_mdr_lammps, "
                         "velocities increasing)") from None
    return x, e
