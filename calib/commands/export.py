"""``nfdcal export lammps``: the LAMMPS input lines of a calibrated law.

    nfdcal export lammps --params results/calibration/parameters.json
    nfdcal export lammps --params P.json --type 2 --wall zlo 0.0
    nfdcal export lammps --params P.json --wall-region bowl
    nfdcal export lammps --params P.json --wall zlo 0.0 --wall-E 2.1e11 --wall-nu 0.3
    nfdcal export lammps --params pair.json --like-params-out results/calibration/like   (a counter-body table)

Prints, from a parameter file (``nfdcal calibrate``, ``nfdcal material --params-out``,
``nfdcal fit-data --params-out``), the lines that put its law into a LAMMPS input with the plugin
of ``nfdcal lammps build`` (nfdmodel/lammps/README.md):

    pair_style nfd/vz
    pair_coeff T T E nu sigma_y Ca_hat Kc_hat window [P_min/P_Y] P_max/P_Y
    fix nfd_wall all nfd/wall/vz FACE COORD E nu sigma_y Ca_hat Kc_hat window P_max/P_Y   (--wall)
    fix nfd_wall_region all nfd/wall/region/vz REGION-ID E nu ...   (--wall-region: a region's surface)

numbers in SI units to 17 significant digits (LAMMPS reads back the file's values exactly), the
window the constants were fitted on (its lower end, the lowest unloading fitted, when above first
yield: the plugin counts contacts that turn below it). The constants are the material's (Ca_hat, Kc_hat of a sphere
on a flat: the dimensionless constants transfer to any pair, nfdmodel/README.md: the dimensionless constants).
A vz-table file (its tables, too long for a line) is named by its absolute path, which the
plugin reads:

    pair_style nfd/vz-table
    pair_coeff T T file /abs/path/params.json
    fix nfd_wall all nfd/wall/vz-table FACE COORD file /abs/path/params.json              (--wall)
    fix nfd_wall_region all nfd/wall/region/vz-table REGION-ID file /abs/path/params.json (--wall-region)

and a vz-unload file (``nfdcal calibrate --ship unload``: the tables with the dent and unloading
exponent) the same way, on pair_style nfd/vz-unload and the fixes nfd/wall/vz-unload and
nfd/wall/region/vz-unload.

With --wall-E E_W --wall-nu NU_W the wall lines carry ``wall_material E_W NU_W`` after the
constants: a wall of that elastic material (E* of the sphere and the wall in series, first yield
in the sphere; nfdmodel/lammps/README.md, Walls of their own material); without them the wall is
a rigid flat.

A file calibrated on a deformable counter-body (``nfdcal calibrate --counter-E ...``) gives the
pair's law, used in place of the substitution (nfdmodel/lammps/README.md, Mixing); the like-type
lines take each material's law from the master tables. A vz file (two constants) writes them on
the lines, from the master table (``nfdcal material``):

    pair_coeff T T E nu sigma_y Ca_hat Kc_hat window W         (the sphere, master table)
    pair_coeff T2 T2 E2 nu2 sigma_y2 Ca_hat Kc_hat window W    (a sphere counter-body, type T2 = T + 1)
    pair_coeff T T2 Ca_hat Kc_hat window W                     (the pair's calibrated constants)
    fix nfd_wall all nfd/wall/vz FACE COORD E nu sigma_y Ca_hat Kc_hat window W &
        wall_material E2 nu2 pair_constants Ca_hat Kc_hat window W                 (a flat counter-body)

A vz-table file (what ``nfdcal calibrate --counter-E ...`` ships by default) names files, which
the plugin reads: the pair file itself, and a file per like type that this command writes to
``--like-params-out DIR`` (required then), ``DIR/like_type_T.json``:

    nfdcal export lammps --params pair.json --like-params-out DIR [--counter-type T2]
    pair_style nfd/vz-table
    pair_coeff T T file /abs/DIR/like_type_T.json      (the sphere, vz master table)
    pair_coeff T2 T2 file /abs/DIR/like_type_T2.json   (a sphere counter-body)
    pair_coeff T T2 file /abs/pair.json                (the pair's calibrated tables)
    fix nfd_wall all nfd/wall/vz-table FACE COORD file /abs/DIR/like_type_T.json &
        wall_material E2 nu2 pair_constants file /abs/pair.json                    (a flat counter-body)

A vz-unload file (``nfdcal calibrate --counter-E ... --ship unload``) is exported the same way on
pair_style nfd/vz-unload and the fixes nfd/wall/vz-unload, nfd/wall/region/vz-unload: its like-type
files hold the vz master table's vz-unload law (the file ``nfdcal material --v-max V --law vz-unload
--params-out`` writes), the pair file its own tables with its dent and unloading exponent.

Each like-type file is the one ``nfdcal material --v-max V --params-out`` writes for that material
and radius (calib.commands.material.vz_table_law, the same code): the vz master table's law,
a_p/a_Y and C_R against P/P_Y (and for a vz-unload pair file the dent ratio and unloading exponent
against P_max/P_Y, VZMasterTable.unload_law), declared on the whole window the table vouches for at
that material, the material's own range. That law does not depend on V (V is only checked against
the window), so no V is chosen here: the like-type law covers every impact the table covers. The
windows are compared in P/P_Y, what the plugin counts per contact: a like-type law ending below
the pair file's declared P_max/P_Y is named in one warning line (its contacts beyond are counted
by the plugin at run time). The counter-body's file states the sphere's density (the pair file
holds no other; the plugin takes each atom's mass from the input). An existing file is never
replaced unless --overwrite is given, the input --params never; every target is checked before
any is written.

An elastic sphere counter-body's own contacts need a yield stress (the plugin's elastic law,
nfd/hertz, is a pair style of its own, not a type of nfd/vz or nfd/vz-table): --counter-sigma-y
SIGMA_Y2 gives it, at least the value at which the counter-body would yield before the sphere in
the pair (A_Y(nu) sigma_Y), since the pair was calibrated with it elastic.

What the plugin cannot hold is refused in one line: an elastic sphere counter-body without
--counter-sigma-y, a flat counter-body that yields before the sphere (the plugin's
walls are elastic), a vz-table or vz-unload counter-body file without --like-params-out, a like-type
material outside the master table.

The contact models follow the constants on both lines when asked for (nfdmodel/lammps/README.md,
Friction, rolling and twisting): --mu MU gives ``tangential mindlin_rescale/force NULL 0 MU``
(--tangential another of LAMMPS's Mindlin variants, --x-gamma-t its damping), --rolling K GAMMA
MU_R ``rolling sds K GAMMA MU_R``, --twisting marshall (or sds K GAMMA MU_T), --damping MODEL VALUE
``damping viscoelastic|tsuji|coeff_restitution VALUE``.

A file that states a rate law ("rate_law": the rate-aware law on its vz or vz-table law) gives the plugin's
keyword after the constants, on the pair_coeff and the wall lines: ``rate cowper-symonds D q`` or ``rate
johnson-cook C eps_dot_0`` (``c C`` after it when the file's c is not its form's default; the relaxing form,
"form": "relaxing", adds ``relaxing K``); a counter-body file with one is refused.
"""
from __future__ import annotations

