"""What the command line answers when it refuses or reports (calib.cli, calib.commands, nfdmodel.validation
bound_text): a refusal names the input that makes the case impossible and its range, and a bound it
suggests is accepted when followed; the default impact velocities refused name --sigma-y; a pair impact's
suggested v_in is accepted by both meshes; --drops says which tests it interpolated; Ctrl-C and
``kill PID`` end a command alike ("interrupted", exit 130); every command that reports progress has
--quiet. Each case is its own test, in the style of tests/test_bad_input_cli.py.
"""
import os
import re
import signal
import subprocess
import sys
import time

import pytest

from calib.cli import build_parser, main
from nfdmodel.validation import bound_text

# "need v_max <= 0.2195", "need --counter-E >= 5.594e+09", "need dt < 7.65e-10": the flag, the side, the bound
SUGGESTION = re.compile(r"need (-{0,2}[A-Za-z_][\w-]*) ([<>]=?) ([-+0-9.eE]+)")
FLAGS = {"v_max": "--v-max", "v_in": "--v-in", "dt": "--dt"}

# (argv refused with a suggested bound): following the first suggestion, the command runs (exit 0)
SUGGESTING = [
    ["material", "--v-max", "10"],                                          # guards: the bound printed rounded down
    ["impact", "--v-in", "1000", "--dry-run"],
    ["impact", "--sigma-y", "1e6", "--v-in", "1e-9", "--dry-run"],
    ["impact", "--v-in", "1e-6", "--contact-size", "1e-4", "--dry-run"],
    ["impact", "--sigma-y", "1e11", "--dry-run"],                            # the default velocities: --sigma-y
    ["impact", "--sigma-y", "1e6", "--dry-run"],
    ["impact", "--counter-E", "2e11", "--v-in", "1e-9", "--dry-run"],        # the block's element floor
    ["impact", "--counter-E", "7e10", "--counter-R", "0.3", "--counter-rho", "2699", "--v-in", "3.5e-8",
     "--dry-run"],                                                           # a counter-sphere larger than R1
    ["impact", "--counter-E", "1e5", "--dry-run"],
    ["impact", "--counter-E", "2e11", "--counter-R", "1e-3", "--counter-rho", "7850", "--dry-run"],   # defaults
    ["calibrate", "--quiet", "--counter-E", "1e5", "--dry-run"],
    ["calibrate", "--quiet", "--counter-E", "2e11", "--counter-R", "1e-4", "--counter-rho", "7850", "--dry-run"],
    ["hertz", "--counter-E", "7e6", "--P-max", "20", "--dry-run"],
    ["hertz", "--counter-E", "2e11", "--counter-R", "1e-4", "--dry-run"],  # a counter-sphere too small
    ["calibrate", "--quiet", "--v-max", "10", "--dry-run"],                 # beyond the FE's reach
    ["calibrate", "--quiet", "--E", "100e9", "--nu", "0.34", "--sigma-y", "250e6", "--rho", "8500", "--R", "0.005",
     "--v-max", "10", "--dry-run"],               # beyond the estimating law's domain, inside the finite FE's reach
    ["collide", "--v-in", "0.1", "--dt", "1e-3"],
]


