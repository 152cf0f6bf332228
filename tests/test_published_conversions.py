"""The converter's own outputs pass the validator: every MaterialX example of the published corpus
converted to USD (OpenPBR plus its UsdPreviewSurface fallback), to Standard Surface .mtlx and to
glTF validates without an error its source did not already have (a value the source report already
called out of range may stay so)."""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest
from click.testing import CliRunner

from cli.main import cli
from openpbr_tools.validate import validate_paths

CORPUS = Path(__file__).resolve().parent / "data" / "published" / "materialx"
EXAMPLES = sorted(p.relative_to(CORPUS).as_posix() for p in (CORPUS / "resources" / "Materials" / "Examples").rglob("*.mtlx"))
OUTPUTS = {"usda": [], "mtlx": ["--to", "standard_surface"], "gltf": []}
# (example, output, code): a value the source already reports as outside its recommended range
SOURCE_ALREADY_SAID = {("resources/Materials/Examples/StandardSurface/standard_surface_velvet.mtlx", "usda", "OPBR301")}


@pytest.fixture(scope="module")
def corpus(tmp_path_factory):
    folder = tmp_path_factory.mktemp("published")
    shutil.copytree(CORPUS, folder / "materialx")
    return folder / "materialx"


def _errors(path) -> set[str]:
    return {d.code for d in validate_paths([str(path)]).diagnostics if str(d.severity) == "error"}


@pytest.mark.parametrize("output", sorted(OUTPUTS))
@pytest.mark.parametrize("example", EXAMPLES)
def test_a_converted_example_has_no_new_error(corpus, tmp_path, example, output):
    source = corpus / example
    target = tmp_path / f"out.{output}"
    images = corpus / "resources" / "Images"
    result = CliRunner().invoke(cli, ["convert", str(source), "-o", str(target), "--allow-outside", str(images),
                                      *OUTPUTS[output]], catch_exceptions=False)
    assert result.exit_code in (0, 1), result.output
    new = _errors(target) - _errors(source) - {code for e, o, code in SOURCE_ALREADY_SAID if (e, o) == (example, output)}
    assert new == set()
