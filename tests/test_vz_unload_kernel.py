"""The vz-unload law in the C kernel (nfdmodel/nfd_unload.h through nfd_step) against its scalar
specification, nfdmodel.reference.vz_unload_step: a C caller (nfd_kernel.c compiled alone,
-std=c99 -pedantic -Werror) and the native backend, over random histories of loading, partial
unloading, reloading below and past the turning point, overloading and separation, and at the
tables' edges (first yield, every node of the loading and unloading tables, beyond the last
unloading node where the tables are held); the tables' rules refused by nfd_unload_table_init."""
import shutil
import subprocess
from pathlib import Path

import numpy as np
import pytest

import nfdmodel
from nfdmodel import ContactPair, Material, VZTableParams, VZUnloadParams, get_law, native, reference

pytestmark = [pytest.mark.laws,
              pytest.mark.skipif(native._native is None, reason="the compiled kernel is not built here")]

PAIR = ContactPair.sphere_flat(Material.reference(), 0.1)
BENT = VZTableParams(PAIR, (1.0, 3.0, 10.0, 41.0, 200.0, 1000.0), (0.0, 0.06, 0.25, 0.9, 3.0, 10.0),
                     (1.0, 1.02, 1.1, 1.4, 2.5, 6.0))
PARAMS = VZUnloadParams.from_table(BENT, (1.0, 2.2, 7.1, 41.0), (0.0, 0.05, 0.2, 0.45), (1.5, 1.46, 1.41, 1.36))
RTOL = 1e-12
LAW = get_law("vz-unload")


def spec_tables(params):
    a, u = params._arrays, params._unload
    return (tuple(list(a[k]) for k in ("x", "f", "df", "g", "dg")),
            tuple(list(u[k]) for k in ("x", "rho", "drho", "m", "dm")))


def spec(deltas: np.ndarray) -> np.ndarray:
    """reference.vz_unload_step along deltas (steps x contacts): rows (P, delta_max, P_max, delta_res,
    K_u, m) per step and contact."""
    table, unloading = spec_tables(PARAMS)
    histories = [reference.ExponentHistory(m=0.0) for _ in range(deltas.shape[1])]
    rows = np.empty(deltas.shape + (6,))
    for k, row in enumerate(deltas):
        for j, delta in enumerate(row):
            P, h = reference.vz_unload_step(float(delta), histories[j], PAIR.R_star, PAIR.E_star, PAIR.P_Y,
                                            PAIR.delta_Y, PAIR.a_Y, table, unloading)
            histories[j] = h
            rows[k, j] = (P, h.delta_max, h.P_max, h.delta_res, h.K_u, h.m)
    return rows


