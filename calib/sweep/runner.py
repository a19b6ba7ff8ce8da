"""One resumable, keyed runner for every sweep: parameter tables, the master table, FE stability,
mesh ladders.

A sweep is a list of tasks, each a picklable dict with a ``"key"`` (a hash of everything that
determines its result). ``run_sweep`` reads the finished results from ``FOLDER/<key>.json``,
runs the rest (in this process, on local processes, or on a Dask distributed cluster), and writes
each result atomically to ``FOLDER/<key>.json`` the moment it is done, so an interrupted sweep
loses nothing finished and a rerun computes only what is missing. A sweep whose fit changes while
its FE does not passes ``refit``: every stored result is refitted from the FE data it keeps (no
FE; the key names the FE, the row its fit) and written back when it changed. Missing meshes are built here,
one at a time, before any worker starts (gmsh is a process-wide singleton), so workers only read
the mesh cache. A warning a worker issues is issued again in the parent (``_relaying``): the
command shows it as its own one line, the same text from several workers once.
"""
from __future__ import annotations

import contextlib
import functools
import json
import multiprocessing
import os
import signal
import threading
import time
import warnings
from dataclasses import dataclass
from pathlib import Path
from typing import Callable, Iterable, Iterator

from calib import output
from calib.interrupt import terminate_as_interrupt
from calib.optional import require
from meshes.hemisphere import hemisphere_mesh, mesh_path


@dataclass(frozen=True)
class SweepResult:
    """The rows in task order, and how many were computed in this run or reused from the folder
    (``refitted`` of them refitted from their stored FE data)."""
    rows: list
    computed: int
    reused: int
    refitted: int = 0


def cached_result(folder: Path, key: str, keep: Callable[[dict], bool]) -> dict | None:
    """The finished result ``FOLDER/<key>.json`` if it is readable and ``keep`` accepts it."""
    path = Path(folder) / f"{key}.json"
    if not path.is_file():
        return None
    try:
        row = json.loads(path.read_text(encoding="utf-8"))
    except (OSError, json.JSONDecodeError):
        return None  # unreadable (e.g. written by hand): recompute
    return row if isinstance(row, dict) and keep(row) else None


def build_meshes(specs: Iterable, progress: Callable[[str], None]) -> None:
    """Build the hemisphere meshes (meshes.hemisphere.HemisphereMeshSpec, or tuples of them) not
    yet in the cache."""
    seen = set()
    flat = [spec for item in specs for spec in (item if isinstance(item, (list, tuple)) else (item,))]
    for spec in flat:
        if spec is None or spec.cache_key() in seen:
            continue
        seen.add(spec.cache_key())
        if not mesh_path(spec).is_file():
            progress(f"meshing (contact size {spec.contact_size:.3g} m)")
            hemisphere_mesh(spec)


def results(function: Callable[[dict], dict], tasks: list, workers: int = 1,
            scheduler: str | None = None) -> Iterator[dict]:
    """Yield ``function(task)`` as tasks finish: in this process (workers = 1), on ``workers``
    local processes (spawned: no forked copies of threads or gmsh state; they end with the
    sweep, whether it finishes, is interrupted, terminated or killed), or on the Dask
    distributed cluster at ``scheduler``. ``function`` must be module-level (it is pickled)."""
    if scheduler:
        distributed = require("distributed", "dask", "a sweep on a Dask cluster (--scheduler)")
        with distributed.Client(scheduler) as client:
            for future in distributed.as_completed(client.map(function, tasks, pure=False)):
                yield future.result()
        return
    if workers <= 1 or len(tasks) <= 1:
        for task in tasks:
            yield function(task)
        return
    context = multiprocessing.get_context("spawn")
    with ignoring_ctrl_c():
        pool = context.Pool(min(workers, len(tasks)), initializer=die_with_parent, initargs=(os.getpid(),))
    try:
        with terminate_as_interrupt():
            for answer in pool.imap_unordered(functools.partial(_relaying, function), tasks):
                yield _relayed(answer)
        pool.close()
    except BaseException:               # Ctrl-C, kill PID, or the caller gave up: no orphans
        pool.terminate()
        raise
    finally:
        pool.join()


