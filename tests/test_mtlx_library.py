"""The MaterialX library index behind validate's start-up: which standard file defines which node
category, cached per MaterialX version, and the subset a document gets is enough for MaterialX's
own Document.validate() to reach the same verdict as with every library loaded."""

from __future__ import annotations

import json

import MaterialX as mx
import pytest

from openpbr_tools.io.mtlx import library


@pytest.fixture()
def fresh(tmp_path, monkeypatch):
    monkeypatch.setenv("OPENPBR_CACHE_DIR", str(tmp_path / "cache"))
    library.index.cache_clear()
    yield tmp_path / "cache"
    library.index.cache_clear()


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
