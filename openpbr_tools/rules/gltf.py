"""glTF: checks that only make sense for glTF assets (extension declarations, texture and image
references, KHR_texture_transform). Rules whose meaning is the same as a MaterialX rule reuse its code.
"""

from __future__ import annotations

RULES = ()


def check(asset, context):
    if asset.format != "gltf":
        return
    yield from ()
