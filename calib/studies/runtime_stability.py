"""results/stability/runtime_*: stability of the runtime laws and collisions on extreme cases.

Regenerate with ``nfdcal stability [--out DIR]`` (default DIR = results/stability; about 30 s on
one core). Files:

Every case runs on each backend of this install (the compiled kernel "native" and the numpy
reference; column ``backend``), and a case whose outcome differs between them is a failure.

* runtime_stability.csv   one row per case and backend: inputs, largest Newton iteration count, errors,
                          outcome ("ok", "warned: <TimeStepWarning>", "clear error: <message>",
                          or "FAIL: <why>", which must never appear);
* runtime_stability.json  stamp (commit, wall time), the summary (counts per outcome, largest
                          Newton count, worst errors per group) and the same rows.

Groups of cases (SI units; dimensionless groups P/P_Y, delta/delta_Y, Ca_hat, Kc_hat):

``force``      every law on overlaps delta / R* = 1e-15 .. 0.5 and on the vz loading curve up to
               P / P_Y = 1e6 (vz: less where its contact radius would reach R*, the end of its
               domain, where an overlap must be refused), in float64 and float32, for R = 1e-6 .. 10 m, nu = 0 .. 0.49,
               E / sigma_Y = 50 .. 5000 and (vz) Ca, Kc at 1e-3, 1 and 1e3 x the paper's values
               (Ca_hat, Kc_hat scaled). Errors: ``force_error`` = max |P(delta(P)) / P - 1| on
               the explicit loading curve (paper eq. 3.4, the Newton solve's accuracy);
               ``continuity_error`` = max |P - P_max| / P_max when the overlap stays at the
               turning point (unloading curve through it, paper 3.22), and after a half unload
               and a reload past it.
``collision``  sphere-on-flat impacts, v_in / v_Y = 0.1 .. 1e4, every law, extreme materials and
               Ca, Kc; dt = min(contact time / 200, unloading time / 20) from the estimate of
               :func:`nfdmodel.collision_reference`. Errors against that exact energy balance:
               ``e_velocity_error``, ``e_energy_error`` (relative), ``P_max_error`` (relative),
               ``contact_time_error`` (simulated vs estimated duration), ``energy_balance_error``
               = |(1/2) m* (v_in^2 - v_out^2) - dissipated energy of the final history| /
               ((1/2) m* v_in^2) (the simulation's own energy bookkeeping).
``dt``         the reference aluminium at R = 1 mm (contacts of microseconds), vz, three
               velocities: dt from 1e-9 s up to twice the leap-frog stability limit 2 t_unload / pi;
               rows with dt above the warning limit must carry the TimeStepWarning, the others
               must be accurate (errors < 1 %, else "FAIL: silently inaccurate"); dt at or beyond
               the stability limit must be refused ("clear error").

Bad parameter combinations (e.g. Kc at 1e3 x) must give "clear error" rows naming the
parameter and its admissible range; NaN, inf or any other exception is a FAIL.
"""
from __future__ import annotations

import math
import time
import warnings
from pathlib import Path

import numpy as np

from calib.output import RESULTS, stamp, stamp_comment, write_csv, write_json
from nfdmodel import (NEWTON_MAX_ITERATIONS, ContactPair, Material, TimeStepWarning, VZParams, collide,
                      collision_reference, get_law, native, vz_newton_iterations)

DEFAULT_OUT = RESULTS / "stability"
CSV_NAME = "runtime_stability.csv"
JSON_NAME = "runtime_stability.json"

RADII = (1e-6, 1e-3, 0.1, 10.0)                  # m
POISSON = (0.0, 0.3, 0.45, 0.49)
STRENGTH_RATIOS = (50.0, 700.0, 5000.0)          # E / sigma_Y
FACTORS_CA = (1e-3, 1.0, 1e3)                    # x the paper's Ca_hat
FACTORS_KC = (0.0, 1e-3, 1.0, 1e3)               # x the paper's Kc_hat
VELOCITY_RATIOS = (0.1, 1.0, 10.0, 100.0, 1e3, 1e4)   # v_in / v_Y
ACCURACY_LIMIT = 1e-2             # an unwarned collision must be this accurate (e, P_max)
CONTINUITY_LIMIT = 1e-12          # relative force jump allowed at a turning point (round-off)
YOUNG = 70e9                      # Pa; E / sigma_Y sets sigma_Y
DENSITY = 2699.0                  # kg/m^3

