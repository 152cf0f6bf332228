"""Every rule says which renderer behaviour it protects against, with its source (issue: a gate
teams can switch on must explain each finding). Citations are https URLs or owner/repo:path in a
public GitHub repository (each path was checked against a snapshot of its repository when written)."""

from __future__ import annotations

import re

import pytest
from click.testing import CliRunner

from cli.group import cli
from openpbr_tools.rules import all_rules
from openpbr_tools.rules.provenance import PROVENANCE
from openpbr_tools.rules_doc import protects, sources

CITATION = re.compile(r"^(https://\S+|[A-Za-z0-9_.-]+/[A-Za-z0-9_.-]+:[\w./-]+)$")


def test_every_rule_has_provenance_and_nothing_else_does():
    assert set(PROVENANCE) == set(all_rules())


@pytest.mark.parametrize("code", sorted(all_rules()))
def test_provenance_is_a_sentence_and_citations(code):
    rule = all_rules()[code]
    assert len(protects(rule)) > 40 and protects(rule).endswith((".", ")"))
    assert sources(rule) and all(CITATION.match(c) for c in sources(rule)), sources(rule)


def test_openpbr_rules_shows_both():
    page = CliRunner().invoke(cli, ["rules", "OPBR504"]).output
    assert "Protects against" in page and "Source" in page and "pxr/imaging/hio/stbImage.cpp" in page
