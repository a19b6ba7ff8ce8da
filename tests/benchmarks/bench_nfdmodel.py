"""Benchmark of the runtime model (a script that prints a table; not collected by pytest).

    .venv/bin/python tests/benchmarks/bench_nfdmodel.py [--contacts 1000000] [--repeats 5]

1. Force evaluation for N contacts with random histories, `vz` against Hertz in the same run, on
   both backends (the compiled kernel "native" and the numpy reference; nfdmodel.backend).
   Baselines: numpy's fastest Hertz, k d sqrt(d) in three array operations, and the native
   `hertz` law. Targets: native vz step <= 1.5x numpy's k d sqrt(d) and <= 2x native
   hertz. Histories: turning points delta_max log-uniform in [2, 100] delta_Y
   (every contact has yielded). Then one DEM-like step: a fraction f of the contacts loads
   beyond its turning point by a relative increment uniform in (0, 1e-3] (plastic loading: a
   Newton solve), the others unload/reload below it (uniform in [delta_res, delta_max]) or are
   separated (10 %). The table scans f; the "jump" row draws the new approach anywhere in
   [0, 2 delta_max] (large jumps, poor Newton start). Timed per scenario, in the same run:
   hertz `force`; vz pure `force` (step + a copying commit: every history array is copied as
   soon as one turning point moves); vz `step` + in-place `commit` (what a DEM loop that owns
   its history does; the contacts it moved are restored, untimed, before each repeat). Each is
   timed over --repeats back-to-back runs (best of), hertz first, as before. Newton iterations
   per plastically loading contact: mean and max.
   Memory floor: the bytes a step must move per contact (module constants below: what each
   pass reads and writes, float64 and int64) divided by the machine's bandwidth, measured in the
   same run as a large array copy; "floor x" is that time over numpy's k d sqrt(d), the ratio no
   kernel with this data layout (separate history arrays, a sparse update, then the commit)
   can beat. The floor counts 8 bytes per sparse access; memory moves 64-byte lines, so at low
   loading fractions the sorted updates touch a larger share of the history (column "lines": the
   fraction of cache lines a sparse pass over n contacts touches, 1 - (1 - f)^8).
   Solve: the compiled batch solve of the loading contacts alone (nfd_vz_load with its gather and
   scatter, what the step adds to the unloading pass), ns per loading contact: the arithmetic,
   which is what a jump adds to a step (6 evaluations of the residual and the explicit start
   instead of the 2 evaluations of a continuation).
2. The 10-velocity collision sweep (0.02..0.2 m/s, dt = 1e-6 s, reference case) per law
   (target: <= 1 s).
"""
from __future__ import annotations

import argparse
import time
import warnings
from dataclasses import fields

import numpy as np

from nfdmodel import RangeWarning, VZParams, VZState, backend, collide, get_law, native, vz_newton_iterations
from nfdmodel.native import _native

# Bytes per contact of one vz step + in-place commit (float64 / int64 = 8 bytes):
UNLOADING_BYTES = 8 * (4 + 2)     # read delta, delta_res, K_u, delta_max; write force, index
# per contact that loads: gather delta and a_e_max (2), write the 5 trial fields (5), the solve's
# passes (read 2 write 3; read 2; read 2 write 4; read 1), scatter the force with the statistics
# (read index, P, a_e; write force: 4), the commit (read index and 5 fields, read-modify-write 5
# history arrays at random positions: 6 + 10)
LOADING_BYTES = 8 * (2 + 5 + (5 + 2 + 6 + 1) + 4 + 6 + 10)
HERTZ_BYTES = 8 * 6                # k d sqrt(d): three passes, each reads 8 and writes 8 bytes
DOUBLES_PER_LINE = 8               # a 64-byte cache line


def best_time(function, repeats: int, setup=None) -> float:
    """Shortest wall time of ``function(*setup())`` over ``repeats`` back-to-back runs; setup is
    not timed."""
    best = np.inf
    for _ in range(repeats):
        arguments = setup() if setup is not None else ()
        started = time.perf_counter()
        function(*arguments)
        best = min(best, time.perf_counter() - started)
    return best


