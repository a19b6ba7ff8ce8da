"""The tested specimen and what the vz law predicts for its measurements (``nfdcal fit-data``).

**The law** (README, The model; Vu-Quoc & Zhang 1999, Proc. R. Soc. Lond. A 455, eqs. 2.5,
3.4-3.7, 3.19-3.22), for a sphere of radius R on a rigid flat (R* = R, E* = E / (1 - nu^2)):

    P_Y = pi^3 R*^2 (A_Y(nu) sigma_Y)^3 / (6 E*^2) [N],   a_Y = (3 P_Y R* / (4 E*))^(1/3) [m]
    a_p = Ca <P - P_Y>,  C_R = 1 + Kc <P - P_Y>,  Ca = Ca_hat a_Y / P_Y [m/N],  Kc = Kc_hat / P_Y [1/N]

What the law predicts for the data (calib.fit.measured.data):

    impacts         the exact quasi-static impact by energy balance (nfdmodel.collision_reference):
                    (1/2) m v_in^2 = W_l(delta_max), e = sqrt(W_u / W_l), P_max, contact time
                    t_load + t_unload. The law is rate-independent, so this is what a time-stepped
                    collision converges to (``collide``, O(dt^2)) and what a drop test measures.
                    Scaled, e = e(v_in / v_Y; Ca_hat, Kc_hat) exactly, with
                    v_Y = sqrt(4 P_Y delta_Y / (5 m)) proportional to sigma_Y^(5/2).
    force-approach  the law driven along each test's measured approach, as
                    calib.fit.calibration.drive_law (the driver of the FE force fit) drives it,
                    but every row at once: the law's history is its turning point (nfdmodel.history:
                    delta_max and what follows from it), which after rows 1..k is the virgin
                    state loaded to the running maximum M_k = max(0, delta_1..delta_k). So
                    P_k = P(delta_k; virgin loaded to M_k): two calls of the law on n contacts
                    instead of n calls on one (10k rows: 1.3 ms instead of 1.1 s).

**Many drop tests** (:func:`predict_impacts`): repeated v_in are evaluated once. Data with more
than ``EXACT_SPEEDS`` distinct v_in get the law's e, P_max and contact time at nodes and a
quintic spline between them (scipy.interpolate.make_interp_spline) of ln y: below v_Y in ln v
(Hertz: ln y is linear in ln v, reproduced exactly), above v_Y in u = sqrt(ln(v / v_Y)), which
smooths the law's onset of plasticity at v_Y, ``NODES_PER_UNIT_U`` nodes per unit of u. Measured
against the law at 4001 speeds from 0.3 v_Y to 1e4 v_Y (or full contact) for sigma_Y 14 MPa..1.3
GPa and Ca_hat 0.001..0.5, Kc_hat 1e-5..0.9: e and P_max within 4e-10, the contact time within
5e-8, far below any measured scatter; the nodes sit at fixed u, so
the spline moves smoothly with the parameters and the fit's finite differences see no jumps
(tests/test_fit_data_refusals.py::test_many_drop_tests_are_interpolated_within_1e_8).

**Residuals** (:func:`relative_residuals`), per group: r = (y_law - y) / y for e, P_max and the
contact time [-], and r = (P_law - P) / max(|P|, P_floor) for the forces [-] (P_floor:
calib.fit.measured.data, the FE force fit's weighting).
"""
from __future__ import annotations

import math
import warnings
from dataclasses import dataclass

import numpy as np
from scipy.interpolate import make_interp_spline

from calib.fit.master_table import MasterTable
from calib.fit.measured.data import ForceApproachData, Measurements
from nfdmodel import ContactPair, Material, PlausibilityWarning, RangeWarning, VZParams, collision_reference, get_law

EXACT_SPEEDS = 500              # at most this many distinct v_in: the law at each (more: interpolated)
NODES_PER_UNIT_U = 72           # interpolation nodes per unit of u = sqrt(ln(v / v_Y)) above v_Y
ELASTIC_NODES = 8               # nodes below v_Y (the law is Hertz there: exact in ln v)
SPLINE_DEGREE = 5


