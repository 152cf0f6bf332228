"""Locating the data the package ships: ``schemas/``, ``libraries/`` and ``samples/``.

Installed, they live inside the ``openpbr_tools`` package; in a source checkout (editable install or
running from the tree) they are the top-level folders beside it.
"""

from __future__ import annotations

import json
import os
from functools import lru_cache

_PACKAGE = os.path.dirname(os.path.abspath(__file__))


def data_dir(name: str):
    """The folder ``schemas``, ``libraries`` or ``samples`` (a :class:`pathlib.Path`)."""
    from pathlib import Path  # lazy: pathlib costs ~3 ms of every start-up; the validator reads data through data_folder

    return Path(data_folder(name))


@lru_cache(maxsize=None)
def data_folder(name: str) -> str:
    """The folder ``schemas``, ``libraries`` or ``samples``, as a string path."""
    for candidate in (os.path.join(_PACKAGE, name), os.path.join(os.path.dirname(_PACKAGE), name)):
        if os.path.isdir(candidate) and os.listdir(candidate):
            return candidate
    raise FileNotFoundError(f"openpbr-tools data folder {name!r} is missing from the installation")


@lru_cache(maxsize=None)
def load_json(relative: str) -> dict:
    """A JSON file under ``schemas/``, parsed once per process."""
    with open(os.path.join(data_folder("schemas"), relative), encoding="utf-8") as handle:
        return json.load(handle)
