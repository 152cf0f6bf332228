"""The converter's outputs pass the validator over the input space, not only on examples: seeded
materials of every model (tests/generated_materials.py: every parameter over its whole legal range,
absent-means-default, values exactly on closed bounds) in three document colour spaces, converted to
USD, to .mtlx in each model and to glTF, validate without an error their source did not have."""

from __future__ import annotations

import collections

import pytest

from generated_materials import COLORSPACES, KINDS, archetype_document, document
from openpbr_tools import tables
from openpbr_tools.convert import convert_file
from openpbr_tools.translate.common import Settings
from openpbr_tools.validate import Options, validate_paths

OUTPUTS = {"usda": None, "mtlx": None, "standard_surface.mtlx": "standard_surface", "gltf_pbr.mtlx": "gltf_pbr",
           "preview.mtlx": "UsdPreviewSurface", "gltf": None}
MATERIALS_PER_DOCUMENT = 12


def _errors(path) -> collections.Counter:
    report = validate_paths([str(path)], options=Options(use_config=False, jobs=1))
    return collections.Counter(d.code for d in report.diagnostics if str(d.severity) == "error")


def test_the_generator_sweeps_every_parameter_and_keeps_sources_valid(tmp_path):
    for model in tables.MODELS:
        source = tmp_path / f"{model}.mtlx"
        source.write_text(document(model, "acescg", 0, 40))
        assert _errors(source) == collections.Counter(), model
        text = source.read_text()
        swept = [n for n, p in tables.table(model).parameters.items() if p.role not in ("normal", "tangent")
                 and p.type not in ("string", "filename")]
        assert all(f'name="{n}"' in text for n in swept), model


@pytest.mark.parametrize("colorspace", COLORSPACES)
@pytest.mark.parametrize("model", tables.MODELS)
def test_every_output_of_a_generated_material_has_no_new_error(tmp_path, model, colorspace):
    source = tmp_path / "source.mtlx"
    source.write_text(document(model, colorspace, 1, MATERIALS_PER_DOCUMENT))
    already = _errors(source)
    new = {}
    for suffix, target in OUTPUTS.items():
        out = tmp_path / f"out.{suffix}"
        convert_file(str(source), str(out), target, Settings())
        found = _errors(out) - already
        if found:
            new[suffix] = dict(found)
    assert new == {}


@pytest.mark.parametrize("colorspace", COLORSPACES)
def test_the_archetype_corpus_is_valid_covers_every_kind_and_converts_without_new_errors(tmp_path, colorspace):
    """The fidelity corpus of the kinds artists author (generated_materials.KINDS): valid sources, every
    kind present, and every output validates without an error its source did not have."""
    text, kinds = archetype_document(colorspace, 5, 40)
    assert set(kinds) == set(KINDS)
    source = tmp_path / "archetypes.mtlx"
    source.write_text(text)
    assert _errors(source) == collections.Counter()
    new = {}
    for suffix, target in OUTPUTS.items():
        out = tmp_path / f"out.{suffix}"
        convert_file(str(source), str(out), target, Settings())
        found = _errors(out)
        if found:
            new[suffix] = dict(found)
    assert new == {}
