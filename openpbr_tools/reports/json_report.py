"""The machine reports: one JSON document (``schemas/report.schema.json``) or JSON Lines, one
diagnostic per line for aggregation. Keys are in a fixed order, so output is byte-stable."""

from __future__ import annotations

import json

from .. import __version__
from ..diagnostics import Severity
from ..validate import Report


def as_dict(report: Report, fail_on: Severity | None = Severity.ERROR) -> dict:
    return {
        "tool": {"name": "openpbr", "version": __version__},
        "summary": {
            "files": len(report.files),
            "materials": sum(r.materials for r in report.files),
            "error": report.count(Severity.ERROR),
            "warning": report.count(Severity.WARNING),
            "info": report.count(Severity.INFO),
            "exit_code": report.exit_code(fail_on),
        },
        "files": [{"path": r.path, "materials": r.materials, "readable": not r.unreadable} for r in report.files],
        "diagnostics": [d.as_dict() for d in report.diagnostics],
    }


def to_json(report: Report, fail_on: Severity | None = Severity.ERROR) -> str:
    return json.dumps(as_dict(report, fail_on), indent=2, ensure_ascii=False) + "\n"


def to_jsonl(report: Report) -> str:
    return "".join(json.dumps(d.as_dict(), ensure_ascii=False, sort_keys=False) + "\n" for d in report.diagnostics)
