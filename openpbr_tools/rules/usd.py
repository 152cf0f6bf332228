"""USD: checks that only make sense for USD stages (shader ids, USD types, metersPerUnit,
UsdPreviewSurface conventions). Rules whose meaning is the same as a MaterialX rule reuse its code.
"""

from __future__ import annotations

RULES = ()


def check(asset, context):
    if asset.format != "usd":
        return
    yield from ()
