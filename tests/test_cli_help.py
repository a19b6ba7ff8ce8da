"""Every command's --help prints its help and exits 0 (argparse formats each help text with %:
a bare percent sign in a help string is a traceback, not a help page)."""
import pytest

from calib.cli import build_parser


def subcommands():
    parser = build_parser()
    found = []
    for action in parser._subparsers._group_actions:        # argparse keeps the subcommands only here
        for name, sub in action.choices.items():
            found.append(name)
            nested = getattr(sub, "_subparsers", None)
            if nested is not None:
                found.extend(f"{name} {inner}" for group in nested._group_actions for inner in group.choices)
    return found


@pytest.mark.parametrize("command", subcommands())
def test_every_command_prints_its_help(command, capsys):
    with pytest.raises(SystemExit) as exit_info:
        build_parser().parse_args([*command.split(), "--help"])
    assert exit_info.value.code == 0
    assert "usage:" in capsys.readouterr().out
