"""The hemisphere mesh: geometry, boundaries, refinement, cache (meshes.hemisphere)."""
import numpy as np
import pytest

from meshes.hemisphere import HemisphereMeshSpec, hemisphere_mesh, load_msh, mesh_path

COARSE = HemisphereMeshSpec(radius=0.1, contact_size=2e-4, refined_radius=2e-3,
                            refined_depth=1e-3, far_size=2e-2, growth=0.3)


@pytest.fixture(scope="module")
def cache(mesh_cache):
    return mesh_cache


@pytest.fixture(scope="module")
def coarse(cache):
    return hemisphere_mesh(COARSE, cache_dir=cache)


@pytest.mark.parametrize("field, value", [("radius", -1.0), ("contact_size", 0.0),
                                          ("refined_radius", 0.2), ("far_size", 1.0),
                                          ("growth", 2.0), ("contact_size", float("nan")),
                                          ("grading", -0.1), ("grading", 1.0)])
def test_spec_rejects_bad_values_naming_the_parameter(field, value):
    with pytest.raises(ValueError, match=field):
        HemisphereMeshSpec(**{field: value})


def test_area_is_the_quarter_disc_and_elements_are_valid(coarse):
    from skfem import Basis, ElementTriP2, Functional

    basis = Basis(coarse.mesh, ElementTriP2())
    area = Functional(lambda w: 1.0 + 0.0 * w.x[0]).assemble(basis)
    R = COARSE.radius
    assert area == pytest.approx(np.pi * R ** 2 / 4, rel=1e-5)  # quadratic arcs: O((far_size/R)^4), 1.4e-6 here
    assert np.all(basis.mapping.detDF(basis.X) > 0)  # no inverted element
    # the volume of the solid hemisphere 2/3 pi R^3 via the 2 pi r weight
    volume = Functional(lambda w: 2 * np.pi * w.x[0]).assemble(basis)
    assert volume == pytest.approx(2 / 3 * np.pi * R ** 3, rel=1e-5)


def test_boundaries_match_gmsh_physical_groups(coarse):
    import meshio

    raw = meshio.read(coarse.path)
    m = coarse.mesh
    for name in ("axis", "top", "surface"):
        lines = raw.cells_dict["line3"][raw.cell_sets_dict[name]["line3"]]
        facets = coarse.boundaries[name]
        assert facets.size == lines.shape[0]
        # same end points (as coordinate pairs, order-free)
        ours = np.sort(np.round(m.p[:, m.facets[:, facets]].T.reshape(-1, 4), 12), axis=0)
        theirs = raw.points[lines[:, :2]][:, :, :2].reshape(-1, 4)
        key = lambda a: np.sort(np.sort(a.reshape(-1, 2, 2), axis=1).reshape(-1, 4), axis=0)
        np.testing.assert_allclose(key(ours), key(np.round(theirs, 12)), atol=1e-12)


def test_skfem_meshio_import_drops_quadratic_line_groups(coarse):
    """Why we identify boundaries geometrically: skfem maps only 'line' (not 'line3') facets."""
    from skfem import MeshTri2

    m = MeshTri2.load(coarse.path)
    groups = m.boundaries or {}
    assert not {"axis", "top", "surface"} <= set(groups)  # if this fails, skfem learnt line3


def test_contact_zone_is_uniformly_fine_and_far_field_coarse(coarse):
    m = coarse.mesh
    facets = coarse.boundaries["surface"]
    ends = m.p[:, m.facets[:, facets]]  # (2, 2, n)
    length = np.hypot(*(ends[:, 1] - ends[:, 0]))
    r_mid = ends[0].mean(axis=0)
    fine = r_mid < COARSE.refined_radius
    h = COARSE.contact_size
    # gmsh meets a uniform size on the arc to an integer number of segments (measured: all
    # 0.9935 h, 10 of them); the far field grows to far_size (measured: 0.992 far_size)
    assert abs(fine.sum() - COARSE.refined_radius / h) <= 1
    np.testing.assert_allclose(length[fine], h, rtol=0.02)
    assert 0.9 * COARSE.far_size < length.max() <= 1.05 * COARSE.far_size


