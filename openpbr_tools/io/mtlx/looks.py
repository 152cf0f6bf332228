"""MaterialX looks and look groups (material assignments to geometry, visibility) through a conversion:
recorded as data when a document is read (:func:`record_looks`), added to a written document with the
materials' written names (:func:`add_look`). What an output cannot hold is reported by the convert
pipeline (``openpbr_tools.convert._looks``)."""

from __future__ import annotations


def record_looks(asset, document, location) -> None:
    """The document's own looks and look groups, as data a conversion carries to a .mtlx output
    (``asset.extra["looks"]``: each one's category, name, location, its MaterialX text, and its material
    assignments as (assign name, material, location)), and the names of the materials that come from
    XIncludes with their files (``asset.extra["included_material_names"]``: name -> the included file, as the
    path guard resolved it). ``location``: the reader's element -> :class:`~openpbr_tools.model.Location`."""
    import MaterialX as mx  # lazy: the reader imports MaterialX when it reads a document

    looks = []
    for element in list(document.getLookGroups()) + list(document.getLooks()):
        if element.getActiveSourceUri():
            continue  # an XIncluded file's: it converts with that file
        alone = mx.createDocument()
        _add_collections(alone, document, element)
        copy = (alone.addLookGroup if element.getCategory() == "lookgroup" else alone.addLook)(element.getName())
        copy.copyContentFrom(element)
        assigns = [(a.getName(), a.getMaterial(), location(a)) for a in
                   (element.getMaterialAssigns() if element.getCategory() == "look" else ())]
        looks.append({"category": element.getCategory(), "name": element.getName(), "location": location(element),
                      "text": mx.writeToXmlString(alone), "assigns": assigns})
    if looks:
        asset.extra["looks"] = looks
    included = sorted({m.getName() for m in document.getMaterialNodes() if m.getActiveSourceUri()})
    if included:
        asset.extra["included_material_names"] = {name: document.getChild(name).getActiveSourceUri() for name in included}


def _add_collections(alone, document, look) -> None:
    """The collections ``look``'s assignments name (``collection`` on a materialassign or visibility) and
    those they include, copied into ``alone``: without them MaterialX rejects the look ("Invalid collection
    string")."""
    pending = [child.getAttribute("collection") for child in look.getChildren() if child.hasAttribute("collection")]
    while pending:
        name = pending.pop()
        found = document.getCollection(name) if name else None
        if found is None or alone.getCollection(name) is not None:
            continue
        alone.addCollection(name).copyContentFrom(found)
        pending += [n.strip() for n in found.getIncludeCollectionString().split(",") if n.strip()]


def add_look(document, text: str, renames: dict, left_out) -> None:
    """Add the look (or look group) of ``text`` to ``document``: its material assignments renamed as the
    materials were (``renames``: source material name -> written name), those named in ``left_out`` removed."""
    import MaterialX as mx  # lazy: as in record_looks

    alone = mx.createDocument()
    mx.readFromXmlString(alone, text)
    for element in alone.getChildren():
        if element.getCategory() == "collection":  # one a look assigns to (shared by looks: added once)
            if document.getCollection(element.getName()) is None:
                document.addCollection(element.getName()).copyContentFrom(element)
            continue
        add = document.addLookGroup if element.getCategory() == "lookgroup" else document.addLook
        copy = add(element.getName())
        copy.copyContentFrom(element)
        for assign in (copy.getMaterialAssigns() if element.getCategory() == "look" else ()):
            if assign.getName() in left_out:
                copy.removeChild(assign.getName())
            elif assign.getMaterial() in renames:
                assign.setMaterial(renames[assign.getMaterial()])
