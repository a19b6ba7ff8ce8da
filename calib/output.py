"""Writing results: where they go, atomic files, and the stamp (commit, wall time, mesh) each carries.

A result file is written to a temporary name in the same folder and renamed into place, so a
run killed midway never leaves a half-written file.
"""
from __future__ import annotations

import contextlib
import csv
import ctypes
import errno
import fcntl
import io
import json
import math
import os
import platform
import shutil
import subprocess
import tempfile
from datetime import datetime, timezone
from importlib.metadata import PackageNotFoundError, version
from pathlib import Path
from typing import Any, Iterable, Mapping, Sequence

import numpy as np

# Where results go unless the user names a folder: ./results under the CURRENT directory (a
# relative path, resolved when a file is written), never next to the installed package.
RESULTS = Path("results")
# The source checkout this package runs from, if any (an editable install or a clone on
# sys.path); None for an installed wheel.
_PACKAGE_ROOT = Path(__file__).resolve().parent.parent


def display_path(path) -> str:
    """``path`` relative to the current directory when it lies below it, else absolute."""
    resolved = Path(path).resolve()
    try:
        return str(resolved.relative_to(Path.cwd().resolve()))
    except ValueError:
        return str(resolved)


def _checkout_root() -> Path | None:
    """The git work tree whose tracked files include this module, or None (installed wheel)."""
    try:
        top = subprocess.run(["git", "rev-parse", "--show-toplevel"], cwd=_PACKAGE_ROOT,
                             capture_output=True, text=True, check=True).stdout.strip()
        tracked = subprocess.run(["git", "ls-files", "--error-unmatch", "calib/output.py"],
                                 cwd=top, capture_output=True, text=True)
    except (OSError, subprocess.CalledProcessError):
        return None
    root = Path(top)
    if tracked.returncode != 0 or not (root / "calib" / "output.py").resolve() == Path(__file__).resolve():
        return None
    return root


def package_version() -> str:
    """The installed distribution's version ("unknown" when not installed)."""

    try:
        return version("nfdcal")
    except PackageNotFoundError:
        return "unknown"


# what the provenance's "-dirty" watches: the code, not results/ or calib/data/ (rewritten by a run)
CODE_PATHS = ("calib/*.py", "calib/*/*.py", "calib/scenes/builtin", "meshes", "nfdmodel", "pyproject.toml")


def git_commit() -> str:
    """Provenance of the code: the git commit (``-dirty`` if tracked code changed: the packages and
    pyproject.toml, not the results and data a regeneration rewrites) when running from a
    checkout, else ``nfdcal <version>`` of the installed package."""
    root = _checkout_root()
    if root is None:
        return f"nfdcal {package_version()}"
    try:
        sha = subprocess.run(["git", "rev-parse", "HEAD"], cwd=root, capture_output=True,
                             text=True, check=True).stdout.strip()
        dirty = subprocess.run(["git", "status", "--porcelain", "--untracked-files=no", "--",
                                *CODE_PATHS], cwd=root, capture_output=True, text=True,
                               check=True).stdout.strip()
        return sha + ("-dirty" if dirty else "")
    except (OSError, subprocess.CalledProcessError):
        return f"nfdcal {package_version()}"


def stamp(wall_time_s: float, mesh: Mapping[str, Any] | None = None, **extra: Any) -> dict:
    """Provenance of a result: commit, wall time [s], mesh description, date, machine."""
    out = {
        "git_commit": git_commit(),
        "wall_time_s": round(float(wall_time_s), 4),
        "created_utc": datetime.now(timezone.utc).isoformat(timespec="seconds"),
        "machine": f"{platform.node()} ({os.cpu_count()} cores, Python {platform.python_version()})",
    }
    if mesh is not None:
        out["mesh"] = dict(mesh)
    out.update(extra)
    return out


