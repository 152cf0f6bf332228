"""The broken-file corpus (``tests/data/broken``, see its README): every file holds exactly one
deliberate defect, modelled on what real exporters get wrong, and ``EXPECTED.json`` names the rule
that must catch it at the rule's default severity. Recall is measured per file; an extra *error*
is a false positive unless the entry accepts it under ``also`` with a reason. A planted defect the
toolkit does not catch stays in the corpus, marked ``known_miss`` with the reason; the number of
known misses is pinned below so a new miss (or a fixed one) is noticed."""

from __future__ import annotations

import json
import os
from pathlib import Path

import pytest

from openpbr_tools.rules import all_rules
from openpbr_tools.validate import Options, validate_paths

CORPUS = Path(__file__).parent / "data" / "broken"
EXPECTED = json.loads((CORPUS / "EXPECTED.json").read_text(encoding="utf-8"))
RULES = all_rules()

# Defects planted but not caught with the expected code at the expected severity (listed in
# EXPECTED.json under "known_miss"). Lower it when the toolkit catches one; never raise it to hide a miss.
KNOWN_MISSES = 0

# Families none of whose rules can fire on a validated file without a configuration: translation
# notes come from `convert`/`upgrade`; OPBR008/405/505/506 need a project configuration, which the
# corpus does not use (the other rules of their families are covered).
NOT_FILE_FAMILIES = {"translation"}
FORMATS = {".mtlx", ".usda", ".gltf", ".glb"}


def _findings(entry) -> set[tuple[str, str]]:
    report = validate_paths([str(CORPUS / entry["file"])], options=Options(use_config=False, jobs=1))
    return {(d.code, str(d.severity)) for d in report.diagnostics}


@pytest.fixture(scope="module")
def results():
    return {entry["file"]: _findings(entry) for entry in EXPECTED}


def test_expected_entries_are_well_formed():
    files = [entry["file"] for entry in EXPECTED]
    assert len(files) == len(set(files)), "duplicate entries in EXPECTED.json"
    for entry in EXPECTED:
        name = entry["file"]
        assert (CORPUS / name).is_file(), f"{name}: listed in EXPECTED.json but missing"
        assert name.startswith(entry["code"] + "_"), f"{name}: the name must start with its code {entry['code']}"
        assert entry["code"] in RULES, f"{name}: unknown rule {entry['code']}"
        assert entry["severity"] == str(RULES[entry["code"]].severity), \
            f"{name}: {entry['code']}'s default severity is {RULES[entry['code']].severity}, not {entry['severity']}"
        assert entry.get("defect"), f"{name}: says nothing about its defect"
        for code, reason in entry.get("also", {}).items():
            assert code in RULES and reason, f"{name}: 'also' needs known codes with a reason"
    on_disk = {p.name for p in CORPUS.iterdir() if p.is_file() and p.name.startswith("OPBR")}
    on_disk -= {"OPBR1013_look.mtlx"}  # the MaterialX layer OPBR1013_sublayer_mtlx.usda names, not a case
    assert on_disk == set(files), f"files without an entry: {sorted(on_disk - set(files))}"


def test_coverage_of_formats_and_families():
    assert len(EXPECTED) >= 100
    suffixes = {os.path.splitext(entry["file"])[1] for entry in EXPECTED}
    assert FORMATS <= suffixes, f"formats not covered: {FORMATS - suffixes}"
    families = {RULES[entry["code"]].family for entry in EXPECTED if "known_miss" not in entry}
    every = {rule.family for rule in RULES.values()} - NOT_FILE_FAMILIES
    assert families == every, f"families not covered by a caught defect: {sorted(every - families)}"


@pytest.mark.parametrize("entry", EXPECTED, ids=[entry["file"] for entry in EXPECTED])
def test_defect_is_caught_at_the_right_severity(entry, results):
    found = results[entry["file"]]
    caught = (entry["code"], entry["severity"]) in found
    if "known_miss" in entry:
        assert not caught, f"{entry['file']}: now caught as {entry['code']}; remove its known_miss and lower KNOWN_MISSES"
        return
    assert caught, f"{entry['file']}: expected {entry['code']} ({entry['severity']}), got {sorted(found)}"


@pytest.mark.parametrize("entry", EXPECTED, ids=[entry["file"] for entry in EXPECTED])
def test_one_defect_each(entry, results):
    accepted = {entry["code"], *entry.get("also", {})}
    extra = sorted(code for code, severity in results[entry["file"]] if severity == "error" and code not in accepted)
    assert not extra, f"{entry['file']}: extra errors {extra} beside the planted {entry['code']}"


def test_known_misses_are_counted():
    misses = [entry["file"] for entry in EXPECTED if "known_miss" in entry]
    assert len(misses) == KNOWN_MISSES, f"known misses changed: {misses}"


def test_recall(results):
    caught = sum((e["code"], e["severity"]) in results[e["file"]] for e in EXPECTED)
    assert caught == len(EXPECTED) - KNOWN_MISSES, f"recall {caught}/{len(EXPECTED)}"
