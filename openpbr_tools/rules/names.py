"""Names: are the node categories, node definitions and input names ones the model defines.

Input names are checked against the parameter table of the version the material was settled on
(see :mod:`openpbr_tools.versioning`). A name that belongs to another OpenPBR version is reported
as legacy (OPBR102) rather than unknown, with the versions it belongs to; one a major exporter writes on every
material and no reader reads (schemas/exporter_inputs.json) is noted (OPBR107).
"""

from __future__ import annotations

import difflib

from .. import tables, versioning
from ..diagnostics import Severity
from ..io.mtlx.reader import SHADER_CATEGORIES, known_categories
from ..resources import load_json
from . import Rule
from .usd_examples import stage_example

UNKNOWN_INPUT = Rule(
    "OPBR101", "unknown-input", Severity.ERROR,
    "An input name the shading model does not define (a typo, or another model's name).",
    "Renderers ignore inputs their node definition lacks, so the value silently has no effect. "
    "The hint suggests the closest defined name.",
    passing='<open_pbr_surface name="S" type="surfaceshader">\n  <input name="base_color" type="color3" value="0.5, 0.5, 0.5" />\n</open_pbr_surface>',
    failing='<open_pbr_surface name="S" type="surfaceshader">\n  <input name="base_colour" type="color3" value="0.5, 0.5, 0.5" />\n</open_pbr_surface>',
)
LEGACY_INPUT = Rule(
    "OPBR102", "legacy-input", Severity.WARNING,
    "An input name from an older (or newer) OpenPBR version than the rest of the material.",
    "OpenPBR renamed and removed inputs between 0.2 and 1.1.1 (e.g. base_roughness became "
    "base_diffuse_roughness in 0.4; specular_anisotropy became specular_roughness_anisotropy in 0.5). "
    "A current renderer ignores the old name. `openpbr upgrade` rewrites the material.",
    passing='<open_pbr_surface name="S" type="surfaceshader">\n  <input name="base_diffuse_roughness" type="float" value="0.2" />\n  <input name="coat_darkening" type="float" value="1" />\n</open_pbr_surface>',
    failing='<open_pbr_surface name="S" type="surfaceshader">\n  <input name="base_roughness" type="float" value="0.2" />\n  <input name="coat_darkening" type="float" value="1" />\n</open_pbr_surface>',
)
DUPLICATE_INPUT = Rule(
    "OPBR103", "duplicate-element", Severity.ERROR,
    "Two inputs (or elements) with the same name under one parent.",
    "MaterialX keeps the first and silently drops the second, so the value an author edited last "
    "may not be the one rendered.",
    passing='<open_pbr_surface name="S" type="surfaceshader">\n  <input name="base_weight" type="float" value="0.8" />\n</open_pbr_surface>',
    failing='<open_pbr_surface name="S" type="surfaceshader">\n  <input name="base_weight" type="float" value="0.8" />\n  <input name="base_weight" type="float" value="0.5" />\n</open_pbr_surface>',
)
UNKNOWN_CATEGORY = Rule(
    "OPBR104", "unknown-node-category", Severity.ERROR,
    "A node whose category no node definition declares (often a misspelt shader name).",
    "MaterialX reads such a node without complaint but no renderer can shade it. The hint names "
    "the closest known category.",
    passing='<open_pbr_surface name="S" type="surfaceshader" />',
    failing='<open_pbr_surfce name="S" type="surfaceshader" />',
)
MISSING_NODEDEF = Rule(
    "OPBR105", "missing-nodedef", Severity.ERROR,
    "The nodedef a shader names does not exist, or its version has no definition.",
    "A nodedef attribute must name a node definition of the same category (MaterialX ships "
    "ND_open_pbr_surface_surfaceshader for 1.1.1; this toolkit ships definitions of the legacy "
    "versions in libraries/).",
    passing='<open_pbr_surface name="S" type="surfaceshader" nodedef="ND_open_pbr_surface_surfaceshader" />',
    failing='<open_pbr_surface name="S" type="surfaceshader" nodedef="ND_open_pbr_surface_v2" />',
)
VERSION_MISMATCH = Rule(
    "OPBR106", "version-mismatch", Severity.ERROR,
    "A shader's version attribute disagrees with its nodedef, or names no known version.",
    "The version attribute selects which node definition a renderer uses. A version no definition "
    "has (e.g. version=\"1.2\") or one contradicting the nodedef attribute leaves the choice undefined.",
    passing='<open_pbr_surface name="S" type="surfaceshader" version="1.1.1" />',
    failing='<open_pbr_surface name="S" type="surfaceshader" version="1.2" />',
)