COLUMNS = ("backend", "group", "law", "R", "nu", "E_over_sigma_y", "Ca_factor", "Kc_factor", "Ca_hat",
           "Kc_hat", "dtype", "overlap_min_over_R", "overlap_max_over_R", "load_max_over_P_Y",
           "v_over_v_Y", "dt", "steps_per_contact", "steps_per_unloading", "newton_max",
           "force_error", "continuity_error", "e_velocity_error", "e_energy_error",
           "P_max_error", "contact_time_error", "energy_balance_error", "outcome")


def _pair(R, nu, ratio):
    return ContactPair.sphere_flat(Material(YOUNG, nu, YOUNG / ratio, DENSITY), R)


def _vz_params(pair, Ca_factor, Kc_factor):
    reference = VZParams.reference()
    return VZParams.from_dimensionless(pair, reference.Ca_hat * Ca_factor, reference.Kc_hat * Kc_factor)


def _inputs(group, law, R, nu, ratio, Ca_factor=None, Kc_factor=None, params=None, **extra):
    row = {key: None for key in COLUMNS}
    row.update(group=group, law=law, R=R, nu=nu, E_over_sigma_y=ratio, Ca_factor=Ca_factor,
               Kc_factor=Kc_factor, **extra)
    if params is not None and hasattr(params, "Ca_hat"):
        row.update(Ca_hat=params.Ca_hat, Kc_hat=params.Kc_hat)
    return row


def _finite(*arrays) -> bool:
    return all(np.all(np.isfinite(np.asarray(a, dtype=float))) for a in arrays)


# ------------------------------------------------------------------------------------ force laws
def vz_domain(params) -> tuple[float, float]:
    """(largest overlap [m], largest load [N]) of the vz sweep: 0.5 R* and 1e6 P_Y, or less where
    the law's contact radius would reach R* (its domain ends there: a ValueError). The overlap
    stays below 0.6 x that approach, so the reload to 1.5 x the overlap stays inside too."""
    pair = params.pair
    overlap = min(0.5 * pair.R_star, 0.6 * params.full_contact_approach)
    law = get_law("vz")
    load_at_overlap = float(law.force_function(np.array([overlap]), law.initial_state(1), params)[0][0])
    return overlap, min(1e6 * pair.P_Y, load_at_overlap)


def _force_case(law_name, pair, params, dtype):
    """Overlap sweep, loading-curve accuracy and turning-point continuity for one law/params."""
    law = get_law(law_name)
    law_params = law.params_from(params)
    overlap_max, load_max = vz_domain(params) if law_name == "vz" else (0.5 * pair.R_star, 1e6 * pair.P_Y)
    loads = np.geomspace(1.0001 * pair.P_Y, load_max, 60)
    sweep = np.geomspace(1e-15 * pair.R_star, overlap_max, 200)
    on_curve = params.loading_approach(loads) if law_name == "vz" else np.empty(0)
    if law_name == "vz":                # the end of the law's domain: an overlap beyond is refused
        try:
            law.force_function(np.array([1.01 * params.full_contact_approach]), law.initial_state(1), params)
            return {"outcome": "FAIL: no error where the contact radius exceeds R*"}, 0
        except ValueError:
            pass
    delta = np.concatenate([sweep, on_curve]).astype(dtype)
    state = law.initial_state(delta.size)
    force, loaded = law.force(delta, state, law_params)
    newton = int(vz_newton_iterations(delta, state, law_params).max()) if law_name == "vz" else 0
    held, _ = law.force(delta, loaded, law_params)                     # overlap stays at delta_max
    half, unloaded = law.force(0.5 * delta, loaded, law_params)
    back, _ = law.force(delta, unloaded, law_params)                   # reload to the turning point
    beyond, _ = law.force(1.5 * delta.astype(float), unloaded, law_params)
    if not _finite(force, held, half, back, beyond):
        return {"outcome": "FAIL: non-finite force"}, newton
    if np.any(force < 0) or np.any(half < 0) or np.any(beyond < force):
        return {"outcome": "FAIL: negative force or reloading below the turning point"}, newton
    scale = np.maximum(force, 1e-300)
    continuity = float(max(np.max(np.abs(held - force) / scale), np.max(np.abs(back - force) / scale)))
    out = {"continuity_error": continuity}
    if law_name == "vz":
        P_on_curve = force[sweep.size:]
        # float32 overlaps carry a relative error of 6e-8 into delta, hence into P (dP/P ~ d delta/delta)
        out["force_error"] = float(np.max(np.abs(P_on_curve / loads - 1.0)))
    out["outcome"] = "ok" if continuity <= CONTINUITY_LIMIT else \
        f"FAIL: force jumps at the turning point (relative {continuity:.2g})"
    return out, newton


