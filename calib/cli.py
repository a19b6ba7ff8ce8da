"""``nfdcal``: command-line front end of the calibration pipeline and the runtime model.

Every sub-command lives in ``calib.commands``. Bad input (a ValueError from our own validation,
or an OSError such as a missing input file or an unwritable output folder) is reported as one
line on stderr with exit code 2, never a traceback; so is a usage error.

A negative value in scientific notation may follow its flag (``--dt -1e-6``): argparse reads a
token that starts with '-' as an option unless it looks like -1 or -0.5, so before parsing such
a token is joined to the flag before it (``--dt=-1e-6``, argparse's own spelling of a value)
when that flag takes exactly one value. Flags that take several values (``--v-in``,
``--peaks``) are left alone.
"""
from __future__ import annotations

import argparse
import functools
import importlib
import sys
import warnings

from calib.optional import MissingOptionalPart

# Order is the order shown in --help: model -> FE validation -> calibration -> users.
COMMAND_MODULES = ("collide", "hertz", "calibrate", "run", "table", "material", "fit_data", "stability", "lammps",
                   "export", "results_readme")


class _Parser(argparse.ArgumentParser):
    """argparse whose usage error is ONE line (exit code 2), and which records the flags that
    take exactly one value in ``one_value_flags`` (a set shared with its sub-parsers)."""

    def __init__(self, *args, one_value_flags: set[str] | None = None, **kwargs):
        super().__init__(*args, **kwargs)
        self.one_value_flags = set() if one_value_flags is None else one_value_flags

    def add_argument(self, *args, **kwargs):
        action = super().add_argument(*args, **kwargs)
        if action.option_strings and action.nargs is None:
            self.one_value_flags.update(action.option_strings)
        return action

    def add_subparsers(self, **kwargs):
        kwargs.setdefault("parser_class", functools.partial(_Parser, one_value_flags=self.one_value_flags))
        return super().add_subparsers(**kwargs)

    def error(self, message):
        self.exit(2, f"{self.prog}: error: {message}\n")


def _is_number(token: str) -> bool:
    try:
        float(token)
    except ValueError:
        return False
    return True


def join_negative_values(argv: list[str], one_value_flags: set[str]) -> list[str]:
    """``['--dt', '-1e-6']`` -> ``['--dt=-1e-6']`` for every flag in ``one_value_flags``."""
    joined: list[str] = []
    for token in argv:
        if joined and joined[-1] in one_value_flags and token.startswith("-") and _is_number(token):
            joined[-1] = f"{joined[-1]}={token}"
        else:
            joined.append(token)
    return joined


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


OUTPUT_FLAGS = ("out", "params_out", "master_out", "plot")   # the flags that name where results go


def name_the_output_flag(ns, message: str) -> str:
    """``message`` led by the output flag whose path it names ('--out results/x: cannot write
    results/x/...'), so an error about a written file says which flag to change."""
    for dest in OUTPUT_FLAGS:
        value = getattr(ns, dest, None)
        if value and str(value) in message:
            return f"--{dest.replace('_', '-')} {value}: {message}"
    return message


def main(argv: list[str] | None = None) -> int:
    parser = build_parser()
    argv = sys.argv[1:] if argv is None else list(argv)
    ns = parser.parse_args(join_negative_values(argv, parser.one_value_flags))

    def one_line_warning(message, category, filename, lineno, file=None, line=None):
        print(f"nfdcal {ns.command}: warning: {message}", file=sys.stderr)

    warnings.showwarning = one_line_warning   # a warning is one line too, never file:line noise
    try:
        return int(ns.run(ns) or 0)
    except (ValueError, OSError, MissingOptionalPart) as exc:  # OSError: a missing file, an output folder under a file
        print(f"nfdcal {ns.command}: error: {name_the_output_flag(ns, str(exc))}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print(f"nfdcal {ns.command}: interrupted", file=sys.stderr)
        return 130


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
