"""Hypothesis strategies that build hostile-but-plausible glTF documents, GLB containers, and byte mutations.

Shared by the quick fuzz tests (tests/test_fuzz_gltf.py) and the long run
(tests/benchmarks/fuzz_long_gltf.py). Three kinds of input:

* **structured** :func:`gltf_inputs`: a seed document (the sample materials converted with
  ``openpbr convert``, with and without ``--mesh sphere``, embedded and external images, and a
  material with every gltf_pbr parameter written by the glTF writer) or a document assembled from
  scratch, mutated property by property: every material field and ``KHR_materials_*`` extension
  (taken from :mod:`openpbr_tools.io.gltf.slots`, so a new slot is fuzzed without touching this
  file), values of the wrong type (strings for numbers, arrays of the wrong length, ``null``,
  nested objects, NaN, huge integers), indices out of range, negative or huge, extension lists,
  texture / sampler / image / buffer references, image and buffer URIs (data URIs good and bad,
  absolute paths, ``..``, URLs, percent-escapes, NUL), deep nesting; then serialised with a chosen
  encoding (UTF-8, BOM, UTF-16, invalid UTF-8, unpaired surrogate escapes) and optionally
  truncated or corrupted, or packed in a GLB whose header and chunks are themselves mutated;
* **raw** :func:`mutate_bytes`: random byte edits of a seed ``.gltf`` or ``.glb`` (driven by a
  :class:`random.Random`, for the long run), including overwriting the GLB header and chunk
  length / type fields with boundary values.

The seeds need files (textures, ``.bin`` buffers) beside them: :func:`build_seeds` writes them into
a folder, and every input is written into that same folder.
"""

from __future__ import annotations

import base64
import copy
import json
import os
import random
import struct

import fuzzgen
from hypothesis import strategies as st

from openpbr_tools.io.gltf import slots

SAMPLES = os.path.join(os.path.dirname(__file__), "..", "openpbr_tools", "samples")
PNG_4X4 = base64.b64decode("iVBORw0KGgoAAAANSUhEUgAAAAQAAAAECAIAAAAmkwkpAAAAFElEQVR42mM8kWLEAANMDEgANwcARfYBZsiXQosAAAAASUVORK5CYII=")
GLB_JSON, GLB_BIN = 0x4E4F534A, 0x004E4942


# -- seeds -----------------------------------------------------------------------------------------

class Seeds:
    """Seed documents written into ``folder``: ``documents`` (name -> parsed JSON of a .gltf),
    ``gltf_bytes`` and ``glb_bytes`` (name -> file bytes), all resolvable from ``folder``. Beside
    them: ``escape.png``, a symbolic link to a PNG outside ``folder``, and ``fifo.png``, a FIFO;
    neither may ever be opened."""

    def __init__(self, folder: str):
        self.folder = folder
        self.documents: dict[str, dict] = {}
        self.gltf_bytes: dict[str, bytes] = {}
        self.glb_bytes: dict[str, bytes] = {}
        self.glb_parts: dict[str, tuple[dict, bytes | None]] = {}  # name -> (JSON chunk parsed, BIN chunk)


