"""``openpbr validate``, ``openpbr rules``, ``openpbr info`` and ``openpbr samples``."""

from __future__ import annotations

import json
import os
import sys

import click

from openpbr_tools.diagnostics import Severity
from openpbr_tools.reports import FORMATS

SEVERITIES = ("error", "warning", "info")


def _severity(_ctx, _param, value):
    if value is None or value == "never":
        return None
    return Severity.parse(value)


def _codes(value: str | None) -> frozenset[str]:
    return frozenset(c.strip().upper() for c in (value or "").split(",") if c.strip())


@click.command()
@click.argument("paths", nargs=-1, required=True)
@click.option("--format", "output_format", type=click.Choice(FORMATS), default="text", show_default=True,
              help="Report format: text, json (schemas/report.schema.json), jsonl, sarif (2.1.0), junit, github.")
@click.option("--output", "-o", type=click.Path(dir_okay=False), help="Write the report to a file (atomically).")
@click.option("--fail-on", type=click.Choice(SEVERITIES + ("never",)), default=None,
              help="Exit 1 when a finding reaches this severity [default: the configuration's, else error].")
@click.option("--min-severity", type=click.Choice(SEVERITIES), default="info", show_default=True,
              help="Hide findings below this severity in text output.")
@click.option("--select", metavar="CODES", help="Comma-separated codes or prefixes to run (replaces the configured selection).")
@click.option("--ignore", metavar="CODES", help="Comma-separated codes or prefixes to switch off (adds to the configuration).")
@click.option("--no-config", is_flag=True, help="Ignore [tool.openpbr] / .openpbr.toml files.")
@click.option("--baseline", type=click.Path(dir_okay=False), help="Report only findings not recorded in this baseline file.")
@click.option("--write-baseline", type=click.Path(dir_okay=False), help="Record the current findings as a baseline and exit 0.")
@click.option("--jobs", "-j", type=click.IntRange(min=1), default=None,
              help="Worker processes [default: the number of cores].")
@click.option("--changed-since", metavar="REF", help="Only files git reports changed since REF (and untracked ones).")
@click.option("--shard", metavar="I/N", help="Only shard I of N (a deterministic split of the file list).")
@click.option("--scheduler", metavar="ADDRESS", help="Run on a Dask distributed cluster (needs the dask extra).")
@click.option("--scheduler-timeout", type=float, default=30.0, show_default=True, metavar="SECONDS",
              help="How long to wait for the Dask scheduler.")
@click.option("--progress/--no-progress", default=None, help="Progress bar on stderr [default: when stderr is a terminal].")
@click.option("--allow-outside", multiple=True, type=click.Path(file_okay=False),
              help="A folder outside an asset's own from which its textures, XIncludes, USD arcs and glTF buffers "
                   "may be read (repeatable; adds to the configuration's allow-outside).")
def validate(paths, output_format, output, fail_on, min_severity, select, ignore, no_config, baseline,
             write_baseline, jobs, changed_since, shard, scheduler, scheduler_timeout, progress, allow_outside):
    """Validate OpenPBR materials in files, folders (searched recursively) and glob patterns.

    Settings come from the nearest [tool.openpbr] in pyproject.toml or .openpbr.toml; options
    here override them.

    Exit codes: 0 clean, 1 a finding at or above --fail-on, 2 usage error, bad configuration or
    unreadable input.
    """
    # lazy: `openpbr --help` loads every command module; the library loads when this command runs
    from openpbr_tools.reports import render
    from openpbr_tools.rules import all_rules
    from openpbr_tools.selection import SelectionError, parse_shard
    from openpbr_tools.validate import Options, validate_paths

    selected, ignored = _codes(select), _codes(ignore)
    known = set(all_rules()) if selected or ignored else set()  # every family loads: only when codes are named
    unknown = sorted(c for c in selected | ignored if not any(k.startswith(c) for k in known))
    if unknown:
        raise click.UsageError(f"unknown rule code(s): {', '.join(unknown)}")
    try:
        shard_range = parse_shard(shard) if shard else None
    except SelectionError as error:
        raise click.UsageError(str(error)) from None
    options = Options(select=tuple(sorted(selected)), ignore=tuple(sorted(ignored)), use_config=not no_config,
                      jobs=jobs or os.cpu_count() or 1, changed_since=changed_since, shard=shard_range,
                      scheduler=scheduler, scheduler_timeout=scheduler_timeout,
                      allow_outside=tuple(os.path.abspath(f) for f in allow_outside))
    show_progress = sys.stderr.isatty() if progress is None else progress
    try:
        report = validate_paths(paths, options=options, progress=_progress_bar() if show_progress else None)
    except RuntimeError as error:  # a cluster that cannot be reached
        click.echo(f"openpbr: {error}", err=True)
        sys.exit(2)
    if show_progress:
        click.echo("", err=True)
    fail_on_severity = _severity(None, None, fail_on or _configured_fail_on(paths, no_config) or "error")
    if write_baseline:
        # lazy: `openpbr --help` loads every command module; the library loads when this command runs
        from openpbr_tools.atomic import write_text
        from openpbr_tools.baseline import baseline_text

        try:
            write_text(write_baseline, baseline_text(report, write_baseline))
        except OSError as error:
            click.echo(f"openpbr: cannot write {write_baseline}: {error.strerror or error}", err=True)
            sys.exit(2)
        click.echo(f"wrote {write_baseline} ({len(report.diagnostics)} finding(s))", err=True)
        sys.exit(2 if report.unreadable else 0)
    if baseline:
        # lazy: `openpbr --help` loads every command module; the library loads when this command runs
        from openpbr_tools.baseline import BaselineError, apply_baseline

        try:
            dropped = apply_baseline(report, baseline)
        except BaselineError as error:
            raise click.UsageError(str(error)) from None
        click.echo(f"{dropped} finding(s) in the baseline not shown", err=True)
    color = output is None and output_format == "text" and sys.stdout.isatty()
    text = render(report, output_format, fail_on_severity, click.style if color else None, Severity.parse(min_severity))
    if output:
        # lazy: `openpbr --help` loads every command module; the library loads when this command runs
        from openpbr_tools.atomic import write_text

        try:
            write_text(output, text)
        except OSError as error:
            click.echo(f"openpbr: cannot write {output}: {error.strerror or error}", err=True)
            sys.exit(2)
    else:
        click.echo(text, nl=False)
    sys.exit(report.exit_code(fail_on_severity))


