"""Reports carry names and paths that come from the asset (session 21's red team, M-09 and M-17): a SARIF
``artifactLocation.uri`` is a URI reference (SARIF 2.1.0, 3.4.3, RFC 3986), so the characters a path may hold and a
URI reads otherwise are percent-encoded; a control character in a material name neither breaks JUnit's XML 1.0 nor
starts a line of the text report (where GitHub Actions would run ``::error ::`` as a workflow command)."""

from __future__ import annotations

import json
import xml.etree.ElementTree as ElementTree
from urllib.parse import unquote, urlsplit

import pytest
from click.testing import CliRunner

from cli.group import cli

_EVIL = "evil\u0001\n::error file=injected.txt,line=1::INJECTED\r\nx"


def _gltf(path, name: str) -> None:
    """A material whose message names it: transmission on a fully metallic material (OPBR1211, a warning)."""
    path.write_text(json.dumps({"asset": {"version": "2.0"}, "extensionsUsed": ["KHR_materials_transmission"],
                                "materials": [{"name": name, "extensions": {"KHR_materials_transmission": {
                                    "transmissionFactor": 1.0}}}]}), encoding="utf-8")


@pytest.mark.parametrize("name", ["hash#x.gltf", "q?x.gltf", "per%25cent.gltf", "sp ace.gltf", "ünï.gltf"])
def test_sarif_uris_are_uri_references_that_name_the_file(tmp_path, monkeypatch, name):
    monkeypatch.chdir(tmp_path)
    _gltf(tmp_path / name, "M")
    result = CliRunner().invoke(cli, ["validate", "--no-config", "--format", "sarif", name])
    (uri,) = {r["locations"][0]["physicalLocation"]["artifactLocation"]["uri"]
              for r in json.loads(result.stdout)["runs"][0]["results"]}
    parts = urlsplit(uri)
    assert not parts.scheme and not parts.query and not parts.fragment and unquote(parts.path) == name


def test_a_control_character_in_a_name_stays_on_its_line_and_out_of_the_xml(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    _gltf(tmp_path / "evil.gltf", _EVIL)
    text = CliRunner().invoke(cli, ["validate", "--no-config", "evil.gltf"]).stdout
    assert "OPBR1211" in text and not [line for line in text.splitlines() if line.startswith("::")]
    assert "evil\\x01\\n::error" in text  # shown, escaped
    junit = CliRunner().invoke(cli, ["validate", "--no-config", "--format", "junit", "evil.gltf"]).stdout
    suite = ElementTree.fromstring(junit.encode("utf-8"))  # XML 1.0: was "not well-formed (invalid token)"
    assert "evil\\x01\\n::error" in suite.find(".//system-out").text


def test_the_info_listing_keeps_a_name_on_its_line(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    _gltf(tmp_path / "evil.gltf", _EVIL)
    text = CliRunner().invoke(cli, ["info", "evil.gltf"]).stdout
    assert "evil\\x01\\n::error" in text and not [line for line in text.splitlines() if line.startswith("::")]
