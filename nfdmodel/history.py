"""Per-contact history of the runtime laws, the sparse trial update of a step, and its commit.

MercuryDPM style: a step computes the force and a TRIAL history without touching the state;
the caller then commits it, in place (``commit``: a DEM code that owns its arrays) or into a copy
(``step_and_commit``: the pure ``(delta, state, params) -> (P, new_state)`` form of every law).
Histories are frozen dataclasses of named float64 arrays, one entry per contact [SI]. This
module also checks the arguments every law shares (approaches, forces, states).
"""
from __future__ import annotations

import math
from dataclasses import dataclass, fields
from functools import lru_cache

import numpy as np

from .materials import ContactPair
from .validation import check_real


@dataclass(frozen=True)
class HertzState:
    """Hertz contact has no history; ``n`` is the number of contacts."""

    n: int

    @classmethod
    def virgin(cls, n: int) -> "HertzState":
        return cls(contact_count(n))


@dataclass(frozen=True)
class TurningPointHistory:
    """Per-contact history of an elastoplastic law [SI].

    delta_max [m]: largest approach so far (turning point); P_max [N]: force there;
    delta_res [m]: approach at which the unloading curve through (delta_max, P_max) reaches 0
    (residual indentation; 0 while the contact never yielded); unloading_stiffness: the constant
    K_u of that curve, P = K_u <delta - delta_res>^n ([N/m^n]; each law's module states its K_u,
    e.g. vz's (4/3) E* C_Rmax^(3/2) sqrt(R*), paper eq. 3.22). Each law with a memory subclasses it
    in its own module (adding fields when it needs them).
    """

    delta_max: np.ndarray
    P_max: np.ndarray
    delta_res: np.ndarray
    unloading_stiffness: np.ndarray

    @classmethod
    def virgin(cls, n: int):
        n = contact_count(n)
        return cls(**{f.name: np.zeros(n) for f in fields(cls)})

    @property
    def n(self) -> int:
        return self.delta_max.shape[0]

    def updated(self, index, **values):
        """A new history with the contacts ``index`` moved to a new turning point (no mutation);
        ``values`` gives the new value of every field for those contacts."""
        out = {}
        for f in fields(self):
            array = getattr(self, f.name).copy()
            array[index] = values[f.name]
            out[f.name] = array
        return type(self)(**out)


@dataclass(frozen=True)
class HistoryUpdate:
    """The trial history of one step, sparse: only the contacts whose turning point moved.

    index: the contacts (positions 0..n-1 in the state, increasing, int64) that loaded beyond
    their turning point delta_max in this step, shape (k,);
    values: their new history, a state of the SAME class as the law's state (its
    TurningPointHistory subclass; named fields, [SI] as there) over those k contacts: contact
    index[i] gets values.<field>[i]; a HertzState(0) for hertz (no history);
    n: the number of contacts of the state the step was computed from;
    newton_iterations: the largest number of Newton iterations of the step (vz plastic loading,
    :func:`vz_plastic_solve`; 0 for the other laws and when no contact loads plastically);
    beyond_window: how many of the k contacts loaded beyond the calibrated window of the law's
    constants (vz with a stated window, :mod:`nfdmodel.window`; else 0), and
    largest_load_over_P_Y: the largest P_max / P_Y among them (0 when none).

    Made by :meth:`ContactLaw.step`; applied by :meth:`ContactLaw.commit` (in place) or
    :meth:`ContactLaw.committed` (copy). The contacts not in ``index`` keep their history.
    """

    index: np.ndarray
    values: object
    n: int
    newton_iterations: int = 0
    beyond_window: int = 0
    largest_load_over_P_Y: float = 0.0

    @property
    def size(self) -> int:
        """Number of contacts whose turning point moved (k)."""
        return int(self.index.shape[0])


_EMPTY_VALUES: dict = {}     # history class -> (read-only empty index, empty history): shared, never written


def empty_update(state, n: int) -> HistoryUpdate:
    cls = type(state)
    empty = _EMPTY_VALUES.get(cls)
    if empty is None:
        index = np.empty(0, dtype=np.int64)
        index.flags.writeable = False
        values = HertzState(0) if cls is HertzState else cls(**{name: index.astype(float) for name in
                                                                field_names(cls)})
        for name in field_names(cls):
            getattr(values, name).flags.writeable = False
        empty = _EMPTY_VALUES[cls] = (index, values)
    return HistoryUpdate(empty[0], empty[1], n, 0)


@lru_cache(maxsize=None)
def field_names(cls) -> tuple:
    """Names of the per-contact arrays of a history class (none for HertzState)."""
    return () if cls is HertzState else tuple(f.name for f in fields(cls))


