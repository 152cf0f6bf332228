"""``openpbr``: the console script. ``openpbr validate`` with only paths and common options runs without
importing click (see :mod:`cli.validate_run`); everything else goes to the click group in :mod:`cli.group`.

Exit codes (stable): 0 clean, 1 findings at or above ``--fail-on``, 2 usage error or unreadable input,
130 interrupted (see :mod:`cli.group`).
"""

from __future__ import annotations

import os
import signal
import sys

_interrupted = []


def _on_interrupt(signum, frame) -> None:
    """SIGINT during start-up: an interrupt inside a C extension's import surfaces as its ImportError
    ("initialization failed"; the red team's H#12), which main then says was the interrupt, and so does the
    per-file safety net (openpbr_tools.workers.note_interrupt)."""
    _interrupted.append(signum)
    try:
        from openpbr_tools.workers import note_interrupt  # lazy: the package may be importing right now
    except Exception:  # noqa: BLE001 - an import the interrupt broke: main says it was interrupted
        pass
    else:
        note_interrupt()
    raise KeyboardInterrupt


def main() -> None:
    limit = os.environ.get("OPENPBR_MAX_FILE_MB")
    try:
        valid = limit is None or float(limit) > 0
    except ValueError:
        valid = False
    if not valid:  # (the red team's H#28: "-1" gave a "0 MiB above the -1 MiB limit" per file, "abc" was ignored)
        sys.stderr.write(f"openpbr: OPENPBR_MAX_FILE_MB must be a positive number of MiB, not {limit!r}\n")
        sys.exit(2)
    previous = signal.signal(signal.SIGINT, _on_interrupt)
    try:
        _run()
    except (KeyboardInterrupt, ImportError):
        if not _interrupted:
            raise
        sys.stderr.write("\nopenpbr: interrupted\n")
        sys.exit(130)
    finally:
        signal.signal(signal.SIGINT, previous)


def _run() -> None:
    if sys.argv[1:2] == ["validate"]:
        from cli.validate_run import fast_validate  # lazy: only validate has a click-free way in

        try:
            code = fast_validate(sys.argv[1:])
        except KeyboardInterrupt:
            sys.stderr.write("\nopenpbr: interrupted\n")
            sys.exit(130)  # as cli.group.interrupted, without importing click
        if code is not None:
            sys.exit(code)
    from cli.group import cli  # lazy: click loads only when the fast path declines

    cli(prog_name="openpbr")


if __name__ == "__main__":
    main()