@dataclass(frozen=True)
class Specimen:
    """What the user knows: E [Pa], nu [-], R [m], rho [kg/m^3] of the sphere, and how it was
    tested: ``two_spheres`` False, a sphere on a massive rigid flat (R* = R, E* = E/(1 - nu^2),
    m* = m); True, head-on impacts of two identical spheres (R* = R/2, E* = E/(2(1 - nu^2)),
    m* = m/2, v_in the relative speed, the approach that of the two centres). The law's
    dimensionless constants Ca_hat, Kc_hat are the material's either way (a << R). ``counter``: the
    elastic flat or sphere the sphere hits (calib.fit.counter.CounterBody; None: the rigid flat or the
    identical sphere), whose pair (E*, R*, m*) and pair law (calib.fit.pair_table) the fit takes, from
    ``pair_table`` (a calib.fit.pair_table.PairTable or its CSV path; None: the shipped one)."""

    E: float
    nu: float
    R: float
    rho: float
    two_spheres: bool = False
    counter: object = None
    pair_table: object = None

    def material(self, sigma_y: float) -> Material:
        return Material(self.E, self.nu, sigma_y, self.rho)

    def pair(self, sigma_y: float) -> ContactPair:
        """The tested contact pair."""
        with warnings.catch_warnings():          # the radius was checked (and warned about) once
            warnings.simplefilter("ignore", PlausibilityWarning)
            material = self.material(sigma_y)
            if self.counter is not None:
                return self.counter.pair(material, self.R)
            if self.two_spheres:
                return ContactPair.sphere_sphere(material, self.R, material, self.R)
            return ContactPair.sphere_flat(material, self.R)

    def sphere_flat_params(self, params: VZParams) -> VZParams:
        """The fitted law for this sphere on a rigid flat (what a parameter file describes): the
        same sigma_Y, Ca_hat, Kc_hat and window (in P/P_Y), the pair's own P_Y and a_Y."""
        if not self.two_spheres:
            return params
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", PlausibilityWarning)
            pair = ContactPair.sphere_flat(self.material(params.pair.sigma_y), self.R)
        return VZParams.from_dimensionless(pair, params.Ca_hat, params.Kc_hat, params.window)


def dimensionless_constants(specimen: Specimen, values: dict,
                            table: MasterTable | None) -> tuple[ContactPair, float, float]:
    """The tested pair at ``values["sigma_y"]`` [Pa] and Ca_hat, Kc_hat [-]: those of ``values``,
    else the master table's at (nu, E / sigma_Y)."""
    pair = specimen.pair(values["sigma_y"])
    if "Ca_hat" in values:
        return pair, values["Ca_hat"], values["Kc_hat"]
    return (pair, *table.lookup(specimen.nu, specimen.E / values["sigma_y"]))


def law_parameters(specimen: Specimen, values: dict, table: MasterTable | None) -> VZParams:
    """VZParams from ``values`` (sigma_y [Pa], and Ca_hat, Kc_hat; the master table's at
    (nu, E / sigma_Y) when absent)."""
    return VZParams.from_dimensionless(*dimensionless_constants(specimen, values, table))


def _law_impacts(params: VZParams, v_in: np.ndarray) -> dict:
    reference = collision_reference("vz", params, v_in)
    return {"e": reference.restitution, "P_max": reference.P_max, "contact_time": reference.contact_time_estimate}


