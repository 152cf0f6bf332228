"""``openpbr convert``: translate materials between OpenPBR, Standard Surface, glTF and UsdPreviewSurface."""

from __future__ import annotations

import glob
import os
import re
import sys

import click

from cli.validate_cmd import SEVERITIES, _severity
from cli.validate_run import progress_bar, refuse_input, selection_named
from openpbr_tools.reports import FORMATS

MODELS = ("open_pbr_surface", "standard_surface", "gltf_pbr", "UsdPreviewSurface")
OUTPUT_FORMATS = ("gltf", "glb", "usda", "usdc", "usdz", "mtlx")  # openpbr_tools.batch.OUTPUT_SUFFIXES


@click.command()
@click.argument("inputs", metavar="INPUT...", nargs=-1, required=True)
@click.option("--output", "-o", required=True, type=click.Path(),
              help="Output file: .mtlx, .usda/.usdc/.usdz (OpenPBR plus a UsdPreviewSurface fallback), .gltf/.glb; "
                   "with several inputs, a folder or a glob, or --output-format: the output folder.")
@click.option("--output-format", "batch_format", type=click.Choice(sorted(OUTPUT_FORMATS)),
              help="Batch form: the format of every output, written under --output mirroring the input tree.")
@click.option("--to", "target", type=click.Choice(MODELS), help="Shading model of a .mtlx output [default: open_pbr_surface].")
@click.option("--mesh", type=click.Choice(["sphere"]), help="glTF: add a UV sphere per material so any viewer shows it.")
@click.option("--gltf-drafts", is_flag=True,
              help="glTF: also write the draft KHR_materials_coat, _fuzz, _diffuse_roughness and "
                   "EXT_materials_specular_openpbr beside the ratified fallbacks (exact for OpenPBR).")
@click.option("--nits-per-unit", type=click.FloatRange(min=1e-9), default=1.0, show_default=True,
              help="Nits one unit of a unitless emission weight stands for (MaterialX's reference renders 1).")
@click.option("--allow-outside", multiple=True, type=click.Path(file_okay=False),
              help="A folder outside the input's from which textures may be read or embedded (repeatable).")
@click.option("--candidates/--no-candidates", default=True, show_default=True,
              help="Where the mapping approximates a constant OpenPBR or Standard Surface material, also weigh MaterialX's "
                   "translation graphs' result and keep whichever the lobe evaluator renders closer (reported).")
@click.option("--verify", is_flag=True, help="Render original and result with the lobe evaluator and report CIEDE2000; "
                                            "also fits a thin film's thickness where the target's film model differs, "
                                            "and where a result still renders visibly off, searches the target's "
                                            "colours, weights and roughnesses for a closer one: the written material "
                                            "can differ from the default conversion's (every change is noted).")
@click.option("--threshold", type=click.FloatRange(min=0), default=2.0, show_default=True,
              help="With --verify: warn when a material's mean CIEDE2000 exceeds this.")
@click.option("--max-delta-e", type=click.FloatRange(min=0), default=None, metavar="X",
              help="Implies --verify: exit 1 when a material's mean CIEDE2000 exceeds X (the report names it).")
@click.option("--delta-e-images", type=click.Path(file_okay=False), metavar="DIR",
              help="Implies --verify: write per material and view a side-by-side (original | converted) and a ΔE heat-map PNG.")
@click.option("--report", "html_report", type=click.Path(dir_okay=False), metavar="FILE.html",
              help="Implies --verify: write a self-contained HTML page with previews, ΔE maps, numbers and losses.")
@click.option("--force", is_flag=True, help="Overwrite OUTPUT (batch: any output) if it exists.")
@click.option("--skip-existing", is_flag=True,
              help="Batch: keep an output newer than its input and the toolkit (an interrupted run resumes).")
@click.option("--jobs", "-j", type=click.IntRange(min=1), default=None, help="Batch: worker processes [default: cores].")
@click.option("--changed-since", metavar="REF", help="Batch: only inputs git reports changed since REF.")
@click.option("--shard", metavar="I/N", help="Batch: only shard I of N of the inputs.")
@click.option("--scheduler", metavar="ADDRESS", help="Batch: run on a Dask distributed cluster (needs the dask extra).")
@click.option("--scheduler-timeout", type=float, default=30.0, show_default=True, metavar="SECONDS",
              help="How long to wait for the Dask scheduler.")
