"""Threshold keys are declared in the configuration schema: a misspelt one is an error (OPBR008,
exit 2), never silently ignored, and the schema declares exactly the keys the rules read."""

from __future__ import annotations

from click.testing import CliRunner

from cli.group import cli
from openpbr_tools.resources import load_json


def test_a_misspelt_threshold_is_an_invalid_configuration(write_mtlx):
    path = write_mtlx('<open_pbr_surface name="S" type="surfaceshader" />',
                      config="[thresholds]\nmetal_base_color_min_linaer = 0.3\n")
    result = CliRunner().invoke(cli, ["validate", str(path)])
    assert result.exit_code == 2
    assert "OPBR008" in result.output and "metal_base_color_min_linaer" in result.output


def test_a_declared_threshold_is_accepted(write_mtlx):
    path = write_mtlx('<open_pbr_surface name="S" type="surfaceshader" />',
                      config="[thresholds]\nmetal_base_color_min_linear = 0.3\n")
    assert CliRunner().invoke(cli, ["validate", str(path)]).exit_code == 0


def test_the_schema_declares_exactly_the_thresholds_the_rules_read():
    from openpbr_tools.rules import units
    from openpbr_tools.rules.usd_preview import PREVIEW_LIMITS

    declared = set(load_json("config.schema.json")["$defs"]["thresholds"]["properties"])
    read = set(load_json("plausibility.json")["thresholds"]) | {units.NANOMETRE_SUSPICION_KEY} | set(PREVIEW_LIMITS)
    assert declared == read
