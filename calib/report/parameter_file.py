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


def two_constant_law(path):
    """The paper's two-constant law (nfdmodel.VZParams) of the calibration whose parameter file is
    ``path``, whichever law that file ships: the file's own law when it is vz, else Ca [m/N] and Kc
    [1/N] of the calibration's summary beside it (calibration.json, written by nfdcal calibrate:
    extrapolated from two meshes) on the window they were fitted on."""
    import json

    from nfdmodel import CalibrationWindow, VZParams, load_parameters

    params = load_parameters(path)
    if isinstance(params, VZParams):
        return params
    beside = Path(path).parent / "calibration.json"
    if not beside.is_file():
        raise ValueError(f"{path} holds {type(params).__name__}, not the vz law, and no calibration.json beside it "
                         "gives the two constants Ca, Kc: give a vz parameter file or a calibration's parameters.json")
    summary = json.loads(beside.read_text(encoding="utf-8"))
    return VZParams(params.pair, summary["Ca"], summary["Kc"], CalibrationWindow.from_record(summary["window"]))
