"""Reading and formatting for results/README.md (calib.report.results_index): the summary files
(JSON, stamped CSV), percentages and numbers as the index prints them, Markdown tables, a
result's provenance line and the header of a section."""
from __future__ import annotations

import csv
import json
import math
from pathlib import Path


# ---------------------------------------------------------------- reading
def read_json(path: Path) -> dict | None:
    """The JSON object in ``path``, or None when the file does not exist."""
    if not path.is_file():
        return None
    try:
        return json.loads(path.read_text(encoding="utf-8"))
    except json.JSONDecodeError as exc:
        raise ValueError(f"{path}: not a JSON summary ({exc})") from None


def _number(text: str):
    try:
        value = float(text)
    except ValueError:
        return text
    return int(value) if text.lstrip("-").isdigit() else value


def read_csv(path: Path) -> tuple[dict, list[dict]] | None:
    """(stamp, rows) of a result CSV: its ``# key: json`` header lines and its records (numbers
    parsed), or None when the file does not exist."""
    if not path.is_file():
        return None
    lines = path.read_text(encoding="utf-8").splitlines()
    stamp = {}
    while lines and lines[0].startswith("#"):
        key, _, value = lines.pop(0)[1:].strip().partition(": ")
        stamp[key] = json.loads(value)
    rows = [{k: _number(v) for k, v in row.items()} for row in csv.DictReader(lines)]
    return stamp, rows


# ---------------------------------------------------------------- formatting
def pct(x: float, digits: int = 2) -> str:
    """A relative quantity as a signed percentage: 0.0052 -> '+0.52 %'."""
    return f"{100 * x:+.{digits}f} %"


def apct(x: float, digits: int = 2) -> str:
    """A relative size as an unsigned percentage: 0.0052 -> '0.52 %'."""
    return f"{100 * abs(x):.{digits}f} %"


def g(x, digits: int = 4) -> str:
    """``x`` to ``digits`` significant digits; powers of ten written out only when very small or large."""
    if x is None:
        return "-"
    if x != 0 and not 1e-3 <= abs(x) < 1e5:
        return f"{x:.{digits - 1}e}"
    return f"{x:.{digits}g}"


def num(x: float, digits: int = 3) -> str:
    """``x`` to ``digits`` significant digits, never in powers of ten (a time, a count): 1574.6 -> '1575'."""
    if x == 0:
        return "0"
    decimals = max(0, digits - 1 - math.floor(math.log10(abs(x))))
    return f"{x:.{decimals}f}"


def span(values, fmt=pct) -> str:
    """'low..high' of ``values`` in ``fmt``."""
    values = sorted(values)
    return f"{fmt(values[0])}..{fmt(values[-1])}"


def table(header: list[str], rows: list[list]) -> list[str]:
    """A Markdown table."""
    out = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    out += ["| " + " | ".join(str(c) for c in row) + " |" for row in rows]
    return out + [""]


def provenance(stamp: dict) -> str:
    """One line: the code commit, the mesh, the wall time and the date of a result."""
    parts = [f"commit `{stamp.get('git_commit', 'unknown')}`"]
    mesh = stamp.get("mesh")
    if isinstance(mesh, dict) and "key" in mesh:
        dofs = f"{mesh['dofs']} dofs, " if "dofs" in mesh else ""
        parts.append(f"mesh `{mesh['key']}` ({dofs}contact element {mesh.get('contact_size', 0):g} m)")
    elif isinstance(mesh, dict) and mesh:
        parts.append("mesh " + ", ".join(f"{k} = {json.dumps(v)}" for k, v in mesh.items()))
    if "wall_time_s" in stamp:
        reused = f", {stamp['reused']} of {stamp['computed'] + stamp['reused']} cases reused" if "reused" in stamp else ""
        parts.append(f"wall time {num(stamp['wall_time_s'])} s{reused}")
    if "created_utc" in stamp:
        parts.append(f"created {stamp['created_utc'][:10]}")
    return "Provenance: " + "; ".join(parts) + "."


def files_line(root: Path, *folders: Path) -> str:
    """The files of ``folders`` (top level, not hidden) as links relative to ``root``."""
    links = []
    for folder in folders:
        if folder.is_dir():
            rel = folder.relative_to(root).as_posix()
            names = sorted(p.name + ("/" if p.is_dir() else "") for p in folder.iterdir() if not p.name.startswith("."))
            links += [f"[`{n}`]({rel}/{n})" for n in names]
    return "Files: " + ", ".join(links) + "."


def section(title: str, folders: Path | tuple, root: Path, command: str, stamp: dict | None) -> list[str]:
    folders = folders if isinstance(folders, tuple) else (folders,)
    lines = [f"## {title}", "", files_line(root, *folders), "", f"Regenerate: `{command}`."]
    if stamp:
        lines += ["", provenance(stamp)]
    return lines + [""]


def study_header(title: str, stamp: dict, command: str) -> list[str]:
    """The title, the command that regenerates a study (its stamp's, else ``command``) and its provenance."""
    return [f"## {title}", "", f"Regenerate: `{stamp.get('command', command)}`.", "", provenance(stamp), ""]
