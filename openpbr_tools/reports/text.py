"""The human report: findings grouped by file, colour when the CLI passes a styling function."""

from __future__ import annotations

from typing import Callable

from ..diagnostics import Severity
from ..validate import Report

Style = Callable[..., str]


def _plain(text: str, **_style) -> str:
    return text


SEVERITY_STYLE = {
    Severity.ERROR: {"fg": "red", "bold": True},
    Severity.WARNING: {"fg": "yellow"},
    Severity.INFO: {"fg": "cyan"},
}


def to_text(report: Report, style: Style = _plain, min_severity: Severity = Severity.INFO) -> str:
    """Diagnostics grouped by file: ``line:path.input  severity  CODE  message`` then the hint."""
    lines: list[str] = []
    groups: dict[str, list] = {}
    for diagnostic in report.diagnostics:
        if diagnostic.severity >= min_severity:
            groups.setdefault(diagnostic.location.file, []).append(diagnostic)
    for file in sorted(groups):
        lines.append(style(file, bold=True, underline=True))
        for d in groups[file]:
            where = []
            if d.location.line:
                where.append(f"{d.location.line}")
            element = d.location.path or ""
            if d.location.input:
                element = f"{element}.{d.location.input}" if element else d.location.input
            if element:
                where.append(element)
            place = ":".join(where) if where else "-"
            severity = style(f"{str(d.severity):7}", **SEVERITY_STYLE[d.severity])
            lines.append(f"  {place:32} {severity} {style(d.code, bold=True)}  {d.message}")
            if d.hint:
                lines.append(f"  {'':32} {'':7} {'':7}  hint: {d.hint}")
        lines.append("")
    errors, warnings, infos = (report.count(s) for s in (Severity.ERROR, Severity.WARNING, Severity.INFO))
    materials = sum(r.materials for r in report.files)
    summary = (f"{len(report.files)} file(s), {materials} material(s): "
               f"{errors} error(s), {warnings} warning(s), {infos} info")
    lines.append(style(summary, bold=True))
    return "\n".join(lines) + "\n"
