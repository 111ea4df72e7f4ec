"""``python -m symkf`` and the ``symkf`` command (its entry point is :func:`run`)."""

import sys


def run() -> int:
    """:func:`symkf.cli.main` as the process's entry point (signals stay ignored while Python ends
    the process); a Ctrl-C while the command line is still being imported is one line and exit
    status 130 too, not a traceback."""
    try:
        from .cli import main
    except KeyboardInterrupt:
        print("symkf: interrupted", file=sys.stderr)
        return 130
    return main(entry_point=True)


if __name__ == "__main__":
    raise SystemExit(run())
