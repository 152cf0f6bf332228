"""The glTF document's references between its objects, its node hierarchy and its POSITION bounds: checks the Khronos
glTF-Validator makes (its code in brackets) that concern the data a material is drawn with, read from glTF 2.0.

* 3.3 "Indices": every index "MUST" name an existing object of its array: a mesh primitive's attributes, indices and
  morph targets (accessors), an accessor's and a sparse accessor's bufferView, a bufferView's buffer, a node's mesh,
  camera, skin and children, a scene's nodes, a skin's joints, skeleton and inverseBindMatrices, an animation
  channel's sampler (the animation's own) and target node, an animation sampler's input and output
  [UNRESOLVED_REFERENCE], and the root's scene. A primitive's material, a texture's source and sampler and an image's
  bufferView are judged where they are read (:mod:`.reader`, :mod:`.textures`).
* 3.5.3 "Transformations" and 3.5.2: "the node hierarchy MUST be a set of disjoint strict trees": no node is its own
  ancestor [NODE_LOOP], none is the child of two nodes [NODE_PARENT_OVERRIDE], and a scene lists only root nodes
  [SCENE_NON_ROOT_NODE];
* 3.7.2.1 "Meshes": "POSITION accessor MUST have min and max properties defined"
  [MESH_PRIMITIVE_POSITION_ACCESSOR_WITHOUT_BOUNDS];
* the schema's ``extensions``, on every object, is an object [TYPE_MISMATCH]: null is not.

Only the JSON is read. A reference that is no integer is a type error of the schema, not judged here.
"""

from __future__ import annotations

from typing import Iterator

from .document import GltfDocument
from .layout import missing_scene

#: (the object's array, the referring property, the array it names) of references held directly by a top-level
#: object; a list property (children, joints, nodes) names one object per item.
DIRECT = (("accessors", "bufferView", "bufferViews"), ("bufferViews", "buffer", "buffers"),
          ("nodes", "mesh", "meshes"), ("nodes", "camera", "cameras"), ("nodes", "skin", "skins"),
          ("nodes", "children", "nodes"), ("scenes", "nodes", "nodes"), ("skins", "joints", "nodes"),
          ("skins", "skeleton", "nodes"), ("skins", "inverseBindMatrices", "accessors"))
SINGULAR = {"accessors": "accessor", "bufferViews": "bufferView", "buffers": "buffer", "meshes": "mesh",
            "cameras": "camera", "skins": "skin", "nodes": "node", "samplers": "sampler"}


def dangling(document: GltfDocument) -> Iterator[tuple[str, str, int, str]]:
    """``(JSON pointer of the referring object, property, index, what it should name)`` for every index that names
    nothing (see the module), the root's ``scene`` first (``("/scene", None, ...)``: :func:`.layout.missing_scene`)."""
    scene = missing_scene(document)
    if scene is not None:
        yield "/scene", None, scene, f"names no scene (the file has {len(document.array('scenes'))})"
    for array, name, target in DIRECT:
        for index, item in enumerate(document.array(array)):
            if isinstance(item, dict) and name in item:
                yield from _missing(f"/{array}/{index}", name, item[name], len(document.array(target)), target)
    accessors = len(document.array("accessors"))
    for index, accessor in enumerate(document.array("accessors")):
        sparse = accessor.get("sparse") if isinstance(accessor, dict) else None
        for part in ("indices", "values"):
            held = sparse.get(part) if isinstance(sparse, dict) else None
            if isinstance(held, dict) and "bufferView" in held:
                yield from _missing(f"/accessors/{index}/sparse/{part}", "bufferView", held["bufferView"],
                                    len(document.array("bufferViews")), "bufferViews")
    found: dict[tuple[str, int], list] = {}  # the primitives' (one per property and index: "and N more")
    for pointer, primitive in document.primitives():
        attributes = primitive.get("attributes")
        uses = [(f"{pointer}/attributes", name, value) for name, value in
                (attributes.items() if isinstance(attributes, dict) else ())]
        uses += [(pointer, "indices", primitive["indices"])] if "indices" in primitive else []
        targets = primitive.get("targets")
        for number, morph in enumerate(targets if isinstance(targets, list) else ()):
            uses += [(f"{pointer}/targets/{number}", name, value) for name, value in
                     (morph.items() if isinstance(morph, dict) else ())]
        for where, name, value in uses:
            for missing in _missing(where, name, value, accessors, "accessors"):
                found.setdefault((name, missing[2]), []).append(missing)
    for (_, _), missing in found.items():
        where, name, index, why = missing[0]
        more = len(missing) - 1
        yield where, name, index, why + (f" (and {more} more primitive{'s' if more > 1 else ''})" if more else "")
    for index, animation in enumerate(document.array("animations")):
        if not isinstance(animation, dict):
            continue
        samplers = animation.get("samplers") if isinstance(animation.get("samplers"), list) else []
        for number, sampler in enumerate(samplers):
            for name in ("input", "output"):
                if isinstance(sampler, dict) and name in sampler:
                    yield from _missing(f"/animations/{index}/samplers/{number}", name, sampler[name], accessors,
                                        "accessors")
        channels = animation.get("channels") if isinstance(animation.get("channels"), list) else []
        for number, channel in enumerate(channels):
            if not isinstance(channel, dict):
                continue
            where = f"/animations/{index}/channels/{number}"
            if "sampler" in channel:
                yield from _missing(where, "sampler", channel["sampler"], len(samplers), "samplers")
            target = channel.get("target")
            if isinstance(target, dict) and "node" in target:
                yield from _missing(f"{where}/target", "node", target["node"], len(document.array("nodes")), "nodes")


def _missing(pointer: str, name: str, value, count: int, target: str) -> Iterator[tuple[str, str, int, str]]:
    for index in value if isinstance(value, list) else [value]:
        if isinstance(index, int) and not isinstance(index, bool) and not 0 <= index < count:
            yield pointer, name, index, f"names no {SINGULAR[target]} (the file has {count})"


def hierarchy_problems(document: GltfDocument) -> Iterator[tuple[str, str]]:
    """``(JSON pointer, message)`` for each node that is the child of two nodes or its own ancestor, and each scene
    root that is another node's child (glTF 2.0 3.5.3: disjoint strict trees)."""
    nodes = document.array("nodes")
    parent: dict[int, int] = {}
    for index, node in enumerate(nodes):
        children = node.get("children") if isinstance(node, dict) else None
        for child in children if isinstance(children, list) else ():
            if not (isinstance(child, int) and not isinstance(child, bool) and 0 <= child < len(nodes)):
                continue  # (dangling: judged above)
            if child in parent and parent[child] != index:
                yield (f"/nodes/{index}/children", f"node {child} is a child of nodes {parent[child]} and {index}: glTF's "
                       "node hierarchy is a set of disjoint trees, each node has at most one parent")
            else:
                parent.setdefault(child, index)
    done: set[int] = set()  # (each node walked once: linear in the nodes, however deep the trees)
    for start in range(len(nodes)):
        order: list[int] = []
        position: dict[int, int] = {}
        node = start
        while node is not None and node not in done and node not in position:
            position[node] = len(order)
            order.append(node)
            node = parent.get(node)
        done.update(order)
        if node is not None and node in position:  # the walk came back to itself: a loop
            cycle = order[position[node]:]
            yield (f"/nodes/{node}/children", f"nodes {' -> '.join(str(n) for n in cycle + [node])} form a loop: "
                   "glTF's node hierarchy is a set of disjoint trees; a viewer that walks it never ends, or drops it")
    for index, scene in enumerate(document.array("scenes")):
        roots = scene.get("nodes") if isinstance(scene, dict) else None
        for number, node in enumerate(roots if isinstance(roots, list) else ()):
            if isinstance(node, int) and not isinstance(node, bool) and node in parent:
                yield (f"/scenes/{index}/nodes/{number}", f"scene {index} lists node {node}, which is the child of node "
                       f"{parent[node]}: a scene lists root nodes only, or the node is drawn twice")


def unbounded_positions(document: GltfDocument) -> Iterator[tuple[str, str]]:
    """``(JSON pointer, message)`` for each accessor a primitive's POSITION names that lacks ``min`` or ``max``."""
    reported: set[int] = set()
    for pointer, primitive in document.primitives():
        attributes = primitive.get("attributes")
        index = attributes.get("POSITION") if isinstance(attributes, dict) else None
        accessor = document.item("accessors", index)
        if accessor is None or index in reported or ("min" in accessor and "max" in accessor):
            continue
        reported.add(index)
        yield (f"/accessors/{index}", f"accessor {index} holds the POSITION of {pointer} and has no "
               f"{'min and max' if 'min' not in accessor and 'max' not in accessor else 'min' if 'min' not in accessor else 'max'}"
               ": glTF 2.0 requires the bounds of positions (viewers cull and frame the mesh by them)")


def invalid(document: GltfDocument) -> Iterator[tuple[str, str, str, None]]:
    """:func:`hierarchy_problems` and :func:`unbounded_positions` as the reader observes :mod:`.layout`'s problems:
    ``("gltf_invalid", JSON pointer, message, None)``."""
    for pointer, message in (*hierarchy_problems(document), *unbounded_positions(document),
                             *extensions_not_objects(document)):
        yield "gltf_invalid", pointer, message, None


def extensions_not_objects(document: GltfDocument) -> Iterator[tuple[str, str]]:
    """Every ``extensions`` property that is not an object (null, say), anywhere outside ``extras``."""
    stack = [(document.json, "")]
    found = []
    while stack:
        container, pointer = stack.pop()
        items = container.items() if isinstance(container, dict) else enumerate(container)
        for key, value in items:
            if key == "extensions" and isinstance(container, dict) and not isinstance(value, dict):
                found.append(f"{pointer}/extensions")
            elif isinstance(value, (dict, list)) and key != "extras":
                stack.append((value, f"{pointer}/{key}"))
    for pointer in sorted(found):
        yield pointer, "extensions is not an object (the Khronos glTF-Validator's TYPE_MISMATCH): viewers that read it fail"
