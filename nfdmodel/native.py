"""Which kernel runs the laws: the compiled nfd_kernel.c ("native") or the numpy reference.

nfdmodel/nfd_kernel.c (one dependency-free C99 source, also used by C/C++ DEM codes and the
LAMMPS plugin) is built at install time into ``nfdmodel._native`` when a C compiler is present.
It is then the default; ``NFDCAL_BACKEND=numpy`` in the environment when nfdmodel is imported
forces the numpy kernels (the reference it is tested against, and the fallback when it is not
built). The environment is read once, at import; :func:`use_backend` switches this module's
selection for a block (tests, benchmarks) and never touches ``os.environ``, so child processes
inherit the environment unchanged. The laws call :func:`turning_point_step` /
:func:`hertz_forces` of this module when :func:`active` is true; they validate their arguments
first, exactly as on the numpy path, so bad input gets the same messages on both.
"""
from __future__ import annotations

import contextlib
import os
from typing import NamedTuple

import numpy as np

from .history import HistoryUpdate, check_force, empty_update, field_names
from .limits import LAW_CODES

try:
    from . import _native
    _MISSING = ""
except ImportError as exc:           # not built: no compiler at install time, or a wheel without it
    _native = None
    _MISSING = f"the compiled kernel nfdmodel._native is not built ({exc})"

_STEPS_EXCEEDED = -10
_FORCED_NUMPY = os.environ.get("NFDCAL_BACKEND", "").strip().lower() == "numpy"   # read once
# The selection: whether the compiled kernel runs, and why (backend_info); use_backend swaps it.
_selection = {"active": _native is not None and not _FORCED_NUMPY,
              "why": "forced by NFDCAL_BACKEND=numpy" if _FORCED_NUMPY else ""}


def backend() -> str:
    """"native" (the compiled nfd_kernel.c) or "numpy" (the reference kernels)."""
    return "native" if active() else "numpy"


def backend_info() -> str:
    """Why this backend: built or not, forced by NFDCAL_BACKEND or selected by use_backend."""
    if _native is None:
        return f"numpy: {_MISSING}; install a C compiler and the Python headers, then reinstall nfdcal"
    if not _selection["active"]:
        return f"numpy: {_selection['why']} (the compiled kernel is built)"
    return f"native: the compiled kernel {os.path.basename(_native.__file__)} (NFDCAL_BACKEND=numpy forces numpy)"


@contextlib.contextmanager
def use_backend(name: str):
    """Within the block the laws run on ``name`` ("native" or "numpy"), in this process only
    (os.environ is not touched). ValueError if the native kernel is asked for and not built."""
    if name not in ("native", "numpy"):
        raise ValueError(f"backend out of range: 'native' or 'numpy', got {name!r}")
    if name == "native" and _native is None:
        raise ValueError(f"backend 'native' is not available: {_MISSING}")
    saved = dict(_selection)
    _selection.update(active=name == "native", why=f"selected by use_backend({name!r})")
    try:
        yield
    finally:
        _selection.update(saved)


def available_backends() -> tuple[str, ...]:
    """The backends this install can run: ("native", "numpy") or ("numpy",)."""
    return ("numpy",) if _native is None else ("native", "numpy")


def active() -> bool:
    """True when the laws run on the compiled kernel (module doc)."""
    return _selection["active"]


def kernel_params(pair, Ca: float = 0.0, Kc: float = 0.0, window_P_max: float = float("inf"),
                  K1: float = 0.0, K2: float = 0.0, c1: float = 0.0) -> tuple:
    """The nfd_params struct as the binding takes it (the pair's values computed once in Python,
    so both kernels start from the same numbers)."""
    return (pair.R_star, pair.E_star, pair.P_Y, pair.delta_Y, pair.a_Y, pair.p_Y, pair.hertz_stiffness,
            float(Ca), float(Kc), float(window_P_max), float(K1), float(K2), float(c1), pair.P_Y ** (1.0 / 3.0))


def _contiguous(array) -> np.ndarray:
    return np.ascontiguousarray(array, dtype=np.float64)


