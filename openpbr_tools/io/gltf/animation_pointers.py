"""KHR_animation_pointer channels that animate a material property the asset does not define.

The extension (KhronosGroup/glTF, extensions/2.0/Khronos/KHR_animation_pointer/README.md, "Operation"): "The JSON
Pointer MUST point to a property defined in the asset. A property is considered defined if it is present in the asset
explicitly or if it has a default value and its enclosing object is present", and "Pointers to the asset properties
that do not have a spec-defined default value ... are invalid if the property is not defined in the asset
explicitly". A channel whose pointer names nothing animates nothing (or, in a loader that creates what it reads, a
property no renderer reads).

Only pointers into ``/materials`` are judged (the toolkit knows the material objects' schemas: :mod:`.slots`); a
pointer that resolves in the JSON is defined. Otherwise (:func:`material_pointer_problems`):

* ``enclosing_absent``: the object that would hold the property is not in the asset (a missing material,
  ``pbrMetallicRoughness`` or extension object);
* ``unknown``: the enclosing object is a material object whose schema has no property of that name
  (``roughness`` for ``roughnessFactor``);
* ``no_default``: the property is the schema's but has no default (``attenuationDistance``, a textureInfo).

A property of an object the toolkit has no schema for (an extension it does not read) gets no verdict, and
neither does one whose default it does not record; pointers into ``extras`` are "entirely application specific".
Whether the property is mutable (the Asset Object Model) is not judged. Only the JSON is read.
"""

from __future__ import annotations

from . import slots
from .document import GltfDocument

POINTER = "KHR_animation_pointer"
_TRANSFORM_DEFAULTS = ("offset", "rotation", "scale")  # KHR_texture_transform's schema: texCoord has none
_TEXTURE_INFO_DEFAULTS = ("texCoord", "scale", "strength")  # textureInfo schemas: index is required, no default


def material_pointer_problems(document: GltfDocument) -> list[dict]:
    """``{"pointer", "target", "reason", "property", "enclosing"}`` for each animation channel (``pointer``, at its
    extension object) whose KHR_animation_pointer ``target`` is a material property the asset does not define."""
    found = []
    for a, animation in enumerate(document.array("animations")):
        channels = animation.get("channels") if isinstance(animation, dict) else None
        for c, channel in enumerate(channels if isinstance(channels, list) else ()):
            target = channel.get("target") if isinstance(channel, dict) else None
            extension = ((target.get("extensions") or {}) if isinstance(target, dict) and
                         isinstance(target.get("extensions"), dict) else {}).get(POINTER)
            pointer = extension.get("pointer") if isinstance(extension, dict) else None
            if not isinstance(pointer, str) or not pointer.startswith("/materials/") or "extras" in pointer.split("/"):
                continue  # (extras: "validity and interpretation of the animated values is entirely application specific")
            verdict = _undefined(document.json, pointer)
            if verdict is not None:
                found.append({"pointer": f"/animations/{a}/channels/{c}/target/extensions/{POINTER}",
                              "target": pointer, **verdict})
    return found


def _undefined(root: dict, pointer: str) -> dict | None:
    tokens = [token.replace("~1", "/").replace("~0", "~") for token in pointer.split("/")[1:]]
    enclosing = root
    for depth, token in enumerate(tokens[:-1]):
        enclosing = _child(enclosing, token)
        if enclosing is None:
            return {"reason": "enclosing_absent", "property": tokens[-1], "enclosing": _joined(tokens[:depth + 1])}
    name = tokens[-1]
    if _child(enclosing, name) is not None or not isinstance(enclosing, dict):
        return None
    schema = _schema(tokens[2:-1])
    if schema is None:
        return None
    properties, with_default, without_default = schema
    reason = "unknown" if name not in properties else "no_default" if name in without_default else None
    if name in with_default or reason is None:
        return None
    return {"reason": reason, "property": name, "enclosing": _joined(tokens[:-1])}


def _joined(tokens: list[str]) -> str:
    return "".join("/" + token.replace("~", "~0").replace("/", "~1") for token in tokens)


def _child(value, token: str):
    if isinstance(value, dict):
        return value.get(token)
    if isinstance(value, list) and token.isdigit() and (token == "0" or not token.startswith("0")) and int(token) < len(value):
        return value[int(token)]
    return None


def _container(path: list[str]) -> str | None:
    """The :mod:`.slots` container name of the material object at ``path`` below ``/materials/<n>``, if it is one."""
    if not path:
        return slots.CORE
    if path == [slots.PBR]:
        return slots.PBR
    return path[1] if len(path) == 2 and path[0] == "extensions" else None


def _schema(path: list[str]) -> tuple[frozenset, frozenset, frozenset] | None:
    """(the properties the schema defines, those with a default, those without one) of the material object at ``path``
    below ``/materials/<n>``, or ``None`` for an object the toolkit has no schema for. A property in neither of the
    last two has a default the toolkit does not record (no verdict)."""
    objects = slots.object_properties()
    container = _container(path)
    if container is not None:
        if container not in objects:
            return None
        properties, textures = objects[container]
        factors = [slot for slot in slots.SLOTS if slot.container == container and slot.factor]
        with_default = {slot.factor for slot in factors if slot.default is not None}
        if container == slots.IRIDESCENCE:
            with_default.add(slots.IRIDESCENCE_THICKNESS_MINIMUM[0])
        without_default = set(textures) | {slot.factor for slot in factors if slot.default is None}
        return properties, frozenset(with_default), frozenset(without_default)
    transform = path[-2:] == ["extensions", slots.TEXTURE_TRANSFORM]
    texture_path = path[:-2] if transform else path
    holder = _container(texture_path[:-1]) if texture_path else None
    kind = objects[holder][1].get(texture_path[-1]) if holder in objects else None
    if kind is None:
        return None
    if transform:
        return (frozenset(slots.TEXTURE_TRANSFORM_PROPERTIES + slots.COMMON_PROPERTIES), frozenset(_TRANSFORM_DEFAULTS),
                frozenset(("texCoord",)))
    properties = frozenset(slots.TEXTURE_INFO_PROPERTIES[kind] + slots.COMMON_PROPERTIES)
    return properties, frozenset(p for p in properties if p in _TEXTURE_INFO_DEFAULTS), frozenset(("index",))