import json
import math
import re
import warnings
from pathlib import Path

from calib.commands.common import add_summary_arguments, file_hardening_line, number, print_summary

FACES = ("xlo", "xhi", "ylo", "yhi", "zlo", "zhi")
LAMMPS_ID = re.compile(r"[A-Za-z0-9_]+")      # the characters of a LAMMPS ID (region, fix, ...)


def add_parser(subparsers) -> None:
    parser = subparsers.add_parser("export", help="print the input lines of a calibrated law for a DEM engine (lammps)",
                                   description=__doc__.split("\n\n")[0])
    parser.add_argument("engine", choices=("lammps",), help="the DEM engine (lammps)")
    parser.add_argument("--params", required=True, metavar="FILE", help="a parameter file (nfdcal calibrate, ...)")
    parser.add_argument("--type", default="1", metavar="T", help="the LAMMPS atom type of the material (default 1)")
    parser.add_argument("--counter-type", default=None, metavar="T2",
                        help="the atom type of a sphere counter-body of a counter-body file (default T + 1)")
    parser.add_argument("--like-params-out", default=None, metavar="DIR",
                        help="the folder of the like-type law files of a vz-table counter-body file (like_type_T.json; "
                             "an existing file is replaced only with --overwrite)")
    parser.add_argument("--counter-sigma-y", default=None, metavar="SIGMA_Y2",
                        help="the yield stress [Pa] of the counter-body's own contacts (its like type), for a file "
                             "calibrated on an elastic sphere counter-body")
    parser.add_argument("--overwrite", action="store_true",
                        help="replace existing like_type_T.json files in --like-params-out")
    parser.add_argument("--wall", nargs=2, default=None, metavar=("FACE", "COORD"),
                        help="also the rigid flat wall fix: FACE one of xlo xhi ylo yhi zlo zhi, COORD [m]")
    parser.add_argument("--wall-region", default=None, metavar="REGION-ID",
                        help="also the wall fix of a region's surface (fix nfd/wall/region/<law>; the region defined "
                             "in the input)")
    parser.add_argument("--wall-E", default=None, metavar="E_W",
                        help="the walls' Young's modulus [Pa] (with --wall-nu: wall_material E_W NU_W; absent: a "
                             "rigid flat)")
    parser.add_argument("--wall-nu", default=None, metavar="NU_W", help="the walls' Poisson ratio (with --wall-E)")
    parser.add_argument("--mu", default=None, help="friction coefficient: tangential MODEL NULL X_GAMMA_T MU")
    parser.add_argument("--tangential", default="mindlin_rescale/force",
                        help="the Mindlin variant of --mu (default mindlin_rescale/force: the one for a plastic law)")
    parser.add_argument("--x-gamma-t", default="0", help="tangential damping of --mu (default 0)")
    parser.add_argument("--rolling", nargs=3, default=None, metavar=("K", "GAMMA", "MU_R"),
                        help="rolling sds K [N/m] GAMMA [N s/m] MU_R")
    parser.add_argument("--twisting", nargs="+", default=None, metavar="MODEL",
                        help="twisting marshall, or sds K [N m/rad] GAMMA [N m s/rad] MU_T [m]")
    parser.add_argument("--damping", nargs=2, default=None, metavar=("MODEL", "VALUE"),
                        help="damping viscoelastic C [1/(m s)], or tsuji|coeff_restitution E")
    add_summary_arguments(parser, progress=False)
    parser.set_defaults(run=run, shipped=("table", "vz_table"))   # calib.commands.targets: the tables read


