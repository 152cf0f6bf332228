"""The sample assets shipped with the package: the good ones are clean, the broken ones are caught."""

from __future__ import annotations

from openpbr_tools.resources import data_dir
from openpbr_tools.validate import validate_paths

SAMPLES = data_dir("samples")


def test_good_samples_are_clean():
    good = sorted(str(p) for p in SAMPLES.glob("*.mtlx"))
    assert len(good) >= 4
    report = validate_paths(good)
    assert [d for d in report.diagnostics] == []
    assert report.exit_code() == 0


def test_vendor_export_sample_is_caught_on_every_planted_problem():
    report = validate_paths([str(SAMPLES / "broken" / "vendor_export.mtlx")])
    codes = {d.code for d in report.diagnostics}
    planted = {"OPBR502", "OPBR701", "OPBR704", "OPBR504", "OPBR202", "OPBR301", "OPBR101",
               "OPBR903", "OPBR603", "OPBR605", "OPBR203", "OPBR801"}
    assert planted <= codes
    assert report.exit_code() == 1


def test_legacy_sample_is_reported_as_legacy_and_mixed():
    report = validate_paths([str(SAMPLES / "broken" / "legacy_openpbr_0_2.mtlx")])
    codes = {d.code for d in report.diagnostics}
    assert {"OPBR402", "OPBR404", "OPBR012"} <= codes  # its 1.38 header: MaterialX's upgrade changes nothing else
