"""Translation: what an upgrade or a conversion did to each parameter, and what it could not carry.

These codes are not checks of an input file; they make up the loss report of ``openpbr upgrade``
and ``openpbr convert``, in the same formats as validation. The translators, the baker, the
writers and the upgrader each choose the code where they make a note; every note is located at the
source material and input it concerns (file, line, element path / prim path / JSON pointer, input,
and ``material``), and, where a writer knows it, at the place in the written file (``output``: a
USD prim and input, a glTF ``/materials/N``). Every approximation and every loss is reported; a
clean report means the result renders as the original did. Each rule's examples are run by the test
suite with the command they name.
"""

from __future__ import annotations

from ..diagnostics import Severity
from . import Rule

RENAMED = Rule(
    "OPBR1101", "input-renamed", Severity.INFO,
    "An input was renamed between versions or models; the value is carried exactly.",
    "For instance OpenPBR 0.4 renamed base_roughness to base_diffuse_roughness.",
    passing='<open_pbr_surface name="S" type="surfaceshader">\n  <input name="base_diffuse_roughness" type="float" value="0.3" />\n</open_pbr_surface>',
    failing='<open_pbr_surface name="S" type="surfaceshader">\n  <input name="base_roughness" type="float" value="0.3" />\n</open_pbr_surface>',
    formats=(), example_command=('upgrade', 'IN', '-o', 'out.mtlx'),
)
CONVERTED = Rule(
    "OPBR1102", "value-converted", Severity.INFO,
    "A value was converted exactly (a unit change, an IOR level folded into the IOR).",
    "The result renders as the original did; the message gives the formula and both values.",
    passing='<open_pbr_surface name="S" type="surfaceshader">\n  <input name="base_color" type="color3" value="0.8, 0.2, 0.1" />\n</open_pbr_surface>',
    failing='<open_pbr_surface name="S" type="surfaceshader">\n  <input name="thin_film_weight" type="float" value="1" />\n  <input name="thin_film_thickness" type="float" value="0.5" />\n</open_pbr_surface>',
    formats=(), example_command=('convert', 'IN', '-o', 'out.gltf'),
)
APPROXIMATED = Rule(
    "OPBR1103", "value-approximated", Severity.WARNING,
    "A value had no exact equivalent and was approximated.",
    "The message says how (e.g. a colour opacity averaged to a float) and, where known, the error.",
    passing='<open_pbr_surface name="S" type="surfaceshader">\n  <input name="base_color" type="color3" value="0.8, 0.2, 0.1" />\n</open_pbr_surface>',
    failing='<open_pbr_surface name="S" type="surfaceshader">\n  <input name="fuzz_weight" type="float" value="1" />\n</open_pbr_surface>',
    formats=(), example_command=('convert', 'IN', '-o', 'out.gltf'),
)
NOT_CARRIED = Rule(
    "OPBR1104", "not-carried", Severity.ERROR,
    "A value could not be carried to the target at all.",
    "The result renders differently where this input mattered (e.g. a textured IOR level, which "
    "needs a baked IOR texture). The message says what was dropped.",
    passing='<open_pbr_surface name="S" type="surfaceshader">\n  <input name="base_color" type="color3" value="0.8, 0.2, 0.1" />\n</open_pbr_surface>',
    failing='<open_pbr_surface name="S" type="surfaceshader">\n  <input name="thin_film_weight" type="float" value="1" />\n  <input name="thin_film_thickness" type="float" value="0.5" />\n</open_pbr_surface>',
    formats=(), example_command=('convert', 'IN', '-o', 'out.mtlx', '--to', 'UsdPreviewSurface'),
)
DEFAULT_PINNED = Rule(
    "OPBR1105", "default-pinned", Severity.INFO,
    "An unset input whose default changed between versions was written explicitly.",
    "OpenPBR 1.1 changed thin_film_ior's default from 1.5 to 1.4: an upgraded 1.0 material keeps its "
    "look only if the old default is written out.",
    passing='<open_pbr_surface name="S" type="surfaceshader" version="1.1">\n  <input name="thin_film_weight" type="float" value="1" />\n</open_pbr_surface>',
    failing='<open_pbr_surface name="S" type="surfaceshader" version="1.0">\n  <input name="thin_film_weight" type="float" value="1" />\n</open_pbr_surface>',
    formats=(), example_command=('upgrade', 'IN', '-o', 'out.mtlx'),
)
GRAPH_INSERTED = Rule(
    "OPBR1106", "graph-inserted", Severity.INFO,
    "A node graph was inserted to carry a parameter the target expresses differently.",
    "OpenPBR 0.5 removed specular_rotation: the rotation is carried by rotating the tangent "
    "(a rotate3d node about the normal feeding geometry_tangent).",
    passing='<open_pbr_surface name="S" type="surfaceshader">\n  <input name="specular_roughness_anisotropy" type="float" value="0.5" />\n</open_pbr_surface>',
    failing='<open_pbr_surface name="S" type="surfaceshader">\n  <input name="specular_anisotropy" type="float" value="0.5" />\n  <input name="specular_rotation" type="float" value="0.25" />\n</open_pbr_surface>',
    formats=(), example_command=('upgrade', 'IN', '-o', 'out.mtlx'),
)
LOOK_CHANGED = Rule(
    "OPBR1107", "semantics-changed", Severity.WARNING,
    "The target version interprets an input differently and no exact compensation is known.",
    "OpenPBR 1.1.1 no longer scales a metal's edge tint by specular_weight; a metal with "
    "specular_weight below 1 and a tinted specular_color renders with a different edge colour.",
    passing='<open_pbr_surface name="S" type="surfaceshader" version="1.1">\n  <input name="base_metalness" type="float" value="1" />\n  <input name="specular_weight" type="float" value="0.5" />\n</open_pbr_surface>',
    failing='<open_pbr_surface name="S" type="surfaceshader" version="1.1">\n  <input name="base_metalness" type="float" value="1" />\n  <input name="specular_weight" type="float" value="0.5" />\n  <input name="specular_color" type="color3" value="1, 0.5, 0.2" />\n</open_pbr_surface>',
    formats=(), example_command=('upgrade', 'IN', '-o', 'out.mtlx'),
)