def build_seeds(folder: str) -> Seeds:
    """Convert every sample to ``.gltf`` (with and without ``--mesh sphere``) and ``.glb``, write the
    textured one with data-URI images, and a material with every gltf_pbr parameter, into ``folder``
    (created; its parent receives the file ``escape.png`` points to)."""
    from gltf_support import gltf_pbr_material

    from openpbr_tools.io import read_asset
    from openpbr_tools.io.gltf.writer import write_gltf
    from openpbr_tools.convert import convert_file

    seeds = Seeds(folder)
    os.makedirs(folder, exist_ok=True)
    secret = os.path.join(os.path.dirname(os.path.abspath(folder)), "outside_the_asset.png")
    with open(secret, "wb") as handle:
        handle.write(PNG_4X4)
    os.symlink(secret, os.path.join(folder, "escape.png"))
    os.mkfifo(os.path.join(folder, "fifo.png"))
    samples = sorted(n for n in os.listdir(SAMPLES) if n.endswith(".mtlx"))
    for name in samples:
        stem = name[:-5]
        source = os.path.join(SAMPLES, name)
        convert_file(source, os.path.join(folder, f"{stem}.gltf"))
        convert_file(source, os.path.join(folder, f"{stem}_sphere.gltf"), mesh="sphere")
        convert_file(source, os.path.join(folder, f"{stem}.glb"), mesh="sphere")
    textured = read_asset(os.path.join(folder, "textured_wood.glb"))
    write_gltf(textured.materials, os.path.join(folder, "textured_wood_embedded.gltf"), embed=True, source=textured)
    everything = gltf_pbr_material(
        "Everything", base_color=(0.8, 0.5, 0.2), metallic=0.3, roughness=0.4, occlusion=0.9, transmission=0.2,
        specular=0.7, specular_color=(0.9, 0.8, 0.7), ior=1.6, alpha=0.5, alpha_mode=2, alpha_cutoff=0.3,
        iridescence=0.4, iridescence_ior=1.4, iridescence_thickness=300.0, sheen_color=(0.2, 0.3, 0.4),
        sheen_roughness=0.6, clearcoat=0.5, clearcoat_roughness=0.1, emissive=(0.1, 0.2, 0.3),
        emissive_strength=4.0, thickness=0.02, attenuation_distance=0.5, attenuation_color=(0.9, 0.6, 0.3),
        anisotropy_strength=0.5, anisotropy_rotation=0.7, dispersion=0.1)
    write_gltf([everything], os.path.join(folder, "everything.gltf"), mesh="sphere")
    for name in sorted(os.listdir(folder)):
        path = os.path.join(folder, name)
        if name.endswith(".gltf"):
            with open(path, "rb") as handle:
                seeds.gltf_bytes[name] = handle.read()
            seeds.documents[name] = json.loads(seeds.gltf_bytes[name])
        elif name.endswith(".glb"):
            with open(path, "rb") as handle:
                seeds.glb_bytes[name] = handle.read()
            seeds.glb_parts[name] = _glb_parts(seeds.glb_bytes[name])
    return seeds


def _glb_parts(data: bytes) -> tuple[dict, bytes | None]:
    json_length = struct.unpack_from("<I", data, 12)[0]
    document = json.loads(data[20:20 + json_length])
    rest = data[20 + json_length:]
    return document, (rest[8:8 + struct.unpack_from("<I", rest, 0)[0]] if len(rest) >= 8 else None)


# -- values ----------------------------------------------------------------------------------------

EXTENSION_NAMES = sorted(set(slots.INTERPRETED_MATERIAL_EXTENSIONS + slots.NEUTRAL_EXTENSIONS) | {
    slots.DIFFUSE_TRANSMISSION, slots.UNLIT, slots.SPECULAR_GLOSSINESS, slots.TEXTURE_TRANSFORM,
    "EXT_texture_webp", "KHR_texture_basisu", "VENDOR_materials_magic", "", "KHR_materials_", "\u2603"})
@st.composite
def mostly(draw, common, rare, odds: int = 4):
    """``common`` ``odds`` times out of ``odds + 1``, else ``rare`` (``st.one_of`` would weigh its
    branches equally, and merges repeated ones)."""
    return draw(common) if draw(st.integers(0, odds)) < odds else draw(rare)


HUGE_INTEGERS = [2**31 - 1, 2**31, 2**32, 2**53 + 1, 2**63, 10**30, -(2**63), 10**400]
TEXT = st.text(alphabet=st.characters(blacklist_categories=("Cs",)), max_size=20)
STRINGS = st.one_of(TEXT, st.sampled_from(["", "0", "1.5", "NaN", "true", "null", "OPAQUE", "MASK", "BLEND", "opaque",
                                            "\ud800", "\udfff\ud800", "a\x00b", "\u2603" * 50, "x" * 2000]))
