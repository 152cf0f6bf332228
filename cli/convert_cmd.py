"""``openpbr convert``: translate materials between OpenPBR, Standard Surface, glTF and UsdPreviewSurface."""

from __future__ import annotations

import os
import sys

import click

from cli.validate_cmd import SEVERITIES, _severity
from openpbr_tools.reports import FORMATS

MODELS = ("open_pbr_surface", "standard_surface", "gltf_pbr", "UsdPreviewSurface")


@click.command()
@click.argument("input_path", metavar="INPUT", type=click.Path(dir_okay=False))
@click.option("--output", "-o", required=True, type=click.Path(dir_okay=False),
              help="Output file: .mtlx, .usda/.usdc/.usdz (OpenPBR plus a UsdPreviewSurface fallback), .gltf/.glb.")
@click.option("--to", "target", type=click.Choice(MODELS), help="Shading model of a .mtlx output [default: open_pbr_surface].")
@click.option("--mesh", type=click.Choice(["sphere"]), help="glTF: add a UV sphere per material so any viewer shows it.")
@click.option("--nits-per-unit", type=click.FloatRange(min=1e-9), default=1.0, show_default=True,
              help="Nits one unit of a unitless emission weight stands for (MaterialX's reference renders 1).")
@click.option("--allow-outside", multiple=True, type=click.Path(file_okay=False),
              help="A folder outside the input's from which textures may be read or embedded (repeatable).")
@click.option("--verify", is_flag=True, help="Render original and result with the lobe evaluator and report CIEDE2000.")
@click.option("--threshold", type=click.FloatRange(min=0), default=2.0, show_default=True,
              help="With --verify: warn when a material's mean CIEDE2000 exceeds this.")
@click.option("--max-delta-e", type=click.FloatRange(min=0), default=None, metavar="X",
              help="Implies --verify: exit 1 when a material's mean CIEDE2000 exceeds X (the report names it).")
@click.option("--force", is_flag=True, help="Overwrite OUTPUT if it exists.")
@click.option("--format", "output_format", type=click.Choice(FORMATS), default="text", show_default=True,
              help="Format of the loss report.")
@click.option("--fail-on", type=click.Choice(SEVERITIES + ("never",)), default="never", show_default=True,
              callback=_severity, help="Exit 1 when a report entry reaches this severity (error: something was dropped).")
def convert(input_path, output, target, mesh, nits_per_unit, allow_outside, verify, threshold, max_delta_e, force,
            output_format, fail_on):
    """Convert every material of INPUT (.mtlx, USD, glTF) and write OUTPUT; the report lists every
    conversion, approximation and loss.

    Exit codes: 0 written, 1 written but a report entry reached --fail-on, 2 unreadable input or
    refused output (existing without --force, or the input itself).
    """
    # lazy: `openpbr --help` loads every command module; the library loads when this command runs
    from openpbr_tools.convert import convert_file, output_kind
    from openpbr_tools.diagnostics import Diagnostic
    from openpbr_tools.io import ReadError
    from openpbr_tools.reports import render
    from openpbr_tools.translate.common import Settings
    from openpbr_tools.validate import FileResult, Report, unreadable

    if output_kind(output) is None:
        raise click.UsageError(f"cannot write {output}: use .mtlx, .usda, .usdc, .usdz, .gltf or .glb")
    if target and output_kind(output) != "mtlx":
        raise click.UsageError("--to applies to .mtlx output; USD gets OpenPBR plus UsdPreviewSurface, glTF gets glTF PBR")
    if os.path.exists(output) and os.path.exists(input_path) and os.path.samefile(input_path, output):
        raise click.UsageError("OUTPUT is the input file: openpbr never modifies its input")
    if os.path.exists(output) and not force:
        raise click.UsageError(f"{output} exists; pass --force to overwrite it")
    try:
        result = convert_file(input_path, output, target, Settings(nits_per_unit=nits_per_unit), mesh=mesh,
                              allow_outside=tuple(allow_outside))
    except ReadError as error:
        click.echo(render(Report(files=[unreadable(input_path, error)]), output_format), nl=False)
        sys.exit(2)
    except ValueError as error:
        raise click.UsageError(str(error)) from None
    too_far = []
    if verify or max_delta_e is not None:
        # lazy: `openpbr --help` loads every command module; the library loads when this command runs
        from openpbr_tools.convert import display_name, measure
        from openpbr_tools.convert import verify as verify_conversion

        measured = measure(result)
        limit = threshold if max_delta_e is None else min(threshold, max_delta_e)
        result.diagnostics = sorted(result.diagnostics + verify_conversion(result, limit, measured=measured),
                                    key=Diagnostic.sort_key)
        if max_delta_e is not None:
            too_far = [display_name(source) for source, delta in measured if delta.mean > max_delta_e]
    report = Report(files=[FileResult(input_path, result.diagnostics, materials=len(result.pairs))])
    click.echo(render(report, output_format, fail_on), nl=False)
    click.echo(f"wrote {output} ({len(result.pairs)} material(s))", err=True)
    if too_far:
        click.echo(f"mean CIEDE2000 above --max-delta-e {max_delta_e:g}: {', '.join(sorted(too_far))}", err=True)
        sys.exit(max(1, report.exit_code(fail_on)))
    sys.exit(report.exit_code(fail_on))
