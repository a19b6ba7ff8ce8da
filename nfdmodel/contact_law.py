"""A contact law as one object: its kernel used two ways, and what is derived from it.

MercuryDPM style: compute the trial state, then commit it. ``law.step(delta, state, params) ->
(P, update)`` gives the force and the SPARSE trial history (a :class:`HistoryUpdate` holding only
the contacts whose turning point moved; ``state`` is not modified); ``law.commit(state, update)``
writes it into ``state`` IN PLACE, cost O(len(update.index)); ``law.force(delta, state, params)
-> (P, new_state)`` is the pure function, step + a copying commit. Both warn (one RangeWarning
per call, :mod:`nfdmodel.window`) when contacts of a fitted law load beyond the window its
constants were fitted on; ``law.step_function`` and ``law.force_function`` are the same kernels
without the warning. Derived per contact: the loading work W = integral_0^delta_max P d delta
[J], the dissipated energy W - P_max (delta_max - delta_res) / (n + 1) [J] (n the unloading
exponent, P = K_u <delta - delta_res>^n), contact radii [m] (:class:`ContactDetails`).

Each law module declares its ``LAW = ContactLaw(...)`` next to its kernel; :mod:`nfdmodel.registry`
lists them by name. SI units.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

import numpy as np

from .history import HertzState, HistoryUpdate, apply_update, check_state, check_update
from .materials import as_pair
from .turning_point import elastic_energy
from .window import warn_beyond_window


def plastic_radii(force, a_e, state, params):
    """(a_p, a_ep) [m] of a law whose parameters give the plastic radius a_p(P_max)
    (``params.plastic_radius``, frozen at the turning point on unloading, paper eq. 2.5):
    a_ep = a_e + a_p, the residual radius a_p,max after separation (a_e = 0)."""
    a_p = params.plastic_radius(state.P_max)
    return a_p, a_e + a_p


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
    state_type: type                   # the history class; state_type.virgin(n): n contacts never loaded
    loading_work_function: Callable    # (delta_max, P_max, params) -> work on the virgin curve [J]
    unloading_exponent: float          # n in P = P_max s^n on unloading (a history may carry its own: exponent_of)
    step_function: Callable            # (delta, state, params) -> (P, HistoryUpdate); the same kernel as force
    params_function: Callable          # params -> this law's validated parameters (ValueError naming params)
    radii_function: Callable | None = None   # (P, a_e, new_state, params) -> (a_p, a_ep) [m]; None: a_p = 0,
    #                                          a_ep = a_e, the Hertz radius at P
    fitted: bool = False               # constants fitted on a load window: window flags, domain a < R*
    collision_params: Callable | None = None  # params -> nfd_params tuple of the compiled collision loop;
    #                                           None: nfdmodel.collision runs its numpy loop
    takes_velocity: bool = False       # the kernels take velocity= (the normal approach speed [m/s]) and the
    #                                    loading work the history's rate_factor (nfdmodel.rate_aware)
    reference_function: Callable | None = None   # (params, v_in) -> CollisionReference; None: collision's own

    def step(self, delta, state, params, velocity=None):
        """Force P [N] (shape of ``delta``) and the trial history as a :class:`HistoryUpdate`
        (the contacts whose turning point moved and their new history), without committing it:
        ``state`` is not modified. ``P, update = law.step(delta, state, params)`` then
        ``law.commit(state, update)`` gives the same force and history as
        ``P, state = law.force(delta, state, params)``, bit for bit. One RangeWarning when
        contacts load beyond the calibrated window of the constants (``update.beyond_window``
        counts them; the kernel ``step_function`` counts without warning). ``velocity``: the normal
        approach speed [m/s] per contact, for a law that ``takes_velocity`` (ignored by the others).
        """
        force, update = self.step_function(delta, state, params, *self._velocity(velocity))
        if update.beyond_window:
            warn_beyond_window(self.name, update.beyond_window, update.largest_load_over_P_Y, params.window)
        return force, update

    def _velocity(self, velocity) -> tuple:
        """The extra argument of a kernel that takes the approach speed, () for the others."""
        return (velocity,) if self.takes_velocity else ()

    def force(self, delta, state, params, velocity=None):
        """The pure law: (P [N], new_state); ``state`` is never modified (``new_state`` is
        ``state`` itself when no turning point moved). :meth:`step` plus a copying commit, with
        its RangeWarning; ``force_function`` is the same kernel without the warning."""
        force, update = self.step(delta, state, params, velocity)
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
        return self.state_type.virgin(n)

    def params_from(self, params):
        """This law's parameter object from VZParams / ContactPair / its own parameters."""
        return self.params_function(params)

    def loading_work(self, delta_max, P_max, params):
        """Work done on the virgin loading curve up to (delta_max, P_max) [J]."""
        return self.loading_work_function(np.asarray(delta_max, float), np.asarray(P_max, float),
                                          self.params_from(params))

    def exponent_of(self, state):
        """n of each contact's unloading curve: the history's own ``unloading_exponent`` array
        where the law keeps one per contact (vz-unload), else the law's constant n."""
        return getattr(state, "unloading_exponent", self.unloading_exponent)

    def dissipated_energy(self, state, params):
        """Energy dissipated per contact so far [J]: loading work to the turning point minus the
        elastic energy the unloading curve returns, W(delta_max) - P_max (delta_max - delta_res)/(n+1);
        W the history's own ``loading_work`` where the law keeps one (a path-dependent virgin curve)."""
        if isinstance(state, HertzState):
            return np.zeros(state.n)
        work = getattr(state, "loading_work", None)     # a path-dependent law keeps its own (rate_relaxing)
        if work is None:
            work = self.loading_work_function(np.asarray(state.delta_max, float), np.asarray(state.P_max, float),
                                              self.params_from(params),
                                              *((state.rate_factor,) if self.takes_velocity else ()))
        returned = elastic_energy(state.P_max, state.delta_max, state.delta_res, self.exponent_of(state))
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
            elastic = elastic_energy(force, delta_flat, 0.0, self.unloading_exponent)
            return ContactDetails(force, a_e, zeros, a_e.copy(), zeros, elastic, zeros, new_state,
                                  np.zeros(force.shape, dtype=bool))
        elastic = elastic_energy(force, delta_flat, new_state.delta_res, self.exponent_of(new_state))
        beyond = new_state.P_max > p.window_force if self.fitted else np.zeros(force.shape, dtype=bool)
        if self.radii_function is None:     # no radius model: the Hertz radius at P
            a_p = np.zeros_like(force)
            a_ep = a_e.copy()
        else:
            a_p, a_ep = self.radii_function(force, a_e, new_state, p)
        return ContactDetails(force, a_e, a_p, a_ep, new_state.delta_res.copy(), elastic,
                              self.dissipated_energy(new_state, p), new_state, beyond)

    def contact_radius(self, delta, state, params):
        """Total contact radius a_ep [m] per contact (see :meth:`contact_state`)."""
        return self.contact_state(delta, state, params).a_ep