def law_loading(name: str, params: tuple):
    """The compiled virgin-curve loading of law ``name`` (its NFD_LAW_* code, nfd_limits.h) with
    the nfd_params tuple ``params`` (:func:`kernel_params`), for :func:`turning_point_step`."""
    code = LAW_CODES[name]

    def load(index, delta, state, force, outputs):
        a_e_max = _contiguous(state.a_e_max) if hasattr(state, "a_e_max") else delta   # vz's Newton start
        return _native.load(code, params, index, delta, a_e_max, force, *outputs)

    return load


def kernel_table(params) -> tuple:
    """The tables as the binding takes them: (x, f, g) of a VZTableParams (law vz-table), and
    (x, f, g, x_unload, dent, exponent) of a VZUnloadParams (law vz-unload)."""
    columns = [params.x, params.f, params.g]
    if hasattr(params, "x_unload"):
        columns += [params.x_unload, params.dent, params.exponent]
    return tuple(_contiguous(column) for column in columns)


def table_loading(params: tuple, table: tuple):
    """The compiled loading of the vz-table or vz-unload law: nfd_params ``params`` and the
    tables ``table`` (:func:`kernel_table`), for :func:`turning_point_step`."""

    def load(index, delta, state, force, outputs):
        return _native.load_table(params, table, index, delta, _contiguous(state.P_max), force, *outputs)

    return load


def turning_point_step(load, delta, state, pair, three_halves: bool):
    """The compiled twin of nfdmodel.turning_point.turning_point_step, ``load`` the law's loading
    (:func:`law_loading`, :func:`table_loading`): (P [N], HistoryUpdate, loading statistics
    (largest Newton count, beyond-window count, largest P_max [N], position of the widest
    contact, its radius [m])). A history with an ``unloading_exponent`` (vz-unload) unloads with
    each contact's exponent, which the kernel returns in the a_e_max slot."""
    n = delta.shape[0]
    force = np.empty(n)
    index = np.empty(n, dtype=np.int64)
    exponent = getattr(state, "unloading_exponent", None)
    own = () if exponent is None else (_contiguous(exponent),)
    k, finite = _native.unload(three_halves, delta, _contiguous(state.delta_res), _contiguous(state.unloading_stiffness),
                              _contiguous(state.delta_max), force, index, *own)
    statistics = (0, 0, 0.0, -1, -1.0, 0.0)
    if k == 0:
        update = empty_update(state, n)
    else:
        index = index[:k].copy()
        fifth = "a_e_max" if exponent is None else "unloading_exponent"
        values = {name: np.empty(k) for name in ("delta_max", "P_max", "delta_res", "unloading_stiffness", fifth)}
        outputs = (values["delta_max"], values["P_max"], values["delta_res"], values["unloading_stiffness"],
                   values[fifth])
        statistics = load(index, delta, state, force, outputs)
        finite += statistics[5]          # 0.0 when every force is finite, else inf or NaN
        names = field_names(type(state))
        update = HistoryUpdate(index, type(state)(**{name: values[name] for name in names}), n, int(statistics[0]))
    check_force(force, delta, pair, float(finite))
    return force, update, statistics


def hertz_forces(delta, pair) -> np.ndarray:
    """k_H <delta>^(3/2) [N] per contact, with the overflow check of the numpy path."""
    force = np.empty(delta.shape[0])
    total = _native.hertz(delta, pair.hertz_stiffness, force)
    return check_force(force, delta, pair, float(total))


class RateKernel(NamedTuple):
    """The rate-aware law as the binding takes it (nfd_rate.h): the base law's NFD_LAW_* code, its nfd_params
    tuple (:func:`kernel_params`, R = 1), its tables (:func:`kernel_table`; None for vz) and ``rate`` =
    (NFD_RATE_* code, first constant, second constant, c) of nfd_rate_init."""

    base_law: int
    params: tuple
    table: tuple | None
    rate: tuple


RATE_FIELDS = ("delta_max", "P_max", "delta_res", "unloading_stiffness", "a_e_max", "rate_factor")
RELAXING_FIELDS = RATE_FIELDS + ("strain_rate_per_speed", "loading_work")       # the relaxing law's history


