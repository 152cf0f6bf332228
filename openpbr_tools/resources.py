"""Locating the data the package ships: ``schemas/``, ``libraries/`` and ``samples/``.

Installed, they live inside the ``openpbr_tools`` package; in a source checkout (editable install or
running from the tree) they are the top-level folders beside it.
"""

from __future__ import annotations

import json
from functools import lru_cache
from pathlib import Path

_PACKAGE = Path(__file__).resolve().parent


def data_dir(name: str) -> Path:
    """The folder ``schemas``, ``libraries`` or ``samples``."""
    for candidate in (_PACKAGE / name, _PACKAGE.parent / name):
        if candidate.is_dir() and any(candidate.iterdir()):
            return candidate
    raise FileNotFoundError(f"openpbr-tools data folder {name!r} is missing from the installation")


@lru_cache(maxsize=None)
def load_json(relative: str) -> dict:
    """A JSON file under ``schemas/``, parsed once per process."""
    with open(data_dir("schemas") / relative, encoding="utf-8") as handle:
        return json.load(handle)
