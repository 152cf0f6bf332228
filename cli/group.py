"""The click command group. Sub-commands are imported only when invoked, so that ``openpbr validate``
does not pay for NumPy, colour-science or USD at start-up.

Exit codes (stable): 0 clean, 1 findings at or above ``--fail-on``, 2 usage error or unreadable input.
"""

from __future__ import annotations

import importlib

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


class LazyGroup(click.Group):
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

    Exit codes: 0 clean, 1 findings at or above --fail-on, 2 usage error or unreadable input.
    """
