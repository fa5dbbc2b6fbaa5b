"""Running ``redkin`` in the test process: the one helper the command-line tests share."""

from __future__ import annotations

from redkin.cli.main import main


def run(capsys, argv: list[str]) -> tuple[int, str, str]:
    """Exit code, stdout and stderr of ``redkin ARGV`` in this process (argparse's exit 2 included)."""
    try:
        code = main(argv)
    except SystemExit as stop:
        code = int(stop.code or 0)
    captured = capsys.readouterr()
    return code, captured.out, captured.err
