"""``openpbr validate``, ``openpbr rules``, ``openpbr info`` and ``openpbr samples``."""

from __future__ import annotations

import sys

import click

from openpbr_tools.diagnostics import Severity

SEVERITIES = ("error", "warning", "info")


def _severity(_ctx, _param, value):
    if value is None or value == "never":
        return None
    return Severity.parse(value)


def _codes(value: str | None) -> frozenset[str]:
    return frozenset(c.strip().upper() for c in (value or "").split(",") if c.strip())


@click.command()
@click.argument("paths", nargs=-1, required=True)
@click.option("--format", "output_format", type=click.Choice(["text", "json"]), default="text", show_default=True,
              help="Report format.")
@click.option("--fail-on", type=click.Choice(SEVERITIES + ("never",)), default="error", show_default=True,
              callback=_severity, help="Exit 1 when a finding reaches this severity.")
@click.option("--min-severity", type=click.Choice(SEVERITIES), default="info", show_default=True,
              help="Hide findings below this severity in text output.")
@click.option("--ignore", metavar="CODES", help="Comma-separated rule codes to switch off.")
@click.option("--select", metavar="CODES", help="Comma-separated rule codes to run (all others off).")
@click.option("--output", "-o", type=click.Path(dir_okay=False, writable=True), help="Write the report to a file.")
def validate(paths, output_format, fail_on, min_severity, ignore, select, output):
    """Validate OpenPBR materials in files, folders (searched recursively) and glob patterns.

    Exit codes: 0 clean, 1 a finding at or above --fail-on, 2 usage error or unreadable input.
    """
    from openpbr_tools import report as reporting
    from openpbr_tools.rules import Context, all_rules
    from openpbr_tools.validate import validate_paths

    known = set(all_rules())
    selected, ignored = _codes(select), _codes(ignore)
    unknown = sorted((selected | ignored) - known)
    if unknown:
        raise click.UsageError(f"unknown rule code(s): {', '.join(unknown)}")
    disabled = ignored | (frozenset(known - selected) if selected else frozenset())
    report = validate_paths(paths, Context(disabled=disabled))
    if output_format == "json":
        text = reporting.to_json(report, fail_on)
    else:
        color = output is None and sys.stdout.isatty()
        style = click.style if color else reporting._plain
        text = reporting.to_text(report, style, Severity.parse(min_severity))
    if output:
        from openpbr_tools.atomic import write_text

        write_text(output, text)
    else:
        click.echo(text, nl=False)
    sys.exit(report.exit_code(fail_on))


@click.command()
@click.argument("code", required=False)
@click.option("--format", "output_format", type=click.Choice(["text", "markdown"]), default="text", show_default=True)
def rules(code, output_format):
    """List the rules, or document one rule CODE (what it checks, why, passing and failing examples)."""
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
    import json

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
    from openpbr_tools.resources import data_dir

    click.echo(str(data_dir("samples")))
