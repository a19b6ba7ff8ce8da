"""What a command reads and where it writes: no output ever names an input, not even with --overwrite.

Every command's inputs are declared here or by the command: each input flag given (a scene by the
file its name resolves to), each table's metadata beside it (X.json for a table X.csv, which the
table's loader reads too), and the tables shipped in calib/data that a command reads when a flag is
left at its default (``parser.set_defaults(shipped=...)``: the dests of the flags whose default is a
shipped table, e.g. ("table", "vz_table"), or a function of the namespace returning them). Each
output is compared with each input as files (``os.path.samefile``: through symbolic and hard links,
and a case-insensitive file system's spellings; a path not yet there by its resolved form); an
output folder is compared itself and, for the files the command declares it writes there
(``parser.set_defaults(writes_into=...)``), each of them. A clash is one line naming the output
flag and the input (the dispatcher's exit code 2), before any work.

File outputs that a command replaces only with --overwrite (fit-data, material) are checked by
``refuse_existing``; a plot is a PNG (calib.output.save_figure), so a --plot name ending in
anything but .png is refused (``check_plot_name``) rather than given a format it is not.
"""
from __future__ import annotations

import os
from pathlib import Path

OUTPUT_FLAGS = ("out", "params_out", "master_out", "plot", "like_params_out")   # the flags that name where results go
FOLDER_FLAGS = ("out", "like_params_out")                                      # those that name a folder
INPUT_FLAGS = ("params", "table_params", "lammps_restitution", "impacts", "force_approach", "drops", "table",
               "vz_table", "pair_table", "scene", "flow_curve", "unload_params")   # the flags that name files read
TABLE_FLAGS = ("table", "vz_table", "pair_table", "master_out")   # a table CSV whose metadata is the .json beside it
SHIPPED_NAMES = {"table": "master table", "vz_table": "vz master table", "pair_table": "pair table"}


def flag(dest: str) -> str:
    """'params_out' -> '--params-out' (a positional's dest as it is)."""
    return dest if dest == "scene" else f"--{dest.replace('_', '-')}"


def shipped_table(dest: str) -> Path:
    """The real path of the shipped table a flag's default stands for (calib/data, beside the package)."""
    if dest == "table":
        from calib.fit.master_table import DEFAULT_TABLE
    elif dest == "pair_table":
        from calib.fit.pair_table import DATA_FILE as DEFAULT_TABLE
    else:
        from calib.fit.vz_master_table import DEFAULT_TABLE
    return DEFAULT_TABLE.resolve()


def _scene_file(name: str) -> Path | None:
    """The file a scene argument reads: the path, else the built-in scene of that name."""
    if Path(name).is_file():
        return Path(name)
    from calib.fit.vz_master_scene import scene_path
    from calib.scenes.schema import builtin_scenes

    return builtin_scenes().get(name) or scene_path(name)


def _with_metadata(dest: str, path: Path) -> list[Path]:
    return [path, path.with_suffix(".json")] if dest in TABLE_FLAGS and path.suffix.lower() == ".csv" else [path]


def inputs(ns) -> list[tuple[str, Path]]:
    """(how the message names it, path) of every file the command reads (module doc)."""
    found = []
    for dest in INPUT_FLAGS:
        given = getattr(ns, dest, None)
        if not isinstance(given, str) or not given:
            continue
        path = _scene_file(given) if dest == "scene" else Path(given)
        if path is not None:
            found += [(f"the input {flag(dest)} {given}" + ("" if p == path else f" (its metadata {p})"), p)
                      for p in _with_metadata(dest, path)]
    shipped = getattr(ns, "shipped", ())
    for dest in (shipped(ns) if callable(shipped) else shipped):
        if getattr(ns, dest, None) is None:
            found += [(f"the shipped {SHIPPED_NAMES[dest]} {p} (the default of {flag(dest)})", p)
                      for p in _with_metadata(dest, shipped_table(dest))]
    return found


def same_file(first: Path, second: Path) -> bool:
    """One file under two names: through links and case folding when both exist, else by resolved path."""
    try:
        if first.exists() and second.exists():
            return os.path.samefile(first, second)
    except OSError:
        pass
    return first.resolve() == second.resolve()


def outputs(ns, folders: dict[str, str] | None = None) -> list[tuple[str, str, Path]]:
    """(flag, path as given, file written) of every output path: each file flag given (a table with
    its metadata), each folder (``folders``: {dest: path} of folders the command chose itself) and
    the files the command declares it writes into it."""
    found = []
    for dest in OUTPUT_FLAGS:
        given = (folders or {}).get(dest) or getattr(ns, dest, None)
        if not isinstance(given, (str, os.PathLike)) or not str(given):
            continue
        name = flag(dest) if getattr(ns, dest, None) else f"{flag(dest)} (default)"
        given, path = str(given), Path(given)
        found += [(name, given, p) for p in _with_metadata(dest, path)]
        if dest in FOLDER_FLAGS:
            found += [(name, given, path / file) for file in getattr(ns, "writes_into", ())]
    return found


def refuse_output_over_input(ns, folders: dict[str, str] | None = None) -> None:
    """ValueError naming the output flag and the input when an output names one of the command's
    input files (module doc); ``folders`` adds output folders the command chose itself."""
    read = inputs(ns)
    for out_flag, given, written in outputs(ns, folders):
        for what, path in read:
            if same_file(written, path):
                via = "" if written == Path(given) else f" ({written} would be written)"
                raise ValueError(f"{out_flag} {given} out of range: it is {what}{via}; give another path "
                                 f"(an input file is never overwritten)")


def check_plot_name(ns) -> None:
    """A --plot name that does not end in .png: refused (the plot is a PNG image)."""
    plot = getattr(ns, "plot", None)
    if isinstance(plot, str) and plot and Path(plot).suffix.lower() != ".png":
        raise ValueError(f"--plot {plot} out of range: the plot is a PNG image; give a file name ending in .png")


def refuse_existing(ns, dests) -> None:
    """Before any work: each file output of ``dests`` names a regular file or nothing yet, an existing
    file only with --overwrite, and no two name the same file."""
    from calib import output

    given = [(flag(d), getattr(ns, d)) for d in dests if getattr(ns, d, None)]
    for i, (first, path) in enumerate(given):
        for second, other in given[i + 1:]:
            if same_file(Path(path), Path(other)):
                raise ValueError(f"{first} and {second} name the same file {path}: give two paths")
    for name, path in given:
        try:
            target = output.writable_target(path)
        except OSError as exc:
            raise ValueError(f"{name} {path}: {exc}") from None
        if target.exists() and not getattr(ns, "overwrite", False):
            raise ValueError(f"{name} {path} exists: give --overwrite to replace it (an existing file is never "
                             f"replaced unasked)")
