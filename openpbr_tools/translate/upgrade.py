"""Upgrade OpenPBR materials from a legacy version (0.2 ... 1.1) to a newer one (default 1.1.1).

The upgrade is a chain of steps, one per release (:mod:`openpbr_tools.translate.upgrade_steps`, which
lists what is exact and what is approximated), each emitting *edits* (rename, set a constant,
remove, connect a node graph) and diagnostics. The same edits are applied to the model-neutral
:class:`Material` and, by :mod:`openpbr_tools.io.mtlx.patch`, to the MaterialX document itself, so
everything else in the file (looks, graphs, other nodes) is kept as it was. This module chains the
steps (:func:`upgrade`) and patches a MaterialX file with them (:func:`upgrade_mtlx_file`).
"""

from __future__ import annotations

import copy
from dataclasses import dataclass

from .. import tables
from ..diagnostics import Diagnostic
from ..io.mtlx.patch import apply_edits
from ..io.mtlx.reader import read_mtlx
from ..io.mtlx.xmlscan import decode_document
from ..io.mtlx.writer import document_text
from ..model import Material
from ..rules import Context
from ..versioning import versions_with
from .upgrade_steps import MODEL, STEPS, Edit, GraphNode, Step, Upgrade, apply_edit, fold_ior_level, graph_document

__all__ = ["MODEL", "STEPS", "Edit", "GraphNode", "Upgrade", "UpgradedDocument", "apply_edit", "fold_ior_level",
           "graph_document", "starting_version", "upgrade", "upgrade_mtlx_file"]


def starting_version(material: Material) -> str:
    """The version to upgrade from: the material's, or older when it mixes in legacy names (a
    mixed material is upgraded from the newest version its oldest name belongs to)."""
    start = material.version or tables.latest(MODEL)
    for name in material.inputs:
        owners = versions_with(MODEL, name)
        if owners and tables.version_key(owners[-1]) < tables.version_key(start):
            start = owners[-1]
    return start


def upgrade(material: Material, target: str | None = None, context: Context | None = None) -> Upgrade:
    """Upgrade a copy of ``material`` to ``target`` (default: the latest OpenPBR version)."""
    if material.model != MODEL:
        raise ValueError(f"only {MODEL} materials can be upgraded, not {material.model}")
    target = target or tables.latest(MODEL)
    if target not in tables.versions(MODEL):
        raise ValueError(f"no OpenPBR version {target!r}")
    context = context or Context()
    current = starting_version(material)
    result = Upgrade(copy.deepcopy(material), from_version=current)
    for source, step_target, function in STEPS:
        if tables.version_key(source) < tables.version_key(current):
            continue
        if tables.version_key(step_target) > tables.version_key(target):
            break
        function(Step(result, source, step_target, context))
        current = step_target
    result.material.version = current
    result.material.declared_version = current
    result.material.version_basis = "node version attribute"
    if result.material.nodedef:
        result.material.nodedef = None
    return result


@dataclass(slots=True)
class UpgradedDocument:
    text: str
    upgrades: list[Upgrade]

    @property
    def diagnostics(self) -> list[Diagnostic]:
        found = [d for u in self.upgrades for d in u.diagnostics]
        found.sort(key=Diagnostic.sort_key)
        return found


def upgrade_mtlx_file(path: str, target: str | None = None, context: Context | None = None) -> UpgradedDocument:
    """Upgrade every legacy OpenPBR shader of a MaterialX file; returns the new document's text.

    Raises :class:`openpbr_tools.io.ReadError` for an unreadable file. The input file is not touched.
    """
    import MaterialX as mx  # lazy: MaterialX's bindings (~8 ms) load only when a file is upgraded

    target = target or tables.latest(MODEL)
    with open(path, "rb") as handle:
        data = handle.read()
    asset = read_mtlx(path, data)
    document = mx.createDocument()
    options = mx.XmlReadOptions()
    options.readXIncludeFunction = None
    mx.readFromXmlString(document, decode_document(data), mx.FileSearchPath(), options)
    upgrades = []
    for material in asset.materials:
        if material.model != MODEL:
            continue
        if tables.version_key(starting_version(material)) >= tables.version_key(target):
            continue
        result = upgrade(material, target, context)
        apply_edits(document.getDescendant(material.extra["node_path"]), result.edits, result.material.version)
        upgrades.append(result)
    return UpgradedDocument(document_text(document), upgrades)