def _relaying(function: Callable[[dict], object], task: dict) -> tuple[object, list]:
    """``function(task)`` on a worker, with the warnings it issued there under the worker's
    filters: (result, [(category, text)]). A worker's stderr is not the command's: its warnings are
    the parent's to show (``_relayed``)."""
    with warnings.catch_warnings(record=True) as caught:
        result = function(task)
    return result, [(w.category, str(w.message)) for w in caught]


def _relayed(answer: tuple[object, list]) -> object:
    """The result of ``_relaying``, its warnings issued again in this process, where the command
    shows each as one line (calib.cli) and the same text from several workers once."""
    result, caught = answer
    for category, text in caught:
        warnings.warn(text, category, stacklevel=2)
    return result


OFFER_SLOTS = 8                  # tasks one background process can be offered besides its first
_CLAIMS = None                   # the worker's view of who took each offered task (see Background)


class Background:
    """The other process of ``in_background``: ``background()`` waits for its first task's result;
    ``offer(function, task)`` queues more work behind it, to be taken by whichever process gets to
    it first (work stealing), so neither core idles while the other has work."""

    def __init__(self, pool, first, claims):
        self._pool, self._first, self._claims, self._offered = pool, first, claims, 0

    def __call__(self):
        return _relayed(self._first.get())

    def offer(self, function: Callable[[dict], object], task: dict) -> Callable[[], object | None]:
        """``function(task)`` on the other process once its earlier tasks are done. Returns
        ``take()``: that result (waiting for it) when the other process has started the task,
        else None, the task then being this process's to compute (the other process skips it)."""
        if self._offered >= OFFER_SLOTS:
            return lambda: None
        slot, self._offered = self._offered, self._offered + 1
        pending = self._pool.apply_async(_claimed, (slot, function, task))   # (result, warnings)

        def take():
            with self._claims.get_lock():
                if self._claims[slot] == 0:
                    self._claims[slot] = 1          # this process's: the worker will skip it
                    return None
            return _relayed(pending.get())

        return take


class _InProcess:
    """``in_background`` without another process: the first task runs when its result is asked
    for; offered tasks are left to the caller."""

    def __init__(self, function, task):
        self._function, self._task = function, task

    def __call__(self):
        return self._function(self._task)

    @staticmethod
    def offer(function, task):
        return lambda: None


def _claimed(slot: int, function, task):
    """An offered task on the worker: computed only if the caller has not taken it back."""
    with _CLAIMS.get_lock():
        if _CLAIMS[slot] != 0:
            return None, []
        _CLAIMS[slot] = 2
    return _relaying(function, task)


def _background_worker(parent_pid: int, claims) -> None:
    global _CLAIMS
    _CLAIMS = claims
    die_with_parent(parent_pid)


@contextlib.contextmanager
def in_background(function: Callable[[dict], object], task: dict, parallel: bool = True):
    """``function(task)`` on another local process while the caller works on: yields a Background
    (call it for the result, waiting for it; ``offer`` more tasks to the same process). Runs in this
    process, when the result is asked for, if ``parallel`` is False, the machine has one core, or
    this is already a worker process (a sweep's workers are daemons, which may not start
    processes). The process is spawned and ends with the caller (finished, interrupted or killed),
    like the sweep's workers."""
    if not parallel or (os.cpu_count() or 1) < 2 or multiprocessing.current_process().daemon:
        yield _InProcess(function, task)
        return
    context = multiprocessing.get_context("spawn")
    claims = context.Array("b", OFFER_SLOTS)
    with ignoring_ctrl_c():
        pool = context.Pool(1, initializer=_background_worker, initargs=(os.getpid(), claims))
    try:
        with terminate_as_interrupt():
            yield Background(pool, pool.apply_async(_relaying, (function, task)), claims)
        pool.close()
    except BaseException:
        pool.terminate()
        raise
    finally:
        pool.join()