def exact(value: float) -> str:
    """A float as LAMMPS reads it back exactly (17 significant digits), inf as LAMMPS' 'inf'."""
    return "inf" if math.isinf(value) else repr(float(value))


def quoted(path: str, flag: str = "--params") -> str:
    """A path as one LAMMPS word: in double quotes when it holds white space or a quote-free '#'."""
    if any(c.isspace() for c in path) or "#" in path:
        if '"' in path:
            raise ValueError(f"{flag} path out of range: a path with white space must not contain '\"', got {path}")
        return f'"{path}"'
    return path


def run(ns) -> int:
    from nfdmodel import PYTHON_LAWS, VZParams, load_parameters
    from nfdmodel.parameter_file import law_of

    atom_type = number("--type", ns.type)
    if atom_type != int(atom_type) or atom_type < 1:
        raise ValueError(f"--type out of range: need an integer >= 1 (a LAMMPS atom type), got {ns.type}")
    wall = None
    if ns.wall is not None:
        face, coord = ns.wall
        if face not in FACES:
            raise ValueError(f"--wall FACE out of range: need one of {' '.join(FACES)}, got {face!r}")
        wall = (face, number("--wall COORD", coord, unit="m"))
    if ns.wall_region is not None and not LAMMPS_ID.fullmatch(ns.wall_region):
        raise ValueError("--wall-region REGION-ID out of range: need letters, digits and underscores (a LAMMPS "
                         f"region ID), got {ns.wall_region!r}")
    params = load_parameters(ns.params)
    if law_of(params) in PYTHON_LAWS:   # a law without a compiled kernel: the plugin cannot run it
        raise ValueError(f"--params {ns.params}: law {law_of(params)!r} out of range for export lammps: the LAMMPS "
                         f"plugin does not have it (a Python-only law; nfdcal collide --params runs it); export a vz "
                         f"or vz-table file (nfdcal calibrate --ship table)")
    counter = json.loads(Path(ns.params).read_text(encoding="utf-8")).get("counter_body")
    rate = rate_keyword(ns.params)
    if counter is not None and rate is not None:
        raise ValueError(f"--params {ns.params}: a rate law on a counter-body file out of range for export lammps: "
                         f"its like-type laws come from the master tables; export a file on a rigid flat")
    if counter is not None:
        if file_hardening_line(ns.params) is not None:
            raise ValueError(f"--params {ns.params}: a hardening sphere's file on a counter-body out of range for export "
                             f"lammps: its like-type laws come from the master tables, of perfectly plastic spheres; "
                             f"export the file of each like pair's calibration (nfdcal calibrate --hardening-modulus H)")
        return run_counter(ns, params, counter, int(atom_type), wall)
    for flag, given in (("--counter-type", ns.counter_type), ("--like-params-out", ns.like_params_out),
                        ("--counter-sigma-y", ns.counter_sigma_y),
                        ("--overwrite", ns.overwrite or None)):
        if given is not None:
            raise ValueError(f"{flag} applies to a file calibrated on a counter-body; {ns.params} states none")
    wall_args = wall_material(ns)
    record = _material_of(ns.params)      # E, nu, sigma_y of the sphere (the pair holds E* only)
    window = params.window.P_max_over_P_Y if params.window is not None else math.inf
    summary = {"engine": "lammps", "params": str(ns.params), "E": record["E"], "nu": record["nu"],
               "sigma_y": record["sigma_y"], "window_P_max_over_P_Y": None if math.isinf(window) else window}
    if isinstance(params, VZParams):
        law = "vz"
        numbers = [record["E"], record["nu"], record["sigma_y"], params.Ca_hat, params.Kc_hat]
        law_args = " ".join(exact(v) for v in numbers) + f" window {window_args(params.window)}"
        summary.update(law="vz", Ca_hat=params.Ca_hat, Kc_hat=params.Kc_hat)
    else:
        law = law_of(params)            # vz-table or vz-unload: the plugin reads the file's tables
        law_args = f"file {quoted(str(Path(ns.params).resolve()))}"
        summary.update(law=law, table_nodes=len(params.x))
    if rate is not None:                # the rate-aware law on it: the keyword after the constants
        law_args += " " + rate
        summary.update(rate=rate)
    constants = law_args
    models = model_keywords(ns)
    if models:
        law_args += " " + models
        summary.update(models=models)
    kind = int(atom_type)
    lines = ["# nfdcal export lammps: " + f"{ns.params} (load the plugin first: plugin load $(nfdcal lammps path))",
             f"pair_style nfd/{law}", f"pair_coeff {kind} {kind} {law_args}"]
    hardening = file_hardening_line(ns.params)
    if hardening is not None:           # the header keeps the flow curve the law was calibrated with
        lines[0] += f"\n# calibrated with {hardening}"
        summary.update(hardening=hardening)
    wall_law_args = law_args
    if wall_args:
        wall_law_args = f"{constants} {wall_args}" + (f" {models}" if models else "")
        summary.update(wall_E=number("--wall-E", ns.wall_E), wall_nu=number("--wall-nu", ns.wall_nu))
        steer_wall(record, summary["wall_E"], summary["wall_nu"])
    if wall is not None:
        lines.append(f"fix nfd_wall all nfd/wall/{law} {wall[0]} {exact(wall[1])} {wall_law_args}")
    if ns.wall_region is not None:
        lines.append(f"fix nfd_wall_region all nfd/wall/region/{law} {ns.wall_region} {wall_law_args}")
    summary.update(type=kind, lines=lines[1:])
    print_summary(ns, summary, lines)
    return 0