def random_histories(params, n: int, loading_fraction: float | None, rng):
    """A vz history for n yielded contacts (each loaded to its turning point) and a new approach."""
    law = get_law("vz")
    pair = params.pair
    delta_max = pair.delta_Y * np.exp(rng.uniform(np.log(2.0), np.log(100.0), n))
    _, state = law.force(delta_max, law.initial_state(n), params)
    if loading_fraction is None:                       # "jump"
        delta = delta_max * rng.uniform(0.0, 2.0, n)
    else:
        delta = state.delta_res + (delta_max - state.delta_res) * rng.uniform(0.0, 1.0, n)
        loading = rng.random(n) < loading_fraction
        delta[loading] = delta_max[loading] * (1.0 + rng.uniform(1e-9, 1e-3, loading.sum()))
        separated = ~loading & (rng.random(n) < 0.1)
        delta[separated] = state.delta_res[separated] - 1e-9
    return state, delta


def bandwidth(n: int, repeats: int) -> float:
    """Bytes per second of a large copy (read + write), the machine's streaming bandwidth."""
    source, target = np.ones(4 * n), np.empty(4 * n)
    return 2 * source.nbytes / best_time(lambda: np.copyto(target, source), repeats)


def solve_time(params, state, delta, repeats: int) -> float:
    """Best time [s] of the compiled batch solve of the loading contacts (delta > delta_max) alone:
    nfd_vz_load with its gather of delta, a_e_max and scatter of the forces (NaN on numpy)."""
    if not native.active():
        return float("nan")
    index = np.flatnonzero(delta > state.delta_max).astype(np.int64)
    outputs = [np.empty(index.size) for _ in range(5)]
    force = np.empty(delta.size)
    kernel = native.kernel_params(params.pair, params.Ca, params.Kc, params.window_force, c1=params.c1)
    a_e_max = np.ascontiguousarray(state.a_e_max)
    return best_time(lambda: _native.load(native.LAW_CODES["vz"], kernel, index, delta, a_e_max, force, *outputs),
                     repeats)


def numpy_hertz(delta, k):
    """numpy's fastest Hertz force: k d sqrt(d), three array operations."""
    force = np.sqrt(delta)
    np.multiply(force, delta, out=force)
    return np.multiply(force, k, out=force)


def force_benchmark(n: int, repeats: int, loading_fraction, rng, bytes_per_second: float) -> dict:
    params = VZParams.reference()
    vz, hertz = get_law("vz"), get_law("hertz")
    state, delta = random_histories(params, n, loading_fraction, rng)
    positive = np.maximum(delta, 0.0)
    hertz_state = hertz.initial_state(n)
    owned = VZState(**{f.name: getattr(state, f.name).copy() for f in fields(state)})  # to mutate
    committed = [np.empty(0, dtype=np.int64)]

    def fresh_history():
        """Untimed: undo the previous commit (only the contacts it touched, so that the caches
        are not flushed by a full copy)."""
        index = committed[0]
        for f in fields(state):
            getattr(owned, f.name)[index] = getattr(state, f.name)[index]
        return ()

    def step_and_commit():
        force, update = vz.step(delta, owned, params)
        vz.commit(owned, update)
        committed[0] = update.index
        return force, update

    t_numpy_hertz = best_time(lambda: numpy_hertz(positive, params.pair.hertz_stiffness), repeats)
    t_hertz = best_time(lambda: hertz.force(delta, hertz_state, params.pair), repeats)
    t_pure = best_time(lambda: vz.force(delta, state, params), repeats)
    t_step = best_time(step_and_commit, repeats, fresh_history)
    t_solve = solve_time(params, state, delta, repeats)
    with native.use_backend("numpy"):
        t_numpy_step = best_time(step_and_commit, repeats, fresh_history)
    # check: same force and history both ways
    fresh_history()
    force_step, update = step_and_commit()
    force_pure, state_pure = vz.force(delta, state, params)
    assert np.array_equal(force_step, force_pure)
    assert all(np.array_equal(getattr(owned, f.name), getattr(state_pure, f.name)) for f in fields(state))
    iterations = vz_newton_iterations(delta, state, params)
    solved = iterations[iterations > 0]
    assert int(solved.max() if solved.size else 0) == update.newton_iterations
    loading = solved.size / n
    floor = n * (UNLOADING_BYTES + loading * LOADING_BYTES) / bytes_per_second
    return {"scenario": "jump" if loading_fraction is None else f"f={loading_fraction:g}",
            "n": n, "numpy_hertz_ms": 1e3 * t_numpy_hertz, "hertz_ms": 1e3 * t_hertz, "pure_ms": 1e3 * t_pure,
            "step_ms": 1e3 * t_step, "numpy_step_ms": 1e3 * t_numpy_step,
            "step_over_numpy_hertz": t_step / t_numpy_hertz, "step_over_hertz": t_step / t_hertz,
            "numpy_step_over_numpy_hertz": t_numpy_step / t_numpy_hertz,
            "bytes_per_contact": UNLOADING_BYTES + loading * LOADING_BYTES, "floor_ms": 1e3 * floor,
            "floor_over_numpy_hertz": floor / t_numpy_hertz,
            "pure_ratio": t_pure / t_hertz, "step_ratio": t_step / t_hertz,
            "plastic_loading_fraction": solved.size / n,
            "newton_mean": float(solved.mean()) if solved.size else 0.0,
            "newton_max": update.newton_iterations,
            "lines_touched": 1.0 - (1.0 - loading) ** DOUBLES_PER_LINE,
            "solve_ns_per_loading": 1e9 * t_solve / solved.size if solved.size else float("nan")}


