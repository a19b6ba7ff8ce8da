"""``kill PID`` (SIGTERM) stops a command or a sweep like Ctrl-C.

Inside ``terminate_as_interrupt()`` SIGTERM raises KeyboardInterrupt in the main thread, so the one
Ctrl-C path handles both: calib.cli prints "interrupted" and exits 130, calib.sweep.runner
terminates its workers; every result finished so far is already on disk (calib.output's writers
are atomic). Signal handlers belong to the main thread: elsewhere (as under a test runner's
thread) nothing changes.
"""
from __future__ import annotations

import contextlib
import signal
import threading


@contextlib.contextmanager
def terminate_as_interrupt():
    """SIGTERM raises KeyboardInterrupt while the block runs (module docstring)."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return

    def interrupt(signum, frame):
        raise KeyboardInterrupt

    previous = signal.signal(signal.SIGTERM, interrupt)
    try:
        yield
    finally:
        signal.signal(signal.SIGTERM, previous)
