"""The rule engine: families of checks, each a module with stable codes and a ``check`` generator.

A family module defines ``RULES``, a tuple of :class:`Rule` (code, name, default severity, summary
and documentation with a passing and a failing example), and ``check(asset, context)``, a generator
of :class:`~openpbr_tools.diagnostics.Diagnostic`. Adding a family is adding a module to
``FAMILIES``. ``openpbr rules`` and the README's rule table are generated from these objects.
"""

from __future__ import annotations

import dataclasses
import importlib
import os
from dataclasses import dataclass, field
from functools import lru_cache
from typing import Callable, Iterator

from .. import tables
from ..diagnostics import Diagnostic, Severity
from ..io.paths import PathGuard
from ..model import Asset, Location

FAMILIES = (
    "document",
    "names",
    "values",
    "ranges",
    "version",
    "colorspace",
    "units",
    "textures",
    "texture_content",
    "texture_pixels",
    "structure",
    "mtlx_document",
    "plausibility",
    "usd",
    "usd_preview",
    "usd_texcoords",
    "usd_shading",
    "usd_stage",
    "gltf",
    "gltf_meshes",
    "gltf_geometry",
    "gltf_surfaces",
    "gltf_images",
    "gltf_plausibility",
    "gltf_structure",
    "gltf_schema",
    "translation",
)

#: Families that check one input format only (their modules, and what they import, load only for it).
FAMILY_FORMATS = {"usd": "usd", "usd_preview": "usd", "usd_texcoords": "usd", "usd_shading": "usd", "usd_stage": "usd", "gltf": "gltf",
                "gltf_meshes": "gltf", "gltf_geometry": "gltf", "gltf_surfaces": "gltf", "gltf_images": "gltf",
                "gltf_plausibility": "gltf", "gltf_structure": "gltf", "gltf_schema": "gltf", "mtlx_document": "mtlx", "translation": None}


@dataclass(frozen=True, slots=True)
class Rule:
    """One check. ``passing``/``failing`` are example documents written to ``passing_name`` /
    ``failing_name``: for ``.mtlx`` names, a MaterialX fragment is placed in a document with
    ``colorspace="lin_rec709"`` and a ``surfacematerial`` named ``M`` bound to a shader named ``S``
    (a whole document is used as is); other formats are written verbatim. The test suite runs
    every example. ``example_files`` are files the examples expect to exist beside the document
    (written as small valid images of their suffix's format; ``failing_files`` gives, by name, the
    bytes a file has beside the failing example instead);
    ``example_config`` is a ``.openpbr.toml`` written beside both examples (``failing_config``, when
    set, replaces it for the failing one). A translation note (OPBR11xx) is not found by
    validating a file but by running a command on it: ``example_command`` holds its words after
    ``openpbr`` with ``IN`` standing for the example document (``("convert", "IN", "-o", "out.gltf")``);
    the failing example makes the command report the note, the passing one does not."""

    code: str
    name: str
    severity: Severity
    summary: str
    doc: str
    passing: str | bytes
    failing: str | bytes
    family: str = ""
    example_files: tuple[str, ...] = ()
    failing_files: tuple[tuple[str, bytes], ...] = ()
    passing_name: str = "example.mtlx"
    failing_name: str = "example.mtlx"
    example_config: str = ""
    failing_config: str | None = None
    formats: tuple[str, ...] = ("mtlx", "usd", "gltf")
    example_command: tuple[str, ...] = ()

    def note(self, message: str, location: Location, output: Location | None = None) -> Diagnostic:
        """A finding of this rule at its default severity (writers and the baker, which have no
        :class:`Context`, report this way; :meth:`Context.adjust` applies a configuration later)."""
        return Diagnostic(self.code, self.severity, message, location, None, output)


@dataclass(slots=True)
class Context:
    """What a check may consult besides the asset: the active configuration and the file system.

    ``severity`` overrides the default severity per code; ``disabled`` switches codes off;
    ``thresholds`` and the ``required_*``/``allowed_*`` policies come from the project
    configuration (:mod:`openpbr_tools.config`). ``file_exists`` is injectable so tests and
    sandboxed runs can control file look-ups.
    """

    severity: dict[str, Severity] = field(default_factory=dict)
    disabled: frozenset[str] = frozenset()
    file_exists: Callable[[str], bool] = os.path.exists
    list_dir: Callable[[str], list[str]] = os.listdir
    real_path: Callable[[str], str] = os.path.realpath
    thresholds: dict[str, float] = field(default_factory=dict)
    required_version: str | None = None
    required_colorspace: str | None = None
    allowed_texture_colorspaces: frozenset[str] | None = None
    allow_outside: tuple[str, ...] = ()  # folders besides the asset's own that it may read from
    # the context of a document the asset composes (a USD stage's .mtlx), as if it were listed itself
    for_document: Callable[[str], "Context | None"] | None = None

    def diagnostic(self, rule: Rule, message: str, location: Location, hint: str | None = None,
                   output: Location | None = None) -> Diagnostic:
        return Diagnostic(rule.code, self.severity.get(rule.code, rule.severity), message, location, hint, output)

    def adjust(self, diagnostic: Diagnostic) -> Diagnostic:
        """``diagnostic`` with the configured severity of its code."""
        severity = self.severity.get(diagnostic.code)
        return diagnostic if severity is None else dataclasses.replace(diagnostic, severity=severity)

    def guard(self, asset_path: str) -> PathGuard:
        """The path guard of ``asset_path``'s folder and the allowed folders (every rule that asks
        whether a file is inside asks this one)."""
        return PathGuard.for_asset(asset_path, self.allow_outside, real_path=self.real_path)

    def threshold(self, key: str, default: float) -> float:
        return self.thresholds.get(key, default)


