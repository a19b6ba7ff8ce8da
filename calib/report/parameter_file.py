"""The one writer of parameter files (JSON): what ``nfdmodel.load_parameters`` reads back.

Needs nothing beyond nfdmodel and calib.output, so that ``nfdcal material --params-out`` and
``nfdcal fit-data --params-out`` work without the FE stack (meshio, scikit-fem, gmsh).
"""
from __future__ import annotations

from pathlib import Path

from calib import output
from nfdmodel import parameter_record


def write_parameter_file(path, params, radius: float, material, fit: dict, stamp: dict,
                         counter: dict | None = None, **extra) -> Path:
    """Write, atomically, nfdmodel.parameter_record (law, Ca [m/N], Kc [1/N], the dimensionless
    constants, the yield point, the material and R [m], the counter-body when not a rigid flat,
    units) plus where the constants come from (``fit``), anything in ``extra`` (FE errors, mesh)
    and the provenance ``stamp``."""
    return output.write_json(path, {**parameter_record(params, radius, material, counter), "fit": fit,
                                    **extra, "stamp": stamp})
