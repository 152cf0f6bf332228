"""Never weaker than MaterialX: every .mtlx file in the repository that MaterialX's own
Document.validate() rejects (the shipped samples, the test fixtures, the published corpus) gets at
least one error from `openpbr validate`."""

from __future__ import annotations

from pathlib import Path

import MaterialX as mx
import pytest

from openpbr_tools.resources import data_dir
from openpbr_tools.validate import validate_paths

ROOT = Path(__file__).resolve().parents[1]
FILES = sorted({*ROOT.joinpath("tests").rglob("*.mtlx"), *Path(data_dir("samples")).rglob("*.mtlx")})


@pytest.fixture(scope="module")
def library():
    document = mx.createDocument()
    mx.loadLibraries(mx.getDefaultDataLibraryFolders(), mx.getDefaultDataSearchPath(), document)
    return document


def _materialx_rejects(path: Path, library) -> str | None:
    document = mx.createDocument()
    try:
        mx.readFromXmlFile(document, str(path))
    except Exception as error:  # noqa: BLE001 - MaterialX's own exception types
        return str(error)
    document.setDataLibrary(library)
    valid, message = document.validate()
    return None if valid else message


def test_the_corpus_is_large_and_holds_files_materialx_rejects(library):
    assert len(FILES) >= 200
    assert sum(_materialx_rejects(f, library) is not None for f in FILES) >= 5


@pytest.mark.parametrize("path", FILES, ids=[str(f.relative_to(ROOT)) for f in FILES])
def test_a_file_materialx_rejects_gets_an_error(path, library):
    message = _materialx_rejects(path, library)
    if message is None:
        return  # MaterialX accepts it: nothing to compare (counted by the test above)
    errors = [d for d in validate_paths([str(path)]).diagnostics if str(d.severity) == "error"]
    assert errors, f"MaterialX rejects it ({message.strip().splitlines()[0]}) but openpbr validate reports no error"
