"""The toolkit's outputs and reports stay byte-identical across refactoring.

``tests/data/golden_outputs.json`` was recorded by ``tests/golden_outputs.py`` before the architecture
change of issue 11 (only the convert reports' note locations changed on purpose since: see the commit
that re-recorded them). A difference here means a change of behaviour: if it is intended, re-record
with ``python tests/golden_outputs.py`` and say why in the commit.
"""

from __future__ import annotations

import json

from golden_outputs import RECORD, produce


def test_every_output_and_report_is_byte_identical_to_the_record(tmp_path):
    expected = json.loads(RECORD.read_text(encoding="utf-8"))
    produced = produce(tmp_path / "golden")
    assert len(expected) > 400
    missing = sorted(set(expected) - set(produced))
    extra = sorted(set(produced) - set(expected))
    changed = sorted(k for k in set(expected) & set(produced) if expected[k] != produced[k])
    assert (missing, extra, changed) == ([], [], [])
