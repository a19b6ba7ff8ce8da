"""The compiled kernel (nfdmodel/nfd_kernel.c through nfdmodel._native) against the numpy
reference: every law over hypothesis-generated multi-step histories (loading, unloading,
reloading through the turning point, separation, re-contact, large jumps), float32 and empty
input, the stability report's extreme constants, collisions, the same error messages, and the
backend switch."""
import json
import os
import subprocess
import sys

import numpy as np
import pytest
from hypothesis import HealthCheck, example, given, settings
from hypothesis import strategies as st

import nfdmodel
from nfdmodel import VZParams, VZTableParams, VZUnloadParams, WaltonBraunParams, collide, get_law, native

pytestmark = pytest.mark.skipif(native._native is None, reason="the compiled kernel is not built here")

REF = VZParams.reference()
PAIR = REF.pair
RTOL = 1e-12


NODES = np.geomspace(1.0, 1000.0, 17)
F_NODES = 0.03 * (NODES - 1.0) ** 0.8
TABLE = VZTableParams(PAIR, tuple(NODES), tuple(F_NODES), tuple(1.0 + 0.25 * F_NODES ** 0.9))   # bends over 1..1000 P_Y
# the dent and unloading exponent over the turning point, held beyond 41 P_Y
UNLOAD = VZUnloadParams.from_table(TABLE, (1.0, 2.2, 7.1, 41.0), (0.0, 0.05, 0.2, 0.45), (1.5, 1.46, 1.41, 1.36))


def params_for(name, Ca_factor=1.0, Kc_factor=1.0, pair=PAIR):
    if name == "vz-table":
        return TABLE
    if name == "vz-unload":
        return UNLOAD
    if name == "vz":
        return VZParams(pair, REF.Ca * Ca_factor, REF.Kc * Kc_factor)
    if name == "walton-braun":
        return WaltonBraunParams.from_vz(VZParams(pair, REF.Ca, REF.Kc))
    return pair


def run(name, params, deltas, backend, dtype=np.float64):
    """Forces and histories of a law along ``deltas`` (steps x contacts) on one backend."""
    law = get_law(name)
    state = law.initial_state(deltas.shape[1])
    forces, histories = [], []
    with native.use_backend(backend):
        for row in deltas:
            P, update = law.step(row.astype(dtype), state, params)
            law.commit(state, update)
            forces.append(P)
            fields = ("delta_max", "P_max", "delta_res", "unloading_stiffness") + (
                ("unloading_exponent",) if name == "vz-unload" else ())
            histories.append({f: getattr(state, f).copy() for f in fields} if name != "hertz" else {})
    return np.array(forces), histories


def assert_same(a, b, scale=0.0):
    """Equal to RTOL relative; ``scale`` [the quantity's unit] sets the absolute floor RTOL * scale for a
    quantity that is a cancellation (delta_res just past first yield is delta_max minus nearly itself)."""
    np.testing.assert_allclose(a, b, rtol=RTOL, atol=max(RTOL * scale, 1e-300))


# each history field's natural scale (m, N, N/m) for the absolute floor of assert_same
FIELD_SCALE = {"delta_max": PAIR.delta_Y, "P_max": PAIR.P_Y, "delta_res": PAIR.delta_Y,
               "unloading_stiffness": PAIR.P_Y / PAIR.delta_Y, "unloading_exponent": 1.0}


paths = st.lists(st.lists(st.floats(-3.0, 500.0, allow_nan=False), min_size=1, max_size=25), min_size=1, max_size=6)


@pytest.mark.parametrize("name", ["vz", "vz-table", "thornton", "walton-braun", "hertz", "vz-unload"])
@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow,
                                                                 HealthCheck.function_scoped_fixture])
@given(contact_paths=paths, float32=st.booleans())
@example(contact_paths=[[1.0]], float32=True)      # float32 delta_Y rounds just past first yield
def test_native_equals_numpy_over_random_histories(name, contact_paths, float32):
    steps = max(len(p) for p in contact_paths)
    deltas = np.array([[p[min(k, len(p) - 1)] for p in contact_paths] for k in range(steps)]) * PAIR.delta_Y
    dtype = np.float32 if float32 else np.float64
    params = params_for(name)
    P_numpy, h_numpy = run(name, params, deltas, "numpy", dtype)
    P_native, h_native = run(name, params, deltas, "native", dtype)
    assert_same(P_native, P_numpy)
    for a, b in zip(h_native, h_numpy):
        for field in a:
            assert_same(a[field], b[field], FIELD_SCALE[field])


