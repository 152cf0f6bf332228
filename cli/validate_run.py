"""What ``openpbr validate`` does, without click, and the click-free fast path that runs it.

A pre-commit hook runs ``openpbr validate FILE`` on every commit; importing click (and the
``uuid``/``platform``/``datetime``/``gettext`` modules it pulls in) is about 11 ms of a ~85 ms start-up
(measured: ``tests/benchmarks/bench_startup.py``). So :func:`fast_validate` looks at the argument list
first: when it is only paths and the common options below, each with a value click would accept, it
runs :func:`run_validate` directly; anything else (help, other options, a value click would refuse,
a usage error) returns ``None`` and the click command parses the same arguments and runs the same
:func:`run_validate`. One body, two ways in; a test checks the two give the same bytes and exit code.
"""

from __future__ import annotations

import os
import sys

from openpbr_tools.diagnostics import Severity
from openpbr_tools.reports import FORMATS

SEVERITIES = ("error", "warning", "info")


class UsageProblem(Exception):
    """A usage error found after parsing (unknown rule code, bad shard, bad baseline): the click command
    reports it as click does its own."""


def severity(value: str | None) -> Severity | None:
    """A ``--fail-on`` / ``--min-severity`` value; ``never`` (and no value) is ``None``."""
    if value is None or value == "never":
        return None
    return Severity.parse(value)


def codes(value: str | None) -> frozenset[str]:
    return frozenset(c.strip().upper() for c in (value or "").split(",") if c.strip())


def progress_bar():
    """A ``[####   ] done/total`` bar on stderr, redrawn in place."""
    width = 30

    def show(done: int, total: int) -> None:
        filled = width * done // max(total, 1)
        sys.stderr.write(f"\r[{'#' * filled}{' ' * (width - filled)}] {done}/{total}")
        sys.stderr.flush()

    return show


def _error(message: str) -> None:
    sys.stderr.write(f"{message}\n")
    sys.stderr.flush()


def input_refusal(output, named, read=(), option: str = "OUTPUT") -> str | None:
    """Why writing ``output`` is refused, or ``None``: it is one of the ``named`` input files, or one of the
    files the inputs ``read`` (textures, includes, layers; :mod:`openpbr_tools.outputs`). Every command that
    writes a file asks this before writing, and exits 2 with the message."""
    from openpbr_tools.outputs import NEVER_MODIFIED, overwritten_input  # lazy: only a command that writes asks

    if overwritten_input(output, named) is not None:
        return f"{option} is the input file: {NEVER_MODIFIED}"
    if overwritten_input(output, read) is not None:
        return f"{option} would replace {output}, a file the input reads: {NEVER_MODIFIED}"
    return None


def refuse_input(output, named, read=(), option: str = "OUTPUT") -> None:
    """Exit 2 with :func:`input_refusal`'s one-line message when there is one."""
    reason = input_refusal(output, named, read, option)
    if reason is not None:
        _error(f"openpbr: {reason}")
        sys.exit(2)