def check_update(state, update) -> None:
    """A ValueError naming ``update`` when it does not belong to ``state`` (class, length, index)."""
    if not isinstance(update, HistoryUpdate):
        raise ValueError(f"update must be a HistoryUpdate (from ContactLaw.step), got {type(update).__name__}")
    if type(update.values) is not type(state):
        raise ValueError(f"update does not match state: update.values is a {type(update.values).__name__} "
                         f"but state is a {type(state).__name__} (commit an update to the state of the "
                         f"law that computed it)")
    n = state.n
    if update.n != n:
        raise ValueError(f"update does not match state: update was computed for {update.n} contacts "
                         f"but state holds {n}")
    index = update.index
    if not (isinstance(index, np.ndarray) and index.ndim == 1 and index.dtype.kind in "iu"):
        raise ValueError(f"update.index must be a 1-d integer array of contact positions, got "
                         f"{type(index).__name__} {getattr(index, 'dtype', '')}")
    k = index.shape[0]
    if isinstance(state, HertzState):
        if k:
            raise ValueError(f"update does not match state: a Hertz contact has no history, but "
                             f"update.index holds {k} contacts")
        return
    for name in field_names(type(state)):
        values = getattr(update.values, name)
        if not (isinstance(values, np.ndarray) and values.shape == (k,)):
            raise ValueError(f"update does not match state: update.index has {k} contacts but "
                             f"update.values.{name} has shape {np.shape(values)}")
    if k and not (0 <= int(index.min()) and int(index.max()) < n):
        raise ValueError(f"update.index out of range: contact positions must be in 0..{n - 1} "
                         f"(state holds {n} contacts), got {int(index.min())}..{int(index.max())}")


def apply_update(state, update: HistoryUpdate, copy: bool):
    """Write ``update`` (checked by the caller) into ``state`` (in place) or into a copy of it;
    returns the new state (``state`` itself when the update is empty)."""
    if update.index.shape[0] == 0:
        return state
    names = field_names(type(state))
    if copy:
        state = type(state)(**{name: getattr(state, name).copy() for name in names})
    index, values = update.index, update.values
    for name in names:
        getattr(state, name)[index] = getattr(values, name)
    return state


def contact_count(n) -> int:
    """n as a number of contacts (an integer >= 0), or a ValueError naming n."""
    value = check_real("n", n, low=0, low_inclusive=True, unit="(number of contacts)")
    if value != int(value):
        raise ValueError(f"n must be a whole number of contacts (>= 0), got {n!r}")
    return int(value)


def check_delta(delta, n_expected: int | None):
    """delta as a flat contiguous float64 array and its original shape; ValueError naming delta
    if it is not real, not finite or has the wrong number of contacts (checked before any
    force is computed: no floating-point warnings from bad input)."""
    delta = np.asarray(delta)
    if delta.dtype.kind not in "fiu":
        raise ValueError(f"delta must be a real array of approaches [m], got dtype {delta.dtype}")
    shape = delta.shape
    delta = np.ascontiguousarray(delta, dtype=np.float64).reshape(-1)
    # One cheap reduction first; the elementwise check only when something is off.
    if not math.isfinite(float(np.add.reduce(delta))) and not np.isfinite(delta).all():
        bad = np.flatnonzero(~np.isfinite(delta))
        raise ValueError(f"delta must be finite (no NaN or inf) approaches [m]: contact {bad[0]} is {delta[bad[0]]}"
                         f" ({bad.size} of {delta.size} contacts)")
    if n_expected is not None and delta.shape[0] != n_expected:
        raise ValueError(f"delta has {delta.shape[0]} contacts but the state holds {n_expected}")
    return delta, shape


def check_force(force, delta, pair: ContactPair, total: float | None = None):
    """Overlaps so large that the force overflows (delta ~ 1e100 m) give a ValueError naming
    delta, never inf or NaN in a result. One cheap reduction (or ``total``, a sum of values
    that includes every entry of force, computed by the caller); elementwise only on failure."""
    if total is None:
        total = float(np.add.reduce(force))
    if not math.isfinite(total) and not np.isfinite(force).all():
        worst = int(np.flatnonzero(~np.isfinite(force))[0])
        raise ValueError(f"delta out of range: the force overflows at delta = {delta[worst]:g} m "
                         f"(contact {worst}, delta/R* = {delta[worst] / pair.R_star:.3g}); overlaps "
                         f"this large are far outside any contact model")
    return force


def check_state(state, cls, law):
    if not isinstance(state, cls):
        raise ValueError(f"state for law '{law}' must be a {cls.__name__} "
                         f"(use get_law('{law}').initial_state(n)), got {type(state).__name__}")
    return state


def restore_shape(force, shape):
    """``force`` (flat, as the kernels compute it) in the shape of the caller's ``delta``."""
    return force.reshape(shape) if shape != force.shape else force


def step_and_commit(step, delta, state, params):
    """The pure form of a law: ``step`` (``(delta, state, params) -> (P, HistoryUpdate)``), then
    the update committed into a COPY of ``state``: (P [N], new_state); ``state`` is never
    modified (``new_state`` is ``state`` itself when no turning point moved)."""
    force, update = step(delta, state, params)
    return force, apply_update(state, update, copy=True)