EXPORTER_INPUT = Rule(
    "OPBR107", "exporter-input", Severity.INFO,
    "An input no version of the shading model defines, which a major exporter writes on every material "
    "(schemas/exporter_inputs.json: Blender's USD exporter writes specular on each UsdPreviewSurface).",
    "USD readers ignore it, as they ignore any input their definition lacks; the material renders as if it were "
    "absent, which is what its exporter meant. Noted in a USD file, not reported as an unknown input (OPBR101): "
    "Blender 3.0 to 4.1 wrote it on every UsdPreviewSurface, and those files render as authored. In a MaterialX "
    "document MaterialX rejects the node (\"Node interface error\"), so there it stays OPBR101, as a misspelling "
    "of a defined input does.",
    passing=stage_example('def Material "M"\n{\n    token outputs:surface.connect = </M/P.outputs:surface>\n'
                          '    def Shader "P"\n    {\n        uniform token info:id = "UsdPreviewSurface"\n'
                          '        float inputs:roughness = 0.5\n        token outputs:surface\n    }\n}'),
    failing=stage_example('def Material "M"\n{\n    token outputs:surface.connect = </M/P.outputs:surface>\n'
                          '    def Shader "P"\n    {\n        uniform token info:id = "UsdPreviewSurface"\n'
                          '        float inputs:specular = 0.5\n        token outputs:surface\n    }\n}'),
    passing_name="example.usda", failing_name="example.usda", formats=("usd",),
)

RULES = (UNKNOWN_INPUT, LEGACY_INPUT, DUPLICATE_INPUT, UNKNOWN_CATEGORY, MISSING_NODEDEF, VERSION_MISMATCH,
         EXPORTER_INPUT)


def _closest(name: str, choices) -> str | None:
    match = difflib.get_close_matches(name, sorted(choices), n=1, cutoff=0.6)
    return match[0] if match else None


def check(asset, context):
    for material in asset.materials:
        yield from _check_material(material, context, asset.format)
    for observation in asset.observations:
        if observation.kind == "duplicate_element":
            first, included = observation.detail.get("first_line"), observation.detail.get("first_in")
            where = f" (first in the included {included})" if included else f" (first at line {first})" if first else ""
            yield context.diagnostic(
                DUPLICATE_INPUT,
                f"duplicate element {observation.detail['name']!r}{where}: MaterialX keeps the first and drops this one",
                observation.location, hint="delete one of the two",
            )
        elif observation.kind == "unknown_category":
            category = observation.detail["category"]
            guess = _closest(category, set(SHADER_CATEGORIES) | known_categories())
            yield context.diagnostic(
                UNKNOWN_CATEGORY, f"no node definition declares the category {category!r}",
                observation.location, hint=f"did you mean {guess!r}?" if guess else None,
            )


def _check_material(material, context, file_format: str):
    model = material.model
    available = tables.versions(model)
    if not available:
        return
    if material.declared_version and material.declared_version not in available:
        yield context.diagnostic(
            VERSION_MISMATCH,
            f"{model} has no version {material.declared_version!r} (known: {', '.join(available)})",
            material.location, hint=f"use version=\"{available[-1]}\" or remove the attribute",
        )
    node_type = material.extra.get("type")
    if node_type and node_type != "surfaceshader":
        yield context.diagnostic(
            MISSING_NODEDEF, f"no node definition of {model} outputs type {node_type!r}",
            material.location, hint="shader nodes are type=\"surfaceshader\"",
        )
    if material.nodedef:
        nodedef_version = versioning.nodedef_versions(model).get(material.nodedef)
        if nodedef_version is None:
            yield context.diagnostic(
                MISSING_NODEDEF, f"no node definition named {material.nodedef!r} for {model}",
                material.location, hint=f"did you mean {tables.table(model).nodedef!r}?" if tables.table(model).nodedef else None,
            )
        elif material.declared_version and material.declared_version != nodedef_version:
            yield context.diagnostic(
                VERSION_MISMATCH,
                f"version=\"{material.declared_version}\" but nodedef {material.nodedef} is version {nodedef_version}",
                material.location,
            )
    table = tables.table(model, material.version)
    everything = versioning.all_names(model)
    for name, entry in material.inputs.items():
        if name in table:
            continue
        if name in everything:
            owners = versioning.versions_with(model, name)
            span = owners[0] if len(owners) == 1 else f"{owners[0]} to {owners[-1]}"
            yield context.diagnostic(
                LEGACY_INPUT,
                f"{name!r} is an {model} {span} input, not {material.version} "
                f"(the material's version, {material.version_basis})",
                entry.location, hint="`openpbr upgrade` rewrites legacy inputs for the current version",
            )
            continue
        # (in USD only: UsdShade ignores an input the definition lacks, MaterialX rejects the node, "Node interface error")
        written_by = load_json("exporter_inputs.json").get(model, {}).get(name) if file_format == "usd" else None
        if written_by is not None:
            yield context.diagnostic(EXPORTER_INPUT, f"{model} has no input {name!r}, which no reader reads: {written_by}",
                                     entry.location)
            continue
        guess = _closest(name, table.parameters)
        yield context.diagnostic(
            UNKNOWN_INPUT, f"{model} {material.version} has no input {name!r}",
            entry.location, hint=f"did you mean {guess!r}?" if guess else None,
        )