@pytest.mark.parametrize("Ca_factor, Kc_factor", [(1e-3, 0.0), (1.0, 1.0), (1e3, 1e-3), (1e3, 1.0), (1.0, 1e-3)])
def test_native_equals_numpy_at_the_stability_report_s_extremes(Ca_factor, Kc_factor):
    params = params_for("vz", Ca_factor, Kc_factor)
    top = min(0.5 * PAIR.R_star, 0.6 * params.full_contact_approach)
    overlaps = np.geomspace(1e-15 * PAIR.R_star, top, 300)
    deltas = np.array([overlaps, 0.5 * overlaps, overlaps, 1.5 * overlaps])    # load, unload, reload, beyond
    (P_n, h_n), (P_c, h_c) = (run("vz", params, deltas, b) for b in ("numpy", "native"))
    assert_same(P_c, P_n)
    for a, b in zip(h_c, h_n):
        for field in a:
            assert_same(a[field], b[field])


def test_jumps_far_from_the_turning_point_and_the_iteration_counts():
    rng = np.random.default_rng(3)
    law = get_law("vz")
    delta_max = PAIR.delta_Y * np.exp(rng.uniform(np.log(2), np.log(300), 2000))
    counts = {}
    for backend in ("numpy", "native"):
        with native.use_backend(backend):
            _, state = law.force(delta_max, law.initial_state(delta_max.size), REF)
            P, update = law.step(delta_max * rng.uniform(1.0, 3.0, delta_max.size), state, REF)
            counts[backend] = (P, update.newton_iterations)
            rng = np.random.default_rng(3)
            delta_max = PAIR.delta_Y * np.exp(rng.uniform(np.log(2), np.log(300), 2000))
    assert_same(counts["native"][0], counts["numpy"][0])
    assert counts["native"][1] == counts["numpy"][1]


def test_empty_input_and_window_flags_match():
    window_params = VZParams.reference()
    delta = window_params.loading_approach(PAIR.P_Y * np.array([10.0, 100.0, 300.0]))
    results = {}
    for backend in ("numpy", "native"):
        with native.use_backend(backend):
            law = get_law("vz")
            empty = law.step(np.empty(0), law.initial_state(0), window_params)
            assert empty[0].shape == (0,) and empty[1].size == 0
            _, update = law.step_function(delta, law.initial_state(3), window_params)
            results[backend] = (update.beyond_window, update.largest_load_over_P_Y)
    assert results["native"][0] == results["numpy"][0] == 2
    assert results["native"][1] == pytest.approx(results["numpy"][1], rel=RTOL)


@pytest.mark.parametrize("name", ["vz", "thornton", "walton-braun", "hertz"])
def test_collisions_agree_to_1e_10(name):
    v = np.array([0.002, 0.02, 0.1, 0.2])
    e = {}
    for backend in ("numpy", "native"):
        with native.use_backend(backend):
            e[backend] = collide(name, params_for(name), v).e_velocity
    np.testing.assert_allclose(e["native"], e["numpy"], rtol=1e-10)


@pytest.mark.parametrize("call", [
    lambda: get_law("vz").step(np.array([1e-6, np.nan]), get_law("vz").initial_state(2), REF),
    lambda: get_law("vz").step(np.array([1e300]), get_law("vz").initial_state(1), REF),
    lambda: get_law("vz").step(np.array([0.05]), get_law("vz").initial_state(1), REF),       # a > R*
    lambda: get_law("thornton").step(np.array([1.0, 2.0]), get_law("thornton").initial_state(3), PAIR),
    lambda: get_law("hertz").step(np.array([1e300]), get_law("hertz").initial_state(1), PAIR),
])
def test_bad_input_gives_the_same_message_on_both_backends(call):
    messages = []
    for backend in ("numpy", "native"):
        with native.use_backend(backend):
            with pytest.raises(ValueError) as info:
                call()
            messages.append(str(info.value))
    assert messages[0] == messages[1]


def test_the_yield_factor_of_the_c_kernel_equals_scipy_s():
    """nfd_yield_factor (golden-section search in C, used by the LAMMPS plugin) and
    nfdmodel.yield_factor (scipy's bounded minimiser) give the same A_Y(nu) to 1e-10 relative
    over 0 <= nu <= 0.4999 (measured: 1.3e-15); A_Y(0.3) = 1.61 (Vu-Quoc & Zhang 1999)."""
    nus = np.linspace(0.0, 0.4999, 1001)
    c = np.array([native._native.yield_factor(nu) for nu in nus])
    scipy = np.array([nfdmodel.yield_factor(nu) for nu in nus])
    np.testing.assert_allclose(c, scipy, rtol=1e-10, atol=0.0)
    assert native._native.yield_factor(0.3) == pytest.approx(1.61, abs=5e-3)


