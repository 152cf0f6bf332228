"""Baselines: record today's findings so a team can adopt the validator and fail only on new ones.

A finding's fingerprint is its code, its file (relative to the baseline file's folder, so the
baseline works from any checkout), element path, input and message. Line numbers are left out:
editing an unrelated part of a file moves lines but does not make old findings new. Fingerprints
are counted, so a second identical finding in the same place is new.
"""

from __future__ import annotations

import json
import os
from collections import Counter

from .diagnostics import Diagnostic
from .validate import Report

VERSION = 1
FIELDS = ("code", "file", "path", "input", "message")  # a finding's fingerprint, in order


def fingerprint(diagnostic: Diagnostic, root: str) -> tuple[str, str, str, str, str]:
    location = diagnostic.location
    file = os.path.relpath(os.path.abspath(location.file), root).replace(os.sep, "/")
    return (diagnostic.code, file, location.path or "", location.input or "", diagnostic.message)


def baseline_text(report: Report, baseline_path: str) -> str:
    root = os.path.dirname(os.path.abspath(baseline_path))
    entries = sorted(fingerprint(d, root) for d in report.diagnostics)
    findings = [dict(zip(FIELDS, entry)) for entry in entries]
    return json.dumps({"openpbr_baseline": VERSION, "findings": findings}, indent=2, ensure_ascii=False) + "\n"


class BaselineError(ValueError):
    pass


def load_baseline(baseline_path: str) -> Counter:
    """The fingerprints recorded in ``baseline_path``. A file that is not one (unreadable, not JSON, another
    shape) raises :class:`BaselineError` saying what is wrong in the baseline's terms, never Python's."""
    try:
        with open(baseline_path, encoding="utf-8") as handle:
            data = json.load(handle)
    except OSError as error:
        raise BaselineError(f"cannot read baseline {baseline_path}: {error.strerror or error}") from None
    except ValueError as error:  # not UTF-8, not JSON
        raise BaselineError(f"cannot read baseline {baseline_path}: not a JSON file ({error})") from None
    if not isinstance(data, dict) or data.get("openpbr_baseline") != VERSION:
        raise BaselineError(f"{baseline_path} is not an openpbr baseline (a JSON object with "
                            f"\"openpbr_baseline\": {VERSION}, as --write-baseline writes)")
    findings = data.get("findings")
    if not isinstance(findings, list):
        raise BaselineError(f"{baseline_path}: \"findings\" must be a list of findings, as --write-baseline writes")
    known: Counter = Counter()
    for number, finding in enumerate(findings, 1):
        if not isinstance(finding, dict) or not all(isinstance(finding.get(k), str) for k in FIELDS):
            raise BaselineError(f"{baseline_path}: finding {number} is not an object with the text fields "
                                f"{', '.join(FIELDS)}, as --write-baseline writes")
        known[tuple(finding[k] for k in FIELDS)] += 1
    return known


def apply_baseline(report: Report, baseline_path: str) -> int:
    """Drop the findings recorded in the baseline from ``report``; returns how many were dropped."""
    known = load_baseline(baseline_path)
    root = os.path.dirname(os.path.abspath(baseline_path))
    dropped = 0
    for result in report.files:
        kept = []
        for diagnostic in result.diagnostics:
            key = fingerprint(diagnostic, root)
            if known[key] > 0:
                known[key] -= 1
                dropped += 1
            else:
                kept.append(diagnostic)
        result.diagnostics = kept
    return dropped
