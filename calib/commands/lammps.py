"""``nfdcal lammps``: the LAMMPS plugin of the laws (pair_style nfd/<law> for each law of nfd_limits.h:
nfd/vz, nfd/vz-table, nfd/hertz, nfd/thornton, nfd/walton-braun).

    nfdcal lammps build            # compile it (once per source and LAMMPS version); last line: its path
    nfdcal lammps path             # its path (compiled first if needed): plugin load $(nfdcal lammps path)
    nfdcal lammps build --out DIR  # and a copy in DIR/nfdplugin.so (a folder every MPI rank sees)

The build (compiled once per source, LAMMPS version and compiler, cached, verified before use) is
calib.lammps_plugin. nfdmodel/lammps/README.md documents the styles and has a complete input.
"""
from __future__ import annotations

import shutil
from pathlib import Path

from calib.commands.common import add_summary_arguments, print_summary
from calib.lammps_plugin import PLUGIN_NAME, build_plugin, python_preload
from nfdmodel.limits import LAW_NAMES


def add_parser(subparsers) -> None:
    parser = subparsers.add_parser("lammps", help="build the LAMMPS plugin of the laws (pair_style nfd/vz)",
                                   description=__doc__.split("\n\n")[0])
    actions = parser.add_subparsers(dest="action", required=True, metavar="ACTION")
    build = actions.add_parser("build", help="compile the plugin (cached); the last line is its path")
    build.add_argument("--force", action="store_true", help="compile even when a cached build exists")
    build.add_argument("--out", default=None, metavar="DIR",
                       help="also copy the plugin to DIR/nfdplugin.so (e.g. a folder all MPI ranks see)")
    add_summary_arguments(build, progress=False)
    build.set_defaults(run=run)
    path = actions.add_parser("path", help="print the plugin's path (compiled first if needed)")
    add_summary_arguments(path, progress=False)
    path.set_defaults(run=run)


def run(ns) -> int:
    info = build_plugin(force=getattr(ns, "force", False))
    if getattr(ns, "out", None):
        out = Path(ns.out)
        out.mkdir(parents=True, exist_ok=True)
        copy = out / PLUGIN_NAME
        shutil.copyfile(info["path"], copy)
        info["path"] = str(copy.resolve())
    if ns.action == "path":
        print_summary(ns, info, [info["path"]])
        return 0
    how = ("cached build (built before; --force rebuilds)" if info["cached"]
           else f"built in {info['build_time_s']:.1f} s")
    info["python_preload"] = python_preload()
    print_summary(ns, info, [
        f"pair styles {', '.join(f'nfd/{name}' for name in LAW_NAMES.values())}, wall fixes nfd/wall/* and "
        f"compute nfd/contacts for LAMMPS {info['lammps_version']}: {how}",
        f"compiler: {info['compiler']}",
        "load it in a LAMMPS input with: plugin load <path below> (newton off, atom_style sphere)",
        f"from Python's lammps module: {info['python_preload']}",
        info["path"]])
    return 0
