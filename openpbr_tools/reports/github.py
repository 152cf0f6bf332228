"""GitHub Actions workflow commands: one ``::error``/``::warning``/``::notice`` annotation per
finding, shown inline on the pull request's diff at the file and line."""

from __future__ import annotations

from ..diagnostics import Severity
from ..validate import Report

COMMANDS = {Severity.ERROR: "error", Severity.WARNING: "warning", Severity.INFO: "notice"}


def _data(text: str) -> str:
    return text.replace("%", "%25").replace("\r", "%0D").replace("\n", "%0A")


def _property(text: str) -> str:
    return _data(text).replace(":", "%3A").replace(",", "%2C")


def to_github(report: Report) -> str:
    lines = []
    for d in report.diagnostics:
        properties = [f"file={_property(d.location.file)}"]
        if d.location.line:
            properties.append(f"line={d.location.line}")
        properties.append(f"title={_property(d.code + ' ' + str(d.severity))}")
        element = ".".join(p for p in (d.location.path, d.location.input) if p)
        message = (f"{element}: " if element else "") + d.message + (f" (hint: {d.hint})" if d.hint else "")
        lines.append(f"::{COMMANDS[d.severity]} {','.join(properties)}::{_data(message)}")
    return "".join(line + "\n" for line in lines)
