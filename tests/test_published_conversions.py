"""The converter's own outputs pass the validator: every file of the published corpus (MaterialX's
examples, OpenPBR's examples, the measured materials, OpenUSD's and the USD working group's test
assets, Khronos' glTF samples) converted to USD (OpenPBR plus its UsdPreviewSurface fallback), to
.mtlx in each of the four models and to glTF validates without an error its source did not already
have. Outputs are written in a folder beside the corpus, with the corpus allowed, so texture paths
resolve as they would for a user converting in place."""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest

from openpbr_tools.convert import convert_file
from openpbr_tools.io import ReadError
from openpbr_tools.translate.common import Settings
from openpbr_tools.validate import Options, validate_paths

CORPUS = Path(__file__).resolve().parent / "data" / "published"
SUFFIXES = (".mtlx", ".usda", ".usdc", ".usdz", ".gltf", ".glb")
SOURCES = sorted(p.relative_to(CORPUS).as_posix() for p in CORPUS.rglob("*") if p.suffix in SUFFIXES)
OUTPUTS = {"usda": None, "mtlx": None, "standard_surface.mtlx": "standard_surface", "gltf_pbr.mtlx": "gltf_pbr",
           "preview.mtlx": "UsdPreviewSurface", "gltf": None}


@pytest.fixture(scope="module")
def corpus(tmp_path_factory):
    folder = tmp_path_factory.mktemp("published")
    shutil.copytree(CORPUS, folder / "published")
    return folder / "published"


def _errors(path) -> set[str]:
    report = validate_paths([str(path)], options=Options(use_config=False, jobs=1))
    return {d.code for d in report.diagnostics if str(d.severity) == "error"}


def test_the_corpus_has_sources_of_every_format():
    assert {Path(s).suffix for s in SOURCES} >= {".mtlx", ".usda", ".gltf"} and len(SOURCES) > 250


#: an output's error -> the source format's code for the same fact (a mask that cuts the whole material away: Pixar's
#: opacityThreshold test, whose texture's alpha is 128/255 everywhere, below two materials' thresholds 0.9 and 1)
SAME_FACT = {"OPBR1249": "OPBR1034", "OPBR1034": "OPBR1249"}


@pytest.mark.parametrize("source", SOURCES)
def test_every_output_of_a_published_file_has_no_new_error(corpus, tmp_path, source):
    path = corpus / source
    already = _errors(path)
    new = {}
    for suffix, target in OUTPUTS.items():
        out = tmp_path / f"out.{suffix}"
        try:
            convert_file(str(path), str(out), target, Settings(), allow_outside=(str(corpus),))
        except ReadError as error:
            if error.kind == "no_material":  # nothing convert writes: refused, never an empty output (red team M-14)
                return
            assert already & {"OPBR001", "OPBR002"}, f"{source} reads for validate but not for convert"
            return
        found = {code for code in _errors(out) - already if SAME_FACT.get(code) not in already}
        if found:
            new[suffix] = sorted(found)
    assert new == {}


def test_a_file_converted_to_its_own_model_elsewhere_verifies_as_identical(tmp_path):
    """MaterialX's chess set (textured Standard Surface) to Standard Surface in another folder: the
    output is the source with its texture paths rebased. The rebasing used to rewrite the source's own
    inputs in memory (the translation of a material to its own model was the material itself), so
    --verify read the source's textures at the rebased paths, failed, and reported 26-31 mean ΔE on
    every material of an identical output."""
    source = CORPUS / "materialx/resources/Materials/Examples/StandardSurface/standard_surface_chess_set.mtlx"
    from openpbr_tools.verification import measure

    conversion = convert_file(str(source), str(tmp_path / "out" / "chess.mtlx"), "standard_surface", Settings())
    files = [entry.value.file for s, _ in conversion.pairs for entry in s.inputs.values() if hasattr(entry.value, "file")]
    assert files and all(f.startswith("chess_set/") for f in files)  # the source as authored
    deltas = [delta.mean for _, delta in measure(conversion)]
    assert len(deltas) == 15 and max(deltas) < 1e-6