@lru_cache(maxsize=None)
def _family_module(family: str):
    return importlib.import_module(f"{__name__}.{family}")


@lru_cache(maxsize=1)
def all_rules() -> dict[str, Rule]:
    """Every rule by code, in code order."""
    found: dict[str, Rule] = {}
    for family in FAMILIES:
        for rule in _family_module(family).RULES:
            if rule.code in found:
                raise RuntimeError(f"rule code {rule.code} defined twice")
            found[rule.code] = Rule(**{**_as_dict(rule), "family": family})
    return dict(sorted(found.items(), key=lambda item: int(item[0][4:])))


def _as_dict(rule: Rule) -> dict:
    return {name: getattr(rule, name) for name in Rule.__slots__}


def family_doc(family: str) -> str:
    return (_family_module(family).__doc__ or "").strip()


def check_asset(asset: Asset, context: Context | None = None) -> list[Diagnostic]:
    """Run every family over ``asset``; returns diagnostics sorted by location, without disabled codes."""
    context = context or Context()
    found: list[Diagnostic] = []
    suppressions = asset.suppressions
    if any(m.extra.get("included_from") for m in asset.materials):  # an included document's shader, bound here:
        asset = dataclasses.replace(asset, materials=[  # checked in its own document, which is validated too
            m for m in asset.materials if not m.extra.get("included_from")])
    floors: list[tuple[Diagnostic, frozenset]] = []  # (finding, the codes that say it already): ONLY_WHERE_UNSAID
    for family in FAMILIES:
        if family in FAMILY_FORMATS and FAMILY_FORMATS[family] != asset.format:
            continue  # a family for another format (translation: notes of convert and upgrade, never found here)
        module = _family_module(family)
        floor = getattr(module, "ONLY_WHERE_UNSAID", None)  # the codes whose finding at a property says the same
        try:
            for diagnostic in module.check(asset, context):
                if diagnostic.code not in context.disabled and not (suppressions and _suppressed(diagnostic, suppressions)):
                    if floor is None:
                        found.append(diagnostic)
                    else:
                        floors.append((diagnostic, floor))
        except Exception as error:  # noqa: BLE001 - a defect of a check: reported at the file, the other families run
            from .document import internal_error  # lazy: the rules package's own family module (a cycle at import)

            found.append(internal_error(asset.path, f"the {family} checks", error))
    if floors:  # (said: a finding of one of the codes at the same property, at an object holding it, or inside it)
        said = {(d.code, _element(d)) for d in found}
        found += [d for d, codes in floors if not any(
            (code, element) in said for code in codes for element in _enclosing(_element(d))) and not any(
            code in codes and element.startswith(_element(d) + "/") for code, element in said)]
    found.sort(key=Diagnostic.sort_key)
    return found


def _enclosing(element: str) -> list[str]:
    """``element`` and every element holding it (``a/b/c``: itself, ``a/b``, ``a``)."""
    parts = element.split("/")
    return ["/".join(parts[:n]) for n in range(len(parts), 0, -1)]


def _element(diagnostic: Diagnostic) -> str:
    """The property a finding names: its path and input, as one pointer."""
    location = diagnostic.location
    return "/".join(p.strip("/") for p in (location.path or "", location.input or "") if p and p.strip("/"))



def _suppressed(diagnostic: Diagnostic, suppressions: dict[str, frozenset[str]]) -> bool:
    """Inline suppressions apply to the element they are attached to and everything inside it
    (the document root's apply to the whole file)."""
    location = diagnostic.location
    element = "/".join(p for p in (location.path, location.input) if p)
    for path, codes in suppressions.items():
        if path == "" or element == path or element.startswith(path + "/"):
            if "all" in codes or diagnostic.code in codes:
                return True
    return False


def constant_or_default(material, name: str):
    """The constant of ``name``: as authored, the table's default when unauthored, ``None`` when
    textured or connected."""
    entry = material.inputs.get(name)
    if entry is None:
        parameter = tables.table(material.model, material.version).get(name)
        return parameter.default if parameter is not None else None
    return entry.constant


def for_each_input(asset: Asset) -> Iterator[tuple]:
    """(material, table, input) for every authored input of every material with a table."""
    for material in asset.materials:
        if material.version is None:
            continue
        table = tables.table(material.model, material.version)
        for entry in material.inputs.values():
            yield material, table, entry
