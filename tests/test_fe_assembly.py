"""The element-array assembly (calib.fe.element_arrays) against scikit-fem's assembly of the named
forms (calib.fe.forms): two implementations of the same integrals, equal to round-off."""
import numpy as np
import pytest
from skfem import Basis, asm

from calib.fe.axisym import quadrature_strain, to_form_layout
from calib.fe.forms import internal_force, tangent_stiffness


@pytest.fixture(scope="module")
def arrays(plastic_solver):
    return plastic_solver.elements


def random_tangent(rng, n, n_qp):
    """Symmetric positive definite (4, 4) tangents per point [Pa], like a consistent tangent."""
    A = rng.normal(size=(n, n_qp, 4, 4)) * 1e10
    return np.einsum("egij,egkj->egik", A, A) / 1e10 + 1e10 * np.eye(4)


def test_strain_equals_scikit_fem_interpolation(plastic_solver, arrays):
    u = np.random.default_rng(1).normal(size=plastic_solver.n_dofs) * 1e-6
    reference = quadrature_strain(plastic_solver.basis, u)
    assert np.allclose(arrays.strain(u), reference, rtol=0, atol=1e-12 * np.abs(reference).max())


def test_internal_force_and_tangent_of_a_subset_equal_scikit_fem(plastic_solver, arrays):
    rng = np.random.default_rng(2)
    elements = np.sort(rng.choice(plastic_solver.n_elements, size=40, replace=False))
    n_qp = plastic_solver.n_qp
    stress = rng.normal(size=(elements.size, n_qp, 4)) * 1e8
    tangent = random_tangent(rng, elements.size, n_qp)
    basis = Basis(plastic_solver.basis.mesh, plastic_solver.basis.elem,
                  intorder=plastic_solver.quadrature_order, elements=elements)
    f_reference = asm(internal_force, basis, stress=to_form_layout(stress))
    assert np.allclose(arrays.internal_force(stress, elements), f_reference, rtol=0,
                       atol=1e-12 * np.abs(f_reference).max())
    K_reference = (plastic_solver.TT @ asm(tangent_stiffness, basis, tangent=to_form_layout(tangent))
                   @ plastic_solver.T).toarray()
    K = arrays.matrix(arrays.stiffness_data(tangent, elements)).toarray()
    assert np.allclose(K, K_reference, rtol=0, atol=1e-12 * np.abs(K_reference).max())


def test_restriction_equals_slicing_and_follows_the_free_set(plastic_solver, arrays):
    rng = np.random.default_rng(3)
    data = rng.normal(size=arrays.nnz)
    K = arrays.matrix(data)
    for _ in range(2):
        free = rng.random(arrays.n_q) > 0.1
        for values in (data, 2.0 * data):   # same free set, new values: the cached selection
            assert (arrays.restricted(values, free) != arrays.matrix(values)[free][:, free]).nnz == 0
    assert arrays.matrix(data).nnz == K.nnz == arrays.nnz


def test_elastic_reduced_stiffness_equals_the_reduced_scikit_fem_matrix(elastic_solver):
    K_q = elastic_solver._linear_tangent().toarray()
    K_full = elastic_solver.elastic_stiffness()
    reference = (elastic_solver.TT @ K_full @ elastic_solver.T).toarray()
    assert np.allclose(K_q, reference, rtol=0, atol=1e-12 * np.abs(reference).max())
