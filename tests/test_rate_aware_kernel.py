"""The rate-aware law in the C kernel (nfdmodel/nfd_rate.h) against its scalar specification,
nfdmodel.reference.rate_aware_step, with R from the Python law's a_ref (RateAwareParams.reference_radius):
a C caller (nfd_kernel.c compiled alone, -std=c99 -pedantic -Werror) and the native backend, over random
histories of loading, unloading, reloading, separation and re-contact of contacts first touching at their
own speeds (some without approach: R = 1), for both base laws (vz, vz-table) and both rate laws; the native
and numpy collide (e, P_max, R); R = 1 (Johnson-Cook C = 0, Cowper-Symonds D = inf) equal to the base law bit
for bit; the C home of the rate factors against nfdmodel.strain_rate; bad constants refused by nfd_rate_init
and by the binding, in one line."""
import dataclasses
import math
import shutil
import subprocess
from pathlib import Path

import numpy as np
import pytest

import nfdmodel
from nfdmodel import VZParams, collide, get_law, limits, load_parameters, native
from nfdmodel import rate_aware
from nfdmodel import reference as ref
from nfdmodel.rate_aware import LAW, RateAwareParams, compiled_kernel
from nfdmodel.strain_rate import CowperSymonds, JohnsonCook

pytestmark = [pytest.mark.laws,
              pytest.mark.skipif(native._native is None, reason="the compiled kernel is not built here")]

SHIPPED = Path(__file__).resolve().parent.parent / "results" / "calibration" / "parameters.json"   # vz-table
BASES = {"vz": VZParams.reference(), "vz-table": load_parameters(SHIPPED)}
RATE_LAWS = {"cowper-symonds": CowperSymonds(40.0, 5.0), "johnson-cook": JohnsonCook(0.05, 1e-3)}
RTOL = 1e-12
FIELDS = ("delta_max", "P_max", "delta_res", "unloading_stiffness", "a_e_max", "rate_factor")
CASES = [(base, rate) for base in sorted(BASES) for rate in sorted(RATE_LAWS)]


def spec_step(params: RateAwareParams):
    """The base law's scalar step of nfdmodel.reference with the base's constants."""
    base, pair = params.base, params.pair
    if params.base_law == "vz":
        return lambda d, h: ref.vz_step(d, h, pair.R_star, pair.E_star, pair.P_Y, pair.delta_Y, base.Ca, base.Kc)
    from nfdmodel.pchip import pchip_slopes
    x, f, g = (np.array(v) for v in (base.x, base.f, base.g))
    table = (list(x), list(f), list(pchip_slopes(x, f)), list(g), list(pchip_slopes(x, g)))
    return lambda d, h: ref.vz_table_step(d, h, pair.R_star, pair.E_star, pair.P_Y, pair.delta_Y, pair.a_Y, table)


def kernel_base_step(params: RateAwareParams):
    """The base law's step as the compiled kernel computes it (the native backend, one contact), in the
    scalar form reference.rate_aware_step takes: (delta, History) -> (P, History)."""
    law = get_law(params.base_law)
    names = [f.name for f in dataclasses.fields(law.state_type)]

    def step(delta, history):
        values = {"delta_max": history.delta_max, "P_max": history.P_max, "delta_res": history.delta_res,
                  "unloading_stiffness": history.K_u, "a_e_max": history.a_e_max}
        state = law.state_type(**{name: np.array([values[name]]) for name in names})
        with native.use_backend("native"):
            force, update = law.step_function(np.array([delta]), state, params.base)
        law.commit(state, update)
        return float(force[0]), ref.History(float(state.delta_max[0]), float(state.P_max[0]),
                                            float(state.delta_res[0]), float(state.unloading_stiffness[0]),
                                            float(getattr(state, "a_e_max", [0.0])[0]))

    return step


def spec_first_factor(params: RateAwareParams, speed: float) -> float:
    """R at first contact as reference.rate_aware_first_factor states it, a_ref the Python law's."""
    a_ref = float(params.reference_radius(np.array([speed]))[0]) if speed > 0.0 else 1.0
    return ref.rate_aware_first_factor(speed, a_ref, params.c, lambda rate: float(params.rate_law.factor(rate)))