def collision_benchmark(repeats: int) -> list[dict]:
    params = VZParams.reference()
    velocities = np.linspace(0.02, 0.2, 10)
    rows = []
    for law in ("vz", "thornton", "hertz", "walton-braun"):
        t = best_time(lambda: collide(law, params, velocities, dt=1e-6), repeats)
        result = collide(law, params, velocities, dt=1e-6)
        rows.append({"law": law, "seconds": t, "steps": result.steps,
                     "max_newton": result.max_newton_iterations})
    return rows


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--contacts", type=int, default=1_000_000)
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--seed", type=int, default=0)
    ns = parser.parse_args(argv)
    # the histories go to 100 delta_Y (~800 P_Y), beyond the paper constants' window on purpose:
    # the window check itself is timed (it is part of law.step), its warning is not printed
    warnings.simplefilter("ignore", RangeWarning)
    rng = np.random.default_rng(ns.seed)
    speed = bandwidth(ns.contacts, ns.repeats)
    print(f"Force evaluation, {ns.contacts:,} contacts, best of {ns.repeats}; backend {backend()}; "
          f"copy bandwidth {speed / 1e9:.1f} GB/s")
    print("  k d sqrt(d) = numpy's fastest Hertz; hertz = the native hertz law's force; pure = vz force")
    print("  (step + copying commit); step = vz step + in-place commit, native and numpy kernels;")
    print("  floor = bytes per contact / bandwidth (targets: step <= 1.5x k d sqrt(d), <= 2x hertz);")
    print("  lines = share of cache lines a sparse pass touches; solve = compiled batch solve alone,")
    print("  ns per plastically loading contact")
    print(f"{'scenario':>9} {'kdsqrt ms':>9} {'hertz ms':>9} {'pure ms':>8} {'step ms':>8} {'numpy ms':>9} "
          f"{'step/kdsqrt':>11} {'step/hertz':>10} {'numpy/kdsqrt':>12} {'B/contact':>9} {'floor x':>8} "
          f"{'lines':>6} {'plastic':>8} {'Newton':>7} {'max':>4} {'solve ns':>8}")
    for loading_fraction in (0.0, 0.01, 0.05, 0.1, 0.2, 0.3, 0.5, None):
        r = force_benchmark(ns.contacts, ns.repeats, loading_fraction, rng, speed)
        print(f"{r['scenario']:>9} {r['numpy_hertz_ms']:9.2f} {r['hertz_ms']:9.2f} {r['pure_ms']:8.2f} "
              f"{r['step_ms']:8.2f} {r['numpy_step_ms']:9.2f} {r['step_over_numpy_hertz']:11.2f} "
              f"{r['step_over_hertz']:10.2f} {r['numpy_step_over_numpy_hertz']:12.2f} {r['bytes_per_contact']:9.0f} "
              f"{r['floor_over_numpy_hertz']:8.2f} {r['lines_touched']:6.2f} "
              f"{100 * r['plastic_loading_fraction']:7.1f}% {r['newton_mean']:7.2f} {r['newton_max']:4d} "
              f"{r['solve_ns_per_loading']:8.1f}")
    print()
    print(f"Collision sweep, 10 velocities 0.02..0.2 m/s, dt = 1e-6 s, backend {backend()} (target <= 10 ms)")
    print(f"{'law':>13} {'seconds':>8} {'steps':>6} {'max Newton':>11}")
    for r in collision_benchmark(max(1, ns.repeats // 2)):
        print(f"{r['law']:>13} {r['seconds']:8.3f} {r['steps']:6d} {r['max_newton']:11d}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