def run_counter(ns, params, counter: dict, kind: int, wall) -> int:
    """The lines of a file calibrated on a counter-body (module doc): the like-type laws from the
    master tables, the pair's law on pair_coeff T T2 (a sphere) or the wall fixes (a flat)."""
    from nfdmodel import Material, VZParams
    from nfdmodel.materials import first_to_yield
    from nfdmodel.parameter_file import law_of

    law = "vz" if isinstance(params, VZParams) else law_of(params)      # vz, vz-table or vz-unload
    if ns.wall_E is not None or ns.wall_nu is not None:
        raise ValueError(f"--wall-E, --wall-nu out of range: {ns.params} states the counter-body's material (the "
                         f"wall's); leave them out")
    if law == "vz" and (ns.like_params_out is not None or ns.overwrite):
        raise ValueError(f"--like-params-out, --overwrite apply to a vz-table or vz-unload file calibrated on a "
                         f"counter-body; "
                         f"{ns.params} is a vz law, whose like-type constants go on the pair_coeff lines")
    record = _material_of(ns.params)
    sphere = Material(record["E"], record["nu"], record["sigma_y"], record["rho"])
    window = params.window.P_max_over_P_Y if params.window is not None else math.inf
    models = model_keywords(ns)
    tail = f" {models}" if models else ""
    bodies = [(kind, sphere, record["R"], "the sphere")]      # each like type: (T, material, R [m], which)
    summary = {"engine": "lammps", "params": str(ns.params), "law": law, "type": kind, "counter_body": counter,
               "window_P_max_over_P_Y": None if math.isinf(window) else window}
    if law == "vz":
        summary.update(Ca_hat=params.Ca_hat, Kc_hat=params.Kc_hat)
    else:
        summary.update(table_nodes=len(params.x))
    if models:
        summary.update(models=models)
    if counter["shape"] == "sphere":
        if wall is not None or ns.wall_region is not None:
            raise ValueError(f"--wall, --wall-region out of range: {ns.params} calibrates the sphere on a sphere "
                             f"counter-body, not on a wall")
        counter_sigma_y = like_yield_stress(ns, counter, sphere, law)
        other = number("--counter-type", ns.counter_type) if ns.counter_type is not None else kind + 1
        if other != int(other) or other < 1 or other == kind:
            raise ValueError(f"--counter-type out of range: need an integer >= 1 other than --type {kind}, got "
                             f"{ns.counter_type}")
        other = int(other)
        # the counter-sphere's density (load_parameters requires it; the plugin takes each atom's
        # mass from the input, not from the file)
        bodies.append((other, Material(counter["E"], counter["nu"], counter_sigma_y, counter["rho"]), counter["R"],
                       "the counter-body"))
        summary.update(counter_type=other, counter_sigma_y=counter_sigma_y)
    else:
        for flag, given in (("--counter-type", ns.counter_type), ("--counter-sigma-y", ns.counter_sigma_y)):
            if given is not None:
                raise ValueError(f"{flag} out of range: {ns.params}'s counter-body is a flat (a wall fix)")
        if wall is None and ns.wall_region is None:
            raise ValueError(f"--wall out of range: {ns.params} calibrates the sphere on a flat counter-body: give "
                             f"--wall FACE COORD or --wall-region REGION-ID (the wall fix of that material)")
        if counter["sigma_y"] is not None and first_to_yield((sphere.sigma_y, sphere.nu),
                                                             (counter["sigma_y"], counter["nu"])) == 1:
            raise ValueError(f"--params out of range: {ns.params}'s flat counter-body yields before the sphere (lower "
                             f"A_Y(nu) sigma_y); the plugin's walls are elastic, their contacts yield in the sphere")
    if law == "vz":
        like = {T: like_type_args(body, R, which) for T, body, R, which in bodies}
        pair_args = f"{exact(params.Ca_hat)} {exact(params.Kc_hat)} window {window_args(params.window)}"
    else:
        pair_args = f"file {quoted(str(Path(ns.params).resolve()))}"
        like = like_type_files(ns, params, bodies, summary)
    source = {"vz": "the master table (nfdcal material)", "vz-table": "the vz master table (nfdcal material --v-max)",
              "vz-unload": "the vz master table (nfdcal material --v-max --law vz-unload)"}[law]
    lines = [f"# nfdcal export lammps: {ns.params} (load the plugin first: plugin load $(nfdcal lammps path)); "
             f"like-type laws: {source}, the pair's: the file",
             f"pair_style nfd/{law}", f"pair_coeff {kind} {kind} {like[kind]}{tail}"]
    if counter["shape"] == "sphere":
        other = summary["counter_type"]
        lines.append(f"pair_coeff {other} {other} {like[other]}{tail}")
        lines.append(f"pair_coeff {min(kind, other)} {max(kind, other)} {pair_args}")
    else:
        wall_args = (f"{like[kind]} wall_material {exact(counter['E'])} {exact(counter['nu'])} pair_constants "
                     f"{pair_args}{tail}")
        if wall is not None:
            lines.append(f"fix nfd_wall all nfd/wall/{law} {wall[0]} {exact(wall[1])} {wall_args}")
        if ns.wall_region is not None:
            lines.append(f"fix nfd_wall_region all nfd/wall/region/{law} {ns.wall_region} {wall_args}")
    summary.update(lines=lines[1:])
    print_summary(ns, summary, lines)
    return 0