@contextlib.contextmanager
def ignoring_ctrl_c():
    """Workers started inside ignore Ctrl-C from their first instruction (an ignored signal stays
    ignored across the spawn's exec, before any import): a terminal sends it to its whole process
    group, and the parent alone ends the sweep, terminating its workers and saying "interrupted"
    once (no worker traceback on stderr). Main thread only (where handlers live)."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    previous = signal.signal(signal.SIGINT, signal.SIG_IGN)
    try:
        yield
    finally:
        signal.signal(signal.SIGINT, previous)


def die_with_parent(parent_pid: int) -> None:
    """Worker initializer: a daemon thread ends the worker as soon as its parent is gone (killed
    with SIGKILL, which no handler sees), so no worker computes on for nobody."""
    def watch():
        while os.getppid() == parent_pid:
            time.sleep(0.5)
        os._exit(1)

    threading.Thread(target=watch, name="die-with-parent", daemon=True).start()


def run_sweep(tasks: list, function: Callable[[dict], dict], folder: str | Path, *,
              keep: Callable[[dict], bool] = lambda row: True, mesh_of: Callable[[dict], object] = lambda task: None,
              workers: int = 1, scheduler: str | None = None, prune: bool = False,
              progress: Callable[[str], None] | None = None,
              describe: Callable[[dict], str] = lambda row: "",
              refit: Callable[[dict], dict | None] | None = None) -> SweepResult:
    """Run the tasks whose result is not yet in ``folder`` and return every task's row.

    ``function(task) -> row`` never raises (a failure is a row that ``keep`` rejects: reported,
    not stored, retried on the next run). ``keep(row)``: whether a row is a finished result worth
    storing and reusing. ``mesh_of(task)``: the mesh spec a task needs (built beforehand).
    ``prune``: delete stored results of tasks that are not in this sweep. ``progress`` receives one
    line per finished task (``describe(row)`` appended). ``refit(row)``: a stored row brought to the
    current fit from the FE data it keeps (the row itself when it is current; None when its data
    cannot give the current fit: the task runs again); a changed row is stored in place.
    """
    if scheduler:  # before any work: a missing Dask is one line, not a failure after meshing
        require("distributed", "dask", "a sweep on a Dask cluster (--scheduler)")
    say = progress or (lambda message: None)
    folder = Path(folder)
    keys = [task["key"] for task in tasks]
    if len(set(keys)) != len(keys):
        raise ValueError("sweep tasks must have distinct keys")
    rows, refitted = {}, 0
    for task in tasks:
        row = cached_result(folder, task["key"], keep)
        if row is not None and refit is not None:
            current = refit(row)
            if current is not None and current != row and keep(current):
                output.write_json(folder / f"{task['key']}.json", current)
                refitted += 1
            row = current if current is not None and keep(current) else None
        if row is not None:
            rows[task["key"]] = row
    todo = [task for task in tasks if task["key"] not in rows]
    say(f"{len(tasks)} task(s): {len(tasks) - len(todo)} already done"
        + (f" ({refitted} refitted from their stored FE data)" if refitted else "") + f", {len(todo)} to run")
    build_meshes((mesh_of(task) for task in todo), say)
    for k, row in enumerate(results(function, todo, workers, scheduler), 1):
        if keep(row):
            output.write_json(folder / f"{row['key']}.json", row)   # atomic, as soon as it is done
        rows[row["key"]] = row
        say(f"{k}/{len(todo)} done" + (f": {describe(row)}" if describe(row) else ""))
    if prune and folder.is_dir():
        for stale in folder.glob("*.json"):
            if stale.stem not in rows:
                stale.unlink()
    return SweepResult(rows=[rows[key] for key in keys], computed=len(todo),
                       reused=len(tasks) - len(todo), refitted=refitted)