def spec(params: RateAwareParams, deltas: np.ndarray, speeds: np.ndarray, step) -> np.ndarray:
    """reference.rate_aware_step on the base step ``step`` along deltas (steps x contacts): (P, the six
    history fields) per step and contact."""
    first = [spec_first_factor(params, float(v)) for v in speeds]
    histories = [ref.RateHistory() for _ in speeds]
    rows = np.empty(deltas.shape + (7,))
    for k, row in enumerate(deltas):
        for j, delta in enumerate(row):
            P, h = ref.rate_aware_step(float(delta), histories[j], first[j], step)
            histories[j] = h
            a_e = h.a_e_max if params.base_law == "vz" else 0.0       # vz-table's history keeps no a_e,max
            rows[k, j] = (P, h.delta_max, h.P_max, h.delta_res, h.K_u, a_e, h.rate_factor)
    return rows


def random_histories(params: RateAwareParams, seed: int, contacts: int = 8, cycles: int = 4,
                     steps: int = 10) -> np.ndarray:
    """Approaches [m], steps x contacts: each contact apart (delta < 0) for a random number of steps,
    then cycles of loading past its last peak, unloading to a random fraction (some below the dent:
    separation, some apart), and reloading to 0.5..1.5 of the peak; peaks up to ~150 delta_Y R^2."""
    rng = np.random.default_rng(seed)
    columns = []
    for _ in range(contacts):
        path = list(np.full(rng.integers(0, 6), -0.5))
        peak = 0.0
        for _ in range(cycles):
            peak = max(peak, 0.5) * rng.uniform(1.0, 3.5)
            low = rng.choice([rng.uniform(0.6, 0.98), rng.uniform(-0.3, 0.5)]) * peak
            again = rng.uniform(0.5, 1.5) * peak
            start = path[-1] if path else 0.0
            path += list(np.linspace(start, peak, steps)) + list(np.linspace(peak, low, steps))
            path += list(np.linspace(low, again, steps))
            peak = max(peak, again)
        columns.append(np.minimum(path, 150.0))
    length = max(len(c) for c in columns)
    columns = [np.concatenate([c, np.full(length - len(c), c[-1])]) for c in columns]
    return np.array(columns).T * params.pair.delta_Y


def speeds_of(contacts: int, seed: int) -> np.ndarray:
    """First-contact speeds [m/s]: 0.003..0.08, one contact without approach (v <= 0: R = 1)."""
    speeds = np.random.default_rng(seed).uniform(0.003, 0.08, contacts)
    speeds[-1] = -0.01
    return speeds


@pytest.fixture(scope="module")
def c_caller(tmp_path_factory) -> Path:
    """A C program on nfd_kernel.c alone: reads the law (base and rate codes, the two rate constants, c, m*,
    the 14 nfd_params values of native.kernel_params, the table's nodes), then steps, contacts, each
    contact's first-contact speed and the approaches; prints per step and contact the status, P, the new
    history and R (nfd_rate_step)."""
    compiler = shutil.which("cc") or shutil.which("gcc")
    if compiler is None:
        pytest.skip("no C compiler")
    source = Path(nfdmodel.__file__).parent
    main = tmp_path_factory.mktemp("rate_c") / "rate.c"
    main.write_text("""
#include <stdio.h>
#include <stdlib.h>
#include "nfd_rate.h"
int main(void) {
  int base, law, nodes, steps, n;
  double first, second, c, m_star, v[14], x[NFD_TABLE_MAX_NODES], f[NFD_TABLE_MAX_NODES], g[NFD_TABLE_MAX_NODES];
  static nfd_table t;
  nfd_params p;
  nfd_rate r;
  if (scanf("%d %d %lf %lf %lf %lf", &base, &law, &first, &second, &c, &m_star) != 6) return 1;
  for (int k = 0; k < 14; ++k) if (scanf("%lf", &v[k]) != 1) return 1;
  p.R_star = v[0]; p.E_star = v[1]; p.P_Y = v[2]; p.delta_Y = v[3]; p.a_Y = v[4]; p.p_Y = v[5];
  p.hertz_k = v[6]; p.Ca = v[7]; p.Kc = v[8]; p.window_P_max = v[9]; p.K1 = v[10]; p.K2 = v[11];
  p.c1 = v[12]; p.u_Y = v[13];
  if (scanf("%d", &nodes) != 1 || nodes > NFD_TABLE_MAX_NODES) return 1;
  for (int k = 0; k < nodes; ++k) if (scanf("%lf %lf %lf", &x[k], &f[k], &g[k]) != 3) return 1;
  if (nodes > 0 && nfd_table_init(&t, nodes, x, f, g) != 0) return 2;
  if (nfd_rate_init(&r, base, law, first, second, c) != 0) return 3;
  if (scanf("%d %d", &steps, &n) != 2) return 4;
  nfd_history *h = calloc((size_t)n, sizeof *h);
  double *speed = calloc((size_t)n, sizeof *speed), *R = calloc((size_t)n, sizeof *R);
  for (int j = 0; j < n; ++j) if (scanf("%lf", &speed[j]) != 1) return 4;
  for (int k = 0; k < steps; ++k)
    for (int j = 0; j < n; ++j) {
      double d, P = 0.0, factor = R[j];
      nfd_history next;
      if (scanf("%lf", &d) != 1) return 5;
      int status = nfd_rate_step(&r, d, speed[j], m_star, &p, nodes > 0 ? &t : NULL, &h[j], &factor, &P, &next,
                                 NULL);
      printf("%d %.17g %.17g %.17g %.17g %.17g %.17g %.17g\\n", status, P, next.delta_max, next.P_max,
             next.delta_res, next.K_u, next.a_e_max, factor);
      h[j] = next;
      R[j] = factor;
    }
  free(h); free(speed); free(R);
  return 0;
}
""")
    binary = main.with_suffix("")
    subprocess.run([compiler, "-std=c99", "-Wall", "-Wextra", "-pedantic", "-Werror", "-O2", f"-I{source}",
                    str(main), str(source / "nfd_kernel.c"), "-lm", "-o", str(binary)], check=True)
    return binary