def like_yield_stress(ns, counter: dict, sphere, law: str) -> float:
    """The yield stress [Pa] of a sphere counter-body's own contacts: the file's, or for an elastic
    counter-body (the pair calibrated with it elastic) --counter-sigma-y, which must not make it
    yield before the sphere in the pair (lower A_Y(nu) sigma_Y: the calibration assumed it elastic)."""
    from nfdmodel import yield_factor
    from nfdmodel.materials import yield_pressure

    given = ns.counter_sigma_y
    if counter["sigma_y"] is not None:
        if given is not None:
            raise ValueError(f"--counter-sigma-y out of range: {ns.params} states the counter-body's yield stress "
                             f"({counter['sigma_y']:g} Pa); leave it out")
        return counter["sigma_y"]
    if given is None:
        raise ValueError(f"--params out of range: {ns.params}'s counter-body is elastic (counter_body.sigma_y "
                         f"null), and pair_style nfd/{law} needs its yield stress for its own contacts: give "
                         f"--counter-sigma-y SIGMA_Y2 [Pa], or calibrate with --counter-sigma-y")
    from nfdmodel.validation import bound_text

    sigma = number("--counter-sigma-y", given)
    lowest = yield_pressure(sphere.sigma_y, sphere.nu) / yield_factor(counter["nu"])
    if not sigma >= lowest:
        raise ValueError(f"--counter-sigma-y out of range: need >= {bound_text(lowest, '>=', 6)} Pa (A_Y(nu) sigma_Y at least the "
                         f"sphere's: the pair was calibrated with the counter-body elastic), got {given}")
    return sigma


