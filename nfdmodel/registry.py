"""The laws by name: ``get_law("vz" | "hertz" | "thornton" | "walton-braun") -> ContactLaw``.

A ContactLaw bundles one law's kernel used two ways (MercuryDPM style: compute the trial state,
then commit it):

* ``law.step(delta, state, params) -> (P, update)``: the force and the SPARSE trial history, a
  :class:`HistoryUpdate` holding only the contacts whose turning point moved; ``state`` is not
  modified;
* ``law.commit(state, update)`` writes the update into ``state``'s arrays IN PLACE (the caller
  owns the state), cost O(len(update.index));
* ``law.force(delta, state, params) -> (P, new_state)``: the pure function, step + a copying
  commit.

Both warn (one RangeWarning per call, :mod:`nfdmodel.window`) when vz contacts load beyond the
window its constants were fitted on; ``law.step_function`` and ``law.force_function`` are the
same kernels without the warning (the count stays in ``update.beyond_window``).

``delta`` is the total approach ("overlap") of each contact [m], shape (n,), any float dtype;
``state`` the named per-contact history; ``P`` the normal force [N], float64, >= 0. In a DEM
loop that owns its history, ``P, update = law.step(delta, state, params); law.commit(state,
update)`` avoids copying the n-contact history whenever one contact loads plastically.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Callable

import numpy as np

from .hertz import hertz_force, hertz_step, hertz_work
from .history import (HertzState, HistoryUpdate, ThorntonState, VZState, WaltonBraunState, apply_update, check_state,
                      check_update, contact_count)
from .parameters import VZParams, as_pair
from .thornton import TINY, thornton_force, thornton_loading_work, thornton_step
from .vz import vz_force, vz_step
from .vz_curve import vz_loading_work
from .vz_table import VZTableParams, VZTableState, vz_table_force, vz_table_loading_work, vz_table_step
from .walton_braun import walton_braun_force, walton_braun_params, walton_braun_step
from .window import warn_beyond_window


@dataclass(frozen=True)
class ContactDetails:
    """Per-contact quantities on request [SI]: force P [N]; elastic contact radius a_e [m] (Hertz
    radius at P); plastic radius a_p [m]; total contact radius a_ep [m] (the residual a_p,max
    after separation for vz); delta_res [m]; elastic_energy [J] recoverable at the current state;
    dissipated_energy [J] so far; state: the trial history after this step; beyond_window: True
    where the contact's turning point lies beyond the calibrated window of the law's constants
    (vz with a stated window: P_max above the window's largest force; else False)."""

    force: np.ndarray
    a_e: np.ndarray
    a_p: np.ndarray
    a_ep: np.ndarray
    delta_res: np.ndarray
    elastic_energy: np.ndarray
    dissipated_energy: np.ndarray
    state: object
    beyond_window: np.ndarray


@dataclass(frozen=True)
class ContactLaw:
    """A named force law plus helpers (module doc):

    ``force(delta, state, params) -> (P, new_state)``  pure (``state`` never modified);
    ``step(delta, state, params) -> (P, update)``      force and sparse trial history, not committed;
    ``commit(state, update) -> state``                 writes the update into ``state`` in place.
    """

    name: str
    description: str
    force_function: Callable           # the pure kernel (delta, state, params) -> (P, new_state); no warnings
    state_type: type
    loading_work_function: Callable    # (delta_max, P_max, params) -> work on the virgin curve [J]
    unloading_exponent: float          # n in P = P_max s^n on unloading
    step_function: Callable            # (delta, state, params) -> (P, HistoryUpdate); the same kernel as force

    def step(self, delta, state, params):
        """Force P [N] (shape of ``delta``) and the trial history as a :class:`HistoryUpdate`
        (the contacts whose turning point moved and their new history), without committing it:
        ``state`` is not modified. ``P, update = law.step(delta, state, params)`` then
        ``law.commit(state, update)`` gives the same force and history as
        ``P, state = law.force(delta, state, params)``, bit for bit. One RangeWarning when
        contacts load beyond the calibrated window of the constants (``update.beyond_window``
        counts them; the kernel ``step_function`` counts without warning).
        """
        force, update = self.step_function(delta, state, params)
        if update.beyond_window:
            warn_beyond_window(self.name, update.beyond_window, update.largest_load_over_P_Y, params.window)
        return force, update

    def force(self, delta, state, params):
        """The pure law: (P [N], new_state); ``state`` is never modified (``new_state`` is
        ``state`` itself when no turning point moved). :meth:`step` plus a copying commit, with
        its RangeWarning; ``force_function`` is the same kernel without the warning."""
        force, update = self.step(delta, state, params)
        return force, apply_update(state, update, copy=True)

    def commit(self, state, update: HistoryUpdate):
        """Write ``update`` (from :meth:`step` on this ``state``) into ``state``'s arrays IN PLACE
        and return ``state``; cost O(update.size), nothing is copied.

        The caller owns ``state``: every other reference to it (e.g. a state kept from an
        earlier step, or the ``new_state`` that :meth:`force` returns unchanged when no turning
        point moved) sees the change. Use :meth:`committed` for a copy. An empty update is a
        no-op. ValueError naming ``update`` if it does not belong to ``state`` (other law's
        history class, other number of contacts, positions out of range) or naming ``state``
        if that is not this law's history.
        """
        check_state(state, self.state_type, self.name)
        check_update(state, update)
        return apply_update(state, update, copy=False)

    def committed(self, state, update: HistoryUpdate):
        """:meth:`commit` into a copy: the new history; ``state`` is not modified (it is returned
        itself when the update is empty). This is the commit :meth:`force` uses."""
        check_state(state, self.state_type, self.name)
        check_update(state, update)
        return apply_update(state, update, copy=True)

    def initial_state(self, n: int):
        """History of n virgin contacts (never loaded)."""
        if self.state_type is HertzState:
            return HertzState(contact_count(n))
        return self.state_type.virgin(n)

    def params_from(self, params):
        """This law's parameter object from VZParams / ContactPair / its own parameters."""
        if self.name == "vz":
            if not isinstance(params, VZParams):
                raise ValueError(f"params for law 'vz' must be VZParams, got {type(params).__name__}")
            return params
        if self.name == "vz-table":
            if not isinstance(params, VZTableParams):
                raise ValueError(f"params for law 'vz-table' must be VZTableParams, got {type(params).__name__}")
            return params
        if self.name == "walton-braun":
            return walton_braun_params(params)
        return as_pair(params, self.name)

    def loading_work(self, delta_max, P_max, params):
        """Work done on the virgin loading curve up to (delta_max, P_max) [J]."""
        return self.loading_work_function(np.asarray(delta_max, float), np.asarray(P_max, float),
                                          self.params_from(params))

    def dissipated_energy(self, state, params):
        """Energy dissipated per contact so far [J]: loading work to the turning point minus the
        elastic energy the unloading curve returns, W(delta_max) - P_max (delta_max - delta_res)/(n+1)."""
        if isinstance(state, HertzState):
            return np.zeros(state.n)
        work = self.loading_work(state.delta_max, state.P_max, params)
        returned = state.P_max * (state.delta_max - state.delta_res) / (self.unloading_exponent + 1.0)
        return np.maximum(work - returned, 0.0)

    def contact_state(self, delta, state, params) -> ContactDetails:
        """Force, radii, residual approach and energies per contact after this step."""
        p = self.params_from(params)
        force, new_state = self.force(delta, state, p)   # warns beyond the window, like step
        force = np.reshape(force, -1)
        pair = as_pair(p, self.name)
        a_e = np.asarray(pair.hertz_radius(force), dtype=float).reshape(-1)
        delta_flat = np.asarray(delta, dtype=float).reshape(-1)
        if isinstance(new_state, HertzState):
            zeros = np.zeros_like(force)
            elastic = 0.4 * force * np.maximum(delta_flat, 0.0)
            return ContactDetails(force, a_e, zeros, a_e.copy(), zeros, elastic, zeros, new_state,
                                  np.zeros(force.shape, dtype=bool))
        elastic = force * np.maximum(delta_flat - new_state.delta_res, 0.0) / (self.unloading_exponent + 1.0)
        beyond = np.zeros(force.shape, dtype=bool)
        if self.name in ("vz", "vz-table"):
            a_p = p.plastic_radius(new_state.P_max)
            a_ep = a_e + a_p                # after separation a_e = 0: residual radius a_p,max
            beyond = new_state.P_max > p.window_force
        elif self.name == "thornton":
            a_sq = np.where(new_state.P_max > pair.P_Y,
                            (2.0 * new_state.P_max + pair.P_Y) / (2.0 * math.pi * pair.p_Y), 0.0)
            a_star = np.sqrt(a_sq)
            s = force / np.maximum(new_state.P_max, TINY)
            a_ep = np.where(new_state.P_max > pair.P_Y, a_star * np.cbrt(s), a_e)  # a ~ P^(1/3) at fixed R_p
            a_p = np.maximum(a_ep - a_e, 0.0)
        else:                               # walton-braun has no radius model: Hertz radius at P
            a_p = np.zeros_like(force)
            a_ep = a_e.copy()
        return ContactDetails(force, a_e, a_p, a_ep, new_state.delta_res.copy(), elastic,
                              self.dissipated_energy(new_state, p), new_state, beyond)

    def contact_radius(self, delta, state, params):
        """Total contact radius a_ep [m] per contact (see :meth:`contact_state`)."""
        return self.contact_state(delta, state, params).a_ep


LAWS: dict[str, ContactLaw] = {
    "hertz": ContactLaw("hertz", "Hertz elastic contact (Johnson 1985)", hertz_force, HertzState,
                        hertz_work, 1.5, hertz_step),
    "vz": ContactLaw("vz", "Vu-Quoc & Zhang (1999) elastoplastic NFD model", vz_force, VZState,
                     vz_loading_work, 1.5, vz_step),
    "vz-table": ContactLaw("vz-table", "the NFD model with load-dependent a_p and C_R tables from the FE",
                           vz_table_force, VZTableState, vz_table_loading_work, 1.5, vz_table_step),
    "thornton": ContactLaw("thornton", "Thornton (1997) elastic-perfectly plastic contact",
                           thornton_force, ThorntonState,
                           lambda d, P, pair: thornton_loading_work(d, pair), 1.5, thornton_step),
    "walton-braun": ContactLaw("walton-braun", "Walton & Braun (1986) bilinear hysteretic spring",
                               walton_braun_force, WaltonBraunState,
                               lambda d, P, wb: 0.5 * wb.K1 * np.maximum(d, 0.0) ** 2, 1.0,
                               walton_braun_step),
}


def get_law(name: str) -> ContactLaw:
    """The force law called ``name``: one of 'hertz', 'vz', 'vz-table', 'thornton', 'walton-braun'."""
    if not isinstance(name, str) or name.strip().lower() not in LAWS:
        raise ValueError(f"law must be one of {', '.join(LAWS)}; got {name!r}")
    return LAWS[name.strip().lower()]
