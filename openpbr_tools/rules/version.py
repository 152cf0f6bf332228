"""Version: which OpenPBR version a material is written for, and whether that is a problem.

Files do not record their OpenPBR version reliably; the version is inferred from input names when
neither a ``version`` nor a ``nodedef`` attribute settles it (see :mod:`openpbr_tools.versioning`),
and OPBR401 says how. Names from 0.5 onwards are identical across 0.5, 1.0, 1.1 and 1.1.1, so such
a material is taken to be 1.1.1; note that 1.1 changed thin_film_ior's default from 1.5 to 1.4,
so a 1.0 material that leaves it unset renders differently in 1.1.1.
"""

from __future__ import annotations

from .. import tables
from ..diagnostics import Severity
from ..model import Location
from . import Rule

INFERRED = Rule(
    "OPBR401", "inferred-version", Severity.INFO,
    "How the material's OpenPBR version was determined.",
    "Reported whenever the version did not come from a version or nodedef attribute, so a reader "
    "of the report knows what the other checks assumed. Set version=\"1.1.1\" on the node to state it.",
    passing='<open_pbr_surface name="S" type="surfaceshader" version="1.1.1">\n  <input name="coat_darkening" type="float" value="1" />\n</open_pbr_surface>',
    failing='<open_pbr_surface name="S" type="surfaceshader">\n  <input name="coat_darkening" type="float" value="1" />\n</open_pbr_surface>',
)
LEGACY_VERSION = Rule(
    "OPBR402", "legacy-version", Severity.WARNING,
    "The material is written for an OpenPBR version older than the current one.",
    "Its inputs (e.g. base_roughness, specular_ior_level, thin-film thickness in nanometres) mean "
    "something else, or nothing, to a current renderer. `openpbr upgrade` converts it.",
    passing='<open_pbr_surface name="S" type="surfaceshader">\n  <input name="base_diffuse_roughness" type="float" value="0.2" />\n</open_pbr_surface>',
    failing='<open_pbr_surface name="S" type="surfaceshader">\n  <input name="base_roughness" type="float" value="0.2" />\n  <input name="specular_ior_level" type="float" value="0.5" />\n</open_pbr_surface>',
)
MIXED_MATERIAL = Rule(
    "OPBR403", "mixed-version-material", Severity.ERROR,
    "One material mixes input names of OpenPBR versions that never coexisted.",
    "E.g. base_roughness (0.2/0.3) beside coat_darkening (0.5+): no single version defines both, "
    "so whichever version a renderer assumes, part of the material is ignored.",
    passing='<open_pbr_surface name="S" type="surfaceshader">\n  <input name="base_diffuse_roughness" type="float" value="0.2" />\n  <input name="coat_darkening" type="float" value="1" />\n</open_pbr_surface>',
    failing='<open_pbr_surface name="S" type="surfaceshader">\n  <input name="base_roughness" type="float" value="0.2" />\n  <input name="coat_darkening" type="float" value="1" />\n</open_pbr_surface>',
)
MIXED_DOCUMENT = Rule(
    "OPBR404", "mixed-version-document", Severity.WARNING,
    "Materials of one file are written for different OpenPBR versions.",
    "Usually a file assembled from several sources; upgrade all of it together.",
    passing='<open_pbr_surface name="S" type="surfaceshader">\n  <input name="base_diffuse_roughness" type="float" value="0.2" />\n</open_pbr_surface>\n<open_pbr_surface name="T" type="surfaceshader">\n  <input name="coat_darkening" type="float" value="0.5" />\n</open_pbr_surface>',
    failing='<open_pbr_surface name="S" type="surfaceshader">\n  <input name="base_roughness" type="float" value="0.2" />\n</open_pbr_surface>\n<open_pbr_surface name="T" type="surfaceshader">\n  <input name="coat_darkening" type="float" value="0.5" />\n</open_pbr_surface>',
)

REQUIRED_VERSION = Rule(
    "OPBR405", "required-version", Severity.ERROR,
    "A material's OpenPBR version is not the one the project requires (configuration).",
    "Set `required-version = \"1.1.1\"` in [tool.openpbr] to make every material in the project "
    "target one version; this rule is silent without that setting.",
    passing='<open_pbr_surface name="S" type="surfaceshader" version="1.1.1" />',
    failing='<open_pbr_surface name="S" type="surfaceshader" version="1.0" />',
    example_config='required-version = "1.1.1"\n',
)

