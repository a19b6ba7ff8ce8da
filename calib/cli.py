"""``nfdcal``: command-line front end of the calibration pipeline and the runtime model.

Every sub-command lives in ``calib.commands``. Bad input (a ValueError from our own validation,
or an OSError such as a missing input file or an unwritable output folder) is reported as one
line on stderr with exit code 2, never a traceback; so is a usage error.

A negative value may follow its flag in any notation (``--dt -1e-6``, ``--wall zlo -1e-3``):
argparse reads a token that starts with '-' as an option unless it looks like a negative number,
and its own test for that (-1, -0.5) is widened to scientific notation (``NEGATIVE_NUMBER``), for
flags of one value and of several alike. The range checks then name what is out of range.

A warning is one line on stderr, "nfdcal COMMAND: warning: ...", each text once per command (the
sweep's workers pass theirs to the command, calib.sweep.runner).

Ctrl-C (SIGINT) and ``kill PID`` (SIGTERM) end a command alike: one line "nfdcal COMMAND:
interrupted" on stderr, exit code 130, every result finished so far kept on disk (a sweep stores
each as it finishes; calib.interrupt.terminate_as_interrupt, the one rule for a command and a sweep
run from Python).
"""
from __future__ import annotations

import argparse
import importlib
import re
import sys
import warnings

from calib.commands.targets import OUTPUT_FLAGS, check_plot_name, flag, refuse_output_over_input
from calib.interrupt import terminate_as_interrupt
from calib.optional import MissingOptionalPart

# Order is the order shown in --help: model -> FE validation -> calibration -> users.
COMMAND_MODULES = ("collide", "hertz", "calibrate", "impact", "run", "table", "material", "fit_data", "stability", "lammps",
                   "export", "results_readme")


# A negative number as a person writes it: -1, -0.5, -.5, -1e-6, -2.5E+3 (argparse's own test has no exponent).
NEGATIVE_NUMBER = re.compile(r"^-(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?$")


class _Parser(argparse.ArgumentParser):
    """argparse whose usage error is ONE line (exit code 2) and which reads a token like -1e-6
    after a flag as its value (``NEGATIVE_NUMBER``; no nfdcal flag looks like a number)."""

    def __init__(self, *args, **kwargs):
        super().__init__(*args, **kwargs)
        self._negative_number_matcher = NEGATIVE_NUMBER

    def error(self, message):
        self.exit(2, f"{self.prog}: error: {message}\n")


def build_parser() -> _Parser:
    parser = _Parser(
        prog="nfdcal",
        description="FE-calibrated elastoplastic normal contact laws for DEM (Vu-Quoc & Zhang 1999).",
    )
    sub = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")
    for name in COMMAND_MODULES:
        try:
            module = importlib.import_module(f"calib.commands.{name}")
        except ModuleNotFoundError as exc:
            if exc.name and exc.name.startswith("calib.commands"):
                continue  # sub-command not built yet
            raise
        module.add_parser(sub)
    return parser


def name_the_output_flag(ns, message: str) -> str:
    """``message`` led by the output flag whose path it names ('--out results/x: cannot write
    results/x/...'), so an error about a written file says which flag to change."""
    for dest in OUTPUT_FLAGS:
        value = getattr(ns, dest, None)
        if value and str(value) in message and not message.startswith(flag(dest)):
            return f"{flag(dest)} {value}: {message}"
    return message


def main(argv: list[str] | None = None) -> int:
    parser = build_parser()
    argv = sys.argv[1:] if argv is None else list(argv)
    ns = parser.parse_args(argv)

    shown = set()

    def one_line_warning(message, category, filename, lineno, file=None, line=None):
        text = f"nfdcal {ns.command}: warning: {message}"
        if text not in shown:               # once per command: the same text from another place,
            shown.add(text)                 # check or worker is the same news
            print(text, file=sys.stderr)

    warnings.showwarning = one_line_warning   # a warning is one line too, never file:line noise
    try:
        with terminate_as_interrupt():
            refuse_output_over_input(ns)
            check_plot_name(ns)
            return int(ns.run(ns) or 0)
    except (ValueError, OSError, MissingOptionalPart) as exc:  # OSError: a missing file, an output folder under a file
        print(f"nfdcal {ns.command}: error: {name_the_output_flag(ns, str(exc))}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print(f"nfdcal {ns.command}: interrupted", file=sys.stderr)
        return 130


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
