"""Sparse direct solves behind one tiny interface: ``factorize(A).solve(b)``.

The FE tangent is symmetric; elastic tangents (and the contact/plate-constrained blocks of them)
are positive definite, an elastoplastic consistent tangent may be only semi-definite in places.
The default backend and why are in results/linear_solvers.md (measured on our own matrices by
tests/benchmarks/bench_linear_solvers.py). Every backend falls back to SuperLU (with a symmetric
fill-reducing ordering) when it cannot factorize the matrix, so a caller never sees a backend
failure for a matrix SuperLU can solve.

Backends:
  "cholmod"  CHOLMOD supernodal Cholesky (Chen, Davis, Hager & Rajamanickam 2008) via cholespy
  "splu"     scipy SuperLU, ordering MMD_AT_PLUS_A (the matrix is symmetric)
  "qdldl"    LDL^T with AMD ordering (Stellato et al., OSQP)
  "pardiso"  MKL PARDISO via pypardiso (benchmark only: ~0.8 GB of MKL)
"""
from __future__ import annotations

import logging
from collections import OrderedDict

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

logger = logging.getLogger(__name__)

DEFAULT_METHOD = "qdldl"
METHODS = ("cholmod", "splu", "qdldl", "pardiso")


class Factorization:
    """A factorized square sparse matrix. ``solve(b)`` for b shaped (n,) or (n, k)."""

    method: str

    def solve(self, b: np.ndarray) -> np.ndarray:  # pragma: no cover - interface
        raise NotImplementedError

    def update(self, A) -> bool:
        """Refactorize in place for a matrix with the same sparsity pattern, reusing the
        ordering and symbolic analysis; False (nothing changed) when the backend cannot."""
        return False


class _SuperLU(Factorization):
    method = "splu"

    def __init__(self, A):
        self._lu = spla.splu(sp.csc_matrix(A), permc_spec="MMD_AT_PLUS_A",
                             options={"SymmetricMode": True})

    def solve(self, b):
        return self._lu.solve(np.asarray(b, dtype=float))


class _Cholmod(Factorization):
    method = "cholmod"

    def __init__(self, A):
        from cholespy import CholeskySolverD, MatrixType

        A = sp.csr_matrix(A)
        self.n = A.shape[0]
        self._chol = CholeskySolverD(self.n, A.indptr.astype(np.int32), A.indices.astype(np.int32),
                                     A.data.astype(np.float64), MatrixType.CSR)

    def solve(self, b):
        b = np.ascontiguousarray(b, dtype=np.float64)
        x = np.empty_like(b)
        self._chol.solve(b, x)
        return x


class _UpperTriangle:
    """triu(A) in CSC for the matrices of one sparsity pattern, as qdldl takes them: the permutation
    of A's data computed once, so each matrix of the pattern costs one gather (the same values in
    the same order as scipy's triu, so the factorisation is bit-identical)."""

    def __init__(self, A):
        A = sp.csr_matrix(A)
        self.indptr, self.indices = A.indptr, A.indices
        numbered = sp.csr_matrix((np.arange(1, A.nnz + 1, dtype=float), A.indices, A.indptr), shape=A.shape)
        upper = sp.triu(numbered, format="csc")
        self.select = upper.data.astype(np.int64) - 1
        self.upper_indptr, self.upper_indices, self.shape = upper.indptr, upper.indices, A.shape

    def of(self, A):
        """triu(A) in CSC, or None when A is not of this pattern."""
        if not (sp.isspmatrix_csr(A) and A.shape == self.shape and A.has_canonical_format):
            return None
        same = (A.indptr is self.indptr and A.indices is self.indices) or (
            np.array_equal(A.indptr, self.indptr) and np.array_equal(A.indices, self.indices))
        if not same:
            return None
        return sp.csc_matrix((A.data[self.select], self.upper_indices, self.upper_indptr), shape=self.shape)


class _QDLDL(Factorization):
    method = "qdldl"

    def __init__(self, A):
        import qdldl

        upper = sp.triu(A, format="csc")
        self._ldl = qdldl.Solver(upper, upper=True)
        self._pattern = (upper.indptr.copy(), upper.indices.copy())
        self._upper = None          # the gather of triu for A's pattern, built at the first update
        self._unchecked = None      # a refactorised matrix whose factor no solve has checked yet
        self._replacement = None    # its SuperLU factorisation, if qdldl's was not finite

    def update(self, A) -> bool:
        """Numeric refactorization (about 40 % of a full one on our tangents) when the
        pattern is unchanged; the result is bit-identical to a fresh factorization."""
        upper = self._upper.of(A) if self._upper is not None else None
        if upper is None:
            upper = sp.triu(A, format="csc")
            indptr, indices = self._pattern
            if not (np.array_equal(upper.indptr, indptr) and np.array_equal(upper.indices, indices)):
                return False
            if sp.isspmatrix_csr(A) and A.has_canonical_format:
                gather = _UpperTriangle(A)
                if np.array_equal(gather.upper_indptr, indptr) and np.array_equal(gather.upper_indices, indices):
                    self._upper = gather
        try:
            self._ldl.update(upper, upper=True)
        except (RuntimeError, ValueError, ArithmeticError):
            return False
        # the first solve checks the new factor (a finite solution, else SuperLU of A): the
        # probe a fresh factorisation costs (one extra solve) is saved on every Newton iteration
        self._unchecked, self._replacement = A, None
        return True

    def solve(self, b):
        if self._replacement is not None:
            return self._replacement.solve(b)
        b = np.asarray(b, dtype=float)
        x = self._ldl.solve(b) if b.ndim == 1 else np.column_stack([self._ldl.solve(np.ascontiguousarray(c))
                                                                     for c in b.T])
        if self._unchecked is not None:
            A, self._unchecked = self._unchecked, None
            if not np.all(np.isfinite(x)):
                logger.info("qdldl produced a non-finite refactorisation; falling back to SuperLU")
                try:
                    self._replacement = factorize(A, "splu")
                except np.linalg.LinAlgError:
                    return x              # singular: the caller sees the non-finite solution
                return self._replacement.solve(b)
        return x