def accepted_by_vzparams(Ca_hat, Kc_hat) -> bool:
    try:
        VZParams.from_dimensionless(PAIR, Ca_hat, Kc_hat)
    except ValueError:
        return False
    return True


def test_the_c_admissibility_of_vz_constants_decides_as_vzparams():
    """nfd_vz_admissible (the LAMMPS plugin's check) accepts (Ca_hat, Kc_hat) iff VZParams does, on
    a grid across and beyond the admissible ranges (Ca_hat 5e-9 .. 2e4, Kc_hat 0 and 1e-9 .. 2e4);
    where a cycle is checked, the restitution agrees to 1e-10 (measured: 1.5e-12) and the worst
    turning point is the same load."""
    codes = set()
    for Ca_hat in np.concatenate([[5e-9], np.geomspace(1e-8, 1e4, 13), [2e4]]):
        for Kc_hat in np.concatenate([[0.0], np.geomspace(1e-9, 1e4, 14), [2e4]]):
            code, load, restitution = native._native.vz_admissible(Ca_hat, Kc_hat)
            codes.add(code)
            assert (code == 0) == accepted_by_vzparams(Ca_hat, Kc_hat), (Ca_hat, Kc_hat, code)
            if code in (0, 3):
                trial = object.__new__(VZParams)              # VZParams' own cycle check, unchecked pair
                for name, value in (("pair", PAIR), ("Ca", Ca_hat * PAIR.a_Y / PAIR.P_Y),
                                    ("Kc", Kc_hat / PAIR.P_Y), ("window", None)):
                    object.__setattr__(trial, name, value)
                excess, worst = trial._energy_excess()
                assert restitution == pytest.approx(np.sqrt(1.0 + excess), rel=1e-10, abs=0.0)
                assert load == pytest.approx(worst, rel=1e-9)
    assert codes == {0, 1, 2, 3}          # admissible, out of range, loading turns back, creates energy


@pytest.mark.parametrize("Ca_hat", [1e-7, 1e-4, 0.026, 0.3, 3.0, 100.0])
def test_the_c_admissibility_boundary_is_vzparams_to_1e_8(Ca_hat):
    """Both directions at the boundary: the largest Kc_hat the C check accepts (bisection to 1e-14)
    is VZParams' to 1e-8 relative: VZParams accepts Kc_hat (1 - 1e-8) and refuses (1 + 1e-8). The
    band where the two may differ is thinner (measured: below 1e-12, at Ca_hat = 0.3 between 1e-10
    and 1e-8: the cycle's excess grows slowly with Kc_hat there). Ca_hat >= 3 is bounded by the
    monotone loading, below by the energy."""
    low, high = 0.0, 1e4
    assert native._native.vz_admissible(Ca_hat, low)[0] == 0 and native._native.vz_admissible(Ca_hat, high)[0] != 0
    while high - low > 1e-14 * high:
        middle = 0.5 * (low + high)
        low, high = (middle, high) if native._native.vz_admissible(Ca_hat, middle)[0] == 0 else (low, middle)
    assert native._native.vz_admissible(Ca_hat, high)[0] == (2 if Ca_hat >= 3.0 else 3)
    assert accepted_by_vzparams(Ca_hat, low * (1.0 - 1e-8))
    assert not accepted_by_vzparams(Ca_hat, high * (1.0 + 1e-8))


def test_backend_switch_and_its_reason(monkeypatch):
    """NFDCAL_BACKEND is read once, at import; use_backend switches this process's selection and
    never the environment, which a child process inherits unchanged."""
    environment = dict(os.environ)
    with native.use_backend("native"):
        assert nfdmodel.backend() == "native" and nfdmodel.backend_info().startswith("native: ")
    with native.use_backend("numpy"):
        assert nfdmodel.backend() == "numpy" and "selected by use_backend('numpy')" in nfdmodel.backend_info()
        assert dict(os.environ) == environment
        child = subprocess.run([sys.executable, "-c", "import os; print(os.environ.get('NFDCAL_BACKEND'))"],
                               capture_output=True, text=True, check=True).stdout.strip()
        assert child == str(environment.get("NFDCAL_BACKEND"))
    # the environment after import changes nothing (no read per law call)
    selected = nfdmodel.backend()
    monkeypatch.setenv("NFDCAL_BACKEND", "numpy" if selected == "native" else "")
    assert nfdmodel.backend() == selected
    # forced at import, and use_backend still switches
    code = ("import nfdmodel, json\nfrom nfdmodel import native\nfirst = [nfdmodel.backend(), nfdmodel.backend_info()]\n"
            "with native.use_backend('native'):\n    print(json.dumps(first + [nfdmodel.backend()]))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True,
                         env={**os.environ, "NFDCAL_BACKEND": "numpy"}).stdout
    backend, why, switched = json.loads(out)
    assert backend == "numpy" and "forced by NFDCAL_BACKEND=numpy" in why and switched == "native"
    # without the compiled module (a machine without a compiler), numpy, and it says why
    code = ("import sys; sys.modules['nfdmodel._native'] = None; import nfdmodel, json; "
            "print(json.dumps([nfdmodel.backend(), nfdmodel.backend_info()]))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True,
                         env={**os.environ, "NFDCAL_BACKEND": ""}).stdout
    backend, why = json.loads(out)
    assert backend == "numpy" and "not built" in why


