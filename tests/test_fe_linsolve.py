"""The sparse direct solves (calib.fe.linsolve): every method name (installed or not) solves the
system, a missing backend or one that rejects the matrix falls back to SuperLU on the same
system, a singular matrix is a clear error (never NaN), and the numeric refactorisation equals
a fresh factorisation."""
import logging
import sys

import numpy as np
import pytest
import scipy.sparse as sp

from calib.fe.linsolve import DEFAULT_METHOD, METHODS, factorize


def stiffness_like(n=40, seed=0):
    """A sparse symmetric positive definite matrix (a 1D stiffness plus a random SPD coupling)."""
    rng = np.random.default_rng(seed)
    main = 2.0 + rng.uniform(0.0, 1.0, n)
    A = sp.diags([-np.ones(n - 1), main, -np.ones(n - 1)], [-1, 0, 1], format="lil")
    i, j = rng.integers(0, n, 2 * n), rng.integers(0, n, 2 * n)
    for a, b in zip(i, j):
        if a != b:
            A[a, b] += 0.1
            A[b, a] += 0.1
            A[a, a] += 0.1
            A[b, b] += 0.1
    return sp.csc_matrix(A)


def zero_pivot():
    """Symmetric and nonsingular (a swap block and a 2), with zeros stored on the diagonal: every
    symmetric ordering keeps them there, so LDL^T without pivoting meets a zero pivot; SuperLU
    pivots and solves it."""
    return sp.csc_matrix(([0.0, 1.0, 1.0, 0.0, 2.0], ([0, 0, 1, 1, 2], [0, 1, 0, 1, 2])), shape=(3, 3))


@pytest.mark.parametrize("method", [None, *METHODS])
def test_every_method_solves_the_system(method):
    A = stiffness_like()
    b = np.arange(1.0, A.shape[0] + 1)
    x = factorize(A, method).solve(b)
    np.testing.assert_allclose(x, np.linalg.solve(A.toarray(), b), rtol=1e-11)
    if method is None:
        assert factorize(A).method == DEFAULT_METHOD


def test_failing_backend_falls_back_to_superlu(caplog):
    A, b = zero_pivot(), np.array([1.0, 2.0, 3.0])
    with caplog.at_level(logging.INFO, logger="calib.fe.linsolve"):
        factor = factorize(A, "qdldl")
    assert factor.method == "splu" and "qdldl failed" in caplog.text
    np.testing.assert_allclose(A @ factor.solve(b), b, rtol=1e-14)
    np.testing.assert_allclose(factor.solve(b), [2.0, 1.0, 1.5], rtol=1e-14)  # by hand


def test_refactorisation_with_the_same_pattern_equals_a_fresh_one():
    A = stiffness_like(seed=2)
    B = (A + sp.diags(np.linspace(0.5, 1.5, A.shape[0]))).tocsc()  # same pattern, new values
    b = np.ones(A.shape[0])
    factor = factorize(A, "qdldl")
    assert factor.update(B)
    assert np.array_equal(factor.solve(b), factorize(B, "qdldl").solve(b))  # bit for bit
    stored = B.toarray() != 0
    i, j = next((i, j) for i in range(B.shape[0]) for j in range(i + 1, B.shape[0]) if not stored[i, j])
    C = (B + sp.csc_matrix(([0.1, 0.1], ([i, j], [j, i])), shape=B.shape)).tocsc()
    assert not factor.update(C)  # a new entry: the symbolic analysis no longer applies


def laplacian(n):
    """The 1-D Dirichlet Laplacian: symmetric positive definite, known to every solver."""
    return sp.diags([-np.ones(n - 1), 2 * np.ones(n), -np.ones(n - 1)], [-1, 0, 1], format="csc")


def test_a_missing_backend_falls_back_to_superlu(monkeypatch):
    monkeypatch.setitem(sys.modules, "qdldl", None)  # "not installed": import raises ImportError
    A = laplacian(30)
    factor = factorize(A, "qdldl")
    x = np.arange(1.0, 31.0)
    assert factor.method == "splu"
    np.testing.assert_allclose(factor.solve(A @ x), x, rtol=1e-10)


@pytest.mark.parametrize("method", [m for m in METHODS if m != "pardiso"])
def test_a_singular_matrix_is_a_clear_error_never_nan(method):
    A = laplacian(20).tolil()
    A[5, :] = 0.0
    A[:, 5] = 0.0  # a zero row and column: exactly singular
    with pytest.raises(np.linalg.LinAlgError, match="singular"):
        factorize(A.tocsc(), method)


def test_unknown_backend_is_refused():
    with pytest.raises(ValueError, match="method must be one of"):
        factorize(laplacian(3), "umfpack")