def force_rows() -> list[dict]:
    rows = []
    for R in RADII:
        for nu in POISSON:
            for ratio in STRENGTH_RATIOS:
                pair = _pair(R, nu, ratio)
                for Ca_factor in FACTORS_CA:
                    for Kc_factor in FACTORS_KC:
                        try:
                            params = _vz_params(pair, Ca_factor, Kc_factor)
                        except ValueError as exc:
                            rows.append({**_inputs("force", "vz", R, nu, ratio, Ca_factor, Kc_factor),
                                         "outcome": f"clear error: {exc}"})
                            continue
                        for dtype in (np.float64, np.float32):
                            rows.append(_run_force(pair, params, "vz", dtype, R, nu, ratio,
                                                   Ca_factor, Kc_factor))
                for law in ("hertz", "thornton", "walton-braun"):
                    params = _vz_params(pair, 1.0, 1.0)
                    for dtype in (np.float64, np.float32):
                        rows.append(_run_force(pair, params, law, dtype, R, nu, ratio, None, None))
    return rows


def _run_force(pair, params, law, dtype, R, nu, ratio, Ca_factor, Kc_factor):
    overlap_max, load_max = vz_domain(params) if law == "vz" else (0.5 * pair.R_star, None)
    row = _inputs("force", law, R, nu, ratio, Ca_factor, Kc_factor,
                  params if law == "vz" else None, dtype=np.dtype(dtype).name,
                  overlap_min_over_R=1e-15, overlap_max_over_R=overlap_max / pair.R_star,
                  load_max_over_P_Y=load_max / pair.P_Y if law == "vz" else None)
    try:
        with np.errstate(all="raise"):          # a silent overflow or invalid value is a FAIL
            out, newton = _force_case(law, pair, params, dtype)
        row.update(out, newton_max=newton)
        if newton >= NEWTON_MAX_ITERATIONS:
            row["outcome"] = f"FAIL: Newton hit its cap of {NEWTON_MAX_ITERATIONS} iterations"
    except ValueError as exc:
        row["outcome"] = f"clear error: {exc}"
    except Exception as exc:                    # noqa: BLE001 - the report must list it, not stop
        row["outcome"] = f"FAIL: {type(exc).__name__}: {exc}"
    return row


# ------------------------------------------------------------------------------------ collisions
def _collision_case(law, params, pair, v, dt, dtype=np.float64):
    """One collide() call at one velocity; returns the error fields and the outcome."""
    exact = collision_reference(law, params, [v])
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        result = collide(law, params, np.asarray([v], dtype=dtype), dt=dtype(dt))
    step_warnings = [str(w.message) for w in caught if issubclass(w.category, TimeStepWarning)]
    other = [f"{w.category.__name__}: {w.message}" for w in caught
             if not issubclass(w.category, TimeStepWarning)]
    contact_law = get_law(law)
    work = contact_law.loading_work(result.delta_max, result.P_max, params)
    returned = result.P_max * (result.delta_max - result.delta_res) / (contact_law.unloading_exponent + 1.0)
    dissipated = np.maximum(work - returned, 0.0) if law != "hertz" else 0.0
    kinetic_in = 0.5 * pair.mass_star * v * v
    balance = 0.5 * pair.mass_star * (v * v - result.v_out**2) - dissipated
    out = {"dt": float(result.dt), "newton_max": int(result.max_newton_iterations),
           "steps_per_contact": float(exact.contact_time_estimate[0] / result.dt),
           "steps_per_unloading": float(exact.unloading_time_estimate[0] / result.dt),
           "e_velocity_error": float(abs(result.e_velocity[0] / exact.restitution[0] - 1.0)),
           "e_energy_error": float(abs(result.e_energy[0] / exact.restitution[0] - 1.0)),
           "P_max_error": float(abs(result.P_max[0] / exact.P_max[0] - 1.0)),
           "contact_time_error": float(abs(result.contact_time[0] / exact.contact_time_estimate[0] - 1.0)),
           "energy_balance_error": float(np.max(np.abs(balance)) / kinetic_in)}
    numbers = [value for key, value in out.items() if key != "newton_max"]
    if not _finite(result.v_out, result.e_velocity, result.e_energy, result.P_max, numbers):
        out["outcome"] = "FAIL: non-finite result"
    elif out["newton_max"] >= NEWTON_MAX_ITERATIONS:
        out["outcome"] = f"FAIL: Newton hit its cap of {NEWTON_MAX_ITERATIONS} iterations"
    elif other:
        out["outcome"] = "FAIL: unexpected warning " + other[0]
    elif step_warnings:
        created = max(result.e_velocity[0], result.e_energy[0])
        out["outcome"] = "warned: " + step_warnings[0] + (
            f" [here e = {created:.4g} > 1: leap-frog beyond its stability limit]" if created > 1.0 else "")
    elif max(out["e_velocity_error"], out["e_energy_error"], out["P_max_error"]) > ACCURACY_LIMIT:
        # includes e > 1 beyond the discretisation error (energy created): exact e <= 1
        out["outcome"] = "FAIL: silently inaccurate (no TimeStepWarning)"
    else:
        out["outcome"] = "ok"
    return out


