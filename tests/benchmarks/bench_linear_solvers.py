"""Benchmark: sparse direct solvers on OUR matrices (not a test; prints a table).

Matrices: the elastic tangent of the hemisphere, reduced to the free dofs of a 1500 N Hertz
contact (axis and plate constrained, contact nodes inside the Hertz radius fixed), at the default
mesh and at a finer one (contact_size / 2). Each (matrix, method) runs in a fresh subprocess so
the peak-memory column (resident memory held by the factor) is not polluted.
Columns: factorisation time (best of 3) [s], solve time (one right-hand side) [s], relative
residual, memory held by the factor [MB]. Usage:

    .venv/bin/python tests/benchmarks/bench_linear_solvers.py [--methods qdldl,splu,splu-colamd,cholmod,pardiso]
"""
from __future__ import annotations

import argparse
import json
import subprocess
import sys
import tempfile
from dataclasses import replace
from pathlib import Path

import numpy as np
import scipy.sparse as sp

CHILD = r"""
import json, sys, time
import numpy as np, scipy.sparse as sp, scipy.sparse.linalg as spla
from calib.fe import linsolve
def rss_mb():
    with open("/proc/self/status") as fh:
        return next(int(l.split()[1]) for l in fh if l.startswith("VmRSS")) / 1024
A = sp.load_npz(sys.argv[1]).tocsr(); method = sys.argv[2]
b = np.random.default_rng(0).standard_normal(A.shape[0])
if method == "splu-colamd":  # scipy's default ordering, for comparison
    class F:
        method = "splu-colamd"
        def __init__(self, A): self.lu = spla.splu(A.tocsc())
        def solve(self, b): return self.lu.solve(b)
    make = F
else:
    make = lambda A: linsolve.factorize(A, method)
make(A)  # warm-up: imports, first-call allocations
fac, f = [], None
rss0 = rss_mb()
for _ in range(3):
    del f
    t = time.perf_counter(); f = make(A); fac.append(time.perf_counter() - t)
rss1 = rss_mb()
t = time.perf_counter(); x = f.solve(b); t_solve = time.perf_counter() - t
print(json.dumps({"backend": f.method, "factorize_s": min(fac), "solve_s": t_solve,
                  "residual": float(np.linalg.norm(A @ x - b) / np.linalg.norm(b)),
                  "peak_memory_MB": rss1 - rss0}))
"""


def contact_matrix(spec, P=1500.0):
    from calib.fe import ContactSolver
    from calib.fe.elastic import ElasticMaterial
    from meshes.hemisphere import hemisphere_mesh
    from nfdmodel import ContactPair, Material

    material = Material.reference()
    solver = ContactSolver(hemisphere_mesh(spec), ElasticMaterial(material.E, material.nu))
    K = solver.elastic_stiffness()
    K = (solver.TT @ K @ solver.T).tocsr()
    a = ContactPair.sphere_flat(material, spec.radius).hertz_radius(P)
    free = np.ones(solver.n_q, dtype=bool)
    free[solver.candidate_q[solver.candidate_r <= a]] = False
    free[solver.plate] = False
    return K[free][:, free].tocsr()


def main(argv=None):
    from meshes.hemisphere import HemisphereMeshSpec

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--methods", default="qdldl,splu,splu-colamd,cholmod,pardiso")
    ns = parser.parse_args(argv)
    default = HemisphereMeshSpec()
    meshes = {"default": default, "fine (h/2)": replace(default, contact_size=default.contact_size / 2)}
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for label, spec in meshes.items():
            A = contact_matrix(spec)
            path = Path(tmp) / "A.npz"
            sp.save_npz(path, A)
            for method in ns.methods.split(","):
                out = subprocess.run([sys.executable, "-c", CHILD, str(path), method],
                                     capture_output=True, text=True)
                if out.returncode:
                    rows.append({"mesh": label, "n": A.shape[0], "nnz": A.nnz, "method": method,
                                 "error": out.stderr.strip().splitlines()[-1]})
                    continue
                rows.append({"mesh": label, "n": A.shape[0], "nnz": A.nnz, "method": method,
                             **json.loads(out.stdout.strip().splitlines()[-1])})
    print(f"{'mesh':12s} {'n':>7s} {'nnz':>9s} {'method':8s} {'backend':8s} {'factorize_s':>11s}"
          f" {'solve_s':>8s} {'residual':>9s} {'peak_MB':>8s}")
    for r in rows:
        if "error" in r:
            print(f"{r['mesh']:12s} {r['n']:7d} {r['nnz']:9d} {r['method']:8s} error: {r['error']}")
            continue
        print(f"{r['mesh']:12s} {r['n']:7d} {r['nnz']:9d} {r['method']:8s} {r['backend']:8s}"
              f" {r['factorize_s']:11.4f} {r['solve_s']:8.4f} {r['residual']:9.1e}"
              f" {r['peak_memory_MB']:8.1f}")
    return rows


if __name__ == "__main__":
    main()