def c_input(params: RateAwareParams, speeds, deltas, rate=None) -> str:
    kernel = compiled_kernel(params)
    code, first, second, c = rate if rate is not None else kernel.rate
    table = [] if kernel.table is None else list(zip(*kernel.table))
    lines = [f"{kernel.base_law} {code} {first!r} {second!r} {c!r} {params.pair.mass_star!r}",
             " ".join(repr(float(value)) for value in kernel.params), str(len(table))]
    lines += [" ".join(repr(float(value)) for value in node) for node in table]
    lines += [f"{deltas.shape[0]} {deltas.shape[1]}", " ".join(repr(float(v)) for v in speeds)]
    lines += [" ".join(repr(float(d)) for d in row) for row in deltas]
    return "\n".join(lines) + "\n"


def run_c(binary: Path, params, speeds, deltas, rate=None):
    run = subprocess.run([str(binary)], input=c_input(params, speeds, deltas, rate), capture_output=True, text=True)
    if run.returncode:
        return run.returncode, None, None
    rows = np.array([line.split() for line in run.stdout.splitlines()], dtype=float).reshape(deltas.shape + (8,))
    return 0, rows[..., 0], rows[..., 1:]


def run_law(params, speeds, deltas, backend: str) -> np.ndarray:
    """The law on ``backend``: (P, the six history fields) per step and contact."""
    state = LAW.initial_state(deltas.shape[1])
    rows = np.empty(deltas.shape + (7,))
    with native.use_backend(backend):
        for k, row in enumerate(deltas):
            P, update = LAW.step(row, state, params, velocity=speeds)
            LAW.commit(state, update)
            rows[k] = np.column_stack([P] + [getattr(state, name) for name in FIELDS])
    return rows


def worst_difference(mine: np.ndarray, theirs: np.ndarray) -> float:
    """The largest difference over forces and history fields, each relative to its own size, the force
    and the dent delta_res relative to the contact's turning point (P_max, delta_max): near separation
    both are small differences of large numbers, known to the turning point's round-off only."""
    scale = np.abs(theirs)
    scale[..., 0] = np.maximum(scale[..., 0], np.abs(theirs[..., 2]))
    scale[..., 3] = np.maximum(scale[..., 3], np.abs(theirs[..., 1]))
    difference = np.abs(mine - theirs)
    return float(np.max(np.where(difference > 0.0, difference / np.maximum(scale, 1e-300), 0.0)))