NUMBERS = st.one_of(
    st.floats(-2.0, 3.0), st.sampled_from([0, 1, -1, 0.0, -0.0, 1.0, 0.5, 1.0000001, -1e-9, 1e308, 5e-324, 1e38]),
    st.floats(allow_nan=True, allow_infinity=True), st.integers(-3, 10), st.sampled_from(HUGE_INTEGERS),
)
SCALARS = st.one_of(st.none(), st.booleans(), NUMBERS, STRINGS)
JSON_VALUES = st.recursive(SCALARS, lambda inner: st.one_of(
    st.lists(inner, max_size=4), st.dictionaries(STRINGS, inner, max_size=3)), max_leaves=6)
INDICES = mostly(st.integers(0, 4), st.one_of(st.sampled_from([-1, -(2**31)] + HUGE_INTEGERS),
                                               st.sampled_from(["0", 0.0, 1.5, True, None, [0], {"index": 0}])), 2)
DEEP_DEPTHS = [8, 127, 128, 129, 200, 900, 990, 1000, 5000, 100_000]


def number_lists(width: int):
    return st.one_of(
        st.lists(st.one_of(st.floats(0.0, 1.0), st.floats(-1.0, 2.0)), min_size=width, max_size=width),
        st.lists(NUMBERS, min_size=width, max_size=width),
        st.lists(NUMBERS, max_size=width + 2),
    )


def values_of(width: int):
    """A value for a factor of ``width`` components: mostly plausible, often wrong."""
    plausible = number_lists(width) if width > 1 else st.one_of(st.floats(0.0, 1.0), st.floats(-1.0, 500.0))
    return mostly(plausible, st.one_of(NUMBERS, SCALARS, JSON_VALUES), 2)


@st.composite
def texture_transforms(draw) -> dict:
    transform = {}
    for key, strategy in (("offset", number_lists(2)), ("rotation", st.one_of(st.floats(-7.0, 7.0), NUMBERS)),
                          ("scale", st.one_of(number_lists(2), st.just([0.0, 1.0]))), ("texCoord", INDICES)):
        if draw(st.booleans()):
            transform[key] = draw(mostly(strategy, SCALARS, 3))
    return transform


@st.composite
def texture_infos(draw, kind: str = "textureInfo"):
    if draw(st.integers(0, 9)) == 9:
        return draw(SCALARS)
    info: dict = {}
    if draw(st.integers(0, 7)) < 7:
        info["index"] = draw(INDICES)
    if draw(st.booleans()):
        info["texCoord"] = draw(st.one_of(st.integers(0, 2), INDICES))
    if kind in ("normalTextureInfo", "occlusionTextureInfo") and draw(st.booleans()):
        info["scale" if kind == "normalTextureInfo" else "strength"] = draw(values_of(1))
    if draw(st.integers(0, 3)) == 3:
        extensions = {slots.TEXTURE_TRANSFORM: draw(mostly(texture_transforms(), SCALARS, 3))}
        info["extensions"] = draw(mostly(st.just(extensions), SCALARS, 5))
    if draw(st.integers(0, 9)) == 9:
        info["extras"] = draw(JSON_VALUES)
    return info


def _slot_fields() -> dict[str, list[tuple[str, str, int]]]:
    """container -> [(property, kind, width)]: every factor and texture gltf_slots knows, plus the
    properties of the extensions the reader keeps as data."""
    fields: dict[str, list[tuple[str, str, int]]] = {}
    for slot in slots.SLOTS:
        entries = fields.setdefault(slot.container, [])
        if slot.factor and all(slot.factor != f for f, _, _ in entries):
            width = 4 if slot.factor == "baseColorFactor" else (len(slot.default) if isinstance(slot.default, tuple) else 1)
            entries.append((slot.factor, "alphaMode" if slot.factor == "alphaMode" else "factor", width))
        if slot.texture and all(slot.texture != f for f, _, _ in entries):
            entries.append((slot.texture, slot.texture_kind, 0))
    fields[slots.IRIDESCENCE].append((slots.IRIDESCENCE_THICKNESS_MINIMUM[0], "factor", 1))
    fields[slots.DIFFUSE_TRANSMISSION] = [("diffuseTransmissionFactor", "factor", 1),
                                          ("diffuseTransmissionTexture", "textureInfo", 0),
                                          ("diffuseTransmissionColorFactor", "factor", 3),
                                          ("diffuseTransmissionColorTexture", "textureInfo", 0)]
    fields[slots.UNLIT] = []
    fields[slots.SPECULAR_GLOSSINESS] = [("diffuseFactor", "factor", 4), ("diffuseTexture", "textureInfo", 0),
                                         ("specularFactor", "factor", 3), ("glossinessFactor", "factor", 1),
                                         ("specularGlossinessTexture", "textureInfo", 0)]
    fields["VENDOR_materials_magic"] = [("sparkle", "factor", 1)]
    return fields


SLOT_FIELDS = _slot_fields()


@st.composite
def field_values(draw, kind: str, width: int):
    if kind == "alphaMode":
        return draw(st.one_of(st.sampled_from(list(slots.ALPHA_MODES)), SCALARS))
    if kind == "factor":
        return draw(values_of(width))
    return draw(texture_infos(kind))


@st.composite
def containers(draw, name: str) -> dict:
    fields = SLOT_FIELDS[name]
    chosen = draw(st.lists(st.sampled_from(fields), max_size=len(fields), unique=True)) if fields else []
    return {field: draw(field_values(kind, width)) for field, kind, width in chosen}


@st.composite
def materials(draw):
    if draw(st.integers(0, 19)) == 19:
        return draw(SCALARS)
    material: dict = {}
    if draw(st.integers(0, 4)) < 4:
        material["name"] = draw(st.one_of(st.sampled_from(["M", "Brass", "M", ""]), STRINGS, SCALARS))
    material.update(draw(containers(slots.CORE)))
    if draw(st.integers(0, 3)) < 3:
        material[slots.PBR] = draw(mostly(containers(slots.PBR), SCALARS, 5))
    names = [n for n in SLOT_FIELDS if n not in (slots.CORE, slots.PBR)]
    chosen = draw(st.lists(st.sampled_from(names), max_size=5, unique=True))
    if chosen or draw(st.integers(0, 5)) == 5:
        material["extensions"] = draw(mostly(
            st.just({name: draw(mostly(containers(name), SCALARS, 5)) for name in chosen}), SCALARS, 5))
    for key in ("doubleSided", "extras"):
        if draw(st.integers(0, 5)) == 5:
            material[key] = draw(JSON_VALUES)
    return material


HOSTILE_URIS = st.sampled_from([
    "data:image/png;base64," + base64.b64encode(PNG_4X4).decode(), "data:image/png;base64,iVBORw0KGgo!!!not-base64",
    "data:image/png;base64,", "data:image/png,%89PNG", "data:,", "data:image/jpeg;base64,/9j/4AAQ", "data:",
    "data:application/octet-stream;base64," + base64.b64encode(bytes(range(256)) * 8).decode(),
    "data:image/png;base64," + base64.b64encode(PNG_4X4[:30]).decode(),
    "textures/wood_normal.png", "textures/VarnishedWood_base_color.png", "car_paint_sphere.bin",
    "VarnishedWood_material_metallicRoughnessTexture.png", "textures%2Fwood_normal.png", "missing.png",
    "/etc/passwd", "../../etc/passwd", "..%2F..%2Fetc%2Fpasswd", "http://example.com/a.png", "file:///etc/passwd",
    "C:\\textures\\a.png", "\\\\server\\share\\a.png", "a\x00b.png", "%00.png", "\ud800.png", "", ".", "textures",
    "textures/", "a.exr", "a.tif", "x" * 5000 + ".png", "%ff%fe.png", "escape.png", "fifo.png",
])
URIS = mostly(HOSTILE_URIS, st.one_of(STRINGS, SCALARS), 3)


@st.composite
def images(draw):
    image: dict = {}
    choice = draw(st.integers(0, 4))
    if choice <= 2:
        image["uri"] = draw(URIS)
    elif choice == 3:
        image["bufferView"] = draw(INDICES)
    if draw(st.booleans()):
        image["mimeType"] = draw(st.one_of(st.sampled_from(["image/png", "image/jpeg", "image/webp", "image/ktx2",
                                                            "image/x-exr", "text/plain", ""]), SCALARS))
    if draw(st.integers(0, 9)) == 9:
        image["name"] = draw(STRINGS)
    return image


@st.composite
def textures(draw):
    texture: dict = {}
    if draw(st.integers(0, 5)) < 5:
        texture["source"] = draw(INDICES)
    if draw(st.booleans()):
        texture["sampler"] = draw(INDICES)
    if draw(st.integers(0, 5)) == 5:
        name = draw(st.sampled_from(list(slots.EXTENSION_MIME_TYPES.values())))
        texture["extensions"] = {name: draw(st.one_of(st.fixed_dictionaries({"source": INDICES}), SCALARS))}
    return texture


WRAPS = st.one_of(st.sampled_from([33071, 33648, 10497, 9728, 0, -1, 2**40]), SCALARS)
SAMPLERS = st.fixed_dictionaries({}, optional={"wrapS": WRAPS, "wrapT": WRAPS, "magFilter": WRAPS, "minFilter": WRAPS})
BUFFERS = st.fixed_dictionaries({"byteLength": st.one_of(st.integers(0, 40000), INDICES)}, optional={"uri": URIS})
BUFFER_VIEWS = st.fixed_dictionaries({"buffer": INDICES, "byteLength": st.one_of(st.integers(0, 40000), INDICES)},
                                     optional={"byteOffset": st.one_of(st.integers(0, 40000), INDICES)})


@st.composite
def primitives(draw):
    names = draw(st.lists(st.sampled_from(["POSITION", "NORMAL", "TEXCOORD_0", "TEXCOORD_1", "TEXCOORD_2",
                                           "TEXCOORD_", "TEXCOORD_x", "TEXCOORD_\u00b2", "TEXCOORD_" + "9" * 5000,
                                           "TEXCOORD_-1", "TEXCOORD_01"]), max_size=5, unique=True))
    primitive = {"attributes": draw(mostly(st.just({name: 0 for name in names}), SCALARS, 5))}
    if draw(st.integers(0, 4)) < 4:
        primitive["material"] = draw(INDICES)
    return primitive


@st.composite
def extension_lists(draw):
    return draw(st.one_of(st.lists(st.sampled_from(EXTENSION_NAMES), max_size=6), st.lists(SCALARS, max_size=3), SCALARS))


@st.composite
def scratch_documents(draw) -> dict:
    """A document built from scratch: every top-level array the reader looks at, of any shape."""
    document: dict = {"asset": draw(mostly(
        st.builds(lambda: {"version": "2.0"}),
        st.one_of(st.fixed_dictionaries({"version": st.one_of(st.sampled_from(["2.0", "2.1", "2", "1.0", "3.0", "", "2.0.0"]),
                                                              SCALARS)}, optional={"minVersion": SCALARS}), SCALARS),
        8))}
    for key, strategy, most in (("materials", materials(), 5), ("textures", textures(), 4), ("images", images(), 4),
                                ("samplers", SAMPLERS, 2), ("buffers", BUFFERS, 2), ("bufferViews", BUFFER_VIEWS, 3)):
        if draw(st.integers(0, 4)) < 4:
            document[key] = draw(mostly(st.lists(strategy, max_size=most), SCALARS, 6))
    if draw(st.booleans()):
        document["meshes"] = draw(mostly(st.lists(st.fixed_dictionaries({"primitives": mostly(
            st.lists(primitives(), max_size=3), SCALARS, 6)}), max_size=2), SCALARS, 6))
    for key in ("extensionsUsed", "extensionsRequired"):
        if draw(st.booleans()):
            document[key] = draw(extension_lists())
    if draw(st.integers(0, 5)) == 5:
        document["extensions"] = {draw(st.sampled_from(EXTENSION_NAMES)): draw(JSON_VALUES)}
    return document


# -- mutating a document ---------------------------------------------------------------------------

def _paths(value, prefix=()) -> list[tuple]:
    """Every JSON path (tuple of keys and indices) in ``value``, containers included."""
    found = [prefix]
    if isinstance(value, dict):
        for key, child in value.items():
            found.extend(_paths(child, prefix + (key,)))
    elif isinstance(value, list):
        for index, child in enumerate(value):
            found.extend(_paths(child, prefix + (index,)))
    return found


def _parent(document, path):
    for key in path[:-1]:
        document = document[key]
    return document


@st.composite
def mutated(draw, document: dict) -> dict:
    """``document`` with 1-6 edits at random places: a value replaced (by a hostile value, a value of
    the wrong type, an index out of range), removed, wrapped in an array, or a material field or
    extension added from the slot table."""
    document = copy.deepcopy(document)
    for _ in range(draw(st.integers(1, 6))):
        spare_asset = draw(st.integers(0, 9)) < 9  # else most edits of a small seed would break its header
        paths = [p for p in _paths(document) if p and not (spare_asset and p[0] == "asset")]
        operation = draw(st.sampled_from(["replace", "replace", "remove", "wrap", "add_field", "add_field", "index",
                                          "uri", "string", "number"]))
        if operation == "uri":  # an image or buffer gets a hostile URI
            array = draw(st.sampled_from(["images", "buffers"]))
            found = document.setdefault(array, [])
            if isinstance(found, list):
                if not found or draw(st.booleans()):
                    found.append({"byteLength": 4} if array == "buffers" else {})
                entry = found[draw(st.integers(0, len(found) - 1))]
                if isinstance(entry, dict):
                    entry["uri"] = draw(URIS)
            continue
        if operation in ("string", "number"):  # a string (name, URI, extension) or a number becomes hostile
            wanted = str if operation == "string" else (int, float)
            found = [p for p in _paths(document) if p and p[0] != "asset" and isinstance(_parent(document, p)[p[-1]], wanted)]
            if found:
                path = draw(st.sampled_from(found))
                _parent(document, path)[path[-1]] = draw(STRINGS if operation == "string" else NUMBERS)
            continue
        if operation == "add_field":
            found = document.get("materials")
            if isinstance(found, list) and found and isinstance(found[0], dict):
                material = found[draw(st.integers(0, len(found) - 1))]
                if isinstance(material, dict):
                    container = draw(st.sampled_from(sorted(SLOT_FIELDS)))
                    fields = SLOT_FIELDS[container]
                    if container == slots.CORE:
                        target = material
                    elif container == slots.PBR:
                        target = material.setdefault(slots.PBR, {})
                    else:
                        extensions = material.setdefault("extensions", {})
                        target = extensions.setdefault(container, {}) if isinstance(extensions, dict) else None
                    if isinstance(target, dict) and fields:
                        field, kind, width = draw(st.sampled_from(fields))
                        target[field] = copy.deepcopy(draw(field_values(kind, width)))
            continue
        if not paths:
            continue
        path = draw(st.sampled_from(paths))
        parent = _parent(document, path)
        key = path[-1]
        if operation == "replace":  # copies: strategies hand out shared literals ([0], {"index": 0})
            parent[key] = copy.deepcopy(draw(st.one_of(JSON_VALUES, NUMBERS, INDICES)))
        elif operation == "index":
            parent[key] = copy.deepcopy(draw(INDICES))
        elif operation == "wrap":
            parent[key] = [parent[key]]
        else:
            del parent[key]
    return document


# -- serialising -----------------------------------------------------------------------------------

@st.composite
def encoded(draw, document) -> bytes:
    """``document`` as bytes: JSON with a chosen encoding, maybe a deeply nested value spliced in."""
    text = json.dumps(document, ensure_ascii=draw(st.booleans()), indent=draw(st.sampled_from([None, None, 2])))
    if draw(st.integers(0, 14)) == 14:  # a deep value appended as extras
        depth = draw(st.sampled_from(DEEP_DEPTHS))
        opener, closer = draw(st.sampled_from([("[", "]"), ('{"a":', "}")]))
        deep = opener * depth + "1" + closer * depth
        if text.endswith("}") and text != "{}":
            text = text[:-1] + ', "extras": ' + deep + "}"
        else:
            text = deep
    encoding = draw(st.sampled_from(["utf-8"] * 15 + ["utf-8-sig", "utf-16", "utf-16-le", "latin-1", "invalid"]))
    if encoding == "invalid":
        data = text.encode("utf-8", "surrogatepass")
        position = draw(st.integers(0, len(data)))
        return data[:position] + draw(st.sampled_from([b"\xff", b"\xc3", b"\xed\xa0\x80", b"\x80\x80", b"\x00"])) + data[position:]
    return text.encode(encoding, "surrogatepass" if encoding.startswith("utf") else "replace")


JSON_INSERTS = [b"{", b"}", b"[", b"]", b'"', b",", b":", b"\\", b"\x00", b"\xff", b"\\ud800", b"1e999", b"-"]


def byte_edits(data: bytes):
    """:func:`fuzzgen.byte_edits` with JSON's tokens, leaving most documents whole."""
    return fuzzgen.byte_edits(data, JSON_INSERTS, unchanged=8)


LENGTHS = [0, 1, 3, 4, 7, 8, 12, 2**31 - 1, 2**31, 2**32 - 1, 2**30]


@st.composite
def glb_containers(draw, json_bytes: bytes, binary: bytes | None) -> bytes:
    """A GLB holding ``json_bytes`` (and ``binary``); one time in three with 1-3 of its header and
    chunk fields mutated: magic, version, total length, chunk lengths (off by a few, gigabytes),
    chunk types, chunk order, an extra chunk, padding."""
    fields = ["magic", "version", "total", "length", "type", "order", "extra", "pad"]
    damaged = {draw(st.sampled_from(fields)) for _ in range(draw(st.integers(1, 3)))} if draw(st.integers(0, 2)) == 2 else set()
    pad = draw(st.sampled_from([b"\x00", b"", b"\t"])) if "pad" in damaged else b" "
    json_chunk = json_bytes + pad * (-len(json_bytes) % 4)
    chunks = [[GLB_JSON, json_chunk]]
    if binary is not None:
        chunks.append([GLB_BIN, binary + b"\x00" * (-len(binary) % 4)])
    if "extra" in damaged:
        chunks.append([draw(st.sampled_from([GLB_BIN, GLB_JSON, 0, 0x12345678])), draw(st.binary(max_size=16))])
    if "order" in damaged:
        chunks.reverse()
    if "type" in damaged:
        chunks[draw(st.integers(0, len(chunks) - 1))][0] = draw(st.sampled_from([GLB_BIN, GLB_JSON, 0, 0x4E4F534B, 0xFFFFFFFF]))
    lengths = [len(data) for _, data in chunks]
    if "length" in damaged:
        which = draw(st.integers(0, len(chunks) - 1))
        lengths[which] = draw(st.one_of(st.sampled_from(LENGTHS), st.integers(max(0, lengths[which] - 8), lengths[which] + 8)))
    body = b"".join(struct.pack("<II", length, kind) + data for length, (kind, data) in zip(lengths, chunks))
    magic = draw(st.sampled_from([b"GLTF", b"gltf", b"\x00\x00\x00\x00", b"glT"])) if "magic" in damaged else b"glTF"
    version = draw(st.sampled_from([1, 3, 0, 2**32 - 1])) if "version" in damaged else 2
    total = 12 + len(body)
    if "total" in damaged:
        total = draw(st.one_of(st.sampled_from(LENGTHS), st.integers(max(0, total - 8), total + 8)))
    return magic + struct.pack("<II", version, total) + body


@st.composite
def gltf_inputs(draw, seeds: Seeds) -> tuple[str, bytes]:
    """(suffix, bytes): a structured glTF input; three in four a ``.gltf``, else a ``.glb`` (half of
    them a seed GLB whose JSON chunk is mutated and whose binary chunk, images and mesh, is kept)."""
    kind = draw(st.integers(0, 7))
    if kind == 6:
        document, binary = seeds.glb_parts[draw(st.sampled_from(sorted(seeds.glb_parts)))]
        text = json.dumps(draw(mutated(document))).encode("utf-8", "surrogatepass")
        return ".glb", draw(byte_edits(draw(glb_containers(text, binary))))
    if draw(st.integers(0, 2)) < 2:
        document = draw(mutated(seeds.documents[draw(st.sampled_from(sorted(seeds.documents)))]))
    else:
        document = draw(scratch_documents())
        if draw(st.booleans()):
            document = draw(mutated(document))
    if kind == 7:
        binary = None
        if draw(st.booleans()):
            binary = draw(st.sampled_from([b"", PNG_4X4, bytes(64), _seed_binary(seeds)]))
            if draw(st.booleans()):
                document = dict(document, buffers=[{"byteLength": len(binary)}],
                                bufferViews=[{"buffer": 0, "byteLength": len(PNG_4X4)}],
                                images=[{"bufferView": 0, "mimeType": "image/png"}])
        text = json.dumps(document).encode("utf-8", "surrogatepass")
        return ".glb", draw(byte_edits(draw(glb_containers(text, binary))))
    return ".gltf", draw(byte_edits(draw(encoded(document))))


def _seed_binary(seeds: Seeds) -> bytes:
    path = os.path.join(seeds.folder, "car_paint_sphere.bin")
    with open(path, "rb") as handle:
        return handle.read()


# -- raw byte mutation (the long run) --------------------------------------------------------------

INSERTS = [b"{", b"}", b"[", b"]", b'"', b",", b":", b"\\u", b"\x00", b"\xc3", b"\xff", b"null", b"-1", b"1e999", b"[[[["]
INTERESTING = [0, 1, 4, 8, 12, 0x7FFFFFFF, 0x80000000, 0xFFFFFFFF, GLB_JSON, GLB_BIN]


def mutate_bytes(rng: random.Random, data: bytes, glb: bool) -> bytes:
    """1-16 random edits of ``data``: byte flips, inserts of JSON punctuation, deletions, truncation;
    for a GLB also boundary values written over the header and chunk length / type fields."""
    data = bytearray(data)
    for _ in range(rng.randint(1, 16)):
        if not data:
            break
        choice = rng.random()
        if glb and choice < 0.25:
            offsets = [8, 12, 16] + ([20 + struct.unpack_from("<I", data, 12)[0]] if len(data) >= 16 else [])
            offset = rng.choice(offsets)
            value = rng.choice(INTERESTING + [rng.randrange(2**32), len(data) + rng.randint(-8, 8)]) % 2**32
            if offset + 4 <= len(data):
                struct.pack_into("<I", data, offset, value)
            continue
        position = rng.randrange(len(data))
        if choice < 0.5:
            data[position] = rng.randrange(256)
        elif choice < 0.7:
            data[position:position] = rng.choice(INSERTS)
        elif choice < 0.9:
            del data[position:position + rng.randint(1, 32)]
        else:
            data = data[:position]
    return bytes(data)
