"""``openpbr``: the console script. ``openpbr validate`` with only paths and common options runs without
importing click (see :mod:`cli.validate_run`); everything else goes to the click group in :mod:`cli.group`.

Exit codes (stable): 0 clean, 1 findings at or above ``--fail-on``, 2 usage error or unreadable input,
130 interrupted (see :mod:`cli.group`).
"""

from __future__ import annotations

import sys


def main() -> None:
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
