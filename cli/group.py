"""The click command group. Sub-commands are imported only when invoked, so that ``openpbr validate``
does not pay for NumPy, colour-science or USD at start-up.

Exit codes (stable): 0 clean, 1 findings at or above ``--fail-on``, 2 usage error or unreadable input,
130 interrupted (Ctrl-C, SIGINT: the shell's 128 + 2, so CI never takes an interrupt for findings).
"""

from __future__ import annotations

import importlib
import sys

import click

from openpbr_tools import __version__

# name -> "module:attribute" of a click command
COMMANDS = {
    "validate": "cli.validate_cmd:validate",
    "rules": "cli.validate_cmd:rules",
    "info": "cli.validate_cmd:info",
    "samples": "cli.validate_cmd:samples",
    "upgrade": "cli.upgrade_cmd:upgrade",
    "convert": "cli.convert_cmd:convert",
    "preview": "cli.evaluate_cmd:preview",
    "compare": "cli.evaluate_cmd:compare",
}


INTERRUPTED = 130  # 128 + SIGINT, what a shell reports for a command stopped by Ctrl-C


def interrupted() -> None:
    """Exit 130 after Ctrl-C / SIGINT. click's own handling exits 1, the documented code for findings."""
    sys.stderr.write("\nopenpbr: interrupted\n")
    sys.stderr.flush()
    sys.exit(INTERRUPTED)


class LazyGroup(click.Group):
    def invoke(self, ctx: click.Context):
        try:
            return super().invoke(ctx)
        except KeyboardInterrupt:
            interrupted()

    def list_commands(self, ctx: click.Context) -> list[str]:
        return sorted(COMMANDS)

    def get_command(self, ctx: click.Context, name: str) -> click.Command | None:
        target = COMMANDS.get(name)
        if target is None:
            return None
        module_name, attribute = target.split(":")
        return getattr(importlib.import_module(module_name), attribute)


@click.group(cls=LazyGroup, context_settings={"help_option_names": ["-h", "--help"]})
@click.version_option(__version__, prog_name="openpbr")
def cli() -> None:
    """Read, validate, translate and verify OpenPBR Surface materials.

    Exit codes: 0 clean, 1 findings at or above --fail-on, 2 usage error, unreadable input or refused
    output (never an input), 130 interrupted (Ctrl-C).
    """