def run_validate(paths, *, output_format="text", output=None, fail_on=None, min_severity="info", select=None,
                 ignore=None, no_config=False, baseline=None, write_baseline=None, jobs=None, changed_since=None,
                 shard=None, scheduler=None, scheduler_timeout=30.0, progress=None, allow_outside=()) -> int:
    """Validate ``paths``, write the report (stdout or ``output``), and return the exit code.

    Raises :class:`UsageProblem` before anything is read or written when a rule code or shard is bad.
    """
    # lazy: the library loads when the command runs, not when `openpbr --help` lists it
    from openpbr_tools.reports import render
    from openpbr_tools.rules import all_rules
    from openpbr_tools.selection import SelectionError, check_ref, parse_shard
    from openpbr_tools.validate import Options, validate_paths

    selected, ignored = codes(select), codes(ignore)
    known = set(all_rules()) if selected or ignored else set()  # every family loads: only when codes are named
    unknown = sorted(c for c in selected | ignored if not any(k.startswith(c) for k in known))
    if unknown:
        raise UsageProblem(f"unknown rule code(s): {', '.join(unknown)}")
    try:
        shard_range = parse_shard(shard) if shard else None
        if changed_since is not None:
            check_ref(changed_since)
    except SelectionError as error:
        raise UsageProblem(str(error)) from None
    writes = [(name, option) for name, option in ((output, "--output"), (write_baseline, "--write-baseline")) if name]
    if writes:
        from openpbr_tools.validate import discover  # lazy: as above

        named = list(paths) + discover(paths)[0]
        for name, option in writes:
            reason = input_refusal(name, named, option=option)
            if reason is not None:
                _error(f"openpbr: {reason}")
                return 2
    options = Options(select=tuple(sorted(selected)), ignore=tuple(sorted(ignored)), use_config=not no_config,
                      jobs=jobs or os.cpu_count() or 1, changed_since=changed_since, shard=shard_range,
                      scheduler=scheduler, scheduler_timeout=scheduler_timeout,
                      allow_outside=tuple(os.path.abspath(f) for f in allow_outside))
    show_progress = sys.stderr.isatty() if progress is None else progress
    try:
        report = validate_paths(paths, options=options, progress=progress_bar() if show_progress else None)
    except RuntimeError as error:  # a cluster that cannot be reached
        _error(f"openpbr: {error}")
        return 2
    if show_progress:
        _error("")
    if report.unselected and not report.files:
        _error(f"openpbr: note: {selection_named(changed_since, shard)} left none of the {report.unselected} file(s) found; "
               "nothing was validated")
    for name, option in writes:  # the files the assets read (textures, includes, layers) are known now
        reason = input_refusal(name, [r.path for r in report.files],
                               [f for r in report.files for f in r.reads], option)
        if reason is not None:
            _error(f"openpbr: {reason}")
            return 2
    fail_on_severity = severity(fail_on or _configured_fail_on(paths, no_config) or "error")
    if write_baseline:
        # lazy: only a baseline run needs the writer
        from openpbr_tools.atomic import write_text
        from openpbr_tools.baseline import baseline_text

        try:
            write_text(write_baseline, baseline_text(report, write_baseline))
        except OSError as error:
            _error(f"openpbr: cannot write {write_baseline}: {error.strerror or error}")
            return 2
        _error(f"wrote {write_baseline} ({len(report.diagnostics)} finding(s))")
        return 2 if report.unreadable else 0
    if baseline:
        # lazy: only a baseline run needs the baseline reader
        from openpbr_tools.baseline import BaselineError, apply_baseline

        try:
            dropped = apply_baseline(report, baseline)
        except BaselineError as error:
            raise UsageProblem(str(error)) from None
        _error(f"{dropped} finding(s) in the baseline not shown")
    style = None
    if output is None and output_format == "text" and sys.stdout.isatty():
        from click import style  # lazy: only a coloured report on a terminal needs click's styling
    text = render(report, output_format, fail_on_severity, style, Severity.parse(min_severity))
    if output:
        # lazy: only a report written to a file needs the atomic writer
        from openpbr_tools.atomic import write_text

        try:
            write_text(output, text)
        except OSError as error:
            _error(f"openpbr: cannot write {output}: {error.strerror or error}")
            return 2
    else:
        sys.stdout.write(text)
        sys.stdout.flush()
    return report.exit_code(fail_on_severity)


def selection_named(changed_since: str | None, shard: str | None) -> str:
    """The options that narrowed the file list, as typed (for the note that they left nothing)."""
    return " and ".join(f"{option} {value}" for option, value in (("--changed-since", changed_since),
                                                                   ("--shard", shard)) if value)



def _configured_fail_on(paths, no_config: bool) -> str | None:
    if no_config:
        return None
    # lazy: only a run that reads the configuration needs its parser
    from openpbr_tools.config import ConfigError, configured_fail_on, find_config

    first = os.path.abspath(paths[0]) if paths else os.getcwd()
    folder = first if os.path.isdir(first) else os.path.dirname(first)
    try:
        return configured_fail_on(find_config(folder))
    except ConfigError:
        return None  # reported per file by validate_paths


# The options the fast path takes: option -> (keyword of run_validate, the values click accepts; None: any
# value that is not a folder, as click.Path(dir_okay=False)). Flags: option -> (keyword, value).
_VALUED = {
    "--format": ("output_format", FORMATS),
    "--fail-on": ("fail_on", SEVERITIES + ("never",)),
    "--min-severity": ("min_severity", SEVERITIES),
    "--output": ("output", None),
    "-o": ("output", None),
}
_FLAGS = {"--no-config": ("no_config", True), "--progress": ("progress", True), "--no-progress": ("progress", False)}


def fast_arguments(arguments: list[str]) -> tuple[list[str], dict] | None:
    """``(paths, keywords)`` when click would parse ``arguments`` (those after ``validate``) the same way
    with nothing to complain about; else ``None``."""
    paths: list[str] = []
    keywords: dict = {}
    position = 0
    while position < len(arguments):
        argument = arguments[position]
        position += 1
        if not argument.startswith("-"):
            paths.append(argument)
            continue
        name, equals, value = argument.partition("=")
        if name in _FLAGS and not equals:
            keyword, flag = _FLAGS[name]
            keywords[keyword] = flag
            continue
        if name not in _VALUED or (name == "-o" and equals):
            return None
        if not equals:
            if position == len(arguments) or arguments[position].startswith("-"):
                return None
            value = arguments[position]
            position += 1
        keyword, choices = _VALUED[name]
        if (choices is not None and value not in choices) or (choices is None and (not value or os.path.isdir(value))):
            return None
        keywords[keyword] = value
    return (paths, keywords) if paths else None


def fast_validate(argv: list[str]) -> int | None:
    """The exit code of ``openpbr validate ...`` run without click, or ``None`` when click should parse ``argv``."""
    if argv[:1] != ["validate"]:
        return None
    parsed = fast_arguments(argv[1:])
    if parsed is None:
        return None
    paths, keywords = parsed
    return run_validate(tuple(paths), **keywords)  # none of the options taken here can raise UsageProblem