class _Pardiso(Factorization):
    method = "pardiso"

    def __init__(self, A):
        import pypardiso

        self._solver = pypardiso.PyPardisoSolver(mtype=-2)  # real symmetric indefinite
        self._A = sp.triu(A, format="csr")
        self._solver.factorize(self._A)

    def solve(self, b):
        return self._solver.solve(self._A, np.asarray(b, dtype=float))


_BACKENDS = {"cholmod": _Cholmod, "splu": _SuperLU, "qdldl": _QDLDL, "pardiso": _Pardiso}


def factorize(A, method: str | None = None) -> Factorization:
    """Factorize the symmetric sparse matrix ``A`` with ``method`` (default DEFAULT_METHOD).

    Falls back to SuperLU when the backend is not installed or rejects the matrix (e.g. not
    positive definite for Cholesky). Raises ValueError for an unknown method and
    numpy.linalg.LinAlgError when even SuperLU finds the matrix singular.
    """
    method = DEFAULT_METHOD if method is None else method
    if method not in _BACKENDS:
        raise ValueError(f"method must be one of {METHODS}, got {method!r}")
    if method != "splu":
        try:
            factor = _BACKENDS[method](A)
            if _finite_probe(factor, A.shape[0]):
                return factor
            logger.info("%s produced a non-finite factor; falling back to SuperLU", method)
        except ImportError:
            logger.info("%s not installed; falling back to SuperLU", method)
        except (RuntimeError, ValueError, ArithmeticError) as exc:
            logger.info("%s failed (%s); falling back to SuperLU", method, exc)
    try:
        return _SuperLU(A)
    except RuntimeError as exc:  # SuperLU: "Factor is exactly singular"
        raise np.linalg.LinAlgError(f"singular matrix: {exc}") from exc


def _finite_probe(factor: Factorization, n: int) -> bool:
    """A cheap guard: CHOLMOD may return a factor with NaN instead of raising."""
    x = factor.solve(np.ones(n))
    return bool(np.all(np.isfinite(x)))


class FactorCache:
    """The factorisations of one solver's tangents, so each is computed once.

    A linear material's tangent depends only on the active set and the control: its factorisation
    is kept under ``key`` (the ``size`` most recent). A nonlinear material's changes every Newton
    iteration, but while its sparsity ``pattern`` (the constraints) repeats, the last factorisation
    is refactorised numerically only (same ordering and symbolic analysis: bit-identical to a fresh
    one, about 40 % of its cost; Factorization.update). ``count``: factorisations computed.
    """

    def __init__(self, method: str | None = None, size: int = 4):
        self.method, self.size = method, size
        self._by_key: OrderedDict = OrderedDict()
        self._last_pattern, self._last = None, None
        self.count = 0

    def cached(self, key):
        """The factorisation kept under ``key`` (None: none, or ``key`` is None)."""
        if key is None or key not in self._by_key:
            return None
        self._by_key.move_to_end(key)
        return self._by_key[key]

    def factor(self, matrix, key, pattern: bytes | None = None, wrap=None):
        """A new factorisation of ``matrix``: kept under ``key`` (a linear material), else numeric
        only when ``pattern`` repeats the last one's; ``wrap`` (optional) turns the factorisation
        into the solver returned and kept."""
        wrap = wrap or (lambda factor: factor)
        self.count += 1
        if key is None and pattern is not None and self._last_pattern == pattern and self._last.update(matrix):
            return wrap(self._last)
        factor = factorize(matrix, self.method)
        if key is None:
            self._last_pattern, self._last = pattern, factor
            return wrap(factor)
        self._by_key[key] = solver = wrap(factor)
        while len(self._by_key) > self.size:
            self._by_key.popitem(last=False)
        return solver

    def block(self, K, free, key, pattern: bytes | None = None):
        """(factorisation of K[free, free], new factorisations 0 or 1): kept under ``key`` (a linear
        material), else numeric only while ``pattern`` (the constraints that shape K) and ``free``
        repeat."""
        cached = self.cached(key)
        if cached is not None:
            return cached, 0
        pattern = None if pattern is None else pattern + free.tobytes()
        return self.factor(K[free][:, free].tocsr(), key, pattern), 1