def test_the_c_source_ships_with_the_package_and_compiles_alone(tmp_path):
    """The kernel is one dependency-free C99 source: it compiles on its own, warning-free, and a
    C caller gets the same force as Python."""
    import shutil
    from pathlib import Path

    compiler = shutil.which("cc") or shutil.which("gcc")
    if compiler is None:
        pytest.skip("no C compiler")
    source = Path(nfdmodel.__file__).parent
    main = tmp_path / "main.c"
    main.write_text('#include <stdio.h>\n#include "nfd_kernel.h"\nint main(void) {\n'
                    f'  nfd_params p = nfd_pair({PAIR.R_star!r}, {PAIR.E_star!r}, {PAIR.p_Y!r});\n'
                    f'  nfd_vz_constants(&p, {REF.Ca!r}, {REF.Kc!r});\n'
                    '  nfd_history h = {0, 0, 0, 0, 0}, next; double P; int iterations;\n'
                    '  int status = nfd_vz_step(1.56e-5, &p, &h, &P, &next, &iterations);\n'
                    '  printf("%d %.17g\\n", status, P); return 0; }\n')
    binary = tmp_path / "main"
    subprocess.run([compiler, "-std=c99", "-Wall", "-Wextra", "-pedantic", "-Werror", "-O2", f"-I{source}",
                    str(main), str(source / "nfd_kernel.c"), "-lm", "-o", str(binary)], check=True)
    status, force = subprocess.run([str(binary)], capture_output=True, text=True, check=True).stdout.split()
    expected = get_law("vz").force_function(np.array([1.56e-5]), get_law("vz").initial_state(1), REF)[0][0]
    assert int(status) == 0 and float(force) == pytest.approx(expected, rel=1e-12)


def test_a_c_caller_gets_the_vz_table_law_of_python(tmp_path):
    """nfd_table_init + nfd_vz_table_step from C: the same forces and turning points as the
    numpy kernel along a load-unload-reload path through and beyond the table."""
    import shutil
    from pathlib import Path

    compiler = shutil.which("cc") or shutil.which("gcc")
    if compiler is None:
        pytest.skip("no C compiler")
    source = Path(nfdmodel.__file__).parent
    deltas = np.concatenate([np.geomspace(0.5, 300.0, 40), np.linspace(300.0, 100.0, 5), np.geomspace(150.0, 1500.0, 20)])
    listing = lambda values: ", ".join(repr(float(v)) for v in values)       # noqa: E731
    main = tmp_path / "table.c"
    main.write_text(f"""
#include <stdio.h>
#include "nfd_kernel.h"
int main(void) {{
  double x[] = {{{listing(TABLE.x)}}}, f[] = {{{listing(TABLE.f)}}}, g[] = {{{listing(TABLE.g)}}};
  double d[] = {{{listing(deltas * PAIR.delta_Y)}}};
  nfd_params p = nfd_pair({PAIR.R_star!r}, {PAIR.E_star!r}, {PAIR.p_Y!r});
  nfd_table t;
  if (nfd_table_init(&t, {len(TABLE.x)}, x, f, g) != 0) return 1;
  nfd_history h = {{0, 0, 0, 0, 0}}, next;
  for (int i = 0; i < {deltas.size}; ++i) {{
    double P; int it;
    int status = nfd_vz_table_step(d[i], &p, &t, &h, &P, &next, &it);
    printf("%d %.17g %.17g %.17g\\n", status, P, next.delta_res, next.K_u);
    h = next;
  }}
  return 0;
}}
""")
    binary = tmp_path / "table"
    subprocess.run([compiler, "-std=c99", "-Wall", "-Wextra", "-pedantic", "-Werror", "-O2", f"-I{source}",
                    str(main), str(source / "nfd_kernel.c"), "-lm", "-o", str(binary)], check=True)
    rows = np.array([line.split() for line in subprocess.run([str(binary)], capture_output=True, text=True,
                                                                check=True).stdout.splitlines()], dtype=float)
    with native.use_backend("numpy"):
        law, state, expected = get_law("vz-table"), get_law("vz-table").initial_state(1), []
        for delta in deltas * PAIR.delta_Y:
            P, state = law.force(np.array([delta]), state, TABLE)
            expected.append([0.0, P[0], state.delta_res[0], state.unloading_stiffness[0]])
    np.testing.assert_allclose(rows, np.array(expected), rtol=1e-12)


