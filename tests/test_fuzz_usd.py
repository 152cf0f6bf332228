"""Quick fuzzing of the USD path: no stage makes validation or reporting raise, and no layer
outlives the read. The long run (100,000+ inputs, crash isolation) is
tests/benchmarks/fuzz_long_usd.py; every input it found a failure with is replayed here."""

from __future__ import annotations

import random
import subprocess
import sys
import tempfile
import time
from functools import lru_cache
from pathlib import Path

import pytest
from fuzzgen_usd import mutate_bytes, seed_documents, usda_documents
from hypothesis import HealthCheck, given, settings

from openpbr_tools.reports import FORMATS, render
from openpbr_tools.rules import Context
from openpbr_tools.validate import Report, validate_file

FOLDER = Path(tempfile.mkdtemp(prefix="openpbr-fuzz-usd-"))
CONTEXT = Context(file_exists=lambda path: False, list_dir=lambda path: [])  # never touch the disk for textures
FIXTURES = sorted((Path(__file__).parent / "fixtures" / "fuzz_usd").iterdir())
# What each regression input must give: None when the stage is read, else a fragment of the one
# diagnostic that refuses it (so a fix cannot pass by refusing everything, and a refusal that comes
# from usd-core failing late, after the damage, does not count).
EXPECTED = {
    "arc_path_with_nul.usda": None,  # os.path.realpath raised ValueError on the arc's path
    "array_of_colours_on_an_input.usda": None,  # a color3f[] value reached the value rules as nested tuples
    "crate_child_spec_is_none.usdc": "does not hold",  # a child spec that is None (AttributeError)
    "crate_child_without_name_aborts.usdc": "does not hold",  # usd-core aborted the process (SIGABRT)
    "crate_child_without_name_aborts_2.usdc": "does not hold",
    "crate_path_list_op_declares_512m_paths.usdc": "refused before parsing",  # 4.3 GB touched
    "crate_toc_declares_184m_sections.usdc": "refused before parsing",  # 6 GB touched for a 1 KiB file
    "crate_token_vector_declares_1g_tokens.usd": "refused before parsing",  # 8.5 GB touched, 20 s
    "crate_token_vector_declares_788m_tokens.usdc": "refused before parsing",  # 6.3 GB touched
    "crate_child_spec_is_none_2.usdc": "spec type",  # a negative spec type: a child spec read as None
    "package_crate_list_op_declares_352m_items.usdz": "refused before parsing",  # 2.9 GB touched
    "crate_lists_a_child_it_does_not_hold_aborts.usdc": "does not hold",  # usd-core aborted (SIGABRT)
    "outside_arc_beside_a_variant_set.usda": None,  # locating the arc met a variant set (its missing layers: OPBR1042)
    "outside_payload_beside_a_variant_set.usda": None,
    "package_crate_spec_type_negative_segfaults.usdz": "spec type",  # a segmentation fault (SIGSEGV)
    "package_layer_arc_not_utf8.usdz": "not valid UTF-8",  # an arc's asset path raised UnicodeDecodeError
    "parse_error_quotes_invalid_utf8.usda": "not valid UTF-8",  # str() of usd-core's error raised
    "text_arrays_and_matrices_on_inputs.usda": None,
    "texture_path_with_nul.usda": None,  # the texture rule's realpath raised ValueError  # token[] and matrix values broke the value rules
    "validator_message_not_utf8.usdc": None,  # a usd-core validator's message was not UTF-8
}
# Inputs that made usd-core abort or crash the process: replayed in a child process too, so a regression
# fails this test instead of killing the test run.
ABORTED = ("crate_child_spec_is_none.usdc", "crate_child_without_name_aborts.usdc",
           "crate_child_without_name_aborts_2.usdc", "crate_lists_a_child_it_does_not_hold_aborts.usdc",
           "package_crate_spec_type_negative_segfaults.usdz")


def exercise(path: Path):
    """Validate and render every report format; the layer must not outlive the read. (The long run
    also converts every material; translators are not this module's subject.)"""
    from pxr import Sdf

    result = validate_file(str(path), CONTEXT)
    for output_format in FORMATS:
        render(Report(files=[result]), output_format)
    assert not Sdf.Layer.Find(str(path)), "usd-core's registry still holds the stage's layer"
    return result


@lru_cache(maxsize=1)
def seeds():
    return seed_documents()


@settings(max_examples=120, derandomize=True, deadline=None, database=None, suppress_health_check=list(HealthCheck))
@given(usda_documents())
def test_no_text_stage_makes_validation_raise(data):
    path = FOLDER / "fuzz.usda"
    path.write_bytes(data)
    exercise(path)


@pytest.mark.parametrize("suffix", [".usda", ".usdc", ".usdz"])
def test_no_corrupted_stage_makes_validation_raise(suffix):
    rng = random.Random(f"usd{suffix}")
    path = FOLDER / f"raw{suffix}"
    for _ in range(50):
        path.write_bytes(mutate_bytes(rng.choice(seeds()[suffix]), rng))
        exercise(path)


def test_the_seeds_are_valid_stages_so_mutations_start_from_real_files():
    """Otherwise the raw mutations above would only ever test the first failure point."""
    for suffix in (".usdc", ".usdz"):
        path = FOLDER / f"seed{suffix}"
        path.write_bytes(seeds()[suffix][0])
        assert not exercise(path).unreadable


@pytest.mark.parametrize("path", FIXTURES, ids=[p.name for p in FIXTURES])
def test_regressions_found_by_fuzzing_stay_fixed(path):
    """Each input the long run failed on: no exception, bounded time, read or refused as recorded."""
    if path.name in ABORTED:
        done = subprocess.run([sys.executable, "-m", "cli.main", "validate", "--format", "json", "--no-config", str(path)],
                              capture_output=True, text=True, timeout=120, check=False)
        assert done.returncode == 2, f"exit code {done.returncode}: {done.stderr[-500:]}"
    start = time.perf_counter()
    result = exercise(path)
    assert time.perf_counter() - start < 3
    expected = EXPECTED[path.name]
    if expected is None:
        assert not result.unreadable, result.diagnostics
    else:
        (refusal,) = result.diagnostics
        assert refusal.code == "OPBR002" and expected in refusal.message
