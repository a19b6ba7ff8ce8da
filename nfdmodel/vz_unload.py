"""The vz-table loading curve with the FE's dent and unloading exponent (law name "vz-unload").

The vz-table law (nfdmodel.vz_table) unloads along a Hertz curve, exponent 3/2, whose curvature
C_R = g(x_m) is chosen so that the returned work, hence e, is the FE's; the FE unloads with an
exponent of 1.31-1.47 (Etsion, Kligerman & Kadin 2005, J. Appl. Mech. 72, 173, report the same),
so the dent and the unloading curve miss while e is right. This law keeps the loading structure
and takes the unloading from two more tables over the turning point x_m = P_max / P_Y:

    loading (x = P/P_Y):  delta / delta_Y = D(x) = (x^(1/3) + f(x))^2 / g(x)     (Hertz below P_Y)
    contact radius:       a = a_e(P) + a_Y f(x_m),  a_e(P) = (3 P R* / (4 E*))^(1/3)
    dent:                 delta_res = rho(x_m) delta_max,    rho(1) = 0,   0 <= rho < 1
    unloading/reloading:  P = P_max ((delta - delta_res) / (delta_max - delta_res))^m(x_m),
                          m(1) = 3/2,  m > 0;   P = 0 for delta <= delta_res
    returned work:        W_u = P_max (delta_max - delta_res) / (m + 1)
    e^2 = W_u / W_l,      W_l = integral_0^delta_max P d delta on the loading curve

f = a_p/a_Y and g = C_R are the vz-table law's tables (PCHIP; here fitted to the FE's contact
radius and loading curve: calib.fit.unload_fit), rho and m monotone piecewise-cubic (PCHIP)
interpolants of their values at the nodes ``x_unload`` (x_unload[0] = 1, where the contact is
Hertz's: rho = 0, m = 3/2), held at their last node's values beyond it. Below P_Y the law IS
Hertz's (delta_res = 0, m = 3/2: the FE's elastic unloading). The force is continuous at every
turning point (the curve passes through (delta_max, P_max)); reloading after a partial unload
retraces the curve up to the turning point and loads on the virgin curve beyond it; a constant
delta keeps the force. Admissible tables: D strictly increasing up to where the contact radius
reaches R* (vz-table's check) and no load-unload cycle returning more work than it took
(W_u <= W_l: e <= 1), checked when the parameters are built. The history stores
K_u = P_max / (delta_max - delta_res)^m and m per contact (VZUnloadState). This module is the
law as one unit (parameters, history, numpy kernel, ``LAW``); the scalar specification is
``nfdmodel.reference.vz_unload_step``; the compiled twin is nfd_unload.h (the native backend runs
it, the LAMMPS plugin's pair_style nfd/vz-unload and wall fixes too; the kernel keeps m in
nfd_history's a_e_max slot).
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from . import native
from .contact_law import ContactLaw, plastic_radii
from .hertz import hertz_kernel
from .history import (HistoryUpdate, TurningPointHistory, check_delta, check_force, check_state, empty_update,
                      restore_shape, step_and_commit)
from .pchip import pchip_evaluate, pchip_slopes
from .validation import check_real
from .vz_table import VZTableParams, checked_loading_update, compiled_table_step

HERTZ_EXPONENT = 1.5            # m at first yield: the elastic unloading of a Hertz contact


@dataclass(frozen=True)
class VZUnloadState(TurningPointHistory):
    """History of the vz-unload law: delta_max [m], P_max [N], delta_res [m],
    unloading_stiffness K_u [N/m^m] and unloading_exponent m [-] of the curve
    P = K_u <delta - delta_res>^m through the turning point (m = 0 for a virgin contact)."""

    unloading_exponent: np.ndarray


@dataclass(frozen=True)
class VZUnloadParams(VZTableParams):
    """The vz-unload law of a contact pair: the loading tables of :class:`VZTableParams` (x, f, g,
    window) and the unloading tables over the turning point, ``x_unload`` = P_max/P_Y (x_unload[0]
    = 1, increasing), ``dent`` = delta_res/delta_max (dent[0] = 0, each in [0, 1)) and
    ``exponent`` = m (exponent[0] = 3/2, each > 0) at those nodes."""

    x_unload: tuple = ()
    dent: tuple = ()
    exponent: tuple = ()
    _unload: dict = field(default=None, init=False, repr=False, compare=False)

    def __post_init__(self):
        columns = {}
        for name in ("x_unload", "dent", "exponent"):
            values = getattr(self, name)
            if isinstance(values, (str, bytes)) or not hasattr(values, "__len__"):
                raise ValueError(f"table {name} must be a list of numbers, got {values!r}")
            columns[name] = tuple(check_real(f"table {name}[{k}]", v) for k, v in enumerate(values))
            object.__setattr__(self, name, columns[name])
        n = len(columns["x_unload"])
        if n < 2 or len(columns["dent"]) != n or len(columns["exponent"]) != n:
            raise ValueError(f"table: x_unload, dent and exponent need the same length >= 2, got {n}, "
                             f"{len(columns['dent'])}, {len(columns['exponent'])}")
        x, rho, m = (np.array(columns[name]) for name in ("x_unload", "dent", "exponent"))
        if x[0] != 1.0 or rho[0] != 0.0 or m[0] != HERTZ_EXPONENT:
            raise ValueError(f"table out of range: the first unloading node is first yield: need x_unload[0] = 1, "
                             f"dent[0] = 0, exponent[0] = 1.5, got {x[0]:g}, {rho[0]:g}, {m[0]:g}")
        if not np.all(np.diff(x) > 0):
            raise ValueError("table x_unload out of range: node loads P_max/P_Y must increase strictly")
        if not np.all((rho >= 0.0) & (rho < 1.0)):
            raise ValueError(f"table dent out of range: delta_res/delta_max must be in [0, 1), got "
                             f"{rho.min():g}..{rho.max():g}")
        if not np.all(m > 0.0):
            raise ValueError(f"table exponent out of range: the unloading exponent must be > 0, got {m.min():g}")
        object.__setattr__(self, "_unload", {"x": x, "rho": rho, "m": m, "drho": pchip_slopes(x, rho),
                                             "dm": pchip_slopes(x, m)})
        super().__post_init__()      # the loading tables, then _check_admissible with the unloading

    @classmethod
    def from_table(cls, table: VZTableParams, x_unload, dent, exponent) -> "VZUnloadParams":
        """The loading tables of ``table`` with the given unloading tables."""
        return cls(table.pair, table.x, table.f, table.g, table.window, tuple(x_unload), tuple(dent),
                   tuple(exponent))

    def unloading_tables(self, x_max):
        """(rho, m) at the turning points x_m = P_max/P_Y (rho = 0, m = 3/2 at and below x = 1;
        held at the last node's values beyond it)."""
        u = self._unload
        at = np.clip(np.asarray(x_max, dtype=float), 1.0, u["x"][-1])
        rho = pchip_evaluate(u["x"], u["rho"], u["drho"], at)[0]
        m = pchip_evaluate(u["x"], u["m"], u["dm"], at)[0]
        return rho, m

    def _scaled_returned_work(self, x):
        """W_u / (P_Y delta_Y) from the turning point x: x D(x) (1 - rho(x)) / (m(x) + 1)."""
        rho, m = self.unloading_tables(x)
        return x * self.scaled_approach(x) * (1.0 - rho) / (m + 1.0)


def vz_unload_params(params) -> VZUnloadParams:
    """``params`` when it is a VZUnloadParams, else a ValueError naming params."""
    if not isinstance(params, VZUnloadParams):
        raise ValueError(f"params for law 'vz-unload' must be VZUnloadParams, got {type(params).__name__}")
    return params


def _loading(delta, state, index, params: VZUnloadParams):
    """New turning points of the contacts ``index`` loading on the virgin curve at ``delta``."""
    pair = params.pair
    P = hertz_kernel(delta, pair)
    delta_res = np.zeros_like(delta)
    stiffness = np.full_like(delta, pair.hertz_stiffness)
    exponent = np.full_like(delta, HERTZ_EXPONENT)
    plastic = np.flatnonzero(delta > pair.delta_Y)
    iterations = 0
    if plastic.size:
        start = np.maximum(state.P_max[index[plastic]] / pair.P_Y, 1.0)
        x, iterations = params.solve(delta[plastic] / pair.delta_Y, start)
        rho, m = params.unloading_tables(x)
        d = delta[plastic]
        d_res = np.minimum(rho * d, np.nextafter(d, 0.0))   # the curve drops to zero below delta_max
        P[plastic], delta_res[plastic], exponent[plastic] = x * pair.P_Y, d_res, m
        stiffness[plastic] = P[plastic] / (d - d_res) ** m      # through the turning point
    values = VZUnloadState(delta_max=delta, P_max=P, delta_res=delta_res, unloading_stiffness=stiffness,
                           unloading_exponent=exponent)
    return values, iterations


def vz_unload_step(delta, state: VZUnloadState, params: VZUnloadParams):
    """One vz-unload step without committing it: (P [N], HistoryUpdate) (module doc)."""
    vz_unload_params(params)
    check_state(state, VZUnloadState, "vz-unload")
    delta, shape = check_delta(delta, state.n)
    if native.active():
        force, update = compiled_table_step(delta, state, params)
        return restore_shape(force, shape), update
    pair = params.pair
    with np.errstate(over="ignore", invalid="ignore"):
        gap = np.maximum(delta - state.delta_res, 0.0)
        force = state.unloading_stiffness * gap ** state.unloading_exponent
        loading = np.flatnonzero(delta > state.delta_max)
        if loading.size:
            values, iterations = _loading(delta[loading], state, loading, params)
            force[loading] = values.P_max
            update = HistoryUpdate(loading, values, state.n, int(iterations))
        else:
            update = empty_update(state, state.n)
    check_force(force, delta, pair)
    return restore_shape(force, shape), checked_loading_update(update, params)


def vz_unload_force(delta, state: VZUnloadState, params: VZUnloadParams):
    """The pure vz-unload law: (P [N], new_state) (vz_unload_step + a copying commit)."""
    return step_and_commit(vz_unload_step, delta, state, params)


def vz_unload_loading_work(delta_max, P_max, params: VZUnloadParams):
    """Work on the virgin curve up to (delta_max, P_max) [J] (the vz-table curve's)."""
    return params.loading_work(delta_max, P_max)


LAW = ContactLaw("vz-unload", "the vz-table loading curve with the FE's dent and unloading exponent tables",
                 vz_unload_force, VZUnloadState, vz_unload_loading_work, HERTZ_EXPONENT, vz_unload_step,
                 params_function=vz_unload_params, radii_function=plastic_radii, fitted=True)