@pytest.mark.parametrize("argv", SUGGESTING, ids=[" ".join(a) for a in SUGGESTING])
def test_a_suggested_bound_is_accepted_when_followed(argv, tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    assert main(argv) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "Traceback" not in err, err
    found = SUGGESTION.search(err)
    assert found, err
    name, _, value = found.groups()
    flag = FLAGS.get(name, name)
    followed = list(argv)
    if flag in followed:
        followed[followed.index(flag) + 1] = value
    else:
        followed += [flag, value]
    assert main(followed) == 0, (followed, capsys.readouterr().err)


@pytest.mark.parametrize("value, side", [(0.219558, "<="), (0.219558, ">="), (1.00049e-9, ">="), (99999.9, "<="),
                                         (1.2345e8, ">="), (0.2196, "<="), (-3.14159, "<=")])
def test_a_printed_bound_lies_inside(value, side):
    text = bound_text(value, side)
    assert (float(text) <= value) if side == "<=" else (float(text) >= value), text
    assert abs(float(text) / value - 1.0) < 2e-3, text          # four digits: the nearest inside


@pytest.mark.parametrize("sigma_y, side", [("1e11", "<="), ("3e8", "<="), ("1e6", ">=")])
def test_the_default_impact_velocities_name_the_yield_stress(sigma_y, side, capsys):
    """No --v-in: the study's velocities are multiples of v_Y, so a material whose study the FE
    cannot run is --sigma-y out of range (with E as given), never a --v-in the user did not type."""
    assert main(["impact", "--sigma-y", sigma_y, "--dry-run"]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and err.startswith("nfdcal impact: error: --sigma-y out of range"), err
    assert f"need --sigma-y {side} " in err and "or give --v-in" in err


def test_drops_say_which_tests_were_interpolated(tmp_path):
    """More distinct velocities than the FE runs: each test off the FE's velocities is marked, and
    the summary line says how many and by which rule; e at an FE velocity is the FE's own."""
    from calib.commands.impact import drop_lines
    from calib.studies import impact_drops

    v = [0.01 * 1.5 ** k for k in range(impact_drops.MOST_VELOCITIES + 3)]
    path = tmp_path / "drops.csv"
    path.write_text("v_in,e\n" + "".join(f"{x!r},0.8\n" for x in v))
    fe = impact_drops.velocities(impact_drops.read(path))
    assert len(fe) == impact_drops.MOST_VELOCITIES
    records = [{"v_in": x, "e": 0.9 - 0.01 * k, "P_max": 100.0 * (k + 1), "contact_time": 1e-4} for k, x in enumerate(fe)]
    rows = impact_drops.compare(impact_drops.read(path), records)
    at_fe = [r for r in rows if not r["interpolated"]]
    assert {r["v_in"] for r in at_fe} == {v[0], v[-1]}                 # the range's ends are FE velocities
    assert all(r["e_fe"] == records[0 if r["v_in"] == v[0] else -1]["e"] for r in at_fe)
    lines = drop_lines(path, records, tmp_path)
    assert f"{len(v) - 2} of the {len(v)} tests against the FE interpolated" in lines[-1]
    assert "e linearly in log v_in" in lines[-1]
    assert "interpolated" in (tmp_path / "drops.csv").read_text().splitlines()[-len(v) - 1]
    few = [{"v_in": x, "e": 0.8} for x in v[:3]]
    assert len(drop_lines(_write(tmp_path / "few.csv", v[:3]), few, tmp_path)) == 1   # nothing interpolated: silent


def _write(path, v):
    path.write_text("v_in,e\n" + "".join(f"{x!r},0.8\n" for x in v))
    return path


@pytest.mark.skipif(not os.path.isdir("/proc"), reason="POSIX signals")
@pytest.mark.parametrize("how", [signal.SIGINT, signal.SIGTERM], ids=["SIGINT", "SIGTERM"])
def test_an_interrupted_command_says_so(how, tmp_path):
    """Ctrl-C and kill PID during an FE run outside a sweep (nfdcal hertz): one line, exit 130."""
    env = {**os.environ, "XDG_CACHE_HOME": str(tmp_path / "cache")}
    process = subprocess.Popen([sys.executable, "-m", "calib.cli", "hertz", "--steps", "1000",
                                "--out", str(tmp_path / "h"), "--quiet"], env=env, stdout=subprocess.DEVNULL,
                               stderr=subprocess.PIPE, text=True)
    # the signal lands in the FE loop: after the mesh is written (1000 loads take seconds more on an idle machine)
    deadline = time.monotonic() + 120.0
    while not list((tmp_path / "cache").rglob("*.msh")) and process.poll() is None and time.monotonic() < deadline:
        time.sleep(0.05)
    time.sleep(0.5)
    assert process.poll() is None, process.stderr.read()
    process.send_signal(how)
    process.wait(timeout=60)
    err = process.stderr.read().strip().splitlines()
    assert process.returncode == 130 and err == ["nfdcal hertz: interrupted"], (process.returncode, err)


PROGRESS_COMMANDS = ["calibrate", "hertz", "impact", "run", "stability", "table"]


@pytest.mark.parametrize("command", PROGRESS_COMMANDS)
def test_every_command_with_progress_has_quiet(command):
    actions = build_parser()._subparsers._group_actions[0].choices[command]._option_string_actions
    assert "--quiet" in actions


def test_hertz_quiet_dry_run(tmp_path, capsys):
    assert main(["hertz", "--quiet", "--dry-run", "--out", str(tmp_path / "h")]) == 0
    assert capsys.readouterr().err == ""


def test_a_warning_is_one_line_once(tmp_path, capsys):
    """The same warning issued again by later checks (the master table's window beyond the FE's
    reach, met by each estimate of the impact: three lines before) is shown once, as one line."""
    assert main(["impact", "--E", "1e6", "--sigma-y", "2e4", "--rho", "10", "--v-in", "0.1", "--dry-run",
                 "--out", str(tmp_path / "i")]) == 0
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("nfdcal impact: warning: window beyond the FE's reach"), err


def _warning_task(task: dict) -> dict:
    """A sweep task that warns on its worker (module-level: spawned workers import it)."""
    import warnings

    warnings.warn(f"worker note {task['n'] % 2}", UserWarning)
    return {"key": task["key"], "n": task["n"]}


def test_a_workers_warnings_reach_the_command(capfd):
    """Warnings issued on the sweep's worker processes are shown by the command, one line each,
    each text once (not the workers' file:line lines)."""
    import warnings

    from calib.sweep.runner import results

    tasks = [{"key": f"k{n}", "n": n} for n in range(4)]
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("default")
        rows = list(results(_warning_task, tasks, workers=2))
    assert sorted(r["n"] for r in rows) == [0, 1, 2, 3]
    assert sorted({str(w.message) for w in caught}) == ["worker note 0", "worker note 1"]
    assert "worker note" not in capfd.readouterr().err           # nothing printed by the workers themselves


@pytest.mark.skipif(not os.path.isdir("/proc"), reason="reads /proc")
def test_ctrl_c_to_the_process_group_of_a_sweep_is_one_line(tmp_path, mesh_cache):
    """A terminal's Ctrl-C reaches the sweep's workers too: they ignore it, the command ends them
    and prints one line (no worker traceback, no 'Process SpawnPoolWorker' line)."""
    from conftest import TINY_GRID_SCENE
    from test_sweep_termination import children

    scene = tmp_path / "ctrl_c.toml"
    scene.write_text(TINY_GRID_SCENE.format(name="ctrl_c", nu="[0.2, 0.3]", ratio="[300.0, 500.0, 800.0]", steps=40))
    env = {**os.environ, "XDG_CACHE_HOME": str(mesh_cache.parent / "xdg")}
    process = subprocess.Popen([sys.executable, "-m", "calib.cli", "table", str(scene), "--workers", "2", "--out",
                                str(tmp_path / "out"), "--quiet"], env=env, stdout=subprocess.DEVNULL,
                               stderr=subprocess.PIPE, text=True, start_new_session=True)
    deadline = time.time() + 60
    while time.time() < deadline and len(children(process.pid)) < 2:
        time.sleep(0.2)
    time.sleep(1.0)
    os.killpg(process.pid, signal.SIGINT)
    process.wait(timeout=60)
    assert process.returncode == 130
    err = process.stderr.read()
    assert err.strip().splitlines() == ["nfdcal table: interrupted"], err