def test_the_batch_solve_of_the_c_api_equals_the_step_contact_by_contact(tmp_path):
    """nfd_vz_load (many loading contacts at once, its fast path vectorised) gives bit for bit
    nfd_vz_step's turning points and the largest Newton count, over first loading below and
    above yield, small increments from a turning point and large jumps (the safe path)."""
    import shutil
    from pathlib import Path

    compiler = shutil.which("cc") or shutil.which("gcc")
    if compiler is None:
        pytest.skip("no C compiler")
    source = Path(nfdmodel.__file__).parent
    main = tmp_path / "batch.c"
    main.write_text(r"""
#include <stdio.h>
#include <string.h>
#include "nfd_kernel.h"
#define N 3000
int main(void) {
  nfd_params p = nfd_pair(%r, %r, %r);
  nfd_vz_constants(&p, %r, %r);
  static double delta[N], a_e[N], P[N], res[N], K[N];
  static nfd_history start[N], expected[N];
  int most = 0, mismatches = 0;
  for (int i = 0; i < N; ++i) {
    nfd_history virgin = {0, 0, 0, 0, 0};
    double f;
    int it;
    double d_old = p.delta_Y * (0.01 + 0.1 * (i %% 997));        /* a turning point, or none */
    nfd_vz_step(d_old, &p, &virgin, &f, &start[i], &it);
    if (i %% 5 == 0) memset(&start[i], 0, sizeof start[i]);        /* first loading */
    double factor = (i %% 3 == 0) ? 1.0 + 1e-4 * (i %% 7) + 1e-9 : 1.0 + 0.37 * (i %% 11);   /* small or a jump */
    delta[i] = (start[i].delta_max > 0 ? start[i].delta_max : p.delta_Y * 0.02 * (i %% 200)) * factor + 1e-12;
    a_e[i] = start[i].a_e_max;
    nfd_vz_step(delta[i], &p, &start[i], &f, &expected[i], &it);
    if (it > most) most = it;
  }
  int batch_most = nfd_vz_load(N, &p, delta, a_e, P, res, K);
  for (int i = 0; i < N; ++i)
    mismatches += memcmp(&P[i], &expected[i].P_max, 8) || memcmp(&res[i], &expected[i].delta_res, 8)
                  || memcmp(&K[i], &expected[i].K_u, 8) || memcmp(&a_e[i], &expected[i].a_e_max, 8);
  printf("%%d %%d %%d\n", mismatches, most, batch_most);
  return 0;
}
""" % (PAIR.R_star, PAIR.E_star, PAIR.p_Y, REF.Ca, REF.Kc))
    binary = tmp_path / "batch"
    subprocess.run([compiler, "-std=c99", "-Wall", "-Wextra", "-Werror", "-O3", "-fno-math-errno", f"-I{source}",
                    str(main), str(source / "nfd_kernel.c"), "-lm", "-o", str(binary)], check=True)
    mismatches, most, batch_most = map(int, subprocess.run([str(binary)], capture_output=True, text=True,
                                                             check=True).stdout.split())
    assert mismatches == 0 and most == batch_most and most > 2      # the safe path was exercised


def test_the_collision_loop_in_c_gives_the_python_loop_s_numbers_and_errors():
    v = np.linspace(0.02, 0.2, 10)
    results = {}
    for backend in ("numpy", "native"):
        with native.use_backend(backend):
            r = collide("vz", REF, v, dt=1e-6)
            results[backend] = r
            with pytest.raises(ValueError) as info:
                collide("vz", REF, v, dt=1e-6, max_steps=100)
            results[backend + " error"] = str(info.value)
    a, b = results["numpy"], results["native"]
    for field in ("v_out", "e_velocity", "e_energy", "P_max", "delta_max", "delta_res", "contact_time"):
        np.testing.assert_allclose(getattr(b, field), getattr(a, field), rtol=1e-12)
    assert (a.steps, a.max_newton_iterations) == (b.steps, b.max_newton_iterations)
    assert results["numpy error"] == results["native error"]
