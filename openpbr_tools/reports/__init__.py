"""Report formats for ``openpbr validate`` (and the loss reports of upgrade and convert).

Every renderer returns a string and is deterministic; the CLI chooses one with ``--format``.
"""

from __future__ import annotations

from typing import Callable

from ..diagnostics import Severity
from ..validate import Report

FORMATS = ("text", "json", "jsonl", "sarif", "junit", "github")


def render(report: Report, output_format: str, fail_on: Severity | None = Severity.ERROR,
           style: Callable[..., str] | None = None, min_severity: Severity = Severity.INFO) -> str:
    if output_format == "text":
        from .text import _plain, to_text  # lazy: the format is chosen at run time (--format); only its renderer is loaded

        return to_text(report, style or _plain, min_severity)
    if output_format == "json":
        from .json_report import to_json  # lazy: the format is chosen at run time (--format); only its renderer is loaded

        return to_json(report, fail_on)
    if output_format == "jsonl":
        from .json_report import to_jsonl  # lazy: the format is chosen at run time (--format); only its renderer is loaded

        return to_jsonl(report)
    if output_format == "sarif":
        from .sarif import to_sarif  # lazy: the format is chosen at run time (--format); only its renderer is loaded

        return to_sarif(report, fail_on)
    if output_format == "junit":
        from .junit import to_junit  # lazy: the format is chosen at run time (--format); only its renderer is loaded

        return to_junit(report, fail_on)
    if output_format == "github":
        from .github import to_github  # lazy: the format is chosen at run time (--format); only its renderer is loaded

        return to_github(report)
    raise ValueError(f"unknown report format {output_format!r}")