def like_type_files(ns, params, bodies, summary: dict) -> dict:
    """``file PATH`` of each like type's law (module doc), of the pair file's law (vz-table or
    vz-unload, from the vz master table), written to --like-params-out DIR as like_type_T.json: every target checked before any is written, an existing file replaced only
    with --overwrite, the input never. A like law whose window ends below the pair's declared top
    (in P/P_Y, what the plugin counts) is named in one warning line."""
    from calib.commands.material import vz_table_law, write_vz_table_law
    from calib.output import writable_target
    from nfdmodel import RangeWarning
    from nfdmodel.parameter_file import law_of

    law = law_of(params)                # vz-table or vz-unload: the like types' files hold the same law
    if ns.like_params_out is None:
        raise ValueError(f"--like-params-out out of range: {ns.params} is a {law} law calibrated on a "
                         f"counter-body, and pair_style nfd/{law} takes each like type's law as a file: give "
                         f"--like-params-out DIR, where to write them (like_type_T.json)")
    folder = Path(ns.like_params_out)
    if folder.exists() and not folder.is_dir():
        raise ValueError(f"--like-params-out {folder} out of range: it is not a folder; give a folder (created "
                         f"when missing) for the like-type files")
    found, written = {}, []
    for T, body, R, which in bodies:
        try:
            found[T] = vz_table_law(body, R, law_name=law)
        except ValueError as exc:
            raise ValueError(f"the like-type law of {which} (vz master table): {exc}") from None
        target = folder / f"like_type_{T}.json"
        try:
            resolved = writable_target(target).resolve()
        except OSError as exc:
            raise ValueError(f"--like-params-out {folder}: {exc}") from None
        if resolved == Path(ns.params).resolve():
            raise ValueError(f"--like-params-out {folder} out of range: {target} is the input --params {ns.params}; "
                             f"give another folder (an input file is never overwritten)")
        if resolved.exists() and not ns.overwrite:
            raise ValueError(f"--like-params-out {folder}: {target} exists: give --overwrite to replace it (an "
                             f"existing file is never replaced unasked)")
        written.append((target, f"file {quoted(str(target.resolve()), '--like-params-out')}"))
    top = params.window.P_max_over_P_Y if params.window is not None else params.x[-1]   # the plugin's window
    laws, args = [], {}
    for (T, body, R, which), (target, args[T]) in zip(bodies, written):
        write_vz_table_law(target, found[T], body, R)
        like_window = found[T]["law"].window
        laws.append({"type": T, "file": str(target.resolve()), "window": like_window.record(),
                     "v_in_window": list(found[T]["v_in_window"])})
        if like_window.P_max_over_P_Y < top:
            warnings.warn(f"the like-type law of {which} (type {T}) ends at {like_window.P_max_over_P_Y:.4g} P_Y, "
                          f"below the pair's window ({top:.4g} P_Y): its contacts beyond are counted by the plugin",
                          RangeWarning, stacklevel=2)
    summary.update(like_type_laws=laws)
    return args


