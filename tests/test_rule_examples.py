"""Every rule's documented examples behave as documented: the failing example triggers the rule,
the passing one does not. The examples are what `openpbr rules CODE` shows, so documentation and
behaviour cannot drift apart."""

from __future__ import annotations

import pytest

from openpbr_tools.rules import all_rules

RULES = [r for r in all_rules().values() if r.formats]
REPORT_ONLY = [r for r in all_rules().values() if not r.formats]


@pytest.mark.parametrize("rule", RULES, ids=[r.code for r in RULES])
def test_failing_example_triggers_rule(rule, write_mtlx, codes_of):
    config = rule.example_config if rule.failing_config is None else rule.failing_config
    path = write_mtlx(rule.failing, name=rule.failing_name, files=rule.example_files, config=config)
    assert rule.code in codes_of(path)


@pytest.mark.parametrize("rule", RULES, ids=[r.code for r in RULES])
def test_passing_example_does_not_trigger_rule(rule, write_mtlx, codes_of):
    path = write_mtlx(rule.passing, name=rule.passing_name, files=rule.example_files, config=rule.example_config)
    assert rule.code not in codes_of(path)


def test_every_rule_has_documentation_and_distinct_examples():
    for rule in RULES:
        assert rule.summary and rule.doc, rule.code
        failing = (rule.failing, rule.failing_name, rule.failing_config)
        assert failing != (rule.passing, rule.passing_name, None), rule.code


def test_rules_without_examples_are_loss_report_codes_tested_elsewhere():
    """Codes with no example file describe translation results (tests/test_upgrade.py)."""
    assert REPORT_ONLY and all(r.family == "translation" for r in REPORT_ONLY)
