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


def fingerprint(diagnostic: Diagnostic, root: str) -> tuple[str, str, str, str, str]:
    location = diagnostic.location
    file = os.path.relpath(os.path.abspath(location.file), root).replace(os.sep, "/")
    return (diagnostic.code, file, location.path or "", location.input or "", diagnostic.message)


def baseline_text(report: Report, baseline_path: str) -> str:
    root = os.path.dirname(os.path.abspath(baseline_path))
    entries = sorted(fingerprint(d, root) for d in report.diagnostics)
    findings = [dict(zip(("code", "file", "path", "input", "message"), entry)) for entry in entries]
    return json.dumps({"openpbr_baseline": VERSION, "findings": findings}, indent=2, ensure_ascii=False) + "\n"


class BaselineError(ValueError):
    pass


def load_baseline(baseline_path: str) -> Counter:
    try:
        with open(baseline_path, encoding="utf-8") as handle:
            data = json.load(handle)
        if data.get("openpbr_baseline") != VERSION:
            raise BaselineError(f"{baseline_path} is not an openpbr baseline (version {VERSION})")
        return Counter(tuple(f[k] for k in ("code", "file", "path", "input", "message")) for f in data["findings"])
    except (OSError, ValueError, KeyError, TypeError, AttributeError) as error:
        if isinstance(error, BaselineError):
            raise
        raise BaselineError(f"cannot read baseline {baseline_path}: {error}") from None


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
