"""``openpbr validate``, ``openpbr rules``, ``openpbr info`` and ``openpbr samples``."""

from __future__ import annotations

import sys

import click

from cli.validate_run import SEVERITIES, UsageProblem, run_validate, severity
from openpbr_tools.reports import FORMATS
from openpbr_tools.reports.json_report import dumps


def _severity(_ctx, _param, value):
    return severity(value)


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

    Exit codes: 0 clean, 1 a finding at or above --fail-on, 2 usage error, bad configuration,
    unreadable input or refused output (--output or --write-baseline naming an input or a file it
    reads); 130 interrupted.
    """
    try:
        code = run_validate(paths, output_format=output_format, output=output, fail_on=fail_on,
                            min_severity=min_severity, select=select, ignore=ignore, no_config=no_config,
                            baseline=baseline, write_baseline=write_baseline, jobs=jobs, changed_since=changed_since,
                            shard=shard, scheduler=scheduler, scheduler_timeout=scheduler_timeout, progress=progress,
                            allow_outside=allow_outside)
    except UsageProblem as problem:
        raise click.UsageError(str(problem)) from None
    sys.exit(code)


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
        click.echo(dumps(entries, indent=2))
    else:
        click.echo(describe_text(entries), nl=False)
    sys.exit(2 if failed else 0)


@click.command()
def samples():
    """Print the folder of sample materials shipped with the package."""
    # lazy: `openpbr --help` loads every command module; the library loads when this command runs
    from openpbr_tools.resources import data_dir

    click.echo(str(data_dir("samples")))
