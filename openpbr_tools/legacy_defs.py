"""Node definitions of the legacy OpenPBR versions, generated from the parameter tables.

MaterialX ships only the current OpenPBR definition. ``libraries/open_pbr_surface_legacy_defs.mtlx``
declares the interface of every older version (no implementation graph: they are for validation
and for tools that must read legacy documents, not for rendering), named after MaterialX's
convention for versioned definitions (``ND_standard_surface_surfaceshader_100`` is 1.0.0): OpenPBR
0.5 is ``ND_open_pbr_surface_surfaceshader_05``. The shipped file is checked against this generator
by the test suite, so the tables stay the single source.
"""

from __future__ import annotations

from . import tables
from .io.mtlx.writer import document_text
from .values import format_value

MODEL = "open_pbr_surface"
LIBRARY_FILE = "open_pbr_surface_legacy_defs.mtlx"


def nodedef_name(version: str) -> str:
    return f"ND_{MODEL}_surfaceshader_{version.replace('.', '')}"


def legacy_versions() -> tuple[str, ...]:
    return tables.versions(MODEL)[:-1]


def generate() -> str:
    import MaterialX as mx  # lazy: MaterialX's bindings (~8 ms) load only when the definitions are generated

    document = mx.createDocument()
    for version in legacy_versions():
        table = tables.table(MODEL, version)
        nodedef = document.addNodeDef(nodedef_name(version), "surfaceshader", MODEL)
        nodedef.setVersionString(version)
        nodedef.setNodeGroup("pbr")
        nodedef.setDocString(f"OpenPBR Surface {version} (legacy interface; upgrade with `openpbr upgrade`)")
        for name, parameter in table.parameters.items():
            port = nodedef.addInput(name, parameter.type)
            if parameter.default is not None:
                port.setValueString(format_value(parameter.default, parameter.type))
            if parameter.default_geomprop:
                port.setDefaultGeomPropString(parameter.default_geomprop)
            if parameter.uniform:
                port.setIsUniform(True)
            if parameter.unit == "scene_length":
                port.setUnitType("distance")
            for attribute, bound in (("uimin", parameter.hard_min), ("uimax", parameter.hard_max),
                                     ("uisoftmin", parameter.soft_min), ("uisoftmax", parameter.soft_max)):
                if bound is not None:
                    port.setAttribute(attribute, format_value(bound, "float" if not isinstance(bound, tuple) else parameter.type))
            if parameter.group:
                port.setAttribute("uifolder", parameter.group.title())
    return document_text(document)
