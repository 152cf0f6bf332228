"""What glTF's JSON schema and its URI syntax ask of the document outside the material objects: the root's
arrays, the extension names it declares, the properties of images, textures and samplers, the URIs of images and
buffers, and the bufferViews that hold images.

Each is a check the Khronos glTF-Validator makes (its code in brackets):

* glTF.schema.json: every array of the root (``materials``, ``textures``, ``samplers``, ``extensionsUsed``...) has
  ``minItems`` 1, so an empty one is invalid (omit the property) [EMPTY_ENTITY]; ``extensionsUsed`` and
  ``extensionsRequired`` are arrays of strings [ARRAY_TYPE_MISMATCH, TYPE_MISMATCH];
* image.schema.json, texture.schema.json, sampler.schema.json name every property of those objects
  (:data:`TEXTURE_OBJECT_PROPERTIES`); another is ignored by every viewer [UNEXPECTED_PROPERTY];
* glTF 2.0, 3.6.1 and 3.8.2: a ``uri`` is an RFC 3986 URI (or a relative reference), which the validator parses
  as Dart's ``Uri.parse`` does [INVALID_URI]: a scheme starts with a letter and holds letters, digits, ``+``, ``-``
  and ``.``; an authority's host in brackets is an IPv6 address with its closing bracket, other hosts hold no bracket,
  and a port is digits (:func:`uri_syntax_error`; percent escapes and spaces the validator accepts, and so does this);
* 3.6.1.1: a bufferView's ``target`` says what it holds, vertex attributes (34962) or indices (34963); one that
  holds an image has none, and is no accessor's that a mesh primitive draws with: loaders upload such a view to the
  GPU as vertex or index data [BUFFER_VIEW_TARGET_OVERRIDE] (:func:`image_view_problems`).

Only the JSON is read. Each problem is ``(observation kind, JSON pointer, message, property)``, as
:mod:`.layout`'s, for the reader to observe.
"""

from __future__ import annotations

import ipaddress
import re
from json import dumps as json_text
from typing import Iterator

from .document import GltfDocument, vertex_attributes

#: The root's arrays (glTF.schema.json: each with ``minItems`` 1).
ROOT_ARRAYS = ("extensionsUsed", "extensionsRequired", "accessors", "animations", "buffers", "bufferViews", "cameras",
               "images", "materials", "meshes", "nodes", "samplers", "scenes", "skins", "textures")
#: The properties of the objects a texture is made of (image, texture and sampler schemas), besides
#: ``extensions`` and ``extras``.
TEXTURE_OBJECT_PROPERTIES = {"images": ("uri", "mimeType", "bufferView", "name"),
                             "textures": ("sampler", "source", "name"),
                             "samplers": ("magFilter", "minFilter", "wrapS", "wrapT", "name")}
TARGETS = {34962: "ARRAY_BUFFER, vertex attributes", 34963: "ELEMENT_ARRAY_BUFFER, indices"}
_SCHEME = re.compile(r"[A-Za-z][A-Za-z0-9+.-]*")
_SCHEME_PART = re.compile(r"([^:/?#]*):")
_AUTHORITY = re.compile(r"//([^/?#]*)")


def root_problems(document: GltfDocument) -> Iterator[tuple[str, str, str, str | None]]:
    """Empty root arrays, and declared extension names that are no strings."""
    for name in ROOT_ARRAYS:
        if document.json.get(name) == []:
            yield ("gltf_invalid", f"/{name}", f"{name} is an empty array, which glTF's schema does not allow (at least "
                   "one item): loaders that check the schema refuse the file; omit the property instead", None)
    for key in ("extensionsUsed", "extensionsRequired"):
        names = document.json.get(key)
        if key in document.json and not isinstance(names, list):
            yield "gltf_invalid", f"/{key}", f"{key} must be an array of extension names, not {json_text(names)}", None
            continue
        for index, name in enumerate(names if isinstance(names, list) else ()):
            if not isinstance(name, str):
                yield ("gltf_invalid", f"/{key}/{index}", f"{key} holds {json_text(name)}, which is no extension name "
                       "(a string): loaders that check the declarations refuse the file", None)


def uri_syntax_error(uri: str) -> str | None:
    """Why ``uri`` is no URI a URI parser accepts (a scheme that does not start with a letter, an unclosed IPv6
    bracket, a port that is not a number), or ``None``. Data URIs are :mod:`.document`'s."""
    scheme = _SCHEME_PART.match(uri)
    if scheme is not None and not _SCHEME.fullmatch(scheme.group(1)):
        return (f"its scheme {scheme.group(1)!r} is empty or does not start with a letter followed by letters, digits, "
                "'+', '-' or '.'")
    authority = _AUTHORITY.match(uri[scheme.end():] if scheme else uri)
    if authority is None:
        return None
    host = authority.group(1).rsplit("@", 1)[-1]
    port = ""
    if host.startswith("["):
        end = host.find("]")
        if end < 0 or (host[end + 1:] and not host[end + 1:].startswith(":")):
            return "its host opens an IPv6 address with '[' and does not close it with ']'"
        try:
            ipaddress.IPv6Address(host[1:end].split("%", 1)[0])
        except ValueError:
            return f"its host {host[:end + 1]!r} is no IPv6 address"
        port = host[end + 2:]
    elif "[" in host or "]" in host:
        return f"its host {host.partition(':')[0]!r} holds a bracket, which only encloses an IPv6 address"
    else:
        port = host.partition(":")[2]
    if port and not port.isdigit():
        return f"its port {port!r} is not a number"
    return None


def image_view_problems(document: GltfDocument) -> Iterator[tuple[str, str, str, str | None]]:
    """Images whose bufferView has a ``target``, or is read by a mesh primitive's accessor (attribute, indices,
    morph target)."""
    drawn: dict[int, str] = {}  # bufferView -> the first primitive property that draws with it
    for pointer, primitive in document.primitives():
        for where, accessor_index in [(f"{pointer}/indices", primitive.get("indices"))] + \
                vertex_attributes(pointer, primitive):
            accessor = document.item("accessors", accessor_index)
            view = accessor.get("bufferView") if accessor is not None else None
            if isinstance(view, int) and not isinstance(view, bool):
                drawn.setdefault(view, where)
    for index, image in enumerate(document.array("images")):
        view_index = image.get("bufferView") if isinstance(image, dict) else None
        view = document.item("bufferViews", view_index)
        if view is None:
            continue
        target = view.get("target")
        if target is not None:
            kind = TARGETS.get(target, "a GPU buffer") if isinstance(target, int) else "a GPU buffer"
            yield ("gltf_invalid", f"/images/{index}", f"the image's bufferView {view_index} has target "
                   f"{json_text(target)} ({kind}): a view of image data has none, and loaders that honour the target "
                   "upload the image's bytes to the GPU as mesh data", "bufferView")
        elif view_index in drawn:
            yield ("gltf_invalid", f"/images/{index}", f"the image's bufferView {view_index} is also mesh data "
                   f"({drawn[view_index]} draws with an accessor on it): one view holds one kind of data, and these "
                   "bytes cannot be both vertices and an image", "bufferView")
