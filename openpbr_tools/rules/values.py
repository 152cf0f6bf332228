"""Values: does each input have the type its definition declares and a value that parses.

MaterialX reads ``"1,5"`` for a float as 1.0 and ``"0.5"`` for a colour3 as black; these rules
parse every value strictly (see :mod:`openpbr_tools.values`).
"""

from __future__ import annotations

from ..diagnostics import Severity
from ..io.usd.types import MATERIALX_TO_USD
from ..model import Connection, Texture
from ..values import is_finite
from . import Rule, for_each_input

TYPE_MISMATCH = Rule(
    "OPBR201", "type-mismatch", Severity.ERROR,
    "An input's type differs from the type its node definition declares.",
    "A renderer either rejects the input or reinterprets it (a float read as a colour, a colour "
    "truncated to a float). geometry_opacity, for instance, was color3 in OpenPBR 0.2 and is float since 0.5.",
    passing='<open_pbr_surface name="S" type="surfaceshader">\n  <input name="geometry_opacity" type="float" value="1" />\n</open_pbr_surface>',
    failing='<open_pbr_surface name="S" type="surfaceshader">\n  <input name="specular_roughness" type="color3" value="0.3, 0.3, 0.3" />\n</open_pbr_surface>',
)
UNPARSABLE = Rule(
    "OPBR202", "unparsable-value", Severity.ERROR,
    "A value string does not parse as its type (wrong component count, decimal comma, trailing text).",
    "MaterialX's parser is lenient: \"1,5\" for a float reads as 1.0 and \"0.5\" for a color3 as "
    "(0, 0, 0), without any warning. Components are separated by commas; the decimal separator is a point.",
    passing='<open_pbr_surface name="S" type="surfaceshader">\n  <input name="specular_ior" type="float" value="1.5" />\n</open_pbr_surface>',
    failing='<open_pbr_surface name="S" type="surfaceshader">\n  <input name="specular_ior" type="float" value="1,5" />\n</open_pbr_surface>',
)
NON_FINITE = Rule(
    "OPBR203", "non-finite-value", Severity.ERROR,
    "A value is NaN or infinite.",
    "NaN and infinity poison every pixel they touch (and propagate through texture filtering and "
    "denoisers). Often the output of a broken export script.",
    passing='<open_pbr_surface name="S" type="surfaceshader">\n  <input name="base_weight" type="float" value="1" />\n</open_pbr_surface>',
    failing='<open_pbr_surface name="S" type="surfaceshader">\n  <input name="base_weight" type="float" value="nan" />\n</open_pbr_surface>',
)
UNIFORM_CONNECTED = Rule(
    "OPBR204", "uniform-connected", Severity.ERROR,
    "A uniform input (e.g. geometry_thin_walled) is driven by a texture or a node.",
    "Uniform inputs must be constant over the surface (OpenPBR 1.1.1 made geometry_thin_walled "
    "uniform); shading languages reject a varying connection or ignore it. A graph of constants and arithmetic "
    "is constant over the surface and passes: MaterialX's own translation graphs, applied to constants "
    "(standard_surface_to_gltf_pbr feeding gltf_pbr's uniform attenuation_color), are validated and rendered by "
    "MaterialX as they are.",
    passing='<open_pbr_surface name="S" type="surfaceshader">\n  <input name="geometry_thin_walled" type="boolean" value="true" />\n</open_pbr_surface>',
    failing='<image name="mask" type="boolean">\n  <input name="file" type="filename" value="mask.png" />\n</image>\n<open_pbr_surface name="S" type="surfaceshader">\n  <input name="geometry_thin_walled" type="boolean" nodename="mask" />\n</open_pbr_surface>',
)

