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


def test_every_data_file_is_in_a_listed_package_and_matches_its_package_data():
    """setuptools installs a data file when its folder is a listed package (a folder of data only is a
    namespace package, named too) and its name matches that package's package-data patterns."""
    config = _pyproject()["tool"]["setuptools"]
    assert config["package-dir"] == {"openpbr_tools.schemas": "schemas", "openpbr_tools.libraries": "libraries"}
    listed, data = set(config["packages"]), config["package-data"]
    roots = {"schemas": "openpbr_tools.schemas", "libraries": "openpbr_tools.libraries",
             "openpbr_tools/samples": "openpbr_tools.samples", "openpbr_tools/evaluate/data": "openpbr_tools.evaluate.data"}
    checked = 0
    for folder, package in roots.items():
        for file in (ROOT / folder).rglob("*"):
            if not file.is_file() or file.suffix in (".py", ".pyc") or "__pycache__" in file.parts:
                continue
            owner = ".".join((package, *file.parent.relative_to(ROOT / folder).parts))
            assert owner in listed, f"{file}: add {owner!r} to [tool.setuptools] packages"
            assert any(file.match(pattern) for pattern in data.get(owner, ())), \
                f"{file} matches no package-data pattern of {owner}: {data.get(owner)}"
            checked += 1
    assert checked >= 28