VERIFIED = Rule(
    "OPBR1108", "verified", Severity.INFO,
    "`convert --verify`: the colour difference between the original and the converted material.",
    "Both materials are rendered by the toolkit's lobe evaluator on the same lit sphere; the message "
    "gives CIEDE2000 mean, 95th percentile and maximum over the sphere's pixels. Textured inputs are "
    "evaluated at their fallback or default value.",
    passing='<open_pbr_surface name="S" type="surfaceshader">\n  <input name="fuzz_weight" type="float" value="1" />\n  <input name="fuzz_color" type="color3" value="1, 0, 0" />\n  <input name="base_color" type="color3" value="0, 0, 1" />\n</open_pbr_surface>',
    failing='<open_pbr_surface name="S" type="surfaceshader">\n  <input name="base_color" type="color3" value="0.8, 0.2, 0.1" />\n</open_pbr_surface>',
    formats=(), example_command=('convert', 'IN', '-o', 'out.mtlx', '--to', 'UsdPreviewSurface', '--verify'),
)
VERIFY_THRESHOLD = Rule(
    "OPBR1109", "verify-above-threshold", Severity.WARNING,
    "`convert --verify`: the converted material differs visibly from the original.",
    "The mean CIEDE2000 over the preview sphere is above --threshold (default 2, about the smallest "
    "difference a viewer notices side by side). The other entries of the report say what was approximated.",
    passing='<open_pbr_surface name="S" type="surfaceshader">\n  <input name="base_color" type="color3" value="0.8, 0.2, 0.1" />\n</open_pbr_surface>',
    failing='<open_pbr_surface name="S" type="surfaceshader">\n  <input name="fuzz_weight" type="float" value="1" />\n  <input name="fuzz_color" type="color3" value="1, 0, 0" />\n  <input name="base_color" type="color3" value="0, 0, 1" />\n</open_pbr_surface>',
    formats=(), example_command=('convert', 'IN', '-o', 'out.mtlx', '--to', 'UsdPreviewSurface', '--verify'),
)

RULES = (RENAMED, CONVERTED, APPROXIMATED, NOT_CARRIED, DEFAULT_PINNED, GRAPH_INSERTED, LOOK_CHANGED,
         VERIFIED, VERIFY_THRESHOLD)


def check(asset, context):
    return iter(())