def _run_collision(group, law, params, pair, v_ratio, dt_rule, R, nu, ratio, Ca_factor=None,
                   Kc_factor=None, dtype=np.float64):

    row = _inputs(group, law, R, nu, ratio, Ca_factor, Kc_factor, params if law == "vz" else None,
                  v_over_v_Y=v_ratio, dtype=np.dtype(dtype).name)
    try:
        v = v_ratio * pair.v_Y
        exact = collision_reference(law, params, [v])
        dt = dt_rule(exact)
        row["dt"] = float(dt)
        with np.errstate(all="raise"):
            row.update(_collision_case(law, params, pair, v, dt, dtype))
    except ValueError as exc:
        row["outcome"] = f"clear error: {exc}"
    except Exception as exc:                    # noqa: BLE001
        row["outcome"] = f"FAIL: {type(exc).__name__}: {exc}"
    return row


def _grid_dt(exact) -> float:
    # 12 steps in the unloading phase (the warning asks for 10): errors ~ 0.3 %, cheap
    return min(float(exact.contact_time_estimate[0]) / 100.0, float(exact.unloading_time_estimate[0]) / 12.0)


REFERENCE_MATERIAL = (0.1, 0.3, 700.0)              # R [m], nu, E / sigma_Y (the paper's aluminium)
EXTREME_MATERIALS = ((1e-6, 0.3, 700.0), (10.0, 0.3, 700.0), (0.1, 0.49, 50.0), (0.1, 0.49, 5000.0),
                     (1e-3, 0.0, 5000.0))
COLLISION_VZ_FACTORS = ((1.0, 1.0), (1e-3, 0.0), (1e3, 0.0), (1e3, 1.0), (1e3, 1e3), (1.0, 1e-3),
                        (1e-3, 1.0), (1.0, 1e3))


def collision_rows() -> list[dict]:
    """Reference material: every law, and vz with every (Ca, Kc) scaling; extreme materials: vz
    and thornton (hertz and walton-braun scale exactly with the material); float32 inputs."""
    rows = []
    cases = [(REFERENCE_MATERIAL, factors, ("vz",)) for factors in COLLISION_VZ_FACTORS[1:]]
    cases.insert(0, (REFERENCE_MATERIAL, (1.0, 1.0), ("vz", "thornton", "walton-braun", "hertz")))
    cases += [(material, (1.0, 1.0), ("vz", "thornton")) for material in EXTREME_MATERIALS]
    for (R, nu, ratio), (Ca_factor, Kc_factor), laws in cases:
        pair = _pair(R, nu, ratio)
        try:
            params = _vz_params(pair, Ca_factor, Kc_factor)
        except ValueError as exc:
            rows.append({**_inputs("collision", "vz", R, nu, ratio, Ca_factor, Kc_factor),
                         "outcome": f"clear error: {exc}"})
            continue
        for law in laws:
            for v_ratio in VELOCITY_RATIOS:
                rows.append(_run_collision("collision", law, params, pair, v_ratio, _grid_dt,
                                           R, nu, ratio, Ca_factor if law == "vz" else None,
                                           Kc_factor if law == "vz" else None))
    # float32 inputs (velocity and dt) on the reference case
    pair = _pair(*REFERENCE_MATERIAL)
    params = _vz_params(pair, 1.0, 1.0)
    for v_ratio in (1.0, 100.0, 1e4):
        rows.append(_run_collision("collision", "vz", params, pair, v_ratio, _grid_dt, *REFERENCE_MATERIAL,
                                   1.0, 1.0, dtype=np.float32))
    return rows


DT_VELOCITY_RATIOS = (1.0, 100.0, 1e3)   # the paper's constants reach R* at ~3300 v_Y
DT_RADIUS = 1e-3       # m: microsecond contacts, so dt = 1e-9 s stays cheap


