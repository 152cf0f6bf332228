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

_ORM = ('<nodegraph name="NG_orm">\n  <image name="orm" type="color3">\n    <input name="file" type="filename" '
        'value="orm.png" />\n  </image>\n  <extract name="rough" type="float">\n    <input name="in" type="color3" '
        'nodename="orm" />\n    <input name="index" type="integer" value="1" />\n  </extract>\n  <extract name="metal" '
        'type="float">\n    <input name="in" type="color3" nodename="orm" />\n    <input name="index" type="integer" '
        'value="2" />\n  </extract>\n  <output name="out_roughness" type="float" nodename="rough" />\n  <output '
        'name="out_metalness" type="float" nodename="metal" />\n</nodegraph>\n<open_pbr_surface name="S" '
        'type="surfaceshader">\n  <input name="base_metalness" type="float" nodegraph="NG_orm"{output} />\n'
        '</open_pbr_surface>\n<surfacematerial name="M" type="material">\n  <input name="surfaceshader" '
        'type="surfaceshader" nodename="S" />\n</surfacematerial>')
OUTPUT_UNNAMED = Rule(
    "OPBR811", "graph-output-unnamed", Severity.ERROR,
    "An input connects to a node graph with several outputs without naming one (output=).",
    "The MaterialX specification: \"If the referenced node/nodegraph has multiple outputs, output is required\". "
    "MaterialX's validate() accepts the document and connects the graph's first output, so base_metalness reads the "
    "roughness an ORM graph declares first: an exporter that writes nodegraph= alone wires the wrong map without a "
    "word. Name the output.",
    passing=_ORM.format(output=' output="out_metalness"'), failing=_ORM.format(output=""), example_files=("orm.png",),
)
_SPACE = ('<normal name="n" type="vector3">\n  <input name="space" type="string" value="{space}" />\n</normal>\n'
          + _MATERIAL.format(input="geometry_normal", type="vector3", node="n", extra=""))
NORMAL_SPACE = Rule(
    "OPBR812", "shader-normal-not-world-space", Severity.WARNING,
    "A shader's normal or tangent input is fed by a normal, tangent or bitangent node in object or model space.",
    "OpenPBR's and Standard Surface's normal and tangent inputs are world-space vectors (their nodedefs default them "
    "to Nworld and Tworld, and the BSDFs shade in world space): an object-space normal is right only while the "
    "object is untransformed, and shading turns with the object's rotation. Use space=\"world\" (the default).",
    passing=_SPACE.format(space="world"), failing=_SPACE.format(space="object"),
)
_HEX = ('<{image} name="hex" type="{type}">\n  <input name="file" type="filename" value="normal.png" />\n</{image}>\n'
        '<normalmap name="nm" type="vector3">\n  <input name="in" type="vector3" nodename="hex" />\n</normalmap>\n'
        + _MATERIAL.format(input="geometry_normal", type="vector3", node="nm", extra=""))
HEXTILED_NORMAL = Rule(
    "OPBR813", "hextiled-normal-map", Severity.ERROR,
    "A normalmap reads a hextiledimage.",
    "hextiledimage rotates each hexagonal tile's lookup by a random angle (its rotation input, 0-360 degrees by "
    "default) but a normal map's texels are vectors in the tangent frame, which the rotation does not turn: the "
    "bumps of each tile light from a different direction. MaterialX's stdlib has hextilednormalmap, which rotates "
    "the vectors with the lookup.",
    passing=_HEX.format(image="image", type="vector3"), failing=_HEX.format(image="hextiledimage", type="vector3"),
    example_files=("normal.png",),
)
_LOOK = ('<open_pbr_surface name="S" type="surfaceshader" />\n<surfacematerial name="M" type="material">\n  <input '
         'name="surfaceshader" type="surfaceshader" nodename="S" />\n</surfacematerial>\n<collection name="C_legs" '
         'includegeom="/table/leg_*" />\n<look name="L">\n  <materialassign name="MA" material="M" {target} />\n</look>')
ASSIGN_BOTH = Rule(
    "OPBR814", "assignment-geom-and-collection", Severity.WARNING,
    "A look's materialassign names both a geom and a collection.",
    "The MaterialX specification lets a geometry assignment name either geometry (geom) or a collection, not both; "
    "MaterialX's validate() does not check it, and applications resolve it differently (one of the two, or their "
    "union), so the material lands on different geometry per application.",
    passing=_LOOK.format(target='collection="C_legs"'),
    failing=_LOOK.format(target='geom="/table/top" collection="C_legs"'),
)
_UV_SET = ('<texcoord name="uv" type="vector2">\n  <input name="index" type="integer" value="{index}" />\n</texcoord>\n'
           '<image name="nmap" type="vector3">\n  <input name="file" type="filename" value="normal.png" />\n  <input '
           'name="texcoord" type="vector2" nodename="uv" />\n</image>\n<normalmap name="nm" type="vector3">\n  <input '
           'name="in" type="vector3" nodename="nmap" />\n</normalmap>\n'
           + _MATERIAL.format(input="geometry_normal", type="vector3", node="nm", extra=""))
NORMALMAP_UV_SET = Rule(
    "OPBR815", "normal-map-uv-set-tangent", Severity.WARNING,
    "A normal map reads a UV set other than 0 while its normalmap node uses the default tangent frame.",
    "ND_normalmap's tangent and bitangent default to Tworld and Bworld, the tangent frame renderers build from the "
    "mesh's first UV set; a normal map baked in another UV set's layout is decoded in the wrong frame wherever the "
    "two layouts are rotated or mirrored against each other. Connect a tangent (and bitangent) of that UV set, or "
    "bake the map in UV set 0.",
    passing=_UV_SET.format(index=0), failing=_UV_SET.format(index=1), example_files=("normal.png",),
)

RULES = (CHANNEL_OUT_OF_RANGE, IMPLEMENTATION_MISSING, DEFAULT_VERSIONS, LOOK_GEOMETRY, COLORSPACE_ON_CONNECTION,
         NORMALMAP_NEGATIVE, OUTPUT_UNNAMED, NORMAL_SPACE, HEXTILED_NORMAL, ASSIGN_BOTH, NORMALMAP_UV_SET)


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
        elif observation.kind == "mtlx_output_unnamed":
            yield context.diagnostic(
                OUTPUT_UNNAMED, f"{detail['input']} of {detail['node']!r} connects to node graph {detail['graph']!r}, which "
                f"has {len(detail['outputs'])} outputs ({', '.join(detail['outputs'])}), without naming one: MaterialX "
                f"connects {detail['chosen']!r}", where, hint="add output=\"...\" naming the output meant")
        elif observation.kind == "mtlx_normal_space":
            yield context.diagnostic(
                NORMAL_SPACE, f"{detail['input']} reads {detail['category']} node {detail['node']!r} in {detail['space']} "
                "space, where the shading model takes world-space vectors", where,
                hint="set its space to \"world\" (the default)")
        elif observation.kind == "mtlx_hextiled_normal":
            yield context.diagnostic(
                HEXTILED_NORMAL, f"{detail['node']!r} decodes the hextiledimage {detail['image']!r}, whose random per-tile "
                "rotation turns the lookup but not the normals in it", where,
                hint="use a hextilednormalmap node in place of the hextiledimage and normalmap")
        elif observation.kind == "mtlx_assign_geom_and_collection":
            yield context.diagnostic(
                ASSIGN_BOTH, f"look {detail['look']!r} assigns to geom {detail['geom']!r} and collection "
                f"{detail['collection']!r}: the specification allows one of them", where,
                hint="keep the collection (add the geometry to it) or the geom")
        elif observation.kind == "mtlx_normalmap_uv_set":
            yield context.diagnostic(
                NORMALMAP_UV_SET, f"{detail['node']!r} decodes {detail['image']!r}, read in UV set {detail['index']}, in the "
                "default tangent frame, which follows UV set 0", where,
                hint="connect a tangent of that UV set to the normalmap, or bake the map in UV set 0")
