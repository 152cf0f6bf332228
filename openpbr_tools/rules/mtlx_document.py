"""A MaterialX document's own elements (io/mtlx/document_checks.py observes them): an extract past its input's
channels, a custom node's missing shader source, two default versions of one node, a look assignment with a Maya DAG
path, a colour space on a connected input, a normal map flipped by a negative strength."""

from __future__ import annotations

from ..diagnostics import Severity
from . import Rule

_MATERIAL = ('<open_pbr_surface name="S" type="surfaceshader">\n  <input name="{input}" type="{type}" nodename="{node}"{extra} />\n'
             '</open_pbr_surface>\n<surfacematerial name="M" type="material">\n  <input name="surfaceshader" '
             'type="surfaceshader" nodename="S" />\n</surfacematerial>')
_EXTRACT = ('<image name="mask" type="{type}">\n  <input name="file" type="filename" value="mask.png" />\n</image>\n'
            '<extract name="smooth" type="float">\n  <input name="in" type="{type}" nodename="mask" />\n'
            '  <input name="index" type="integer" value="3" />\n</extract>\n')
CHANNEL_OUT_OF_RANGE = Rule(
    "OPBR807", "channel-out-of-range", Severity.ERROR,
    "An extract node reads a channel its input does not have (index 3 of a color3: the alpha of an image read as "
    "three channels).",
    "ND_extract_color3 takes an index of 0 to 2 (MaterialX's stdlib); MaterialX's validate() does not check the value, "
    "and its GLSL indexes the vector past its end, which GLSL leaves undefined (black, garbage, or a compile error "
    "depending on the driver). Read the image as color4 to reach its alpha.",
    passing=_EXTRACT.format(type="color4") + _MATERIAL.format(input="specular_roughness", type="float", node="smooth", extra=""),
    failing=_EXTRACT.format(type="color3") + _MATERIAL.format(input="specular_roughness", type="float", node="smooth", extra=""),
    example_files=("mask.png",),
)

_CUSTOM = ('<nodedef name="ND_grime_color3" node="grime">\n  <input name="base" type="color3" value="0.5, 0.5, 0.5" />\n'
           '  <output name="out" type="color3" />\n</nodedef>\n<implementation name="IM_grime_color3_genglsl" '
           'nodedef="ND_grime_color3" file="grime.glsl" function="grime_color3" target="genglsl" />\n'
           '<grime name="g" type="color3" />\n')
IMPLEMENTATION_MISSING = Rule(
    "OPBR808", "implementation-source-missing", Severity.ERROR,
    "A custom node's implementation names a source file that is not beside the document that declares it (nor on "
    "MaterialX's library search path).",
    "MaterialX's shader generation reads the implementation's file when it generates the node: without it, "
    "generation fails (\"Failed to get source code from file\") and the material renders in no MaterialX renderer. "
    "Usually a studio node library published without its shaders folder.",
    passing=_CUSTOM + _MATERIAL.format(input="base_color", type="color3", node="g", extra=""),
    failing=_CUSTOM.replace("grime.glsl", "shaders/missing_grime.glsl")
    + _MATERIAL.format(input="base_color", type="color3", node="g", extra=""),
    example_files=("grime.glsl",),
)

_VERSIONED = ('<nodedef name="ND_grime_v1_color3" node="grime" version="1.0" isdefaultversion="true">\n'
              '  <input name="base" type="color3" value="0.5, 0.5, 0.5" />\n  <output name="out" type="color3" />\n'
              '</nodedef>\n<nodegraph name="NG_grime_v1_color3" nodedef="ND_grime_v1_color3">\n'
              '  <output name="out" type="color3" interfacename="base" />\n</nodegraph>\n'
              '<nodedef name="ND_grime_v2_color3" node="grime" version="2.0"{default}>\n'
              '  <input name="base" type="color3" value="0.5, 0.5, 0.5" />\n  <output name="out" type="color3" />\n'
              '</nodedef>\n<nodegraph name="NG_grime_v2_color3" nodedef="ND_grime_v2_color3">\n'
              '  <output name="out" type="color3" interfacename="base" />\n</nodegraph>\n<grime name="g" type="color3" />\n')
DEFAULT_VERSIONS = Rule(
    "OPBR809", "several-default-versions", Severity.WARNING,
    "Two node definitions of one node and signature both say isdefaultversion=\"true\".",
    "The MaterialX specification allows one default version per node and signature: a node instance without a "
    "version attribute takes it. With two, MaterialX binds one of them without a word (the first it finds), so "
    "which look an unversioned node gets depends on definition order. Usually a new version published without "
    "clearing the old one's flag.",
    passing=_VERSIONED.format(default="") + _MATERIAL.format(input="base_color", type="color3", node="g", extra=""),
    failing=_VERSIONED.format(default=' isdefaultversion="true"')
    + _MATERIAL.format(input="base_color", type="color3", node="g", extra=""),
)

_LOOK = ('<constant name="c" type="color3">\n  <input name="value" type="color3" value="0.5, 0.3, 0.2" />\n</constant>\n'
         + _MATERIAL.format(input="base_color", type="color3", node="c", extra="")
         + '\n<look name="L">\n  <materialassign name="MA" material="M" geom="{geom}" />\n</look>')