def test_a_graded_zone_spans_every_contact_radius_with_the_same_number_of_elements(cache):
    """grading g: surface elements of size g r beyond contact_size / g (every contact radius a
    spans a / h = 1 / g of them), uniformly contact_size inside."""
    graded = HemisphereMeshSpec(radius=0.1, contact_size=5e-5, refined_radius=8e-3, refined_depth=3e-3,
                                far_size=2e-2, growth=0.3, grading=0.1)
    m = hemisphere_mesh(graded, cache_dir=cache).mesh
    facets = hemisphere_mesh(graded, cache_dir=cache).boundaries["surface"]
    ends = m.p[:, m.facets[:, facets]]
    length = np.hypot(*(ends[:, 1] - ends[:, 0]))
    r_mid = ends[0].mean(axis=0)
    core = r_mid < 0.8 * graded.contact_size / graded.grading
    np.testing.assert_allclose(length[core], graded.contact_size, rtol=0.05)
    r0 = graded.contact_size / graded.grading          # where the grading takes over
    for a in (1e-3, 2e-3, 4e-3):            # the surface elements within a: r0 / h + int_r0^a dr / (g r)
        assert abs((r_mid < a).sum() - (1.0 + np.log(a / r0)) / graded.grading) <= 1.5
    ring = (r_mid > 2e-3) & (r_mid < 6e-3)
    np.testing.assert_allclose(length[ring] / r_mid[ring], graded.grading, rtol=0.12)


def test_a_uniform_mesh_key_does_not_depend_on_the_grading_field():
    from meshes.keys import stable_key
    from meshes.hemisphere import GENERATOR_VERSION

    fields = {k: v for k, v in COARSE.__dict__.items() if k != "grading"}
    assert COARSE.cache_key() == stable_key({"spec": fields, "generator": GENERATOR_VERSION})
    assert HemisphereMeshSpec(**{**COARSE.__dict__, "grading": 0.1}).cache_key() != COARSE.cache_key()


def test_cache_reuses_rebuilds_corrupt_and_reports_missing(cache, coarse):
    path = mesh_path(COARSE, cache)
    assert path == coarse.path and path.is_file()
    mtime = path.stat().st_mtime_ns
    again = hemisphere_mesh(COARSE, cache_dir=cache)
    assert path.stat().st_mtime_ns == mtime  # reused, not rebuilt
    assert again.mesh.t.shape == coarse.mesh.t.shape
    path.write_text("$MeshFormat\ngarbage\n")
    rebuilt = hemisphere_mesh(COARSE, cache_dir=cache)
    np.testing.assert_allclose(rebuilt.mesh.p, coarse.mesh.p)
    with pytest.raises(FileNotFoundError, match="not found"):
        load_msh(cache / "does-not-exist.msh")


def test_different_specs_get_different_cache_keys():
    assert COARSE.cache_key() != HemisphereMeshSpec().cache_key()
    assert COARSE.cache_key() == HemisphereMeshSpec(**COARSE.__dict__).cache_key()


def test_cache_keys_survive_a_last_digit_change_but_not_a_real_one():
    """A library upgrade moves computed sizes by an ulp (A_Y's bounded search, numpy's cbrt): the
    key stays, so finished results stay finished; a change at 1e-9 is another mesh."""
    from meshes.keys import canonical, stable_key

    h = 0.0001131141190195884
    spec = HemisphereMeshSpec(contact_size=h)
    assert HemisphereMeshSpec(contact_size=0.00011311411901958833).cache_key() == spec.cache_key()
    assert HemisphereMeshSpec(contact_size=h * (1 + 1e-9)).cache_key() != spec.cache_key()
    assert canonical({"a": (0.1 + 0.2, [1, True, None, "x"])}) == {"a": [0.3, [1, True, None, "x"]]}
    assert stable_key({"x": 0.3}) == stable_key({"x": 0.1 + 0.2})