def rate_step(kernel: RateKernel, m_star: float, delta, velocity, state, k: float = 0.0, stiffness: float = 0.0):
    """nfd_rate_step of every contact (the rate-aware law's history ``state``, the normal approach speeds
    ``velocity`` [m/s] per contact, read where a contact first touches; the pair's reduced mass m_star
    [kg]), or with ``k`` > 0 nfd_rate_relaxing_step (the relaxing law's history, element stiffness ``k`` and
    K = k E*/sigma_Y ``stiffness``; the speeds read where a contact loads): (P [N], index of the contacts whose
    history changed, {field: their new values} (RATE_FIELDS, and RELAXING_FIELDS with k), status, largest Newton
    count, beyond-window count, largest P_max [N] at R = 1). A negative status (the first failing contact's code)
    leaves the outputs incomplete."""
    n = delta.shape[0]
    fields = RELAXING_FIELDS if k else RATE_FIELDS
    force = np.empty(n)
    index = np.empty(n, dtype=np.int64)
    values = {name: np.empty(n) for name in fields}
    # the fixed form: one zero input and one scratch output stand for the relaxing form's two extra fields
    unused, scratch = (None, None) if k else (np.zeros(n), np.empty(n))
    inputs = [_contiguous(getattr(state, name)) if name in fields else unused for name in RELAXING_FIELDS]
    outputs = [values[name] if name in fields else scratch for name in RELAXING_FIELDS]
    count, status, _, iterations, beyond, largest = _native.rate_step(
        kernel.base_law, kernel.params, kernel.table, kernel.rate, float(k), float(stiffness), float(m_star),
        _contiguous(delta), _contiguous(velocity), *inputs, force, index, *outputs)
    return (force, index[:count].copy(), {name: v[:count].copy() for name, v in values.items()}, status, iterations,
            beyond, largest)


def collide(name: str, kernel, v_in, dt: float, mass: float, max_steps: int, explain) -> dict:
    """The leap-frog impacts of nfdmodel.collision in C, every velocity in one call: the same
    per-velocity results as collision._time_loop (history not recorded). ``kernel``: the law's
    nfd_params tuple (:func:`kernel_params`); ``explain(delta, v_in)``: the law's numpy step at one
    approach [m] of the impact at v_in [m/s], called where the compiled loop stopped so that its
    ValueError names the cause in the numpy path's words. A :class:`RateKernel`: the rate-aware law
    (nfd_rate_step, m* = ``mass``), whose R per velocity the result holds as "rate_factor"."""
    v_in = np.ascontiguousarray(v_in, dtype=np.float64)
    out = {key: np.zeros(v_in.size) for key in ("v_out", "contact_time", "loading_area", "unloading_area", "P_max",
                                                "delta_max", "delta_res")}
    code, rate = LAW_CODES.get(name), ()
    if isinstance(kernel, RateKernel):
        out["rate_factor"] = np.zeros(v_in.size)
        code, kernel, rate = kernel.base_law, kernel.params, (kernel.table, kernel.rate, out["rate_factor"])
    steps, iterations, status, failed_at, failed_delta = _native.collide(
        code, kernel, v_in, float(dt), float(mass), int(max_steps),
        out["v_out"], out["contact_time"], out["loading_area"], out["unloading_area"], out["P_max"],
        out["delta_max"], out["delta_res"], *rate)
    if status == _STEPS_EXCEEDED:
        raise ValueError(f"max_steps = {max_steps} reached before separation at v_in = {v_in[failed_at]:g} m/s: "
                         f"increase max_steps or dt (dt = {dt:g} s)")
    if status < 0:          # a contact radius at R*, or an overflow: the numpy step says which, in its words
        explain(failed_delta, v_in[failed_at])
        raise ValueError(f"delta out of range at delta = {failed_delta:g} m (v_in = {v_in[failed_at]:g} m/s)")
    return {**out, "steps": int(steps), "max_iterations": int(iterations), "history": None}
