"""Quick structure-aware fuzzing of the glTF read path: no .gltf or .glb input makes validation,
reporting or conversion raise, and every finding has a code and a location. Deterministic (a fixed
hypothesis seed); the long run (100,000+ inputs) is tests/benchmarks/fuzz_long_gltf.py, and every
input it found a failure with is replayed here from tests/fixtures/fuzz_gltf/."""

from __future__ import annotations

import atexit
import functools
import random
import shutil
import tempfile
from pathlib import Path

import pytest
from fuzzgen_gltf import build_seeds, gltf_inputs, mutate_bytes
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from openpbr_tools.reports import FORMATS, render, sarif
from openpbr_tools.translate.convert import MODELS, convert
from openpbr_tools.validate import Report, validate_file

REGRESSIONS = Path(__file__).parent / "fixtures" / "fuzz_gltf"
ROOT = Path(tempfile.mkdtemp(prefix="openpbr-fuzz-gltf-"))
atexit.register(shutil.rmtree, ROOT, True)
SEEDS = build_seeds(str(ROOT / "asset"))  # inputs are written beside the seeds' textures and buffers
QUICK = settings(max_examples=150, deadline=None, database=None, derandomize=True,
                 suppress_health_check=list(HealthCheck))


@pytest.fixture(scope="module", autouse=True)
def rule_pages_once():
    """A SARIF report embeds every rule's page, which depends on the rule alone: format each once."""
    with pytest.MonkeyPatch.context() as patch:
        patch.setattr(sarif, "rule_page", functools.lru_cache(maxsize=None)(sarif.rule_page))
        yield


def exercise(path: Path):
    """Validate, render every report format, convert every material; return the file's result."""
    result = validate_file(str(path), keep_asset=True)
    for diagnostic in result.diagnostics:
        assert diagnostic.code.startswith("OPBR") and diagnostic.location.file, diagnostic
    if result.unreadable:
        assert {d.code for d in result.diagnostics} <= {"OPBR001", "OPBR002"}
    report = Report(files=[result])
    for output_format in FORMATS:
        render(report, output_format).encode("utf-8")  # what the CLI writes to stdout
    for material in (result.asset.materials if result.asset else ()):
        if material.model in MODELS:
            convert(material, "open_pbr_surface")
    return result


def write(suffix: str, data: bytes) -> Path:
    path = Path(SEEDS.folder) / f"fuzz{suffix}"
    path.write_bytes(data)
    return path


def test_the_seeds_are_readable_gltf():
    assert len(SEEDS.documents) >= 9 and len(SEEDS.glb_bytes) >= 4
    for name in sorted(SEEDS.gltf_bytes):
        assert not exercise(Path(SEEDS.folder) / name).unreadable, name


@QUICK
@given(st.data())
def test_no_structured_input_makes_the_read_path_raise(data):
    suffix, content = data.draw(gltf_inputs(SEEDS))
    exercise(write(suffix, content))


@settings(QUICK, max_examples=100)
@given(st.integers(0, 2**32 - 1), st.sampled_from(["gltf", "glb"]))
def test_no_byte_mutation_of_a_seed_makes_the_read_path_raise(seed, kind):
    rng = random.Random(seed)
    pool = SEEDS.gltf_bytes if kind == "gltf" else SEEDS.glb_bytes
    original = pool[rng.choice(sorted(pool))]
    exercise(write("." + kind, mutate_bytes(rng, original, glb=kind == "glb")))


@pytest.mark.parametrize("path", sorted(REGRESSIONS.glob("*.gl*")), ids=lambda p: p.name)
def test_inputs_that_once_failed_stay_fixed(path):
    exercise(path)


def test_every_regression_fixture_is_replayed():
    """A fixture saved in an unexpected form would silently not be replayed."""
    assert sorted(REGRESSIONS.glob("*.gl*")), "no glTF regression fixtures"
    assert all(p.suffix in (".gltf", ".glb") for p in REGRESSIONS.iterdir() if p.is_file() and p.suffix != ".md")
