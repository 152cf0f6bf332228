"""The README's rule table is the one the rule modules generate."""

from __future__ import annotations

import re
from pathlib import Path

from openpbr_tools.rules import all_rules
from openpbr_tools.rules_doc import rule_table

README = Path(__file__).resolve().parents[1] / "README.md"


def test_readme_rule_table_is_generated_from_the_rules():
    text = README.read_text(encoding="utf-8")
    block = re.search(r"<!-- rules:start -->\n(.*)<!-- rules:end -->", text, re.S).group(1)
    assert block == rule_table(all_rules().values(), markdown=True), \
        "regenerate the README table with `openpbr rules --format markdown`"