def window_args(window) -> str:
    """The plugin's window: [P_min/P_Y] P_max/P_Y, the lower end when the fit's lowest unloading is above
    first yield (contacts turning below it are counted), inf for constants that state none."""
    if window is None:
        return "inf"
    low = f"{exact(window.P_min_over_P_Y)} " if window.P_min_over_P_Y > 1.0 else ""
    return low + exact(window.P_max_over_P_Y)


def like_type_args(material, R: float, which: str) -> str:
    """E nu sigma_y Ca_hat Kc_hat window W of a material's own contacts, from the master table."""
    from calib.fit.master_table import MasterTable

    try:
        values = MasterTable.load(None).parameters(material.E, material.nu, material.sigma_y, R, material.rho)
    except ValueError as exc:
        raise ValueError(f"the like-type constants of {which} (master table): {exc}") from None
    numbers = [material.E, material.nu, material.sigma_y, values["Ca_hat"], values["Kc_hat"]]
    return " ".join(exact(v) for v in numbers) + f" window {exact(values['window']['P_max_over_P_Y'])}"


def steer_wall(record: dict, E_wall: float, nu_wall: float) -> None:
    """The substitution's measured miss for this sphere on an elastic wall (calib.fit.substitution):
    one warning line naming the pair calibration where it exceeds 2 % in e."""
    from calib.fit.counter import CounterBody
    from calib.fit.substitution import warn_substitution
    from nfdmodel import Material

    material = Material(E=record["E"], nu=record["nu"], sigma_y=record["sigma_y"], rho=record["rho"])
    warn_substitution(material, record["R"], CounterBody(E_wall, nu_wall))


def wall_material(ns) -> str:
    """``wall_material E_W NU_W`` of --wall-E --wall-nu (each within the range of nfd_limits.h), or
    "" without them (a rigid flat)."""
    from nfdmodel import limits
    from nfdmodel.validation import unit_slip

    if ns.wall_E is None and ns.wall_nu is None:
        return ""
    if ns.wall_E is None or ns.wall_nu is None:
        raise ValueError("--wall-E, --wall-nu out of range: give both (the wall's elastic material) or neither "
                         "(a rigid flat)")
    if ns.wall is None and ns.wall_region is None:
        raise ValueError("--wall-E, --wall-nu apply with --wall or --wall-region (the wall fixes)")
    E = number("--wall-E", ns.wall_E, low=0.0, unit="Pa")
    if not limits.E_MIN <= E <= limits.E_MAX:
        raise ValueError(f"--wall-E out of range for a solid: need {limits.E_MIN:g} <= --wall-E <= {limits.E_MAX:g} Pa "
                         f"(Young's modulus of solids), got {E:g}{unit_slip('E', E)}")
    nu = number("--wall-nu", ns.wall_nu, low=0.0, low_inclusive=True, high=limits.NU_MAX)
    return f"wall_material {exact(E)} {exact(nu)}"


