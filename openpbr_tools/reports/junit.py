"""JUnit XML, for CI systems that show test results (Jenkins, GitLab, Azure, TeamCity).

One ``testcase`` per file; each finding at or above the failing severity is a ``failure`` (an
unreadable file is an ``error``); findings below it are listed in ``system-out``. Control characters from the
asset (a material named with one) are escaped: XML 1.0 cannot hold them (:func:`.printable`). Written with the
standard library's ElementTree; no timestamps, so the output is byte-stable.
"""

from __future__ import annotations

import xml.etree.ElementTree as ElementTree

from ..diagnostics import Diagnostic, Severity
from ..validate import Report
from . import printable


def _line(diagnostic: Diagnostic) -> str:
    location = diagnostic.location
    where = ":".join(str(p) for p in (location.line, ".".join(x for x in (location.path, location.input) if x)) if p)
    text = printable(f"{where} {diagnostic.severity} {diagnostic.code} {diagnostic.message}".strip())
    return text + (f"\n  hint: {printable(diagnostic.hint)}" if diagnostic.hint else "")


def to_junit(report: Report, fail_on: Severity | None = Severity.ERROR) -> str:
    threshold = fail_on or Severity.ERROR + 1
    cases = []
    failures = errors = 0
    by_file: dict[str, list[Diagnostic]] = {}
    for diagnostic in report.diagnostics:
        by_file.setdefault(diagnostic.location.file, []).append(diagnostic)
    names = sorted({r.path for r in report.files} | set(by_file))
    unreadable = {r.path for r in report.files if r.unreadable} | {p.location.file for p in report.problems}
    for name in names:
        case = ElementTree.Element("testcase", {"classname": "openpbr.validate", "name": printable(name),
                                                "file": printable(name)})
        quiet = []
        for diagnostic in by_file.get(name, []):
            if name in unreadable and diagnostic.severity == Severity.ERROR:
                element = ElementTree.SubElement(case, "error", {"type": diagnostic.code,
                                                                 "message": printable(diagnostic.message)})
                element.text = _line(diagnostic)
                errors += 1
            elif diagnostic.severity >= threshold:
                element = ElementTree.SubElement(case, "failure", {"type": diagnostic.code,
                                                                   "message": printable(diagnostic.message)})
                element.text = _line(diagnostic)
                failures += 1
            else:
                quiet.append(_line(diagnostic))
        if quiet:
            ElementTree.SubElement(case, "system-out").text = "\n".join(quiet)
        cases.append(case)
    counts = {"tests": str(len(cases)), "failures": str(failures), "errors": str(errors)}
    suites = ElementTree.Element("testsuites", {"name": "openpbr", **counts})
    suite = ElementTree.SubElement(suites, "testsuite", {"name": "openpbr validate", **counts, "skipped": "0"})
    suite.extend(cases)
    ElementTree.indent(suites)
    return ElementTree.tostring(suites, encoding="unicode", xml_declaration=True) + "\n"