CONSTANT_NORMAL = Rule(
    "OPBR205", "constant-normal", Severity.INFO,
    "A world-space normal input (geometry_normal, coat_normal) is set to a constant vector.",
    "These inputs default to the surface's own world-space normal (defaultgeomprop Nworld) and are meant to "
    "be driven by a decoded normal map. MaterialX's shader generation ignores the constant: it connects the "
    "geometric normal to every unconnected input that has a defaultgeomprop, value or not (ShaderGraph.cpp; "
    "MaterialX's GLSL render of its own gltf_pbr_default example, which authors normal = (0, 0, 1), is the "
    "same with the value, without it, and with (1, 0, 0)). A reader that honours the value instead shades "
    "the whole object as one flat facet facing it, so the asset renders differently there. (0, 0, 1) is "
    "usually a tangent-space 'flat' normal exported as a value. UsdPreviewSurface's normal, in tangent "
    "space, is not concerned. Remove the value.",
    passing='<open_pbr_surface name="S" type="surfaceshader">\n  <input name="specular_roughness" type="float" value="0.3" />\n</open_pbr_surface>',
    failing='<open_pbr_surface name="S" type="surfaceshader">\n  <input name="geometry_normal" type="vector3" value="0, 0, 1" />\n</open_pbr_surface>',
)

RULES = (TYPE_MISMATCH, UNPARSABLE, NON_FINITE, UNIFORM_CONNECTED, CONSTANT_NORMAL)

# USD and glTF readers report their own type names in Input.source_type; equal MaterialX types pass.


def check(asset, context):
    for material, table, entry in for_each_input(asset):
        parameter = table.get(entry.name)
        if entry.error is not None:
            yield context.diagnostic(UNPARSABLE, f"{entry.name}: {entry.error}", entry.location,
                                     hint=_syntax_hint(entry.type))
        elif entry.constant is not None and not is_finite(entry.constant):
            yield context.diagnostic(NON_FINITE, f"{entry.name} is {entry.raw or entry.constant!r}", entry.location,
                                     hint=f"set a finite value (default {parameter.default!r})" if parameter else None)
        if parameter is None:
            continue
        if entry.type is None and asset.format == "mtlx" and entry.raw is not None:
            yield context.diagnostic(
                TYPE_MISMATCH, f"{entry.name} declares no type; {material.model} {material.version} defines it as "
                f"{parameter.type}: MaterialX matches no node definition to the shader ('doesn't match declaration') "
                "and generates no code for it", entry.location, hint=f"declare type=\"{parameter.type}\"")
        elif entry.type and entry.type != parameter.type:
            shown = entry.source_type or entry.type
            if entry.source_type:
                hint = f"author it as {MATERIALX_TO_USD.get(parameter.type, parameter.type)} inputs:{entry.name}"
            else:
                hint = f"declare type=\"{parameter.type}\""
            yield context.diagnostic(
                TYPE_MISMATCH,
                f"{entry.name} is declared {shown}; {material.model} {material.version} defines it as {parameter.type}",
                entry.location, hint=hint,
            )
        if parameter.role == "normal" and parameter.default_geomprop and isinstance(entry.constant, tuple) \
                and (not entry.type or entry.type == parameter.type):
            yield context.diagnostic(
                CONSTANT_NORMAL, f"{entry.name} = {_describe_vector(entry.constant)}: MaterialX ignores it and uses the "
                f"geometric normal ({parameter.default_geomprop}); a reader that honours it shades every point as facing "
                "one direction", entry.location,
                hint="remove the value, or connect a normal map through a normalmap node",
            )
        if parameter.uniform and isinstance(entry.value, (Texture, Connection)) and not getattr(entry.value, "dangling", False) \
                and not (isinstance(entry.value, Connection) and not entry.value.varying):
            yield context.diagnostic(
                UNIFORM_CONNECTED, f"{entry.name} is uniform but is connected to {_describe(entry.value)}",
                entry.location, hint="author a constant value",
            )


def _syntax_hint(type_name: str | None) -> str:
    examples = {"float": "0.5", "color3": "0.8, 0.8, 0.8", "vector3": "0, 0, 1", "boolean": "true",
                "integer": "1", "vector2": "1, 1", "color4": "1, 1, 1, 1"}
    example = examples.get(type_name or "")
    return f"a {type_name} is written like \"{example}\"" if example else "check the value syntax"


def _describe_vector(value: tuple) -> str:
    return "(" + ", ".join(f"{v:g}" for v in value) + ")"


def _describe(value) -> str:
    if isinstance(value, Texture):
        return f"the image {value.file!r}"
    return f"node {value.target!r}"