@click.option("--progress/--no-progress", default=None, help="Batch: progress on stderr [default: when stderr is a terminal].")
@click.option("--format", "output_format", type=click.Choice(FORMATS), default="text", show_default=True,
              help="Format of the loss report.")
@click.option("--fail-on", type=click.Choice(SEVERITIES + ("never",)), default="never", show_default=True,
              callback=_severity, help="Exit 1 when a report entry reaches this severity (error: something was dropped).")
def convert(inputs, output, batch_format, target, mesh, gltf_drafts, nits_per_unit, allow_outside, candidates, verify,
            threshold, max_delta_e, delta_e_images, html_report, force, skip_existing, jobs, changed_since, shard, scheduler, scheduler_timeout, progress, output_format,
            fail_on):
    """Convert every material of INPUT (.mtlx, USD, glTF) and write OUTPUT; the report lists every
    conversion, approximation and loss.

    Batch form: several INPUTs, folders (searched recursively) or globs, or --output-format, write one
    output per input under the folder OUTPUT, mirroring the input tree, with one combined report.

    Exit codes: 0 written, 1 written but a report entry reached --fail-on, 2 unreadable input, no
    material to convert, or refused output (existing without --force, the input itself or a file it
    reads, a batch's output folder holding its input folder); 130 interrupted.
    """
    if batch_format or len(inputs) > 1 or os.path.isdir(inputs[0]) or (glob.has_magic(inputs[0]) and not os.path.exists(inputs[0])):
        if max_delta_e is not None:
            raise click.UsageError("--max-delta-e applies to one input; use --verify --threshold X with several")
        if delta_e_images or html_report:
            raise click.UsageError("--delta-e-images and --report apply to one input")
        _batch(inputs, output, batch_format, target, mesh, nits_per_unit, allow_outside, verify, threshold, force,
               skip_existing, jobs, changed_since, shard, scheduler, scheduler_timeout, progress, output_format, fail_on,
               gltf_drafts, candidates)
        return
    input_path = inputs[0]

    # lazy: `openpbr --help` loads every command module; the library loads when this command runs
    from openpbr_tools.convert import convert_file, output_kind
    from openpbr_tools.diagnostics import Diagnostic
    from openpbr_tools.io import ReadError
    from openpbr_tools.outputs import InputOverwrite, files_read
    from openpbr_tools.reports import render
    from openpbr_tools.translate.common import Settings
    from openpbr_tools.validate import FileResult, Report, unreadable

    if output_kind(output) is None:
        raise click.UsageError(f"cannot write {output}: use .mtlx, .usda, .usdc, .usdz, .gltf or .glb")
    if target and output_kind(output) != "mtlx":
        raise click.UsageError("--to applies to .mtlx output; USD gets OpenPBR plus UsdPreviewSurface, glTF gets glTF PBR")
    refuse_input(output, [input_path])
    if html_report:
        refuse_input(html_report, [input_path], option="--report")
    if os.path.exists(output) and not force:
        raise click.UsageError(f"{output} exists; pass --force to overwrite it")
    verify = verify or max_delta_e is not None or bool(delta_e_images) or bool(html_report)
    try:
        result = convert_file(input_path, output, target, Settings(nits_per_unit=nits_per_unit, gltf_drafts=gltf_drafts,
                                                                        candidates=candidates, fit_films=verify, search=verify),
                              mesh=mesh,
                              allow_outside=tuple(allow_outside))
    except ReadError as error:
        click.echo(render(Report(files=[unreadable(input_path, error)]), output_format), nl=False)
        sys.exit(2)
    except InputOverwrite as error:
        click.echo(f"openpbr: {error}", err=True)
        sys.exit(2)
    except ValueError as error:
        raise click.UsageError(str(error)) from None
    except OSError as error:  # the output's folder cannot be made or written
        click.echo(f"openpbr: cannot write {output}: {error.strerror or error}", err=True)
        sys.exit(2)
    except Exception as error:  # noqa: BLE001 - a defect of the toolkit on this file: OPBR011, exit 2
        _internal_error(input_path, "converting", error, [], 0, output_format)
    too_far = []
    if verify:
        # lazy: `openpbr --help` loads every command module; the library loads when this command runs
        from openpbr_tools.convert import display_name
        from openpbr_tools.verification import compare
        from openpbr_tools.verification import verify as verify_conversion

        limit = threshold if max_delta_e is None else min(threshold, max_delta_e)
        try:
            measured = compare(result, keep_images=bool(delta_e_images or html_report))
            result.diagnostics = sorted(result.diagnostics + verify_conversion(result, limit, measured=measured),
                                        key=Diagnostic.sort_key)
        except Exception as error:  # noqa: BLE001 - as above; the output is written, its verification is not
            _internal_error(input_path, "verifying", error, result.diagnostics, len(result.pairs), output_format)
        if max_delta_e is not None:
            too_far = sorted({display_name(source) for source, c in measured if c.worst.exceeds(max_delta_e)
                              and not c.unread})  # (not measured: verification.verify says why)
        read = files_read(result.asset)
        if delta_e_images:
            write_delta_e_images(delta_e_images, [(display_name(source), c) for source, c in measured], [input_path], read)
        if html_report:
            refuse_input(html_report, [input_path], read, option="--report")
            write_html_report(html_report, f"openpbr convert {os.path.basename(input_path)} -> {os.path.basename(output)}",
                              [(display_name(source), c) for source, c in measured], result.diagnostics, limit)
    report = Report(files=[FileResult(input_path, result.diagnostics, materials=len(result.pairs))])
    click.echo(render(report, output_format, fail_on), nl=False)
    click.echo(f"wrote {output} ({len(result.pairs)} material(s))", err=True)
    if too_far:
        click.echo(f"mean CIEDE2000 above --max-delta-e {max_delta_e:g}: {', '.join(sorted(too_far))}", err=True)
        sys.exit(max(1, report.exit_code(fail_on)))
    sys.exit(report.exit_code(fail_on))


