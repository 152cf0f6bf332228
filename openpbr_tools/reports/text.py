"""The human report: findings grouped by file, colour when the CLI passes a styling function."""

from __future__ import annotations

from typing import Callable

from ..diagnostics import Severity
from ..validate import Report
from . import printable

Style = Callable[..., str]


def _plain(text: str, **_style) -> str:
    return text


SEVERITY_STYLE = {
    Severity.ERROR: {"fg": "red", "bold": True},
    Severity.WARNING: {"fg": "yellow"},
    Severity.INFO: {"fg": "cyan"},
}


def to_text(report: Report, style: Style = _plain, min_severity: Severity = Severity.INFO) -> str:
    """Diagnostics grouped by file: ``line:path.input  severity  CODE  message`` then the hint; the
    files in the report's order (the arguments' problems, then the files as they were given, sorted),
    then the summary line. :func:`text_sections` and :func:`text_summary` are its two parts, for a
    caller writing the report file by file."""
    errors, warnings, infos = (report.count(s) for s in (Severity.ERROR, Severity.WARNING, Severity.INFO))
    materials = sum(r.materials for r in report.files)
    return text_sections(report.diagnostics, style, min_severity) + \
        text_summary(len(report.files), materials, (errors, warnings, infos), style)


def text_sections(diagnostics, style: Style = _plain, min_severity: Severity = Severity.INFO) -> str:
    """The per-file part of the text report: one section per file, in order of first appearance."""
    lines: list[str] = []
    groups: dict[str, list] = {}
    for diagnostic in diagnostics:
        if diagnostic.severity >= min_severity:
            groups.setdefault(diagnostic.location.file, []).append(diagnostic)
    for file, found in groups.items():
        lines.append(style(printable(file), bold=True, underline=True))
        for d in found:
            where = []
            if d.location.line:
                where.append(f"{d.location.line}")
            element = d.location.path or ""
            if d.location.input:
                element = f"{element}.{d.location.input}" if element else d.location.input
            if element:
                where.append(element)
            place = printable(":".join(where) if where else "-")
            severity = style(f"{str(d.severity):7}", **SEVERITY_STYLE[d.severity])
            lines.append(f"  {place:32} {severity} {style(d.code, bold=True)}  {printable(d.message)}")
            if d.hint:
                lines.append(f"  {'':32} {'':7} {'':7}  hint: {printable(d.hint)}")
        lines.append("")
    return "".join(line + "\n" for line in lines)


def text_summary(files: int, materials: int, counts: tuple[int, int, int], style: Style = _plain) -> str:
    """The text report's last line; ``counts``: errors, warnings, infos."""
    errors, warnings, infos = counts
    return style(f"{files} file(s), {materials} material(s): {errors} error(s), {warnings} warning(s), {infos} info",
                 bold=True) + "\n"
