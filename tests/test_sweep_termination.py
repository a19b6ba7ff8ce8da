"""A sweep's workers end with it: `kill PID` (SIGTERM) stops `nfdcal table` like Ctrl-C, SIGKILL of
the parent leaves no worker computing for nobody, and a rerun resumes with nothing finished lost."""
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest
from conftest import TINY_GRID_SCENE

# ~10 s per material: longer than the checks below
SCENE = TINY_GRID_SCENE.format(name="term", nu="[0.2, 0.3]", ratio="[300.0, 800.0]", steps=40)


def children(pid: int) -> set[int]:
    """The processes whose parent is ``pid`` (from /proc)."""
    found = set()
    for entry in Path("/proc").iterdir():
        if entry.name.isdigit():
            try:
                fields = (entry / "stat").read_text().rsplit(")", 1)[1].split()
            except OSError:
                continue
            if int(fields[1]) == pid:
                found.add(int(entry.name))
    return found


def alive(pids) -> set[int]:
    out = set()
    for pid in pids:
        try:
            state = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()[0]
        except OSError:
            continue
        if state != "Z":
            out.add(pid)
    return out


def start_table(tmp_path, mesh_cache):
    scene = tmp_path / "term.toml"
    scene.write_text(SCENE)
    env = {**os.environ, "XDG_CACHE_HOME": str(mesh_cache.parent / "xdg")}
    process = subprocess.Popen([sys.executable, "-m", "calib.cli", "table", str(scene), "--workers", "2",
                                "--out", str(tmp_path / "out"), "--quiet"], env=env,
                               stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    deadline = time.time() + 60
    while time.time() < deadline and len(children(process.pid)) < 2:   # the workers are up
        time.sleep(0.2)
    time.sleep(1.0)
    return process, children(process.pid)


def wait_gone(pids, seconds=3.0):
    deadline = time.time() + seconds
    while time.time() < deadline and alive(pids):
        time.sleep(0.2)
    return alive(pids)


@pytest.mark.skipif(not Path("/proc").is_dir(), reason="reads /proc")
@pytest.mark.parametrize("how", [signal.SIGTERM, signal.SIGKILL], ids=["SIGTERM", "SIGKILL"])
def test_workers_die_with_the_sweep_and_a_rerun_resumes(tmp_path, mesh_cache, how):
    process, workers = start_table(tmp_path, mesh_cache)
    assert len(workers) >= 2, "the sweep did not start its workers"
    process.send_signal(how)
    process.wait(timeout=30)
    assert not wait_gone(workers), "workers outlived the sweep"
    if how == signal.SIGTERM:
        assert process.returncode == 130 and "interrupted" in process.stderr.read()
    finished = {p.name for p in (tmp_path / "out" / "materials").glob("*.json")}
    # the rerun keeps every finished material and computes only the rest
    rerun = subprocess.run([sys.executable, "-m", "calib.cli", "table", str(tmp_path / "term.toml"),
                            "--workers", "2", "--out", str(tmp_path / "out"), "--json"],
                           capture_output=True, text=True, timeout=600,
                           env={**os.environ, "XDG_CACHE_HOME": str(mesh_cache.parent / "xdg")})
    assert rerun.returncode == 0, rerun.stderr
    done = {p.name for p in (tmp_path / "out" / "materials").glob("*.json")}
    assert finished <= done and len(done) == 4