@pytest.fixture(scope="module")
def c_caller(tmp_path_factory) -> Path:
    """A C program on nfd_kernel.c alone: nfd_table_init, nfd_unload_table_init, then nfd_step(
    NFD_LAW_VZ_UNLOAD) along the approaches it reads (first line: steps, contacts), printing per step
    and contact the status, P and the new history."""
    compiler = shutil.which("cc") or shutil.which("gcc")
    if compiler is None:
        pytest.skip("no C compiler")
    source = Path(nfdmodel.__file__).parent
    listing = lambda values: ", ".join(repr(float(v)) for v in values)       # noqa: E731
    main = tmp_path_factory.mktemp("unload_c") / "unload.c"
    main.write_text(f"""
#include <stdio.h>
#include <stdlib.h>
#include "nfd_unload.h"
int main(void) {{
  double x[] = {{{listing(BENT.x)}}}, f[] = {{{listing(BENT.f)}}}, g[] = {{{listing(BENT.g)}}};
  double xu[] = {{{listing(PARAMS.x_unload)}}}, dent[] = {{{listing(PARAMS.dent)}}};
  double m[] = {{{listing(PARAMS.exponent)}}};
  nfd_params p = nfd_pair({PAIR.R_star!r}, {PAIR.E_star!r}, {PAIR.p_Y!r});
  static nfd_table t;
  int steps, n;
  if (nfd_table_init(&t, {len(BENT.x)}, x, f, g) != 0) return 1;
  if (nfd_unload_table_init(&t, {len(PARAMS.x_unload)}, xu, dent, m) != 0) return 2;
  if (scanf("%d %d", &steps, &n) != 2) return 3;
  nfd_history *h = calloc((size_t)n, sizeof *h);
  for (int k = 0; k < steps; ++k)
    for (int j = 0; j < n; ++j) {{
      double d, P; nfd_history next; int it;
      if (scanf("%lf", &d) != 1) return 4;
      int status = nfd_step(NFD_LAW_VZ_UNLOAD, d, &p, &t, &h[j], &P, &next, &it);
      printf("%d %.17g %.17g %.17g %.17g %.17g %.17g\\n", status, P, next.delta_max, next.P_max, next.delta_res,
             next.K_u, next.a_e_max);
      h[j] = next;
    }}
  free(h);
  return 0;
}}
""")
    binary = main.with_suffix("")
    subprocess.run([compiler, "-std=c99", "-Wall", "-Wextra", "-pedantic", "-Werror", "-O2", f"-I{source}",
                    str(main), str(source / "nfd_kernel.c"), "-lm", "-o", str(binary)], check=True)
    return binary