@pytest.mark.parametrize("base_law, rate", CASES)
def test_c_kernel_and_native_backend_equal_the_specification(c_caller, base_law, rate):
    """reference.rate_aware_step on the compiled base step: force and history to 1e-12 (measured: 1.3e-15
    at most); on the scalar base steps of nfdmodel.reference: 1e-12 for vz-table (measured 1e-13), and
    for vz the vz solve's tolerance (its Newton stops apart from the scalar one's: measured 6e-12); the C
    caller and the native backend bit for bit alike."""
    params = RateAwareParams(base_law, BASES[base_law], RATE_LAWS[rate])
    deltas = random_histories(params, seed=7)
    speeds = speeds_of(deltas.shape[1], seed=8)
    code, status, c_rows = run_c(c_caller, params, speeds, deltas)
    assert code == 0 and (status >= 0).all()
    native_rows = run_law(params, speeds, deltas, "native")
    assert np.array_equal(native_rows, c_rows)
    assert worst_difference(c_rows, spec(params, deltas, speeds, kernel_base_step(params))) <= RTOL
    scalar = worst_difference(c_rows, spec(params, deltas, speeds, spec_step(params)))
    assert scalar <= (RTOL if base_law == "vz-table" else limits.VZ_TOLERANCE)
    R = native_rows[-1, :, -1]
    assert R[-1] == 1.0 and (R[:-1] > 1.2).all()                       # v <= 0: no rate; else fixed at touch
    assert (native_rows[..., 2] > 50 * params.pair.P_Y).any()          # deep plastic loading was reached


@pytest.mark.parametrize("base_law, rate", CASES)
def test_native_collide_equals_numpy(base_law, rate):
    """The compiled collision loop (nfd_rate_step per step) against the numpy loop at three speeds: e and
    P_max to 1e-12 (measured: 6e-15 at most), the dent and the dissipated energy too (below)."""
    params = RateAwareParams(base_law, BASES[base_law], RATE_LAWS[rate])
    v = [0.005, 0.02, 0.06]
    with native.use_backend("native"):
        compiled = collide(LAW, params, v, dt=None)
    with native.use_backend("numpy"):
        numpy = collide(LAW, params, v, dt=None)
    np.testing.assert_allclose(compiled.e_velocity, numpy.e_velocity, rtol=1e-12)
    np.testing.assert_allclose(compiled.P_max, numpy.P_max, rtol=1e-12)
    # the dent and the dissipated energy of a barely plastic impact are small differences of large numbers:
    # to 1e-12 of the turning point's approach and of the impact's energy
    np.testing.assert_allclose(compiled.delta_res, numpy.delta_res, rtol=1e-12, atol=1e-12 * numpy.delta_max.min())
    energy = 0.5 * params.pair.mass_star * np.square(v)
    lost, lost_numpy = compiled.dissipated_plastic, numpy.dissipated_plastic
    assert (np.abs(lost - lost_numpy) <= 1e-12 * (np.abs(lost_numpy) + energy)).all()
    assert compiled.steps == numpy.steps


UNIT_RATES = {"johnson-cook C = 0": (limits.RATE_JOHNSON_COOK, 0.0, 1.0),
              "cowper-symonds D = inf": (limits.RATE_COWPER_SYMONDS, math.inf, 5.0)}


@pytest.mark.parametrize("base_law", sorted(BASES))
@pytest.mark.parametrize("unit", sorted(UNIT_RATES))
def test_unit_factor_is_the_base_law_bit_for_bit(c_caller, base_law, unit, monkeypatch):
    """R = 1: the compiled rate-aware law's forces and histories are the base law's, bit for bit (the C
    caller and the native backend against the base law's native step; the compiled collide against the
    base law's). CowperSymonds refuses D = inf in Python: the kernel is given it directly."""
    params = RateAwareParams(base_law, BASES[base_law], JohnsonCook(0.0))
    rate = (*UNIT_RATES[unit], params.c)
    kernel = compiled_kernel(params)._replace(rate=rate)
    monkeypatch.setattr(rate_aware, "compiled_kernel", lambda _: kernel)
    deltas = random_histories(params, seed=3)
    speeds = speeds_of(deltas.shape[1], seed=4)
    mine = run_law(params, speeds, deltas, "native")
    base_law_object = get_law(base_law)
    state = base_law_object.initial_state(deltas.shape[1])
    with native.use_backend("native"):
        for k, row in enumerate(deltas):
            P, update = base_law_object.step(row, state, params.base)
            base_law_object.commit(state, update)
            assert np.array_equal(P, mine[k, :, 0])
            for column, name in enumerate(FIELDS[:4], start=1):
                assert np.array_equal(getattr(state, name), mine[k, :, column])
    code, _, c_rows = run_c(c_caller, params, speeds, deltas, rate)
    assert code == 0 and np.array_equal(c_rows[..., :5], mine[..., :5]) and (mine[-1, :, -1] == 1.0).all()
    v = [0.005, 0.06]
    with native.use_backend("native"):
        compiled, base = collide(LAW, params, v, dt=None), collide(base_law, params.base, v, dt=None)
    assert np.array_equal(compiled.e_velocity, base.e_velocity) and np.array_equal(compiled.P_max, base.P_max)