def _configured_fail_on(paths, no_config: bool) -> str | None:
    if no_config:
        return None
    # lazy: `openpbr --help` loads every command module; the library loads when this command runs
    from openpbr_tools.config import ConfigError, configured_fail_on, find_config

    first = os.path.abspath(paths[0]) if paths else os.getcwd()
    folder = first if os.path.isdir(first) else os.path.dirname(first)
    try:
        return configured_fail_on(find_config(folder))
    except ConfigError:
        return None  # reported per file by validate_paths


def _progress_bar():
    width = 30

    def show(done: int, total: int) -> None:
        filled = width * done // max(total, 1)
        click.echo(f"\r[{'#' * filled}{' ' * (width - filled)}] {done}/{total}", err=True, nl=False)

    return show


@click.command()
@click.argument("code", required=False)
@click.option("--format", "output_format", type=click.Choice(["text", "markdown"]), default="text", show_default=True)
def rules(code, output_format):
    """List the rules, or document one rule CODE (what it checks, why, passing and failing examples)."""
    # lazy: `openpbr --help` loads every command module; the library loads when this command runs
    from openpbr_tools.rules import all_rules
    from openpbr_tools.rules_doc import rule_page, rule_table

    registry = all_rules()
    if code is None:
        click.echo(rule_table(registry.values(), markdown=output_format == "markdown"), nl=False)
        return
    rule = registry.get(code.upper())
    if rule is None:
        raise click.UsageError(f"no rule {code!r}; `openpbr rules` lists them")
    click.echo(rule_page(rule), nl=False)


@click.command()
@click.argument("files", nargs=-1, required=True)
@click.option("--format", "output_format", type=click.Choice(["text", "json"]), default="text", show_default=True)
def info(files, output_format):
    """List the materials in FILES: shading model, version and how it was inferred, textures."""
    # lazy: `openpbr --help` loads every command module; the library loads when this command runs
    from openpbr_tools.inventory import describe, describe_text
    from openpbr_tools.io import ReadError, read_asset
    from openpbr_tools.validate import discover

    paths, problems = discover(files)
    entries, failed = [], bool(problems)
    for problem in problems:
        click.echo(f"{problem.location.file}: {problem.code} {problem.message}", err=True)
    for path in paths:
        try:
            entries.append(describe(read_asset(path)))
        except ReadError as error:
            failed = True
            click.echo(f"{path}: {error.message}", err=True)
    if output_format == "json":
        click.echo(json.dumps(entries, indent=2, ensure_ascii=False))
    else:
        click.echo(describe_text(entries), nl=False)
    sys.exit(2 if failed else 0)


@click.command()
def samples():
    """Print the folder of sample materials shipped with the package."""
    # lazy: `openpbr --help` loads every command module; the library loads when this command runs
    from openpbr_tools.resources import data_dir

    click.echo(str(data_dir("samples")))
