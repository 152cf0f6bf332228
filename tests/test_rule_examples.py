"""Every rule's documented examples behave as documented: the failing example triggers the rule,
the passing one does not. The examples are what `openpbr rules CODE` shows, so documentation and
behaviour cannot drift apart."""

from __future__ import annotations

import pytest

from openpbr_tools.rules import all_rules

RULES = [r for r in all_rules().values() if r.formats]
REPORT_ONLY = [r for r in all_rules().values() if not r.formats]
NOTES = [r for r in REPORT_ONLY if r.code != "OPBR011"]  # OPBR011: a defect of the toolkit (tests/test_internal_errors.py)


@pytest.mark.parametrize("rule", RULES, ids=[r.code for r in RULES])
def test_failing_example_triggers_rule(rule, write_mtlx, codes_of):
    config = rule.example_config if rule.failing_config is None else rule.failing_config
    path = write_mtlx(rule.failing, name=rule.failing_name, files=rule.example_files, config=config,
                      contents=rule.failing_files)
    assert rule.code in codes_of(path)


@pytest.mark.parametrize("rule", RULES, ids=[r.code for r in RULES])
def test_passing_example_does_not_trigger_rule(rule, write_mtlx, codes_of):
    path = write_mtlx(rule.passing, name=rule.passing_name, files=rule.example_files, config=rule.example_config)
    assert rule.code not in codes_of(path)


def test_every_rule_has_documentation_and_distinct_examples():
    for rule in RULES:
        assert rule.summary and rule.doc, rule.code
        failing = (rule.failing, rule.failing_name, rule.failing_config, rule.failing_files)
        assert failing != (rule.passing, rule.passing_name, None, ()), rule.code


def test_rules_without_validation_examples_are_translation_notes_with_a_command():
    """Codes no validation example triggers are the OPBR11xx notes of convert and upgrade, each naming the
    command its examples run with, and OPBR011, the report of a defect of the toolkit (which no file is
    meant to trigger: tests/test_internal_errors.py makes a check fail instead)."""
    assert NOTES and all(r.family == "translation" and r.example_command for r in NOTES)
    assert {r.code for r in REPORT_ONLY} - {r.code for r in NOTES} == {"OPBR011"}


def _command_codes(rule, fragment: str, folder) -> set[str]:
    import json

    from click.testing import CliRunner

    from cli.group import cli
    from conftest import document

    source = folder / "example.mtlx"
    source.write_text(document(fragment), encoding="utf-8")
    words = [str(source) if w == "IN" else str(folder / w) if w.startswith("out.") else w for w in rule.example_command]
    result = CliRunner().invoke(cli, [*words, "--format", "json"], catch_exceptions=False)
    assert result.exit_code in (0, 1), result.output
    return {d["code"] for d in json.loads(result.stdout)["diagnostics"]}


@pytest.mark.parametrize("rule", NOTES, ids=[r.code for r in NOTES])
def test_translation_note_examples_behave_as_documented(rule, tmp_path):
    (tmp_path / "pass").mkdir()
    (tmp_path / "fail").mkdir()
    assert rule.code in _command_codes(rule, rule.failing, tmp_path / "fail")
    assert rule.code not in _command_codes(rule, rule.passing, tmp_path / "pass")
