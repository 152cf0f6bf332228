"""Shared fixtures: writing small MaterialX documents and running the validator on them."""

from __future__ import annotations

import os
import sys
import tempfile
from pathlib import Path

import pytest

sys.path.insert(0, os.path.dirname(__file__))

DOCUMENT = """<?xml version="1.0"?>
<materialx version="1.39" colorspace="lin_rec709">
{body}
  <surfacematerial name="M" type="material">
    <input name="surfaceshader" type="surfaceshader" nodename="S" />
  </surfacematerial>
</materialx>
"""


# The MaterialX library index (openpbr_tools.io.mtlx.library) is cached per run, not in the home folder.
os.environ.setdefault("OPENPBR_CACHE_DIR", tempfile.mkdtemp(prefix="openpbr-test-cache-"))


def document(fragment: str) -> str:
    """Place a MaterialX fragment in a lin_rec709 document with a material M bound to shader S;
    a fragment that is already a whole document is returned unchanged."""
    if fragment.lstrip().startswith(("<?xml", "<materialx")):
        return fragment
    body = "\n".join("  " + line for line in fragment.splitlines())
    return DOCUMENT.format(body=body)


@pytest.fixture
def write_mtlx(tmp_path: Path):
    """write_mtlx(fragment, name="doc.mtlx", files=()) -> path; creates the listed texture files."""

    def write(fragment: str | bytes, name: str = "doc.mtlx", files=(), config: str = "") -> Path:
        path = tmp_path / name
        if config:
            (tmp_path / ".openpbr.toml").write_text(config, encoding="utf-8")
        path.parent.mkdir(parents=True, exist_ok=True)
        if isinstance(fragment, bytes):
            path.write_bytes(fragment)
        elif name.endswith(".mtlx"):
            path.write_text(document(fragment), encoding="utf-8")
        else:
            path.write_text(fragment, encoding="utf-8")
        for file in files:
            target = tmp_path / file
            target.parent.mkdir(parents=True, exist_ok=True)
            target.write_bytes(b"")
        return path

    return write


@pytest.fixture
def codes_of():
    """codes_of(path) -> list of rule codes the validator reports for the file, with the project
    configuration found beside it (as `openpbr validate` runs)."""
    from openpbr_tools.validate import validate_paths

    def run(path) -> list[str]:
        return [d.code for d in validate_paths([str(path)]).diagnostics]

    return run