LOOK_GEOMETRY = Rule(
    "OPBR810", "look-geometry-path-syntax", Severity.WARNING,
    "A look's assignment names its geometry with '|' separators (a Maya DAG path) where MaterialX geometry names use "
    "'/'.",
    "MaterialX geometry names are paths separated by '/' (the specification's \"Geometry Representation\"); a Maya "
    "DAG path such as |table_GRP|top_GEO matches no geometry, so the material is assigned to nothing and the "
    "object renders with its default. Write /table_GRP/top_GEO.",
    passing=_LOOK.format(geom="/table_GRP/top_GEO"), failing=_LOOK.format(geom="|table_GRP|top_GEO"),
)

_ALBEDO = '<image name="bc" type="color3">\n  <input name="file" type="filename" value="albedo.png"{space} />\n</image>\n'
COLORSPACE_ON_CONNECTION = Rule(
    "OPBR509", "colorspace-on-connection", Severity.WARNING,
    "A colorspace attribute sits on a connected input (a shader's base_color fed by an image), where it converts "
    "nothing.",
    "MaterialX applies an input's colorspace to the input's own value; a connected input has none, so the texture "
    "behind it is read unconverted (no sRGB decode in the generated GLSL). Tag the image's file input instead.",
    passing=_ALBEDO.format(space=' colorspace="srgb_texture"')
    + _MATERIAL.format(input="base_color", type="color3", node="bc", extra=""),
    failing=_ALBEDO.format(space="") + _MATERIAL.format(input="base_color", type="color3", node="bc",
                                                        extra=' colorspace="srgb_texture"'),
    example_files=("albedo.png",),
)

_NORMAL = ('<image name="n" type="vector3">\n  <input name="file" type="filename" value="normal.png" />\n</image>\n'
           '<normalmap name="nm" type="vector3">\n  <input name="in" type="vector3" nodename="n" />\n'
           '  <input name="scale" type="{type}" value="{scale}" />\n</normalmap>\n')
NORMALMAP_NEGATIVE = Rule(
    "OPBR720", "normalmap-negative-strength", Severity.WARNING,
    "A normalmap node's float scale is negative (-1 to \"fix\" a DirectX normal map).",
    "ND_normalmap_float multiplies both x and y by its scale, so -1 flips red as well as green: the relief turns "
    "inside out instead of becoming OpenGL's convention. A DirectX map needs only green flipped: the vector2 scale "
    "(1, -1) of ND_normalmap_vector2, or the image's green inverted.",
    passing=_NORMAL.format(type="vector2", scale="1, -1")
    + _MATERIAL.format(input="geometry_normal", type="vector3", node="nm", extra=""),
    failing=_NORMAL.format(type="float", scale="-1")
    + _MATERIAL.format(input="geometry_normal", type="vector3", node="nm", extra=""),
    example_files=("normal.png",),
)

RULES = (CHANNEL_OUT_OF_RANGE, IMPLEMENTATION_MISSING, DEFAULT_VERSIONS, LOOK_GEOMETRY, COLORSPACE_ON_CONNECTION,
         NORMALMAP_NEGATIVE)


def check(asset, context):
    """Runs on MaterialX assets only (rules.FAMILY_FORMATS)."""
    for observation in asset.observations:
        detail, where = observation.detail, observation.location
        if observation.kind == "mtlx_channel_out_of_range":
            yield context.diagnostic(
                CHANNEL_OUT_OF_RANGE, f"{detail['node']!r} extracts channel {detail['index']} of a {detail['type']}, "
                f"which has {detail['channels']} (0 to {detail['channels'] - 1})", where,
                hint="read the image as color4 to reach its alpha (index 3)" if detail["type"] == "color3" else None)
        elif observation.kind == "mtlx_implementation_missing":
            yield context.diagnostic(
                IMPLEMENTATION_MISSING, f"the {detail['target'] or 'shader'} implementation of {detail['node']!r} "
                f"reads {detail['file']!r}, which is not there: MaterialX cannot generate the node", where,
                hint="ship the implementation file with the document (relative to it)")
        elif observation.kind == "mtlx_default_versions":
            yield context.diagnostic(
                DEFAULT_VERSIONS, f"{', '.join(detail['nodedefs'])} are all the default version of {detail['node']!r}: "
                "MaterialX binds one of them silently", where, hint="keep isdefaultversion=\"true\" on one of them")
        elif observation.kind == "mtlx_look_geometry":
            yield context.diagnostic(
                LOOK_GEOMETRY, f"look {detail['look']!r} assigns to {detail['geom']!r}, a path with '|': MaterialX "
                "geometry names use '/', so it matches nothing", where,
                hint=f"write {detail['geom'].replace('|', '/')!r}")
        elif observation.kind == "mtlx_colorspace_on_connection":
            yield context.diagnostic(
                COLORSPACE_ON_CONNECTION, f"{detail['input']} of {detail['node']!r} is connected, so its colorspace "
                f"{detail['colorspace']!r} converts nothing: the texture behind it is read unconverted", where,
                hint="put the colorspace on the image's file input")
        elif observation.kind == "mtlx_normalmap_negative":
            yield context.diagnostic(
                NORMALMAP_NEGATIVE, f"{detail['node']!r} scales the normal map by {detail['scale']:g}, which flips x and "
                "y: a DirectX map needs only green flipped", where,
                hint="use a vector2 scale of (1, -1), or invert the image's green channel")
