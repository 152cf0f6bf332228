"""MaterialX looks through a conversion (:func:`openpbr_tools.convert.convert_file`): the looks of a .mtlx
source carried into a .mtlx output, their assignments following renamed materials (:func:`looks`), with a
note at every assignment, look or XIncluded material the output cannot hold; and the materials of a look
file's XIncludes in its own folder, converted with it (:func:`included_materials`).
"""

from __future__ import annotations

import os

from .diagnostics import Diagnostic
from .io import ReadError, read_asset
from .model import Asset, Location, Material
from .rules.translation import CONVERTED, NOT_CARRIED


def looks(asset: Asset, pairs: list[tuple[Material, Material]], kind: str, context) -> tuple[list, list[Diagnostic]]:
    """A .mtlx source's looks for a .mtlx output (:func:`~openpbr_tools.io.mtlx.writer.to_mtlx_string`'s, their
    assignments following renamed materials), and a note (OPBR1104) at each assignment of a material not
    written, each look of a USD or glTF output, and the XIncluded materials not converted here."""
    notes = []
    renames = {source.material_name: translated.material_name for source, translated in pairs
               if source.material_name}
    included = asset.extra.get("included_material_names") or {}
    for names, rule, sentence in (
            ([n for n in included if n in renames], CONVERTED, "{what} of {where} converted into this output"),
            ([n for n in included if n not in renames], NOT_CARRIED,
             "{what} come from {where} outside the document's folder (or unreadable on their own), which convert as "
             "their own files: this output does not hold them")):
        if names:
            where = f"XIncluded file(s) ({', '.join(sorted({os.path.basename(included[n]) for n in names}))})"
            notes.append(context.diagnostic(rule, sentence.format(what=f"{len(names)} material(s) ({', '.join(names)})",
                                                                  where=where), asset.colorspace_location))
    # the red team's F-05: a source's geometry and its material assignments were dropped without a word
    bound = asset.extra.get("usd_bindings") or 0
    assigned = [p for p in (asset.extra.get("gltf") or {}).get("primitives", ()) if isinstance(p.get("material"), int)]
    if bound or assigned:
        what = (f"{bound} prim(s) with a material binding" if bound else
                f"{len(assigned)} mesh primitive(s) with a material")
        notes.append(context.diagnostic(  # (a note, not a loss of the material: converting materials is the job)
            CONVERTED, f"the source's geometry and material assignments ({what}) are not written: the output holds "
                         "the materials only" + (" (--mesh sphere adds a preview sphere per material)" if kind == "gltf"
                                                 else "") + "; bind them in the scene that uses it",
            asset.colorspace_location or Location(asset.path)))
    carried = []
    for look in asset.extra.get("looks") or ():
        what = f"{look['category']} {look['name']}"
        if kind != "mtlx":
            notes.append(context.diagnostic(
                NOT_CARRIED, f"{what} is not written: {'USD' if kind == 'usd' else 'glTF'} outputs bind materials to "
                             f"geometry, not with MaterialX looks ({len(look['assigns'])} material assignment(s) lost)",
                look["location"]))
            continue
        left_out = set()
        for name, material, location in look["assigns"]:
            if material and material not in renames:
                left_out.add(name)
                why = f"comes from the XIncluded {os.path.basename(included[material])}" if material in included else \
                    "is not in the output"
                notes.append(context.diagnostic(
                    NOT_CARRIED, f"{what}: materialassign {name} assigns {material}, which {why}; the assignment is "
                                 "left out", location))
        carried.append((look["text"], renames, left_out))
    return carried, notes


def included_materials(asset: Asset, allow_outside: tuple[str, ...]) -> list[Material]:
    """The materials of a .mtlx source's XIncluded files in its own folder (a look file's: MaterialX's
    examples keep a look and its materials apart), read as their own documents, so that the output holds
    what the document's looks assign; the reader followed only includes the path guard allows."""
    included = asset.extra.get("included_material_names") or {}
    folder = os.path.dirname(os.path.abspath(asset.path))
    found = []
    for path in sorted({p for p in included.values() if os.path.dirname(p) == folder}):
        try:
            found += [m for m in read_asset(path, allow_outside).materials if m.material_name in included]
        except ReadError:  # unreadable on its own: its materials stay out, and say so (:func:`looks`)
            continue
    return found