def write_delta_e_images(folder, comparisons, named=(), read=()) -> None:
    """Per material and view: ``NAME_SHAPE.png`` (original | converted) and ``NAME_SHAPE_delta_e.png``.
    Refused (exit 2) before any is written when one would replace an input (``named``) or a file an input
    reads (``read``: a texture in the folder given)."""
    # lazy: Pillow and the evaluator load only when images are asked for
    from openpbr_tools.atomic import write_bytes
    from openpbr_tools.evaluate.visual import view_images

    planned = []  # (path, view) of the side-by-side; its ΔE map beside it
    used = set()
    for name, comparison in comparisons:
        stem = re.sub(r"[^A-Za-z0-9_.-]", "_", comparison.name_b if comparison.name_b != comparison.name_a else name)
        while stem in used:
            stem += "_"
        used.add(stem)
        planned += [(os.path.join(folder, f"{stem}_{view.shape}"), view) for view in comparison.views]
    for stem, _ in planned:
        for path in (f"{stem}.png", f"{stem}_delta_e.png"):
            refuse_input(path, named, read, option="--delta-e-images")
    try:
        os.makedirs(folder, exist_ok=True)
        for stem, view in planned:
            images = view_images(view)
            write_bytes(f"{stem}.png", images["side_by_side"])
            write_bytes(f"{stem}_delta_e.png", images["delta_e"])
    except OSError as error:
        click.echo(f"openpbr: {folder}: {error}", err=True)
        sys.exit(2)


def write_html_report(path, title, comparisons, diagnostics, threshold, labels=("original", "converted")) -> None:
    """The visual report (openpbr_tools.reports.html) of ``comparisons`` with the notes at each material."""
    # lazy: as in write_delta_e_images
    from openpbr_tools.atomic import write_text
    from openpbr_tools.evaluate.visual import legend
    from openpbr_tools.reports.html import entry_for, render_html
    from openpbr_tools.rules.translation import VERIFIED, VERIFY_THRESHOLD

    shown = (VERIFIED.code, VERIFY_THRESHOLD.code)  # the report's own numbers, shown as a table instead
    entries = []
    for name, comparison in comparisons:
        at = [d for d in diagnostics if d.location.material == name and d.code not in shown]
        entries.append(entry_for(comparison, at, threshold, name))
    try:
        write_text(path, render_html(title, entries, threshold, legend(), labels))
    except OSError as error:
        click.echo(f"openpbr: {path}: {error}", err=True)
        sys.exit(2)


