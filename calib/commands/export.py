"""``nfdcal export lammps``: the LAMMPS input lines of a calibrated law.

    nfdcal export lammps --params results/calibration/parameters.json
    nfdcal export lammps --params P.json --type 2 --wall zlo 0.0

Prints, from a parameter file (``nfdcal calibrate``, ``nfdcal material --params-out``,
``nfdcal fit-data --params-out``), the lines that put its law into a LAMMPS input with the plugin
of ``nfdcal lammps build`` (nfdmodel/lammps/README.md):

    pair_style nfd/vz
    pair_coeff T T E nu sigma_y Ca_hat Kc_hat window P_max/P_Y
    fix nfd_wall all nfd/wall/vz FACE COORD E nu sigma_y Ca_hat Kc_hat window P_max/P_Y   (--wall)

numbers in SI units to 17 significant digits (LAMMPS reads back the file's values exactly), the
window the constants were fitted on. The constants are the material's (Ca_hat, Kc_hat of a sphere
on a flat: the dimensionless constants transfer to any pair, nfdmodel/README.md: the dimensionless constants).
A vz-table file (its tables, too long for a line) is named by its absolute path, which the
plugin reads:

    pair_style nfd/vz-table
    pair_coeff T T file /abs/path/params.json
    fix nfd_wall all nfd/wall/vz-table FACE COORD file /abs/path/params.json              (--wall)
"""
from __future__ import annotations

import json
import math
from pathlib import Path

from calib.commands.common import add_summary_arguments, number, print_summary

FACES = ("xlo", "xhi", "ylo", "yhi", "zlo", "zhi")


def add_parser(subparsers) -> None:
    parser = subparsers.add_parser("export", help="print the input lines of a calibrated law for a DEM engine (lammps)",
                                   description=__doc__.split("\n\n")[0])
    parser.add_argument("engine", choices=("lammps",), help="the DEM engine (lammps)")
    parser.add_argument("--params", required=True, metavar="FILE", help="a parameter file (nfdcal calibrate, ...)")
    parser.add_argument("--type", default="1", metavar="T", help="the LAMMPS atom type of the material (default 1)")
    parser.add_argument("--wall", nargs=2, default=None, metavar=("FACE", "COORD"),
                        help="also the rigid flat wall fix: FACE one of xlo xhi ylo yhi zlo zhi, COORD [m]")
    add_summary_arguments(parser, progress=False)
    parser.set_defaults(run=run)


def exact(value: float) -> str:
    """A float as LAMMPS reads it back exactly (17 significant digits), inf as LAMMPS' 'inf'."""
    return "inf" if math.isinf(value) else repr(float(value))


def quoted(path: str) -> str:
    """A path as one LAMMPS word: in double quotes when it holds white space or a quote-free '#'."""
    if any(c.isspace() for c in path) or "#" in path:
        if '"' in path:
            raise ValueError(f"--params path out of range: a path with white space must not contain '\"', got {path}")
        return f'"{path}"'
    return path


def run(ns) -> int:
    from nfdmodel import VZParams, load_parameters

    atom_type = number("--type", ns.type)
    if atom_type != int(atom_type) or atom_type < 1:
        raise ValueError(f"--type out of range: need an integer >= 1 (a LAMMPS atom type), got {ns.type}")
    wall = None
    if ns.wall is not None:
        face, coord = ns.wall
        if face not in FACES:
            raise ValueError(f"--wall FACE out of range: need one of {' '.join(FACES)}, got {face!r}")
        wall = (face, number("--wall COORD", coord, unit="m"))
    params = load_parameters(ns.params)
    record = _material_of(ns.params)      # E, nu, sigma_y of the sphere (the pair holds E* only)
    window = params.window.P_max_over_P_Y if params.window is not None else math.inf
    summary = {"engine": "lammps", "params": str(ns.params), "E": record["E"], "nu": record["nu"],
               "sigma_y": record["sigma_y"], "window_P_max_over_P_Y": None if math.isinf(window) else window}
    if isinstance(params, VZParams):
        law = "vz"
        numbers = [record["E"], record["nu"], record["sigma_y"], params.Ca_hat, params.Kc_hat]
        law_args = " ".join(exact(v) for v in numbers) + f" window {exact(window)}"
        summary.update(law="vz", Ca_hat=params.Ca_hat, Kc_hat=params.Kc_hat)
    else:
        law = "vz-table"
        law_args = f"file {quoted(str(Path(ns.params).resolve()))}"
        summary.update(law="vz-table", table_nodes=len(params.x))
    kind = int(atom_type)
    lines = ["# nfdcal export lammps: " + f"{ns.params} (load the plugin first: plugin load $(nfdcal lammps path))",
             f"pair_style nfd/{law}", f"pair_coeff {kind} {kind} {law_args}"]
    if wall is not None:
        lines.append(f"fix nfd_wall all nfd/wall/{law} {wall[0]} {exact(wall[1])} {law_args}")
    summary.update(type=kind, lines=lines[1:])
    print_summary(ns, summary, lines)
    return 0


def _material_of(path) -> dict:
    """The file's material record (E [Pa], nu, sigma_y [Pa]), which load_parameters has checked."""
    return json.loads(Path(path).read_text(encoding="utf-8"))["material"]
