"""The MaterialX library index behind validate's start-up: which standard file defines which node
category, cached per MaterialX version, and the subset a document gets is enough for MaterialX's
own Document.validate() to reach the same verdict as with every library loaded."""

from __future__ import annotations

import glob
import json
import os

import MaterialX as mx
import pytest

from openpbr_tools.io.mtlx import library


@pytest.fixture()
def fresh(tmp_path, monkeypatch):
    monkeypatch.setenv("OPENPBR_CACHE_DIR", str(tmp_path / "cache"))
    for cached in (library.index, library._trimmed, library._library_key):
        cached.cache_clear()
    yield tmp_path / "cache"
    for cached in (library.index, library._trimmed, library._library_key):
        cached.cache_clear()


def _everything():
    document = mx.createDocument()
    mx.loadLibraries(mx.getDefaultDataLibraryFolders(), mx.getDefaultDataSearchPath(), document)
    return document


def test_the_index_knows_every_category_materialx_defines(fresh):
    assert library.known_categories(complete=True) == {nd.getNodeString() for nd in _everything().getNodeDefs()}
    assert {"open_pbr_surface", "standard_surface", "gltf_pbr", "UsdPreviewSurface", "image"} <= library.known_categories()


def test_the_index_is_cached_under_the_materialx_version_and_rebuilt_when_damaged(fresh):
    library.index()
    (cached,) = fresh.iterdir()
    assert mx.getVersionString() in cached.name
    cached.write_text("{not json")
    library.index.cache_clear()
    assert "open_pbr_surface" in library.known_categories()  # rebuilt
    assert json.loads(cached.read_text())["format"] == library.CACHE_FORMAT


def test_an_unwritable_cache_folder_still_works(fresh, monkeypatch, tmp_path):
    blocker = tmp_path / "file"
    blocker.write_text("")
    monkeypatch.setenv("OPENPBR_CACHE_DIR", str(blocker / "below-a-file"))
    library.index.cache_clear()
    assert "open_pbr_surface" in library.known_categories()


@pytest.mark.parametrize("fragment, valid", [
    ('<open_pbr_surface name="S" type="surfaceshader"><input name="base_weight" type="float" value="1" /></open_pbr_surface>', True),
    ('<open_pbr_surface name="S" type="surfaceshader"><input name="base_weight" type="color3" value="1, 1, 1" /></open_pbr_surface>', False),
    ('<standard_surface name="S" type="surfaceshader"><input name="base_color" type="color3" nodename="n" /></standard_surface>'
     '<noise3d name="n" type="color3" />', True),
    ('<gltf_pbr name="S" type="surfaceshader"><input name="metallic" type="float" value="1" /></gltf_pbr>', True),
    ('<UsdPreviewSurface name="S" type="surfaceshader"><input name="opacity" type="vector2" value="1, 1" /></UsdPreviewSurface>', False),
])
def test_the_subset_gives_materialx_the_same_verdict_as_every_library(fresh, fragment, valid):
    text = f'<?xml version="1.0"?>\n<materialx version="1.39">{fragment}</materialx>'
    verdicts = []
    for data_library in (_everything(), None):
        document = mx.createDocument()
        mx.readFromXmlString(document, text)
        used = {e.getCategory() for e in document.traverseTree() if e.isA(mx.Node)}
        document.setDataLibrary(data_library or library.library_for(used))
        verdicts.append(document.validate()[0])
    assert verdicts == [valid, valid]


def test_the_trimmed_definitions_validate_every_corpus_file_as_the_whole_library_does():
    """library_for() hands Document.validate() only the type/unit definitions and the node
    definitions of the categories a document uses; on every .mtlx of the test corpus (published
    MaterialX and USD files, broken files, fixtures) validity and messages equal those against all of
    MaterialX's libraries loaded (mx.loadLibraries)."""
    root = os.path.dirname(os.path.abspath(__file__))
    everything = mx.createDocument()
    mx.loadLibraries(mx.getDefaultDataLibraryFolders(), mx.getDefaultDataSearchPath(), everything)
    compared = 0
    for path in sorted(glob.glob(os.path.join(root, "**", "*.mtlx"), recursive=True)):
        documents = []
        for _ in range(2):
            document = mx.createDocument()
            try:
                mx.readFromXmlFile(document, path)
            except Exception:  # noqa: BLE001 - broken on purpose (the broken corpus): not a library question
                break
            documents.append(document)
        if len(documents) < 2:
            continue
        whole, trimmed = documents
        used = {e.getCategory() for e in whole.traverseTree() if e.isA(mx.Node)}
        whole.setDataLibrary(everything)
        trimmed.setDataLibrary(library.library_for(used))
        expected, found = whole.validate(), trimmed.validate()
        assert (found[0], sorted(found[1].splitlines())) == (expected[0], sorted(expected[1].splitlines())), path
        compared += 1
    assert compared > 300
