"""Example stages shared by the USD rule families (:mod:`.usd`, :mod:`.usd_preview`): the passing
and failing documents of their rules are built from these."""

from __future__ import annotations


def stage_example(body: str, metadata: str = 'defaultPrim = "M"\n    metersPerUnit = 0.01\n    upAxis = "Y"') -> str:
    return f"#usda 1.0\n(\n    {metadata}\n)\n\n{body.strip()}\n"


def openpbr_example(*inputs: str, shader_id: str = "ND_open_pbr_surface_surfaceshader", extra: str = "") -> str:
    lines = "".join(f"        {line}\n" for line in inputs)
    identifier = f'        uniform token info:id = "{shader_id}"\n' if shader_id else ""
    return stage_example(
        'def Material "M"\n{\n    token outputs:mtlx:surface.connect = </M/S.outputs:surface>\n\n'
        f'    def Shader "S"\n    {{\n{identifier}{lines}        token outputs:surface\n    }}\n{extra}}}'
    )
