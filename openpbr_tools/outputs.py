"""Where a command may write: never over a file it reads.

Every command that writes a file (a converted or upgraded document, a report, a baseline, a preview,
an HTML page, ΔE images) asks :func:`overwritten_input` first, with the files it was given and, once it
has read an asset, the files that asset reads (:func:`files_read`): its XIncludes, the MaterialX
documents a USD stage composes, the layers its values come from and its textures. A file is the same
file however it is named (``./a.mtlx``, ``../dir/a.mtlx``, a symbolic or hard link): what is compared is
the file on disk. A name that does not exist yet replaces nothing. The library only answers; the
command refuses (exit 2) with :data:`NEVER_MODIFIED` in its message.
"""

from __future__ import annotations

import os
from typing import Iterable

from .io.paths import Kind, classify
from .model import Asset

NEVER_MODIFIED = "openpbr never modifies its input"


class InputOverwrite(ValueError):
    """A library call asked to write over a file its input reads; the message says which."""


def _same_file(a: str, b: str) -> bool:
    try:
        return os.path.samefile(a, b)
    except (OSError, ValueError):  # either does not exist (or is no file-system name)
        return False


def overwritten_input(output: str | os.PathLike, inputs: Iterable[str | os.PathLike]) -> str | None:
    """The first of ``inputs`` that writing ``output`` would replace, as named in ``inputs``; else ``None``."""
    target = os.fspath(output)
    if not os.path.lexists(target):
        return None
    for path in inputs:
        if _same_file(target, os.fspath(path)):
            return os.fspath(path)
    return None


def files_read(asset: Asset) -> list[str]:
    """The files on disk ``asset`` reads, as far as its reading recorded them: its own file, the documents
    it composes (XIncludes, a USD stage's layers and its arcs to ``.mtlx`` documents), every file a material, input or
    observation is located in (a USD stage's layers), and its textures, resolved against the asset's folder
    and against the document that names them (where each reader looks). Textures inside a package (USDZ)
    and URLs are not files on disk. Over-inclusion is safe: only a file that exists is ever compared."""
    found = [asset.path]
    found += list(asset.extra.get("included_documents", ())) + list(asset.extra.get("layer_files", ()))
    found += [o.detail["document"] for o in asset.observations
              if o.kind == "usd_mtlx_reference" and isinstance(o.detail.get("document"), str)]
    found += [o.location.file for o in asset.observations if o.location and o.location.file]
    anchor = os.path.dirname(os.path.abspath(asset.path))
    for material in asset.materials:
        found += [location.file for location in (material.location, material.material_location)
                  if location is not None and location.file]
        for entry in material.inputs.values():
            if entry.location is not None and entry.location.file:
                found.append(entry.location.file)
        for _, texture in material.textures():
            if texture.packaged or classify(texture.file) in (Kind.URL, Kind.NUL, Kind.EMPTY):
                continue
            found.append(os.path.join(anchor, texture.file))
            if texture.location is not None and texture.location.file:
                found.append(os.path.join(os.path.dirname(os.path.abspath(texture.location.file)), texture.file))
    for observation in asset.observations:
        if observation.kind == "mtlx_image_file" and isinstance(observation.detail.get("file"), str) \
                and classify(observation.detail["file"]) not in (Kind.URL, Kind.NUL, Kind.EMPTY):
            base = observation.location.file if observation.location and observation.location.file else asset.path
            found.append(os.path.join(os.path.dirname(os.path.abspath(base)), observation.detail["file"]))
    return list(dict.fromkeys(found))
