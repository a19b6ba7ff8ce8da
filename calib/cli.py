"""``nfdcal``: command-line front end of the calibration pipeline and the runtime model.

Every sub-command lives in ``calib.commands``. Bad input (a ValueError from our own validation,
or an OSError such as a missing input file or an unwritable output folder) is reported as one
line on stderr with exit code 2, never a traceback.
"""
from __future__ import annotations

import argparse
import importlib
import re
import sys

# Order is the order shown in --help: model -> FE validation -> calibration -> users.
COMMAND_MODULES = ("collide", "hertz", "calibrate", "run", "table", "material", "stability")


class _Parser(argparse.ArgumentParser):
    """argparse with two fixes for a numerical CLI: a negative number in scientific notation
    (``--dt -1e-6``) is a value, not an option (argparse only knows -1 and -0.5), so run()
    can answer with the parameter's range; and a usage error is ONE line, exit code 2."""

    def __init__(self, *args, **kwargs):
        super().__init__(*args, **kwargs)
        self._negative_number_matcher = re.compile(r"^-(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?$")

    def error(self, message):
        self.exit(2, f"{self.prog}: error: {message}\n")


def build_parser() -> argparse.ArgumentParser:
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


def main(argv: list[str] | None = None) -> int:
    parser = build_parser()
    ns = parser.parse_args(argv)
    try:
        return int(ns.run(ns) or 0)
    except (ValueError, OSError) as exc:  # OSError: a missing file, an output folder under a file
        print(f"nfdcal {ns.command}: error: {exc}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print(f"nfdcal {ns.command}: interrupted", file=sys.stderr)
        return 130


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
