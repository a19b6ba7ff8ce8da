"""The rate-aware law as a DEM code with contact models steps it (nfd_rate.h: nfd_rate_contact_params, then the
base law's nfd_step with the nfd_params at sigma_Y R, as the LAMMPS plugin does) against the same law mapped
into the base law's units (nfd_rate_step, the native backend's; tests/test_rate_aware_kernel.py checks it
against nfdmodel.reference): a C caller on nfd_kernel.c alone (-std=c99 -pedantic -Werror) over the random
load/unload/reload/separation histories of that file, both base laws and both rate laws. The two codings
agree to 1e-12 in force and history (force and dent relative to the turning point; measured: 1.7e-15 at
most), R to the bit (vz-table's unused a_e,max aside), and R = 1 gives the base law's nfd_params bit for
bit."""
import shutil
import subprocess
from pathlib import Path

import numpy as np
import pytest

import nfdmodel
from nfdmodel import native
from nfdmodel.rate_aware import RateAwareParams
from test_rate_aware_kernel import (BASES, CASES, RATE_LAWS, c_caller, c_input, random_histories,  # noqa: F401
                                    run_c, speeds_of, worst_difference)

pytestmark = [pytest.mark.laws,
              pytest.mark.skipif(native._native is None, reason="the compiled kernel is not built here")]

RTOL = 1e-12


@pytest.fixture(scope="module")
def params_caller(tmp_path_factory) -> Path:
    """The C caller of test_rate_aware_kernel.py's input, stepping nfd_rate_contact_params + nfd_step."""
    compiler = shutil.which("cc") or shutil.which("gcc")
    if compiler is None:
        pytest.skip("no C compiler")
    source = Path(nfdmodel.__file__).parent
    main = tmp_path_factory.mktemp("rate_params_c") / "rate_params.c"
    main.write_text("""
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "nfd_rate.h"
int main(void) {
  int base, law, nodes, steps, n;
  double first, second, c, m_star, v[14], x[NFD_TABLE_MAX_NODES], f[NFD_TABLE_MAX_NODES], g[NFD_TABLE_MAX_NODES];
  static nfd_table t;
  nfd_params p, scaled, unit;
  nfd_rate r;
  if (scanf("%d %d %lf %lf %lf %lf", &base, &law, &first, &second, &c, &m_star) != 6) return 1;
  for (int k = 0; k < 14; ++k) if (scanf("%lf", &v[k]) != 1) return 1;
  p.R_star = v[0]; p.E_star = v[1]; p.P_Y = v[2]; p.delta_Y = v[3]; p.a_Y = v[4]; p.p_Y = v[5];
  p.hertz_k = v[6]; p.Ca = v[7]; p.Kc = v[8]; p.window_P_max = v[9]; p.K1 = v[10]; p.K2 = v[11];
  p.c1 = v[12]; p.u_Y = v[13];
  nfd_rate_params(&p, 1.0, &unit);                      /* R = 1: p bit for bit */
  if (memcmp(&unit, &p, sizeof p) != 0) return 6;
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
      double d, P = 0.0;
      nfd_history next = h[j];
      if (scanf("%lf", &d) != 1) return 5;
      int status = nfd_rate_contact_params(&r, &p, nodes > 0 ? &t : NULL, m_star, speed[j], d, &R[j], &scaled);
      if (status == NFD_OK)
        status = nfd_step(base, d, &scaled, nodes > 0 ? &t : NULL, &h[j], &P, &next, NULL);
      printf("%d %.17g %.17g %.17g %.17g %.17g %.17g %.17g\\n", status, P, next.delta_max, next.P_max,
             next.delta_res, next.K_u, next.a_e_max, R[j]);
      h[j] = next;
    }
  free(h); free(speed); free(R);
  return 0;
}
""")
    binary = main.with_suffix("")
    subprocess.run([compiler, "-std=c99", "-Wall", "-Wextra", "-pedantic", "-Werror", "-O2", f"-I{source}",
                    str(main), str(source / "nfd_kernel.c"), "-lm", "-o", str(binary)], check=True)
    return binary


@pytest.mark.parametrize("base_law, rate", CASES)
def test_the_scaled_params_step_the_same_law(c_caller, params_caller, base_law, rate):
    params = RateAwareParams(base_law, BASES[base_law], RATE_LAWS[rate])
    deltas = random_histories(params, seed=7)
    speeds = speeds_of(deltas.shape[1], seed=8)
    code, status, mapped = run_c(c_caller, params, speeds, deltas)
    code_scaled, status_scaled, scaled = run_c(params_caller, params, speeds, deltas)
    assert code == 0 and code_scaled == 0 and (status_scaled >= 0).all()
    assert np.array_equal(scaled[..., -1], mapped[..., -1])            # R to the bit
    if base_law == "vz-table":                                          # its history keeps no a_e,max
        scaled[..., 5] = mapped[..., 5]
    assert worst_difference(scaled, mapped) <= RTOL
    assert (scaled[-1, :-1, -1] > 1.2).all() and scaled[-1, -1, -1] == 1.0
