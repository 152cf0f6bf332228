"""Report formats for ``openpbr validate`` (and the loss reports of upgrade and convert).

Every renderer returns a string and is deterministic; the CLI chooses one with ``--format``.
"""

from __future__ import annotations

from typing import Callable

from ..diagnostics import Severity
from ..validate import Report

FORMATS = ("text", "json", "jsonl", "sarif", "junit", "github")


def printable(text: str) -> str:
    """``text`` with every control character (C0, DEL, C1: newlines and tabs too) written as a Python escape
    (``\\n``, ``\\x01``): a name or value taken from an asset then stays on its line of a text report (a newline
    in a material name could otherwise start a line GitHub Actions runs as a ``::error ::`` workflow command) and
    is legal in XML 1.0, which allows no C0 control but tab, newline and carriage return (JUnit)."""
    if text.isprintable():
        return text
    return "".join(c if c.isprintable() or c == " " else c.encode("unicode_escape").decode("ascii") for c in text)
STREAMED = ("text", "jsonl", "github")  # formats that can be written file by file (StreamedReport)


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


class StreamedReport:
    """A report in one of the :data:`STREAMED` formats, written file by file so that a run over many
    files holds only counts: ``begin(problems) + add(result)... + end()`` is, byte for byte, what
    :func:`render` makes of the whole report (text: the sections as the files come, then the summary
    line; jsonl and github: one line per finding, no summary)."""

    def __init__(self, output_format: str, fail_on: Severity | None = Severity.ERROR):
        if output_format not in STREAMED:
            raise ValueError(f"report format {output_format!r} is not written file by file")
        self.output_format, self.fail_on = output_format, fail_on
        self.files = self.materials = 0
        self.counts = {Severity.ERROR: 0, Severity.WARNING: 0, Severity.INFO: 0}

    def _part(self, report: Report) -> str:
        for diagnostic in report.diagnostics:
            self.counts[diagnostic.severity] += 1
        self.files += len(report.files)
        self.materials += sum(r.materials for r in report.files)
        if self.output_format == "text":
            from .text import text_sections  # lazy: as in render

            return text_sections(report.diagnostics)
        return render(report, self.output_format, self.fail_on)

    def begin(self, problems) -> str:
        return self._part(Report(problems=list(problems)))

    def add(self, result) -> str:
        return self._part(Report(files=[result]))

    def end(self) -> str:
        if self.output_format != "text":
            return ""
        from .text import text_summary  # lazy: as in render

        counts = self.counts
        return text_summary(self.files, self.materials, (counts[Severity.ERROR], counts[Severity.WARNING],
                                                         counts[Severity.INFO]))