def test_the_c_rate_factor_is_strain_rate_s():
    """nfd_rate_factor (through a contact whose a_ref is known: R = 1 + (eps_dot / D)^(1/q)) against
    nfdmodel.strain_rate at the same strain rate, both rate laws."""
    params = RateAwareParams("vz", BASES["vz"], RATE_LAWS["cowper-symonds"])
    for rate_law in RATE_LAWS.values():
        params = RateAwareParams("vz", BASES["vz"], rate_law)
        v = np.array([0.004, 0.03, 0.09])
        with native.use_backend("native"):
            _, update = LAW.step(np.full(3, 1e-9), LAW.initial_state(3), params, velocity=v)
        expected = rate_law.factor(v / (params.c * params.reference_radius(v)))
        np.testing.assert_allclose(update.values.rate_factor, expected, rtol=1e-14)


@pytest.mark.parametrize("rate, what", [
    ((limits.RATE_JOHNSON_COOK, -0.1, 1.0, 26.0), "Johnson-Cook C < 0"),
    ((limits.RATE_JOHNSON_COOK, 0.05, 0.0, 26.0), "eps_dot_0 = 0"),
    ((limits.RATE_COWPER_SYMONDS, 0.0, 5.0, 26.0), "Cowper-Symonds D = 0"),
    ((limits.RATE_COWPER_SYMONDS, 40.0, math.nan, 26.0), "q NaN"),
    ((limits.RATE_COWPER_SYMONDS, 40.0, 5.0, 0.0), "c = 0"),
    ((limits.RATE_COWPER_SYMONDS, 40.0, 5.0, math.inf), "c = inf"),
    ((7, 40.0, 5.0, 26.0), "an unknown rate law"),
])
def test_bad_constants_are_refused(c_caller, rate, what):
    """nfd_rate_init refuses them (the C caller stops with its code 3) and the binding in one line naming
    rate; so does a base law other than vz, vz_table."""
    params = RateAwareParams("vz", BASES["vz"], RATE_LAWS["cowper-symonds"])
    deltas = np.zeros((1, 1))
    assert run_c(c_caller, params, [0.01], deltas, rate)[0] == 3, what
    kernel = compiled_kernel(params)._replace(rate=rate)
    with pytest.raises(ValueError, match="^rate out of range: ") as caught:
        native.rate_step(kernel, params.pair.mass_star, np.zeros(1), np.zeros(1), LAW.initial_state(1))
    assert "\n" not in str(caught.value)
    with pytest.raises(ValueError, match="^rate out of range: "):
        native.rate_step(kernel._replace(base_law=limits.LAW_CODES["thornton"], rate=compiled_kernel(params).rate),
                         params.pair.mass_star, np.zeros(1), np.zeros(1), LAW.initial_state(1))


@pytest.mark.parametrize("speed", [1e-130, 500.0])
def test_a_first_contact_the_kernel_refuses_gets_the_numpy_path_s_error(speed):
    """A speed whose impact energy underflows, or whose impact would reach R* (the kernel's NFD_NOT_FINITE,
    NFD_FULL_CONTACT): the native backend says what the numpy path says, in one line."""
    params = RateAwareParams("vz-table", BASES["vz-table"], RATE_LAWS["cowper-symonds"])
    messages = []
    for backend in ("native", "numpy"):
        with native.use_backend(backend), pytest.raises(ValueError, match="^v_in out of range") as caught:
            LAW.step(np.array([1e-9]), LAW.initial_state(1), params, velocity=np.array([speed]))
        messages.append(str(caught.value))
    assert messages[0] == messages[1] and "\n" not in messages[0]
