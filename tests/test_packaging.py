"""The wheel carries every module and data file: pyproject's explicit package list (needed to map
schemas/ and libraries/ into the package) must name every package folder of the source tree."""

from __future__ import annotations

import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def _pyproject() -> dict:
    if sys.version_info >= (3, 11):
        import tomllib
    else:
        import tomli as tomllib
    return tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))


def test_every_python_package_folder_is_listed():
    listed = set(_pyproject()["tool"]["setuptools"]["packages"])
    found = set()
    for top in ("openpbr_tools", "cli"):
        for init in (ROOT / top).rglob("*.py"):
            if "__pycache__" not in init.parts:
                found.add(".".join(init.parent.relative_to(ROOT).parts))
    assert found <= listed, f"add to [tool.setuptools] packages: {sorted(found - listed)}"


def test_data_folders_are_mapped_into_the_package():
    config = _pyproject()["tool"]["setuptools"]
    assert config["package-dir"] == {"openpbr_tools.schemas": "schemas", "openpbr_tools.libraries": "libraries"}
    data = config["package-data"]
    for pattern_owner, folder, suffix in (("openpbr_tools.schemas", "schemas", ".json"),
                                          ("openpbr_tools.libraries", "libraries", ".mtlx"),
                                          ("openpbr_tools.samples", "openpbr_tools/samples", ".mtlx")):
        patterns = data[pattern_owner]
        for file in (ROOT / folder).rglob(f"*{suffix}"):
            relative = file.relative_to(ROOT / folder)
            assert any(relative.match(p) for p in patterns), f"{file} is not in package-data {patterns}"