def dt_rows() -> list[dict]:
    """dt from 1e-9 s to twice the leap-frog stability limit, reference aluminium at R = 1 mm.

    Stability limit of leap-frog for the stiffest (unloading) phase: dt_crit = 2 / omega with
    omega = pi / t_unload (a half-oscillation lasts pi / omega), i.e. dt_crit = 2 t_unload / pi;
    collide() refuses dt >= dt_crit.
    """

    rows = []
    pair = _pair(DT_RADIUS, 0.3, 700.0)
    params = _vz_params(pair, 1.0, 1.0)
    for v_ratio in DT_VELOCITY_RATIOS:
        exact = collision_reference("vz", params, [v_ratio * pair.v_Y])
        limit = 2.0 * float(exact.unloading_time_estimate[0]) / math.pi
        ladder = [dt for dt in (1e-9, 1e-8, 1e-7, 1e-6, 1e-5) if dt < limit]
        ladder += [0.1 * limit, 0.3 * limit, 0.9 * limit, limit, 2.0 * limit]
        for dt in ladder:
            rows.append(_run_collision("dt", "vz", params, pair, v_ratio, lambda _e, dt=dt: dt,
                                       DT_RADIUS, 0.3, 700.0, 1.0, 1.0))
    return rows


# ------------------------------------------------------------------------------------- summary
def summarize(rows: list[dict]) -> dict:
    """Counts per outcome kind, the largest Newton count and the worst errors of accepted runs,
    per group (force rows split by dtype: float32 overlaps carry 6e-8 relative rounding)."""
    kinds = {}
    for row in rows:
        kind = row["outcome"].split(":")[0]
        kinds[kind] = kinds.get(kind, 0) + 1
    groups = {"force float64": lambda r: r["group"] == "force" and r["dtype"] == "float64",
              "force float32": lambda r: r["group"] == "force" and r["dtype"] == "float32",
              "collision": lambda r: r["group"] == "collision", "dt": lambda r: r["group"] == "dt"}
    worst, newton = {}, {}
    for name, member in groups.items():
        accepted = [r for r in rows if member(r) and r["outcome"] == "ok"]
        errors = {key: max((r[key] for r in accepted if r[key] is not None), default=None)
                  for key in ("force_error", "continuity_error", "e_velocity_error",
                              "e_energy_error", "P_max_error", "contact_time_error",
                              "energy_balance_error")}
        worst[name] = {k: v for k, v in errors.items() if v is not None}
        newton[name] = max((r["newton_max"] for r in rows if member(r) and r["newton_max"] is not None),
                           default=0)
    return {"cases": len(rows), "outcomes": kinds, "newton_max": max(newton.values()),
            "newton_max_per_group": newton, "worst_errors_of_ok_rows": worst,
            "failures": [f"{r['group']}/{r['law']}: {r['outcome']}" for r in rows
                         if r["outcome"].startswith("FAIL")]}


def generate(out_dir=DEFAULT_OUT) -> dict:
    """Run every case on every backend this install has (the compiled kernel and the numpy
    reference), write runtime_stability.csv/.json into ``out_dir``; return the summary (per
    backend, and the cases whose outcome differs between them)."""
    started = time.perf_counter()
    per_backend = {}
    for name in native.available_backends():
        with native.use_backend(name):
            per_backend[name] = [{**row, "backend": name} for row in force_rows() + collision_rows() + dt_rows()]
    rows = [row for backend_rows in per_backend.values() for row in backend_rows]
    summary = {**summarize(rows), "backends": {name: summarize(r) for name, r in per_backend.items()}}
    if len(per_backend) == 2:
        pairs = zip(per_backend["native"], per_backend["numpy"])
        summary["backends_disagree"] = [f"{a['group']}/{a['law']} R {a['R']} nu {a['nu']} E/sigma_Y {a['E_over_sigma_y']}: "
                                        f"native {a['outcome']} / numpy {b['outcome']}"
                                        for a, b in pairs if a["outcome"].split(":")[0] != b["outcome"].split(":")[0]]
        summary["failures"] += [f"backends disagree: {d}" for d in summary["backends_disagree"]]
    st = stamp(time.perf_counter() - started, accuracy_limit=ACCURACY_LIMIT,
               command="nfdcal stability")
    out = Path(out_dir)
    write_csv(out / CSV_NAME, rows, COLUMNS, comment=stamp_comment(st))
    write_json(out / JSON_NAME, {"stamp": st, "summary": summary, "columns": list(COLUMNS), "rows": rows})
    return summary
