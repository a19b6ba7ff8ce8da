"""Measured imprints: the drop tests' ``radius`` column [m] fitted on the vz master table's vz-unload law
(``nfdcal fit-data``, the vz-table law).

**The modelling choice.** The radius of the imprint a plastic impact leaves is taken as the contact
radius at the impact's peak: the unloading of a plastic contact is elastic (Johnson 1985, Contact
Mechanics, ch. 6), it lifts the flattened cap off the flat from its edge inwards without moving where
the plastic flattening stood at the peak, so the residual imprint's rim lies close to the peak contact
radius, and an imprint seen on a surface is the footprint the contact left at its widest. Measured on
the FE's state after separation (calib.fit.master_radius_check.residual_rim; the three off-grid materials
below, finite strain, the nodes' graded mesh, surface nodes 2.6-3.6 % of a apart): the residual surface
returns to the sphere (shifted by the dent) at -12.1..-12.6 % of the peak contact radius at 3 P_Y,
-5.6..-6.5 % at 7, -3.4..-4.6 % at 16, -2.4..-4.4 % at 40-100 P_Y; beyond it a low lip (6-10 % of the dent
high) crests at +8..+21 %. Taking that rim as the radius moves sigma_Y fitted with e by -0.25..+0.29 %
(radius residuals +2.2..+14 %): an imprint measured to its rim is fitted to within the target, though its
residual exceeds the law's level.

**Which FE radius.** f_a is fitted to the FE's contact edge by the gap extrapolation
(calib.fe.recovery.contact_radius_from_gap). The pressure extrapolation (contact_radius_from_pressure,
what the dynamic FE's ``contact_radius_max`` records) lies above it by +0.9..+4.3 % at the peaks of
plastic contacts (3-100 P_Y, three off-grid materials, the benchmark below), as the dynamic FE's
largest radius lies above the law's by 1.7..4.9 % (2-100 v_Y): a fit to such radii keeps sigma_Y
within 0.6 % through its e, but its radius residual exceeds the law's level (the summary says so).

**The prediction.** For a drop test at v_in the law's quasi-static impact (nfdmodel.collision_reference,
law "vz-unload") gives the peak force P_max; the imprint radius is the law's contact radius there,

    a = a_Y (x^(1/3) + f_a(x)),   x = P_max / P_Y   [m]

f_a the vz master table's ``radius_a_p_over_a_Y`` column (calib.fit.vz_master_table: fitted to the
FE's contact radius along the nodes' loading branches; within 0.61 % of held-out small-strain FE at 4.7-110
P_Y below the join, -1.95 % above it, tests/benchmarks/master_unload_radius.py).
Two identical spheres: the same with the pair's P_Y and a_Y (R* = R/2). The residual is relative,
r = a_law / a - 1, a group ``radius`` weighted as the others (calib.fit.measured.table_law).

**Sensitivity.** At fixed v_in the peak radius moves as sigma_Y^(-0.09..-0.25) (2..40 v_Y; the law at
nu 0.25, E/sigma_Y 150): a 1 % error in a moves sigma_Y by 4 to 11 %, so the radius sharpens sigma_Y
only through its joint fit with e, and a mis-scaled radius (a unit slip) is refused rather than fitted.

**The model-form level** of the data kinds with a radius (``MODEL_FORM``), measured as the table's
other kinds are (calib.fit.vz_master_check.fit_errors: fit-data's vz-table fit to the noise-free FE
data of off-grid materials, rms of ln(sigma_fit / sigma_true) and of each group's residual): on
direct FE runs that record the contact radius (calib.fit.master_radius_check.fe_run in finite strain,
the table's kinematics above a = 0.05 R; the graded mesh of the table's nodes),
tests/benchmarks/fit_data_radius.py. The table's .json states the other kinds (``model_form``);
:func:`model_form` adds these where it has none. Measured at nu 0.22, E/sigma_Y 2000; nu 0.38, 1500;
nu 0.25, 150 (five drop tests each, 3-100 P_Y, the last to a = 0.1 R): ln(sigma_fit / sigma_true) -0.10,
+0.19, -0.29 % with e and radius (rms 0.21 %), -0.22, -0.25, -0.61 % with e, dent and radius (rms 0.40 %);
the law's radius within -0.95..+0.65 % of the FE's.
"""
from __future__ import annotations

from pathlib import Path

import numpy as np

from calib.fit.measured.data import ImpactData
from calib.fit.vz_master_table import DEFAULT_TABLE

# Measured by tests/benchmarks/fit_data_radius.py (module doc): kind -> u in ln sigma_Y, and
# "kind: group" -> the rms residual of that group on the noise-free FE data.
MODEL_FORM = {"sigma_y": {"drops e+radius": 0.00208, "drops e+dent+radius": 0.004013},
              "residual_rms": {"drops e+radius: e": 0.001627, "drops e+radius: radius": 0.003472,
                               "drops e+dent+radius: e": 0.001937, "drops e+dent+radius: dent": 0.015035,
                               "drops e+dent+radius: radius": 0.003482}}
RADIUS_KINDS = ("drops e+radius", "drops e+dent+radius")


def model_form(table) -> dict:
    """The vz master table's measured model-form levels (its .json, ``model_form``) with the radius
    kinds' (``MODEL_FORM``, measured on the shipped table) where the table states none; another table
    (``--vz-table``) gets its own levels only."""
    form = table.meta.get("model_form", {})
    out = {key: dict(form.get(key, {})) for key in ("sigma_y", "residual_rms")}
    if table.path is None or Path(table.path).resolve() != DEFAULT_TABLE.resolve():
        return {**form, **out}
    for key, levels in MODEL_FORM.items():
        for name, value in levels.items():
            out[key].setdefault(name, value)
    return {**form, **out}


def predicted_radius(law, P_max) -> np.ndarray:
    """The imprint radius [m] the law predicts at the impacts' peak forces P_max [N] (module doc)."""
    return np.asarray(law.contact_radius_at(P_max), dtype=float)


def check_radius(impacts: ImpactData | None, R: float) -> None:
    """ValueError naming the file, the row and the column when a measured imprint radius is not below
    the sphere's radius R [m] (a contact radius is < R; a radius in mm or um reads 1e3 or 1e6 too large)."""
    if impacts is None or impacts.radius is None:
        return
    bad = np.nonzero(np.isfinite(impacts.radius) & (impacts.radius >= R))[0]
    if bad.size:
        i = int(bad[0])
        a = float(impacts.radius[i])
        hint = (f"; it looks like mm (radius x 1e-3 = {a * 1e-3:g} m), give metres" if a * 1e-3 < R else
                f"; it looks like um (radius x 1e-6 = {a * 1e-6:g} m), give metres" if a * 1e-6 < R else "")
        raise ValueError(f"impacts file {impacts.path}: row {int(impacts.rows[i])}, column 'radius': out of range: "
                         f"need 0 < radius < R = {R:g} m (the imprint's radius is below the sphere's), got {a:g}{hint}")


def refuse_on_vz(impacts: ImpactData | None, path) -> None:
    """ValueError when drop tests with a radius column are fitted on --law vz (the two-constant law's
    contact radius is fitted to the force, not measured against the FE's radius)."""
    if impacts is not None and impacts.radius is not None:
        raise ValueError(f"{path}: column 'radius' is fitted on the vz master table's vz-unload law (the default "
                         f"law, --law vz-table), not on --law vz (the two-constant law's contact radius is not "
                         f"measured against the FE's)")
