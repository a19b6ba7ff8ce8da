"""The table of ``nfdcal`` commands in calib/README.md, rendered from the argument parsers that
calib/cli.py builds, so the table and ``nfdcal --help`` say the same.

    python -m calib.cli_readme            # rewrite the table in calib/README.md (a checkout)
    python -m calib.cli_readme --check    # exit 1 when the README's table differs

One row per command (a command with actions, ``nfdcal lammps build | path``, one row per action):
the command with its positional arguments, the parser's one-line help and the output flags it has
(``calib.cli.OUTPUT_FLAGS``) with the default their help names; ``stdout`` when it has none. The
README holds the table between the comments BEGIN and END; tests/test_docs.py compares it.
"""
from __future__ import annotations

import argparse
import re
import sys
from pathlib import Path

from calib.cli import OUTPUT_FLAGS, build_parser

README = Path(__file__).resolve().parent / "README.md"      # calib/README.md
BEGIN = "<!-- the commands table: written by python -m calib.cli_readme from calib/cli.py -->"
END = "<!-- end of the commands table -->"
DEFAULT = re.compile(r"\(default:? (.+?)(?:;|\)|, or )")


def _subparsers(parser: argparse.ArgumentParser) -> argparse._SubParsersAction | None:
    return next((a for a in parser._actions if isinstance(a, argparse._SubParsersAction)), None)


def _positionals(parser: argparse.ArgumentParser) -> str:
    words = []
    for action in parser._actions:
        if action.option_strings or isinstance(action, argparse._SubParsersAction):
            continue
        words.append(action.metavar or ("|".join(action.choices) if action.choices else action.dest.upper()))
    return " ".join(words)


def _outputs(parser: argparse.ArgumentParser) -> str:
    cells = []
    for action in parser._actions:
        if action.dest in OUTPUT_FLAGS and action.option_strings:
            found = DEFAULT.search(action.help or "")
            cells.append(f"`{action.option_strings[-1]}`" + (f" (default {found.group(1).strip()})" if found else ""))
    return ", ".join(cells) or "stdout"


def _cell(text: str) -> str:
    return text.replace("|", "\\|")


def rows(parser: argparse.ArgumentParser | None = None) -> list[tuple[str, str, str]]:
    """(command, what it does, where it writes) of every command, in ``nfdcal --help``'s order."""
    parser = parser or build_parser()
    found = []
    commands = _subparsers(parser)
    for choice in commands._choices_actions:
        sub = commands.choices[choice.dest]
        actions = _subparsers(sub)
        if actions is None:
            command = " ".join(filter(None, (choice.dest, _positionals(sub))))
            found.append((command, choice.help, _outputs(sub)))
            continue
        for action in actions._choices_actions:
            found.append((f"{choice.dest} {action.dest}", action.help, _outputs(actions.choices[action.dest])))
    return found


def render(parser: argparse.ArgumentParser | None = None) -> str:
    """The Markdown table of the commands, between BEGIN and END (both included)."""
    lines = [BEGIN, "| command | what it does | writes |", "|---|---|---|"]
    lines += [f"| `nfdcal {_cell(command)}` | {_cell(help_text)} | {_cell(writes)} |"
              for command, help_text, writes in rows(parser)]
    return "\n".join(lines + [END])


def section(text: str) -> str:
    """The table a README's text holds between BEGIN and END (both included); ValueError without them."""
    start, stop = text.find(BEGIN), text.find(END)
    if start < 0 or stop < start:
        raise ValueError(f"the README has no commands table between {BEGIN!r} and {END!r}")
    return text[start:stop + len(END)]


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--readme", type=Path, default=README, help=f"the README to update (default {README})")
    parser.add_argument("--check", action="store_true", help="write nothing; exit 1 when the table differs")
    ns = parser.parse_args(argv)
    text = ns.readme.read_text(encoding="utf-8")
    current, table = section(text), render()
    if current == table:
        print(f"{ns.readme}: up to date")
        return 0
    if ns.check:
        print(f"{ns.readme}: stale (run python -m calib.cli_readme)")
        return 1
    ns.readme.write_text(text.replace(current, table), encoding="utf-8")
    print(f"{ns.readme}: written")
    return 0


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
