"""Quick structure-aware fuzzing of the MaterialX path: no input makes validation, reporting or
upgrading raise. The long run (100,000+ inputs) is tests/benchmarks/fuzz_long.py."""

from __future__ import annotations

import functools
import tempfile
from pathlib import Path

import pytest
from fuzzgen import mtlx_documents
from hypothesis import HealthCheck, given, settings

from openpbr_tools.reports import FORMATS, render, sarif
from openpbr_tools.rules import Context
from openpbr_tools.translate.upgrade import upgrade_mtlx_file
from openpbr_tools.validate import Report, validate_file

FOLDER = Path(tempfile.mkdtemp(prefix="openpbr-fuzz-"))
CONTEXT = Context(file_exists=lambda path: False, list_dir=lambda path: [])  # never touch the disk for textures


@pytest.fixture(scope="module", autouse=True)
def rule_pages_once():
    """A SARIF report embeds every rule's page, which depends on the rule alone: format each once."""
    with pytest.MonkeyPatch.context() as patch:
        patch.setattr(sarif, "rule_page", functools.lru_cache(maxsize=None)(sarif.rule_page))
        yield


@settings(max_examples=300, deadline=None, database=None, suppress_health_check=list(HealthCheck))
@given(mtlx_documents())
def test_no_document_makes_validation_raise(data):
    path = FOLDER / "fuzz.mtlx"
    path.write_bytes(data)
    result = validate_file(str(path), CONTEXT)
    report = Report(files=[result])
    for output_format in FORMATS:
        render(report, output_format)
    if not result.unreadable:
        upgrade_mtlx_file(str(path))


def test_regressions_found_by_fuzzing_stay_fixed():
    """Every input the long fuzz run found a failure with is kept in tests/fixtures/fuzz_*.mtlx
    (glTF ones, in tests/fixtures/fuzz_gltf/, are replayed by test_fuzz_gltf.py)."""
    fixtures = sorted((Path(__file__).parent / "fixtures").glob("fuzz_*.mtlx"))
    assert fixtures
    for path in fixtures:
        result = validate_file(str(path), CONTEXT)
        render(Report(files=[result]), "sarif")
        if not result.unreadable:
            upgrade_mtlx_file(str(path))
