"""Progress of a long command on stderr: a tqdm status line showing the latest message.

``progress_reporter(quiet, total_s)`` is a context manager that yields ``progress(message)``, the
callable that run_scene, run_table, calibrate and the studies take. On a terminal (and without
--quiet) each message replaces the previous one on a single stderr line with the elapsed time;
given an estimated total run time ``total_s`` [s] (the --dry-run plan's estimate) the line is a
bar of elapsed over estimated time with the time left. Off a terminal (a pipe, a log file, a
test) it is silent, so stdout and stderr stay machine-readable.
"""
from __future__ import annotations

import sys
import time
from collections.abc import Callable, Iterator
from contextlib import contextmanager

from tqdm import tqdm

# with an estimate: message, bar of elapsed / estimated time, time left; without: elapsed, message
WITH_TOTAL = "{desc} |{bar}| {elapsed}<{remaining}"
WITHOUT_TOTAL = "  [{elapsed}] {desc}"


@contextmanager
def progress_reporter(quiet: bool, total_s: float | None = None,
                      stream=None) -> Iterator[Callable[[str], None]]:
    """Yield ``progress(message)``: a tqdm line on ``stream`` (default stderr) when it is a
    terminal and ``quiet`` is false, else a callable that does nothing."""
    stream = sys.stderr if stream is None else stream
    if quiet or not stream.isatty():
        yield lambda message: None
        return
    total = total_s if total_s and total_s > 0 else None
    start = time.perf_counter()
    with tqdm(total=total, file=stream, unit="s", dynamic_ncols=True, leave=False,
              bar_format=WITH_TOTAL if total else WITHOUT_TOTAL) as bar:
        def progress(message: str) -> None:
            if total:   # the bar is elapsed over estimated time, so tqdm's "remaining" is the time left
                bar.update(min(time.perf_counter() - start, total) - bar.n)
            bar.set_description_str(message)

        yield progress
