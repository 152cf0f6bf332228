"""``openpbr preview`` and ``openpbr compare``: lit-sphere contact sheets and CIEDE2000 checks of
translations, on top of :mod:`openpbr_tools.evaluate`."""

from __future__ import annotations

import io
import json
import os
import sys

import click

from cli.validate_run import refuse_input

METRICS = ("mean", "p95", "max")


def _read(path):
    # lazy: `openpbr --help` loads every command module; the library loads when this command runs
    from openpbr_tools.io import ReadError, read_asset
    from openpbr_tools.validate import read_error

    try:
        return read_asset(path)
    except (ReadError, OSError) as error:
        click.echo(f"openpbr: {path}: {read_error(error, path).message}", err=True)
        sys.exit(2)


@click.command()
@click.argument("file", type=click.Path(dir_okay=False))
@click.option("--output", "-o", required=True, type=click.Path(dir_okay=False), help="PNG file to write (.png).")
@click.option("--size", type=click.IntRange(min=16, max=1024), default=128, show_default=True, help="Swatch size in pixels.")
@click.option("--columns", type=click.IntRange(min=1), default=None, help="Swatches per row [default: up to 6].")
@click.option("--shape", type=click.Choice(("sphere", "swatch")), default="sphere", show_default=True,
              help="A UV-mapped sphere, or a flat swatch showing UV space [0, 1]^2.")
@click.option("--environment", type=click.Path(exists=True, dir_okay=False),
              help="Light with a latitude-longitude image (.hdr, .exr, linear) instead of the rig's key light "
                   "and uniform environment.")
@click.option("--allow-outside", multiple=True, type=click.Path(file_okay=False),
              help="A folder outside the input's from which textures may be read (repeatable).")
@click.option("--force", is_flag=True, help="Overwrite OUTPUT if it exists.")
def preview(file, output, size, columns, shape, environment, allow_outside, force):
    """Render every material in FILE (OpenPBR, Standard Surface, glTF PBR or UsdPreviewSurface)
    on a lit sphere (or a texture-space swatch) and write a contact sheet (sRGB PNG) with each
    material's name under it.

    Textures are read per pixel (colour-managed, filtered, with their UV transforms, wrap modes
    and normal maps); what could not be evaluated is listed on stderr. Lighting: a uniform
    environment plus one directional key light, or --environment (see
    openpbr_tools.evaluate.preview).

    Exit codes: 0 written, 2 unreadable input or environment, no materials, or refused output (not .png,
    existing without --force, the input or a file it reads) or output not writable; 130 interrupted.
    """
    # lazy: `openpbr --help` loads every command module; the library loads when this command runs
    from openpbr_tools.atomic import write_bytes
    from openpbr_tools.evaluate.preview import Environment, Rig, contact_sheet
    from openpbr_tools.evaluate.textures import TextureSampler
    from openpbr_tools.evaluate.verify import render_material
    from openpbr_tools.outputs import files_read

    named = [file] + ([environment] if environment else [])
    refuse_input(output, named)
    if not output.lower().endswith(".png"):
        raise click.UsageError(f"cannot write {output}: preview writes a PNG image; name it .png")
    asset = _read(file)
    if not asset.materials:
        click.echo(f"openpbr: {file}: no materials to preview", err=True)
        sys.exit(2)
    refuse_input(output, named, files_read(asset))
    lights = None
    if environment:
        lights = _environment(environment, Environment)
    if os.path.lexists(output) and not force:
        raise click.UsageError(f"{output} exists; pass --force to overwrite it")
    rig = Rig(size=size)
    sampler = TextureSampler.for_asset(asset.path, tuple(allow_outside))
    swatches = []
    for material in asset.materials:
        swatch = render_material(material, rig, sampler, shape, lights)
        for note in swatch.notes:
            click.echo(f"{file}: {material.name}: {note}", err=True)
        swatches.append((material.name, swatch.image))
    try:
        sheet = contact_sheet(swatches, columns=columns)
    except ImportError:
        click.echo("openpbr: preview needs Pillow (pip install pillow)", err=True)
        sys.exit(2)
    buffer = io.BytesIO()
    sheet.save(buffer, format="PNG")
    try:
        write_bytes(output, buffer.getvalue())
    except OSError as error:  # the temporary file's name in the error is not the user's: name the output
        click.echo(f"openpbr: cannot write {output}: {error.strerror or error}", err=True)
        sys.exit(2)
    click.echo(f"{output}: {len(swatches)} material(s)")


def _environment(path, environment_class):
    from openpbr_tools.io.images import load_pixels  # lazy: as above

    try:
        pixels = load_pixels(path)
    except Exception as error:  # noqa: BLE001 - Pillow and OpenImageIO raise many types for undecodable data
        click.echo(f"openpbr: {path}: not a readable latitude-longitude image ({error})", err=True)
        sys.exit(2)
    if pixels.shape[0] < 2 or pixels.shape[1] < 2:
        click.echo(f"openpbr: {path}: too small for an environment ({pixels.shape[1]} x {pixels.shape[0]})", err=True)
        sys.exit(2)
    return environment_class.from_latlong(pixels[:, :, :3])


