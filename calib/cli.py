"""``nfdcal``: command-line front end of the calibration pipeline and the runtime model.

Every sub-command lives in ``calib.commands``. Bad input (a ValueError or a missing file raised
by our own validation) is reported as one line on stderr with exit code 2, never a traceback.
"""
from __future__ import annotations

import argparse
import importlib
import sys

# Order is the order shown in --help: model -> FE validation -> calibration -> users.
COMMAND_MODULES = ("collide", "hertz", "calibrate", "run", "table", "material")


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
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
    except (ValueError, FileNotFoundError) as exc:
        print(f"nfdcal {ns.command}: error: {exc}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print(f"nfdcal {ns.command}: interrupted", file=sys.stderr)
        return 130


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
