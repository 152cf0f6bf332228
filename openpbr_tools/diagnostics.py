"""Diagnostics: what a rule (or a reader that cannot read) reports, and the typed notes of a
translation, a writer, the baker or the upgrader (the OPBR11xx rules): the same data, with the
``output`` location where the note concerns a written file."""

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
    output: Location | None = None  # where in a written file the note applies (prim path, JSON pointer)

    def sort_key(self) -> tuple:
        loc = self.location
        return (loc.file, loc.line or 0, loc.path or "", loc.input or "", self.code, self.message)

    def as_dict(self) -> dict:
        found = {
            "code": self.code,
            "severity": str(self.severity),
            "message": self.message,
            "hint": self.hint,
            "location": _location_dict(self.location),
        }
        if self.output is not None:
            found["output"] = _location_dict(self.output)
        return found


def _location_dict(location: Location) -> dict:
    found = {"file": location.file, "line": location.line, "path": location.path, "input": location.input}
    if location.material is not None:
        found["material"] = location.material
    return found