NOT_BINDING = Rule(
    "OPBR406", "legacy-does-not-bind", Severity.ERROR,
    "A legacy OpenPBR material uses inputs, or a node version, that the installed MaterialX's "
    "open_pbr_surface node definition does not declare.",
    "MaterialX ships only the current definition (OpenPBR 1.1.1 in MaterialX 1.39.5): its "
    "Document.validate() rejects such a document (\"Input 'base_roughness' doesn't match declaration\"), "
    "shader generation fails or ignores the input, and UsdMtlx drops it, so the material does not render "
    "as authored anywhere a stock MaterialX is used. `openpbr upgrade` rewrites it. A pipeline that "
    "registers the toolkit's legacy node definitions (libraries/) with its renderers can lower this to a "
    "warning in the configuration: severity = { OPBR406 = \"warning\" }. A legacy material whose inputs "
    "all still exist binds, and is only OPBR402.",
    passing='<open_pbr_surface name="S" type="surfaceshader">\n  <input name="base_diffuse_roughness" type="float" value="0.3" />\n</open_pbr_surface>',
    failing='<open_pbr_surface name="S" type="surfaceshader">\n  <input name="base_roughness" type="float" value="0.3" />\n</open_pbr_surface>',
)

RULES = (INFERRED, LEGACY_VERSION, MIXED_MATERIAL, MIXED_DOCUMENT, REQUIRED_VERSION, NOT_BINDING)


def check(asset, context):
    settled = {}
    for material in asset.materials:
        if material.model != "open_pbr_surface" or material.version is None:
            continue
        basis = material.version_basis
        if basis.startswith("mixed"):
            yield context.diagnostic(
                MIXED_MATERIAL,
                f"{material.name} mixes input names of different OpenPBR versions; checked as {material.version}",
                material.location, hint="`openpbr upgrade` rewrites it for the current version",
            )
            settled[material.name] = material.version
            continue
        if not basis.startswith(("node version", "nodedef")):
            yield context.diagnostic(
                INFERRED, f"{material.name}: OpenPBR {material.version}, {basis}", material.location,
                hint=f"state it with version=\"{material.version}\"" if asset.format == "mtlx" else None,
            )
        required = context.required_version
        if required and material.version != required:
            yield context.diagnostic(
                REQUIRED_VERSION, f"{material.name} is OpenPBR {material.version}; the project requires {required}",
                material.location, hint="`openpbr upgrade --to " + required + "`",
            )
        current = tables.latest(material.model)
        if tables.version_key(material.version) < tables.version_key(current):
            yield context.diagnostic(
                LEGACY_VERSION, f"{material.name} is OpenPBR {material.version}; the current version is {current}",
                material.location, hint="`openpbr upgrade` converts it",
            )
            yield from _not_binding(material, current, context)
        if not basis.startswith("default"):
            settled[material.name] = material.version
    if len(set(settled.values())) > 1:
        listing = ", ".join(f"{name} {version}" for name, version in sorted(settled.items()))
        yield context.diagnostic(
            MIXED_DOCUMENT, f"materials of different OpenPBR versions in one file: {listing}", Location(asset.path),
        )


def _not_binding(material, current: str, context):
    """OPBR406 for the inputs of a legacy material the current definition lacks, and for a node
    version attribute naming a definition MaterialX does not ship."""
    declared = tables.table(material.model, current)
    for name in sorted(set(material.inputs) - set(declared.parameters)):
        yield context.diagnostic(
            NOT_BINDING, f"{material.name}.{name} is an OpenPBR {material.version} input that OpenPBR {current} (the "
                         "definition MaterialX ships) does not declare: MaterialX rejects it and renderers ignore it",
            material.inputs[name].location, hint="`openpbr upgrade` converts it",
        )
    if material.declared_version and material.declared_version != current:
        yield context.diagnostic(
            NOT_BINDING, f"{material.name} asks for open_pbr_surface version {material.declared_version!r}, which "
                         f"MaterialX does not define (it ships {current})", material.location,
            hint="`openpbr upgrade` converts it and removes the version attribute's old value",
        )
