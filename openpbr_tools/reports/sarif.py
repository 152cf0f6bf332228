"""SARIF 2.1.0, for code-scanning dashboards (GitHub code scanning, Azure DevOps, SARIF viewers).

Every rule is described in ``tool.driver.rules`` with its summary, documentation and examples as
help text; each finding is a ``result`` pointing at the file and line (``physicalLocation``) and
at the element path and input (``logicalLocations``). No timestamps: the output is byte-stable.
"""

from __future__ import annotations

import json
import os
from pathlib import PurePath
from urllib.parse import quote

from .. import __version__
from ..diagnostics import Diagnostic, Severity
from ..rules import Rule, all_rules
from ..rules_doc import rule_page
from ..validate import Report

SCHEMA = "https://docs.oasis-open.org/sarif/sarif/v2.1.0/errata01/os/schemas/sarif-schema-2.1.0.json"
LEVELS = {Severity.ERROR: "error", Severity.WARNING: "warning", Severity.INFO: "note"}


def _uri(file: str) -> str:
    """``artifactLocation.uri``: a URI reference (SARIF 2.1.0, 3.4.3; RFC 3986), so a relative path is
    percent-encoded (``hash#x.mtlx`` would otherwise name ``hash`` with a fragment, ``per%25cent`` another file)."""
    path = PurePath(file)
    if path.is_absolute():
        return path.as_uri()
    return quote(os.fsencode(path.as_posix()), safe="/")  # (the bytes: a name that is not UTF-8 stays exact)


def _descriptor(rule: Rule) -> dict:
    return {
        "id": rule.code,
        "name": rule.name,
        "shortDescription": {"text": rule.summary},
        "fullDescription": {"text": rule.doc},
        "help": {"text": rule_page(rule)},
        "defaultConfiguration": {"level": LEVELS[rule.severity]},
        "properties": {"tags": [rule.family]},
    }


def _result(diagnostic: Diagnostic, index: dict[str, int]) -> dict:
    location = diagnostic.location
    physical: dict = {"artifactLocation": {"uri": _uri(location.file)}}
    if location.line:
        physical["region"] = {"startLine": location.line}
    entry: dict = {"physicalLocation": physical}
    element = "/".join(p for p in (location.path, location.input) if p)
    if element:
        entry["logicalLocations"] = [{"fullyQualifiedName": element, "kind": "member" if location.input else "element"}]
    text = diagnostic.message + (f" (hint: {diagnostic.hint})" if diagnostic.hint else "")
    result = {"ruleId": diagnostic.code, "level": LEVELS[diagnostic.severity], "message": {"text": text},
              "locations": [entry]}
    if diagnostic.code in index:
        result["ruleIndex"] = index[diagnostic.code]
    return result


def to_sarif(report: Report, fail_on: Severity | None = Severity.ERROR) -> str:
    rules = list(all_rules().values())
    index = {rule.code: i for i, rule in enumerate(rules)}
    document = {
        "$schema": SCHEMA,
        "version": "2.1.0",
        "runs": [{
            "tool": {"driver": {"name": "openpbr", "version": __version__, "semanticVersion": __version__,
                                "rules": [_descriptor(r) for r in rules]}},
            "invocations": [{"executionSuccessful": report.exit_code(fail_on) != 2}],
            "columnKind": "unicodeCodePoints",
            "results": [_result(d, index) for d in report.diagnostics],
        }],
    }
    return json.dumps(document, indent=2, ensure_ascii=False) + "\n"