def rate_keyword(path) -> str | None:
    """The plugin's ``rate`` keyword of the file's "rate_law" entry (nfdmodel/parameter_file.py), None without
    one: rate johnson-cook C eps_dot_0 | rate cowper-symonds D q, then ``c C`` when not the form's default and,
    for the relaxing form, ``relaxing K``."""
    from nfdmodel import limits
    from nfdmodel.parameter_file import rate_law_of_file
    from nfdmodel.strain_rate import JohnsonCook

    stated = rate_law_of_file(path)
    if stated is None:
        return None
    relaxing = stated.form == "relaxing"
    default_c = limits.RELAXING_LENGTH_FACTOR if relaxing else limits.RATE_LENGTH_FACTOR
    law, c = stated.rate_law, (default_c if stated.c is None else stated.c)
    words = (["johnson-cook", law.C, law.reference_rate] if isinstance(law, JohnsonCook) else
             ["cowper-symonds", law.D, law.q])
    text = "rate " + words[0] + " " + " ".join("inf" if math.isinf(v) else exact(v) for v in words[1:])
    text += "" if c == default_c else f" c {exact(c)}"
    k = limits.RELAXATION_STIFFNESS if stated.k is None else stated.k
    return text + (f" relaxing {exact(k)}" if relaxing else "")


def _material_of(path) -> dict:
    """The file's material record (E [Pa], nu, sigma_y [Pa]), which load_parameters has checked."""
    return json.loads(Path(path).read_text(encoding="utf-8"))["material"]


def model_keywords(ns) -> str:
    """The contact-model keywords of the flags, in LAMMPS's order, checked by nfdmodel.friction."""
    from nfdmodel.friction import Friction

    keywords, options = [], {}
    if ns.damping is not None:
        model, value = ns.damping
        options.update(damping=model, damping_value=number("--damping VALUE", value))
        keywords.append(f"damping {model} {exact(options['damping_value'])}")
    if ns.mu is not None:
        mu, x_gamma_t = number("--mu", ns.mu), number("--x-gamma-t", ns.x_gamma_t)
        options.update(tangential=ns.tangential, k_t=1.0, mu=mu, x_gamma_t=x_gamma_t)    # k_t NULL: 8 G*
        keywords.append(f"tangential {ns.tangential} NULL {exact(x_gamma_t)} {exact(mu)}")
    if ns.rolling is not None:
        k, gamma, mu_r = (number(f"--rolling {name}", value) for name, value in zip(("K", "GAMMA", "MU_R"), ns.rolling))
        options.update(rolling="sds", k_roll=k, gamma_roll=gamma, mu_roll=mu_r)
        keywords.append(f"rolling sds {exact(k)} {exact(gamma)} {exact(mu_r)}")
    if ns.twisting is not None:
        model, *values = ns.twisting
        if model == "marshall" and not values:
            options.update(twisting="marshall")
            keywords.append("twisting marshall")
        elif model == "sds" and len(values) == 3:
            k, gamma, mu_t = (number(f"--twisting sds {name}", value) for name, value in zip(("K", "GAMMA", "MU_T"),
                                                                                          values))
            options.update(twisting="sds", k_twist=k, gamma_twist=gamma, mu_twist=mu_t)
            keywords.append(f"twisting sds {exact(k)} {exact(gamma)} {exact(mu_t)}")
        else:
            raise ValueError("--twisting out of range: need 'marshall' or 'sds K GAMMA MU_T', got "
                             f"{' '.join(ns.twisting)}")
    if ns.tangential != "mindlin_rescale/force" and ns.mu is None:
        raise ValueError("--tangential applies with --mu only")
    Friction(**options)                # each value within its range, named otherwise
    return " ".join(keywords)
