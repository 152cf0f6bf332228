"""Diagnostics: what a rule (or a reader that cannot read) reports."""

from __future__ import annotations

from dataclasses import dataclass
from enum import IntEnum

from .model import Location


class Severity(IntEnum):
    """Ordered so ``severity >= fail_on`` decides the exit code."""

    INFO = 1
    WARNING = 2
    ERROR = 3

    @classmethod
    def parse(cls, text: str) -> "Severity":
        return cls[text.upper()]

    def __str__(self) -> str:
        return self.name.lower()


@dataclass(frozen=True, slots=True)
class Diagnostic:
    code: str
    severity: Severity
    message: str
    location: Location
    hint: str | None = None

    def sort_key(self) -> tuple:
        loc = self.location
        return (loc.file, loc.line or 0, loc.path or "", loc.input or "", self.code, self.message)

    def as_dict(self) -> dict:
        loc = self.location
        return {
            "code": self.code,
            "severity": str(self.severity),
            "message": self.message,
            "hint": self.hint,
            "location": {"file": loc.file, "line": loc.line, "path": loc.path, "input": loc.input},
        }