def run_c(binary: Path, deltas: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    text = f"{deltas.shape[0]} {deltas.shape[1]}\n" + "\n".join(" ".join(repr(float(d)) for d in row)
                                                               for row in deltas)
    out = subprocess.run([str(binary)], input=text, capture_output=True, text=True, check=True).stdout
    rows = np.array([line.split() for line in out.splitlines()], dtype=float).reshape(deltas.shape + (7,))
    return rows[..., 0], rows[..., 1:]


def run_native(deltas: np.ndarray) -> np.ndarray:
    """The native backend's force and history (the same six columns as spec)."""
    state = LAW.initial_state(deltas.shape[1])
    rows = np.empty(deltas.shape + (6,))
    with native.use_backend("native"):
        for k, row in enumerate(deltas):
            P, update = LAW.step(row, state, PARAMS)
            LAW.commit(state, update)
            rows[k] = np.column_stack([P, state.delta_max, state.P_max, state.delta_res, state.unloading_stiffness,
                                       state.unloading_exponent])
    return rows


def random_histories(seed: int, contacts: int = 12, cycles: int = 6, steps: int = 12) -> np.ndarray:
    """Approaches [m], steps x contacts: per contact, cycles of loading past the last peak (an
    overload), a partial unloading to a random fraction (some below the dent: separation, some to
    negative approaches), and a reload to a random fraction of 0.5..1.5 of the peak."""
    rng = np.random.default_rng(seed)
    columns = []
    for _ in range(contacts):
        peak, path = 0.0, []
        for _ in range(cycles):
            peak = max(peak, 0.3) * rng.uniform(1.0, 4.0)
            low = rng.choice([rng.uniform(0.6, 0.98), rng.uniform(-0.2, 0.5)]) * peak
            again = rng.uniform(0.5, 1.5) * peak
            path += list(np.linspace(path[-1] if path else 0.0, peak, steps)) + list(np.linspace(peak, low, steps))
            path += list(np.linspace(low, again, steps))
            peak = max(peak, again)
        columns.append(np.minimum(path, 450.0))       # delta/delta_Y: the contact radius stays below R*
    return np.array(columns).T * PAIR.delta_Y


def edge_approaches() -> np.ndarray:
    """delta/delta_Y at first yield and at every node load of both tables (D(x) at the node, one ulp
    either side), beyond the last unloading node (the tables held) and up to 1.3x the last loading
    node (the PCHIP's straight continuation), each followed by an unloading to its dent and a reload."""
    nodes = np.unique(np.concatenate([BENT.x, PARAMS.x_unload, [60.0, 300.0]]))
    approaches = BENT.scaled_approach(nodes)
    approaches = approaches[approaches < 450.0]
    columns = []
    for d in approaches:
        for at in (np.nextafter(d, 0.0), d, np.nextafter(d, np.inf)):
            x = float(BENT.solve(np.array([at]))[0][0])
            rho = float(PARAMS.unloading_tables(x)[0])
            columns.append([0.5 * at, at, 0.5 * (1 + rho) * at, rho * at, np.nextafter(rho * at, np.inf), at,
                            1.01 * at])
    return np.array(columns).T * PAIR.delta_Y


@pytest.mark.parametrize("deltas", [random_histories(seed) for seed in (1, 2, 3)] + [edge_approaches()],
                         ids=["random1", "random2", "random3", "table-edges"])
def test_the_c_kernel_and_the_native_backend_follow_the_scalar_specification(c_caller, deltas):
    """Force and every history field within 1e-12 relative of reference.vz_unload_step, from the C
    caller's nfd_step and from the native backend. Two quantities are differences of nearly equal
    numbers, measured on their natural scale instead: the force just above the dent, from a gap of a
    few ulps (within 1e-12 P_Y), and the dent rho(x_m) delta_max just past first yield, where rho is
    small (within 1e-12 delta_max). Measured: force 6e-13 relative, dent 2e-14 delta_max, K_u 1e-13."""
    expected = spec(deltas)
    status, c_rows = run_c(c_caller, deltas)
    assert np.all(status == 0)
    for rows in (c_rows, run_native(deltas)):
        np.testing.assert_allclose(rows[..., 0], expected[..., 0], rtol=RTOL, atol=RTOL * PAIR.P_Y)
        np.testing.assert_array_less(np.abs(rows[..., 3] - expected[..., 3]), RTOL * expected[..., 1] + 1e-300)
        for column in (1, 2, 4, 5):         # delta_max, P_max, K_u, m
            np.testing.assert_allclose(rows[..., column], expected[..., column], rtol=RTOL, atol=1e-300)


@pytest.mark.parametrize("x_unload, dent, exponent", [
    ((1.0, 2.0), (0.0, 1.0), (1.5, 1.4)),            # dent 1: no unloading curve
    ((1.0, 2.0), (0.0, -0.1), (1.5, 1.4)),           # a negative dent
    ((1.0, 2.0), (0.0, 0.1), (1.5, 0.0)),            # exponent 0
    ((1.0, 2.0), (0.0, 0.1), (1.4, 1.4)),            # not Hertz's 3/2 at first yield
    ((1.1, 2.0), (0.0, 0.1), (1.5, 1.4)),            # not starting at first yield
    ((1.0, 1.0), (0.0, 0.1), (1.5, 1.4)),            # nodes not increasing
    ((1.0,), (0.0,), (1.5,)),                        # one node
    ((1.0, 2.0), (0.0, float("nan")), (1.5, 1.4)),   # not a number
])
def test_the_kernel_refuses_unloading_tables_that_break_its_rules(x_unload, dent, exponent):
    """nfd_unload_table_init's rules (nfdmodel.VZUnloadParams refuses the same tables first), seen
    through the binding: a ValueError naming the unloading table."""
    table = native.kernel_table(BENT) + tuple(np.array(c, dtype=float) for c in (x_unload, dent, exponent))
    kernel = native.kernel_params(PAIR)
    delta = np.array([2.0 * PAIR.delta_Y])
    with pytest.raises(ValueError, match="^unloading table out of range"):
        native._native.load_table(kernel, table, np.zeros(1, dtype=np.int64), delta, np.zeros(1), np.empty(1),
                                  *(np.empty(1) for _ in range(5)))
    with pytest.raises(ValueError):
        VZUnloadParams.from_table(BENT, x_unload, dent, exponent)