def _batch(inputs, outdir, batch_format, target, mesh, nits_per_unit, allow_outside, verify, threshold, force,
           skip_existing, jobs, changed_since, shard, scheduler, scheduler_timeout, progress, output_format, fail_on,
           gltf_drafts=False, candidates=True):
    # lazy: `openpbr --help` loads every command module; the library loads when this command runs
    from openpbr_tools import batch
    from openpbr_tools.reports import STREAMED, render
    from openpbr_tools.selection import SelectionError, check_ref, parse_shard
    from openpbr_tools.validate import Options

    if not batch_format:
        raise click.UsageError("several inputs, a folder or a glob need --output-format (gltf, glb, usda, usdc, usdz, mtlx)")
    if target and batch_format != "mtlx":
        raise click.UsageError("--to applies to .mtlx output; USD gets OpenPBR plus UsdPreviewSurface, glTF gets glTF PBR")
    if os.path.exists(outdir) and not os.path.isdir(outdir):
        raise click.UsageError(f"{outdir} is a file; the batch form writes into a folder")
    try:
        shard_range = parse_shard(shard) if shard else None
        if changed_since is not None:
            check_ref(changed_since)
    except SelectionError as error:
        raise click.UsageError(str(error)) from None
    options = Options(jobs=jobs or os.cpu_count() or 1, changed_since=changed_since, shard=shard_range,
                      scheduler=scheduler, scheduler_timeout=scheduler_timeout)
    planned = batch.plan(inputs, outdir, batch_format, force=force, skip_existing=skip_existing, options=options,
                         target=target, nits_per_unit=nits_per_unit, mesh=mesh,
                         allow_outside=tuple(os.path.abspath(f) for f in allow_outside), verify=verify, candidates=candidates,
                         threshold=threshold, gltf_drafts=gltf_drafts)
    show_progress = sys.stderr.isatty() if progress is None else progress
    streamed = output_format in STREAMED and not planned.refusals
    if streamed:  # written as each file finishes, so memory stays flat
        from openpbr_tools.diagnostics import Severity  # lazy: as the imports above
        from openpbr_tools.reports import StreamedReport  # lazy: as the imports above
        from openpbr_tools.validate import FileResult  # lazy: as the imports above

        stream = StreamedReport(output_format, fail_on)
        click.echo(stream.begin(planned.problems), nl=False)
        threshold = fail_on if fail_on is not None else Severity.ERROR

        def on_result(result):
            click.echo(stream.add(result), nl=False)
            worst = [d for d in result.diagnostics if d.severity >= threshold][:1]  # enough for the exit code
            return FileResult(result.path, worst, result.materials, result.unreadable)
    try:
        report = batch.run(planned, options, progress=progress_bar() if show_progress else None,
                           on_result=on_result if streamed else None)
    except RuntimeError as error:  # a cluster that cannot be reached
        raise click.UsageError(str(error)) from None
    if show_progress:
        click.echo("", err=True)
    click.echo(stream.end() if streamed else render(report, output_format, fail_on), nl=False)
    if report.unselected and not planned.jobs and not planned.skipped and not report.problems:
        click.echo(f"openpbr: note: {selection_named(changed_since, shard)} left none of the {report.unselected} "
                   "input(s) found; nothing was converted", err=True)
    written = sum(1 for result in report.files if not result.unreadable)
    click.echo(f"wrote {written} file(s) under {outdir}; {len(planned.skipped)} up to date, skipped", err=True)
    sys.exit(report.exit_code(fail_on))


def _internal_error(path, step, error, diagnostics, materials, output_format):
    """Report OPBR011 (re-raised under OPENPBR_RAISE_INTERNAL_ERRORS) beside what is known, and exit 2."""
    # lazy: as the library imports above
    from openpbr_tools.batch import internal_failure
    from openpbr_tools.reports import render
    from openpbr_tools.validate import Report

    click.echo(render(Report(files=[internal_failure(path, step, error, diagnostics, materials)]), output_format), nl=False)
    sys.exit(2)