@click.command()
@click.argument("file_a", type=click.Path(dir_okay=False))
@click.argument("file_b", type=click.Path(dir_okay=False))
@click.option("--format", "output_format", type=click.Choice(("text", "json")), default="text", show_default=True)
@click.option("--threshold", type=click.FloatRange(min=0.0), default=None,
              help="Exit 1 when a pair's ΔE2000 (see --metric) exceeds this value.")
@click.option("--metric", type=click.Choice(METRICS), default="mean", show_default=True,
              help="Which preview statistic --threshold applies to.")
@click.option("--size", type=click.IntRange(min=16, max=1024), default=128, show_default=True, help="Preview size in pixels.")
@click.option("--delta-e-images", type=click.Path(file_okay=False), metavar="DIR",
              help="Write per pair and view a side-by-side (A | B) and a ΔE heat-map PNG.")
@click.option("--report", "html_report", type=click.Path(dir_okay=False), metavar="FILE.html",
              help="Write a self-contained HTML page with both previews, ΔE maps and numbers per pair.")
@click.option("--allow-outside", multiple=True, type=click.Path(file_okay=False),
              help="A folder outside each file's own from which textures may be read (repeatable).")
def compare(file_a, file_b, output_format, threshold, metric, size, delta_e_images, html_report, allow_outside):
    """Print the CIEDE2000 colour difference (mean / p95 / max over the preview sphere, per texel
    over the texture-space swatch when either material is textured, and the mean over the
    directional-albedo curve) of each pair of materials in FILE_A and FILE_B. Textures are read
    per pixel; --threshold applies to the view that differs most.

    Pairs are matched by material name, or are the single material of each file. Exposure and
    white point: D65, an ideal white diffuser facing the key light has L* = 100.

    Exit codes: 0 all pairs within --threshold (or no threshold), 1 a pair above it, 2 unreadable
    input, nothing to compare or refused output (--report or --delta-e-images naming an input or a
    file it reads); 130 interrupted.
    """
    # lazy: `openpbr --help` loads every command module; the library loads when this command runs
    from openpbr_tools.evaluate.preview import Rig
    from openpbr_tools.evaluate.textures import TextureSampler
    from openpbr_tools.evaluate.verify import compare_materials, pair_materials
    from openpbr_tools.outputs import files_read

    if html_report:
        refuse_input(html_report, [file_a, file_b], option="--report")
    asset_a, asset_b = _read(file_a), _read(file_b)
    read = files_read(asset_a) + files_read(asset_b)
    if html_report:
        refuse_input(html_report, [file_a, file_b], read, option="--report")
    pairing = pair_materials(asset_a.materials, asset_b.materials)
    if not pairing.pairs:
        click.echo(f"openpbr: no materials to compare (no common names between {file_a} and {file_b})", err=True)
        sys.exit(2)
    rig = Rig(size=size)
    sampler_a = TextureSampler.for_asset(asset_a.path, tuple(allow_outside))
    sampler_b = TextureSampler.for_asset(asset_b.path, tuple(allow_outside))
    keep = bool(delta_e_images or html_report)
    results = [compare_materials(a, b, rig, sampler_a, keep_images=keep, sampler_b=sampler_b) for a, b in pairing.pairs]
    failed = [r for r in results if threshold is not None and getattr(r.worst, metric) > threshold]
    if delta_e_images or html_report:
        from cli.convert_cmd import write_delta_e_images, write_html_report  # lazy: as the imports above

        named = [(r.name_a, r) for r in results]
        if delta_e_images:
            write_delta_e_images(delta_e_images, named, [file_a, file_b], read)
        if html_report:
            write_html_report(html_report, f"openpbr compare {file_a} {file_b}", named, [], threshold, ("A", "B"))
    if output_format == "json":
        document = {
            "a": file_a,
            "b": file_b,
            "metric": metric,
            "threshold": threshold,
            "pairs": [dict(r.as_dict(), exceeds=r in failed) for r in results],
            "unmatched": {"a": pairing.unmatched_a, "b": pairing.unmatched_b},
        }
        click.echo(json.dumps(document, indent=2))
    else:
        for r in results:
            label = r.name_a if r.name_a == r.name_b else f"{r.name_a} <-> {r.name_b}"
            flag = "  FAIL" if r in failed else ""
            flat = f"  swatch mean {r.swatch.mean:.2f}  p95 {r.swatch.p95:.2f}  max {r.swatch.max:.2f}" if r.swatch else ""
            click.echo(
                f"{label}: ΔE2000 mean {r.preview.mean:.2f}  p95 {r.preview.p95:.2f}  max {r.preview.max:.2f}"
                f"{flat}  (albedo mean {r.albedo.mean:.2f}){flag}"
            )
            for note in r.notes:
                click.echo(f"  note: {note}")
        for name in pairing.unmatched_a:
            click.echo(f"only in {file_a}: {name}", err=True)
        for name in pairing.unmatched_b:
            click.echo(f"only in {file_b}: {name}", err=True)
    sys.exit(1 if failed else 0)
