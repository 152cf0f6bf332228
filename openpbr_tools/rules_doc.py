"""Rule documentation generated from the rule objects: ``openpbr rules`` and the README's table."""

from __future__ import annotations

import textwrap

from .rules import Rule, family_doc
from .rules.provenance import PROVENANCE


def rule_table(rules, markdown: bool = False) -> str:
    rules = list(rules)
    if markdown:
        lines = ["| code | name | severity | checks |", "|---|---|---|---|"]
        lines += [f"| {r.code} | `{r.name}` | {r.severity} | {r.summary} |" for r in rules]
        return "\n".join(lines) + "\n"
    width = max(len(r.name) for r in rules)
    return "".join(f"{r.code}  {r.name:{width}}  {str(r.severity):7}  {r.summary}\n" for r in rules)


def _example(text: str | bytes) -> str:
    if isinstance(text, bytes):
        return "    (binary bytes: " + text[:16].hex(" ") + ")"
    return textwrap.indent(text.rstrip(), "    ")


def _command(rule: Rule) -> str:
    if not rule.example_command:
        return ""
    return " (" + " ".join(["openpbr", *rule.example_command]).replace(" IN ", " example.mtlx ") + ")"


def rule_page(rule: Rule) -> str:
    """The ruff-style page for one rule: what it does, why, examples, family background."""
    parts = [
        f"{rule.code} {rule.name} ({rule.severity})",
        "",
        "What it checks",
        textwrap.indent(textwrap.fill(rule.summary, 96), "  "),
        "",
        "Why it matters",
        textwrap.indent(textwrap.fill(rule.doc, 96), "  "),
        "",
        "Protects against",
        textwrap.indent(textwrap.fill(protects(rule), 96), "  "),
        "",
        "Source",
        "\n".join(f"  {citation}" for citation in sources(rule)),
        "",
        "Passes" + _command(rule),
        _example(rule.passing),
        "",
        "Fails" + _command(rule),
        _example(rule.failing),
        "",
        f"Family: {rule.family}",
        textwrap.indent(family_doc(rule.family), "  "),
        "",
    ]
    return "\n".join(parts)


def protects(rule: Rule) -> str:
    """What goes wrong, in which renderer or tool, when the rule's finding is ignored."""
    return PROVENANCE[rule.code][0]


def sources(rule: Rule) -> list[str]:
    """Where that behaviour is specified or implemented: URLs and ``owner/repository:path`` citations."""
    return PROVENANCE[rule.code][1].split("; ")
