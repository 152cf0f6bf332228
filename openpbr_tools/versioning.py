"""Which version of its shading model a material is written for, and how we know.

No file in the wild records its OpenPBR version reliably, so the version is settled in this order:
the node's ``version`` attribute when it names a version we have a table for; the version a
``nodedef`` attribute names; otherwise inferred from the input names (the newest version whose
table has every recognised name). Names that belong to no version (typos) are left out of the
inference; a material whose names fit no single version is "mixed".
"""

from __future__ import annotations

from functools import lru_cache

from . import tables
from .model import Material


@lru_cache(maxsize=None)
def _names_by_version(model: str) -> dict[str, frozenset[str]]:
    return {v: tables.names(model, v) for v in tables.versions(model)}


@lru_cache(maxsize=None)
def all_names(model: str) -> frozenset[str]:
    names: frozenset[str] = frozenset()
    for version_names in _names_by_version(model).values():
        names |= version_names
    return names


@lru_cache(maxsize=None)
def nodedef_versions(model: str) -> dict[str, str]:
    """Nodedef name -> version: the names the tables give (MaterialX's current definitions) and
    the versioned names (``ND_<model>_surfaceshader_<digits>``, as MaterialX names
    ``ND_standard_surface_surfaceshader_100`` and this toolkit's legacy OpenPBR library does)."""
    found = {}
    for version in tables.versions(model):
        found[f"ND_{model}_surfaceshader_{version.replace('.', '')}"] = version
        nodedef = tables.table(model, version).nodedef
        if nodedef:
            found[nodedef] = version
    return found


def versions_with(model: str, name: str) -> list[str]:
    """The versions of ``model`` whose table has an input called ``name``."""
    return [v for v, names in _names_by_version(model).items() if name in names]


def candidates(model: str, names) -> tuple[str, ...]:
    """Versions whose tables contain every recognised name in ``names``, oldest first."""
    known = all_names(model)
    relevant = [n for n in names if n in known]
    return tuple(v for v, table_names in _names_by_version(model).items() if all(n in table_names for n in relevant))


def settle(material: Material) -> None:
    """Fill ``material.version``, ``version_basis`` and ``version_candidates``."""
    model = material.model
    available = tables.versions(model)
    if not available:
        material.version, material.version_basis = None, "no parameter table for this model"
        return
    fits = candidates(model, material.inputs)
    material.version_candidates = fits
    declared = material.declared_version
    if declared and declared in available:
        material.version, material.version_basis = declared, "node version attribute"
        return
    nodedef_version = nodedef_versions(model).get(material.nodedef or "")
    if nodedef_version:
        material.version, material.version_basis = nodedef_version, f"nodedef {material.nodedef}"
        return
    if not fits:
        # Mixed names: take the version that explains the most of them, and say so.
        known = all_names(model)
        relevant = [n for n in material.inputs if n in known]
        best = max(available, key=lambda v: (sum(n in _names_by_version(model)[v] for n in relevant), tables.version_key(v)))
        material.version, material.version_basis = best, "mixed: input names from more than one version"
        return
    if len(fits) == len(available) or not any(n in all_names(model) for n in material.inputs):
        material.version, material.version_basis = available[-1], "default (no version-specific input names)"
        return
    material.version = fits[-1]
    if len(fits) == 1:
        material.version_basis = "inferred from input names"
    else:
        material.version_basis = f"inferred from input names (consistent with {fits[0]} to {fits[-1]})"