def _to_jsonable(obj: Any) -> Any:
    if isinstance(obj, Mapping):
        return {str(k): _to_jsonable(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [_to_jsonable(v) for v in obj]
    if isinstance(obj, np.ndarray):
        return _to_jsonable(obj.tolist())
    if isinstance(obj, (np.floating, float)):
        value = float(obj)
        if not math.isfinite(value):
            raise ValueError(f"refusing to write a non-finite number ({value}) to a result file")
        return value
    if isinstance(obj, np.integer):
        return int(obj)
    if isinstance(obj, np.bool_):
        return bool(obj)
    if isinstance(obj, Path):
        return str(obj)
    return obj


def to_json(obj: Any) -> str:
    """JSON text of ``obj`` (numpy scalars and arrays converted; NaN and inf rejected)."""
    return json.dumps(_to_jsonable(obj), indent=2, allow_nan=False) + "\n"


def _umask() -> int:
    mask = os.umask(0)        # the only way to read it: set and restore at once
    os.umask(mask)
    return mask


def new_file_mode() -> int:
    """The permission bits a new file gets under the user's umask (0o666 & ~umask)."""
    return 0o666 & ~_umask()


def writable_target(path: str | os.PathLike) -> Path:
    """The file that writing ``path`` replaces: ``path`` itself, or the file a symbolic link
    points to (written through, the link kept). OSError naming ``path`` as given if it is, or
    points to, anything but a regular file (a folder, a FIFO, a device): those are never
    replaced."""
    given = Path(path)
    target = given.resolve() if given.is_symlink() else given
    if target.exists() and not target.is_file():
        kind = ("a folder" if target.is_dir() else "a FIFO" if target.is_fifo() else
                "a device" if target.is_block_device() or target.is_char_device() else
                "a socket" if target.is_socket() else "not a regular file")
        via = f" (a link to {target})" if target != given else ""
        raise OSError(f"cannot write {given}{via}: it is {kind}; give the path of a file")
    return target


def atomic_write_bytes(path: str | os.PathLike, data: bytes) -> Path:
    """Write ``data`` to ``path`` atomically (temporary file in the same folder, then rename),
    with the user's umask; a symbolic link is written through. Only a regular file is ever
    replaced (``writable_target``); an OS error names ``path``, never the temporary file."""
    given = Path(path)
    path = writable_target(given)
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".tmp")
    except OSError as exc:
        raise OSError(f"cannot write {given}: {exc.strerror or exc}") from None
    try:
        with os.fdopen(fd, "wb") as fh:
            fh.write(data)
            fh.flush()
            os.fsync(fh.fileno())
        os.chmod(tmp, new_file_mode())  # mkstemp makes 0600: follow the umask like open() would
        os.replace(tmp, path)
    except BaseException as exc:
        try:
            os.unlink(tmp)
        except FileNotFoundError:
            pass
        if isinstance(exc, OSError):
            raise OSError(f"cannot write {given}: {exc.strerror or exc}") from None
        raise
    return given


_RENAME_EXCHANGE = 2          # renameat2 flag (Linux >= 3.15): swap two paths in one step
_AT_FDCWD = -100


def exchange_paths(first: Path, second: Path) -> bool:
    """Swap two existing paths in one atomic step (Linux renameat2 with RENAME_EXCHANGE): any
    reader sees either the old or the new entry under each name, never neither. False where the
    C library, kernel or file system does not offer it; nothing is changed then."""
    try:
        libc = ctypes.CDLL(None, use_errno=True)
        renameat2 = libc.renameat2
    except (OSError, AttributeError):
        return False
    renameat2.argtypes = [ctypes.c_int, ctypes.c_char_p, ctypes.c_int, ctypes.c_char_p, ctypes.c_uint]
    if renameat2(_AT_FDCWD, os.fsencode(first), _AT_FDCWD, os.fsencode(second), _RENAME_EXCHANGE) == 0:
        return True
    code = ctypes.get_errno()
    if code in (errno.EINVAL, errno.ENOSYS, errno.EOPNOTSUPP):
        return False
    raise OSError(code, os.strerror(code), str(second))


def _manifest(name: str) -> str:
    return f".{name}.files"


def _carry_over(folder: Path, staging: Path, stale: set[str]) -> None:
    """Give ``staging`` every entry of ``folder`` that the new results do not replace (hard links,
    or copies where the file system has none), so that swapping the two folders keeps the user's
    other files; the files in ``stale`` (relative paths: the previous set of the same name that
    the new one does not write) are left behind. A new file whose old name is a symbolic link to
    a file is written through the link (``writable_target``), and the link itself is carried over."""
    for old in sorted(folder.rglob("*")):
        relative = old.relative_to(folder)
        new = staging / relative
        if relative.as_posix() in stale and not new.exists():
            continue
        if old.is_symlink():
            if new.exists() and not new.is_symlink() and new.is_file():
                os.replace(new, writable_target(old))
            if not new.is_symlink():
                new.parent.mkdir(parents=True, exist_ok=True)
                os.symlink(os.readlink(old), new)
        elif old.is_dir():
            if new.exists() and not new.is_dir():
                raise OSError(f"cannot write {old}: it is a folder; give the path of a file")
            new.mkdir(parents=True, exist_ok=True)
            shutil.copymode(old, new)
        elif not new.exists():
            new.parent.mkdir(parents=True, exist_ok=True)
            try:
                os.link(old, new)
            except OSError:
                shutil.copy2(old, new)
        else:
            writable_target(old)                 # a FIFO, a device, ... is never replaced


@contextlib.contextmanager
def all_or_nothing(folder: str | os.PathLike, name: str | None = None):
    """A staging folder for a set of results that belong together: write into the folder this
    yields. When the block ends without an error, the staging folder receives the old folder's
    other files (hard links) and the two are swapped in one atomic rename (``exchange_paths``),
    so that ``folder`` holds either the whole old set or the whole new one, at any instant. An
    error, Ctrl-C or kill before the swap leaves ``folder`` as it was; one after it leaves the new
    set. A symbolic link to a folder is written through (the folder it points to is swapped).
    Where the platform cannot swap (no renameat2), the old folder is renamed aside, the new one
    renamed in and the old one removed: a kill between those two renames leaves the old set
    under ``.NAME.*.old`` beside ``folder`` and no ``folder``.

    ``name`` (e.g. "calibration") makes the files a named set: the set's file list is kept in
    ``folder/.<name>.files``, and the files of the previous set of that name that the new one
    does not write are removed by the swap (a calibration with other peaks leaves no stale path
    files), while every other file in ``folder`` stays."""
    folder = Path(folder)
    real = folder.resolve() if folder.is_symlink() else folder
    if real.exists() and not real.is_dir():
        raise OSError(f"cannot write into {folder}: it is not a folder")
    try:
        real.parent.mkdir(parents=True, exist_ok=True)
        staging = Path(tempfile.mkdtemp(prefix=f".{real.name}.", suffix=".staging", dir=real.parent))
        os.chmod(staging, real.stat().st_mode & 0o7777 if real.exists() else 0o777 & ~_umask())
    except OSError as exc:
        raise OSError(f"cannot write into {folder}: {exc.strerror or exc}") from None
    try:
        yield staging
        try:
            stale: set[str] = set()
            if name is not None:
                written = sorted(f.relative_to(staging).as_posix() for f in staging.rglob("*") if f.is_file())
                previous = real / _manifest(name)
                if previous.is_file():
                    try:
                        stale = set(json.loads(previous.read_text(encoding="utf-8"))) - set(written)
                    except (ValueError, TypeError):
                        stale = set()               # an unreadable list: keep every old file
                (staging / _manifest(name)).write_text(json.dumps(written, indent=0), encoding="utf-8")
            if not real.exists():
                os.rename(staging, real)
                return
            _carry_over(real, staging, stale)
            if not exchange_paths(staging, real):
                aside = Path(tempfile.mkdtemp(prefix=f".{real.name}.", suffix=".old", dir=real.parent))
                os.rename(real, aside / real.name)
                os.rename(staging, real)
                shutil.rmtree(aside, ignore_errors=True)
        except OSError as exc:
            raise OSError(f"cannot write into {folder}: {exc.strerror or exc}") from None
    finally:
        shutil.rmtree(staging, ignore_errors=True)     # after a swap: the old set


@contextlib.contextmanager
def one_writer(folder: str | os.PathLike, flag: str = "--out"):
    """Hold the results folder ``folder`` for this process: a second nfdcal run that asks for it
    meanwhile gets an OSError at once naming the folder and the process holding it (an advisory
    lock, ``flock`` on ``.<folder name>.lock`` beside the folder, released when the block ends or
    the process dies)."""
    folder = Path(folder)
    real = folder.resolve() if folder.is_symlink() else folder
    lock = real.parent / f".{real.name}.lock"
    while True:                         # the lock file is removed at the end: lock the file the path names
        try:
            real.parent.mkdir(parents=True, exist_ok=True)
            handle = os.open(lock, os.O_RDWR | os.O_CREAT, 0o666)
        except OSError as exc:
            raise OSError(f"cannot write into {folder}: {exc.strerror or exc}") from None
        try:
            fcntl.flock(handle, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            holder = os.pread(handle, 32, 0).decode("ascii", "replace").strip() or "unknown"
            os.close(handle)
            raise OSError(f"cannot write into {folder}: another nfdcal run (process {holder}) is writing there; "
                          f"wait for it to finish or give another {flag}") from None
        try:
            if os.fstat(handle).st_ino == os.stat(lock).st_ino:
                break
        except FileNotFoundError:
            pass
        os.close(handle)                # removed by the run that held it: take the new one
    try:
        os.ftruncate(handle, 0)
        os.pwrite(handle, str(os.getpid()).encode("ascii"), 0)
        yield real
    finally:
        with contextlib.suppress(OSError):
            os.unlink(lock)
        os.close(handle)


def atomic_write_text(path: str | os.PathLike, text: str) -> Path:
    return atomic_write_bytes(path, text.encode("utf-8"))


def write_json(path: str | os.PathLike, obj: Any) -> Path:
    return atomic_write_text(path, to_json(obj))


def write_csv(path: str | os.PathLike, rows: Sequence[Mapping[str, Any]],
              columns: Iterable[str] | None = None, comment: str | None = None) -> Path:
    """Write a list of records as CSV. ``comment`` lines (e.g. the stamp) go first, prefixed '#'."""
    columns = list(columns) if columns is not None else (list(rows[0].keys()) if rows else [])
    buf = io.StringIO()
    if comment:
        for line in comment.splitlines():
            buf.write(f"# {line}\n")
    writer = csv.DictWriter(buf, fieldnames=columns, extrasaction="ignore", lineterminator="\n")
    writer.writeheader()
    for row in rows:
        writer.writerow({k: _format_cell(row.get(k)) for k in columns})
    return atomic_write_text(path, buf.getvalue())


def _format_cell(value: Any) -> Any:
    if isinstance(value, (float, np.floating)):
        return repr(float(value))
    if isinstance(value, np.integer):
        return int(value)
    return value


def stamp_comment(st: Mapping[str, Any]) -> str:
    """One-line-per-key text of a stamp, for CSV headers."""
    return "\n".join(f"{k}: {json.dumps(_to_jsonable(v))}" for k, v in st.items())


def save_figure(fig, path: str | os.PathLike, dpi: int = 130) -> Path:
    """Save a matplotlib figure atomically as PNG and close it."""
    plt = pyplot()

    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=dpi, bbox_inches="tight")
    plt.close(fig)
    return atomic_write_bytes(path, buf.getvalue())


def pyplot():
    """matplotlib.pyplot on the non-interactive Agg backend (no display on CI machines); imported
    on the first plot (0.5 s that a run without plots does not pay)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt
