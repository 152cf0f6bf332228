"""Structure: is every material wired to a shader, and does every connection lead somewhere.

A ``surfacematerial`` with no surface shader renders as the renderer's error material; a
``nodename`` that names no node is read by MaterialX without complaint and renders the input's
default. Procedural graphs the toolkit cannot interpret are kept and reported (OPBR803), so a
conversion never drops them silently.
"""

from __future__ import annotations

from ..diagnostics import Severity
from ..model import Connection
from . import Rule

NO_SHADER = Rule(
    "OPBR801", "material-without-shader", Severity.ERROR,
    "A material has no surface shader connected.",
    "The material renders as the renderer's fallback (often bright magenta or black).",
    passing='<open_pbr_surface name="S" type="surfaceshader" />',
    failing='<?xml version="1.0"?>\n<materialx version="1.39" colorspace="lin_rec709">\n  <open_pbr_surface name="S" type="surfaceshader" />\n  <surfacematerial name="M" type="material" />\n</materialx>\n',
)
DANGLING = Rule(
    "OPBR802", "dangling-connection", Severity.ERROR,
    "A connection or reference names a node, graph output or material that does not exist.",
    "MaterialX reads it without complaint; the input silently falls back to its default value.",
    passing='<open_pbr_surface name="S" type="surfaceshader">\n  <input name="base_weight" type="float" value="1" />\n</open_pbr_surface>',
    failing='<open_pbr_surface name="S" type="surfaceshader">\n  <input name="base_weight" type="float" nodename="weight_map" />\n</open_pbr_surface>',
)
UNINTERPRETED = Rule(
    "OPBR803", "procedural-input", Severity.INFO,
    "An input is driven by a node graph the toolkit does not interpret (not an image lookup).",
    "Its values cannot be range-checked. A conversion to a .mtlx or USD output keeps the graph for MaterialX "
    "shaders (rewired, with a mapping written after it as MaterialX nodes where one is needed); glTF and "
    "UsdPreviewSurface hold no graph, so a conversion to them drops it, reported rather than silently lost.",
    passing='<open_pbr_surface name="S" type="surfaceshader">\n  <input name="base_color" type="color3" value="0.5, 0.5, 0.5" />\n</open_pbr_surface>',
    failing='<noise3d name="n" type="color3" />\n<open_pbr_surface name="S" type="surfaceshader">\n  <input name="base_color" type="color3" nodename="n" />\n</open_pbr_surface>',
)
UNASSIGNED = Rule(
    "OPBR804", "shader-without-material", Severity.INFO,
    "A surface shader no material refers to.",
    "Harmless but often a leftover: the shader is never rendered.",
    passing='<open_pbr_surface name="S" type="surfaceshader" />',
    failing='<?xml version="1.0"?>\n<materialx version="1.39" colorspace="lin_rec709">\n  <open_pbr_surface name="S" type="surfaceshader" />\n</materialx>\n',
)

NOT_READ = Rule(
    "OPBR805", "material-shader-not-read", Severity.INFO,
    "A material's surface shader is none of the shading models the toolkit reads.",
    "A renderer-specific or custom shader (a nodedef without a node graph around OpenPBR, Standard "
    "Surface, glTF PBR or UsdPreviewSurface) is neither checked nor converted: a conversion leaves the "
    "material out and reports it (an error there). Custom nodes whose definition wraps one of those "
    "shaders are read as that shader. Info: the file is not wrong, the toolkit's reach ends.",
    passing='<open_pbr_surface name="S" type="surfaceshader" />\n<surfacematerial name="M" type="material">\n'
            '  <input name="surfaceshader" type="surfaceshader" nodename="S" />\n</surfacematerial>',
    failing='<nodedef name="ND_toon" node="toon">\n  <output name="out" type="surfaceshader" />\n</nodedef>\n'
            '<toon name="S" type="surfaceshader" />\n<surfacematerial name="M" type="material">\n'
            '  <input name="surfaceshader" type="surfaceshader" nodename="S" />\n</surfacematerial>',
)

_SPLIT = ('<nodegraph name="NG">\n  <image name="orm" type="color3">\n'
          '    <input name="file" type="filename" value="orm.png" colorspace="none" />\n  </image>\n'
          '  <separate3 name="split" type="multioutput">\n    <input name="in" type="color3" nodename="orm" />\n'
          '  </separate3>\n  <output name="rough" type="float" nodename="split"{output} />\n</nodegraph>\n'
          '<open_pbr_surface name="S" type="surfaceshader">\n'
          '  <input name="specular_roughness" type="float" nodegraph="NG" output="rough" />\n</open_pbr_surface>')
MULTIOUTPUT_UNNAMED = Rule(
    "OPBR806", "multioutput-connection-unnamed", Severity.WARNING,
    "A connection to a node with several outputs (separate3, a glTF colour image) names none of them (no output=).",
    "MaterialX's specification asks for the output attribute where the node has more than one; MaterialX itself "
    "then connects the first (a separate3's red channel, outr) without a word and validate() passes, while the "
    "author usually meant another channel (roughness in green of an ORM map). Name the output.",
    passing=_SPLIT.format(output=' output="outg"'), failing=_SPLIT.format(output=""), example_files=("orm.png",),
)

RULES = (NO_SHADER, DANGLING, UNINTERPRETED, UNASSIGNED, NOT_READ, MULTIOUTPUT_UNNAMED)


def check(asset, context):
    for observation in asset.observations:
        if observation.kind == "material_without_shader":
            yield context.diagnostic(
                NO_SHADER, f"material {observation.detail.get('material')!r} has no surface shader",
                observation.location, hint="connect its surfaceshader input to a shader node",
            )
        elif observation.kind == "unsupported_shader":
            yield context.diagnostic(
                NOT_READ, f"material {observation.detail.get('material')!r} uses a {observation.detail.get('category')} "
                          "shader, which the toolkit does not read: not checked, and left out of conversions",
                observation.location,
            )
        elif observation.kind == "multioutput_unnamed":
            yield context.diagnostic(
                MULTIOUTPUT_UNNAMED, f"the connection to {observation.detail['category']} node "
                f"{observation.detail['node']!r} names no output: MaterialX takes its first", observation.location,
                hint="add output=\"...\" naming the channel meant (outr, outg, outb)")
        elif observation.kind == "dangling_reference":
            target, reason = observation.detail.get("target"), observation.detail.get("ends")
            yield context.diagnostic(
                DANGLING, f"{observation.detail.get('attribute', 'reference')} {target!r} "
                          + (reason if reason else "does not exist"), observation.location,
            )
    for material in asset.materials:
        if material.material_name is None and asset.format == "mtlx":
            yield context.diagnostic(
                UNASSIGNED, f"shader {material.name!r} is not bound to any material", material.location,
            )
        for entry in material.inputs.values():
            value = entry.value
            if not isinstance(value, Connection):
                continue
            if value.dangling:
                yield context.diagnostic(  # (the reader's reason, where it has one: an undeclared output is authored)
                    DANGLING, f"{entry.name} is connected to {value.target!r}: {value.reason}" if value.reason
                    else f"{entry.name} is connected to {value.target!r}, which does not exist",
                    entry.location, hint="fix the connection (nodename/nodegraph/output, or the USD connection path), or author a value",
                )
            else:
                what = f"{value.category} node {value.target!r}" if value.category else repr(value.target)
                kept = "kept by a conversion to .mtlx or USD (MaterialX shaders), dropped by one to glTF or " \
                    "UsdPreviewSurface" if value.graph_xml else "dropped on conversion"
                yield context.diagnostic(
                    UNINTERPRETED, f"{entry.name} is driven by {what}: not checked, and {kept}",
                    entry.location,
                )
