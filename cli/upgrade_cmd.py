"""``openpbr upgrade``: rewrite legacy OpenPBR (0.2 ... 1.1) materials for a newer version."""

from __future__ import annotations

import os
import sys

import click

from cli.validate_cmd import SEVERITIES, _severity
from cli.validate_run import refuse_input
from openpbr_tools.reports import FORMATS


@click.command()
@click.argument("input_path", metavar="INPUT", type=click.Path(dir_okay=False))
@click.option("--output", "-o", required=True, type=click.Path(dir_okay=False), help="The upgraded .mtlx file.")
@click.option("--to", "target", default=None, help="Target OpenPBR version (default: the latest, 1.1.1).")
@click.option("--force", is_flag=True, help="Overwrite OUTPUT if it exists.")
@click.option("--format", "output_format", type=click.Choice(FORMATS), default="text", show_default=True,
              help="Format of the report of what was converted, approximated or dropped.")
@click.option("--fail-on", type=click.Choice(SEVERITIES + ("never",)), default="error", show_default=True,
              callback=_severity, help="Exit 1 when a report entry reaches this severity (error: something was dropped).")
def upgrade(input_path, output, target, force, output_format, fail_on):
    """Upgrade the legacy OpenPBR shaders of INPUT (.mtlx) and write OUTPUT; everything else in the
    document is kept. The report lists every rename, conversion, approximation and loss.

    Exit codes: 0 written, 1 written but a report entry reached --fail-on, 2 unreadable input or
    refused output (existing without --force, or the input itself); 130 interrupted.
    """
    # lazy: `openpbr --help` loads every command module; the library loads when this command runs
    from openpbr_tools.reports import render
    from openpbr_tools import tables
    from openpbr_tools.atomic import write_text
    from openpbr_tools.io import ReadError, read_asset
    from openpbr_tools.outputs import files_read
    from openpbr_tools.translate.upgrade import upgrade_mtlx_file
    from openpbr_tools.validate import FileResult, Report, unreadable

    if not input_path.lower().endswith(".mtlx") or not output.lower().endswith(".mtlx"):
        raise click.UsageError("upgrade reads and writes .mtlx files")
    if target is not None and target not in tables.versions("open_pbr_surface"):
        raise click.UsageError(f"unknown OpenPBR version {target!r} (known: {', '.join(tables.versions('open_pbr_surface'))})")
    refuse_input(output, [input_path])
    if os.path.exists(output) and not force:
        raise click.UsageError(f"{output} exists; pass --force to overwrite it")
    try:
        result = upgrade_mtlx_file(input_path, target)
        read = files_read(read_asset(input_path))  # (its XIncludes and textures are never written over either)
    except (ReadError, OSError) as error:
        report = Report(files=[unreadable(input_path, error)])
        click.echo(render(report, output_format), nl=False)
        sys.exit(2)
    refuse_input(output, [input_path], read)
    try:
        write_text(output, result.text)
    except OSError as error:
        click.echo(f"openpbr: cannot write {output}: {error.strerror or error}", err=True)
        sys.exit(2)
    report = Report(files=[FileResult(input_path, result.diagnostics, materials=len(result.upgrades))])
    text = render(report, output_format, fail_on)
    click.echo(text, nl=False)
    click.echo(f"wrote {output} ({len(result.upgrades)} material(s) upgraded)", err=True)
    sys.exit(report.exit_code(fail_on))