def _interpolated_impacts(params: VZParams, speeds: np.ndarray) -> dict:
    """The law's predictions at sorted distinct ``speeds`` [m/s] from nodes and a spline (module doc)."""
    v_Y = params.pair.v_Y
    names = ("e", "P_max", "contact_time")
    out = np.empty((speeds.size, len(names)))

    def interpolate(where, x_nodes, speeds_at_nodes, x_wanted):   # ln e, ln P_max, ln t_c: one spline, 3 columns
        at = _law_impacts(params, speeds_at_nodes)
        out[where] = np.exp(make_interp_spline(x_nodes, np.log(np.column_stack([at[n] for n in names])),
                                               k=SPLINE_DEGREE)(x_wanted))

    elastic = speeds <= v_Y
    if elastic.any():
        nodes = np.geomspace(speeds[0], v_Y, ELASTIC_NODES)
        interpolate(elastic, np.log(nodes), nodes, np.log(speeds[elastic]))
    if not elastic.all():
        u_max = math.sqrt(math.log(speeds[-1] / v_Y))
        u = np.linspace(0.0, u_max, max(int(math.ceil(NODES_PER_UNIT_U * u_max)) + 1, 4 * SPLINE_DEGREE))
        interpolate(~elastic, u, v_Y * np.exp(u**2), np.sqrt(np.log(speeds[~elastic] / v_Y)))
    return {name: out[:, k] for k, name in enumerate(names)}


def predict_impacts(params: VZParams, v_in) -> dict:
    """e [-], P_max [N], contact_time [s] of sphere-on-flat impacts at ``v_in`` [m/s] (module doc:
    the law at each distinct v_in, interpolated beyond ``EXACT_SPEEDS`` of them)."""
    v_in = np.asarray(v_in, dtype=float)
    speeds, inverse = np.unique(v_in, return_inverse=True)
    if speeds.size == v_in.size and speeds.size <= EXACT_SPEEDS:
        return _law_impacts(params, v_in)
    at = _law_impacts(params, speeds) if speeds.size <= EXACT_SPEEDS else _interpolated_impacts(params, speeds)
    return {name: y[inverse.reshape(v_in.shape)] for name, y in at.items()}


def drive_along(params: VZParams, approach: np.ndarray) -> np.ndarray:
    """The vz law's force [N] along one contact's approach history [m], every row at once
    (module doc): the virgin contact loaded to the running maximum, then set to each row."""
    law = get_law("vz")
    turning = np.maximum.accumulate(np.maximum(approach, 0.0))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RangeWarning)
        at_turning, loaded = law.force(turning, law.initial_state(approach.size), params)
        force, _ = law.force(approach, loaded, params)
    return np.where(approach >= turning, at_turning, force)


def predict_forces(params: VZParams, forces: ForceApproachData) -> list[np.ndarray]:
    """The law's force [N] along each test's measured approach (a virgin contact per test)."""
    return [drive_along(params, approach) for _, approach, _ in forces.tests]


def impact_residuals(data: Measurements, predicted: dict) -> dict[str, np.ndarray]:
    """The drop tests' relative residuals, e and (where measured) P_max, contact_time, dent and radius,
    of a law's predictions at the measured v_in (arrays by name)."""
    out = {"e": predicted["e"] / data.impacts.e - 1.0}
    for name in ("P_max", "contact_time", "dent", "radius"):
        measured = getattr(data.impacts, name)
        if measured is not None and np.isfinite(measured).any():
            seen = np.isfinite(measured)
            out[name] = predicted[name][seen] / measured[seen] - 1.0
    return out


def relative_residuals(data: Measurements, params: VZParams, impacts: dict | None = None) -> dict[str, np.ndarray]:
    """Per group (e, P_max, contact_time, force): the relative residuals of the law (module doc).
    ``impacts``: the law's predictions at the measured v_in (default: :func:`predict_impacts`)."""
    out = {}
    if data.impacts is not None:
        out.update(impact_residuals(data, predict_impacts(params, data.impacts.v_in) if impacts is None else impacts))
    if data.forces is not None:
        floor = data.forces.force_floor
        predicted = predict_forces(params, data.forces)
        out["force"] = np.concatenate([(p - f) / np.maximum(np.abs(f), floor)
                                       for p, (_, _, f) in zip(predicted, data.forces.tests)])
    return out
