"""Read glTF 2.0 (``.gltf`` JSON with external or data-URI resources, ``.glb``) into an :class:`~openpbr_tools.model.Asset`.

Every glTF material becomes a ``gltf_pbr`` 2.0.1 :class:`~openpbr_tools.model.Material` (MaterialX's
``ND_gltf_pbr_surfaceshader``) whose inputs are the gltf_pbr parameters it authors (:mod:`.slots`: where each lives):

* a factor without a texture is a :class:`Constant`; a texture is a :class:`Texture` whose
  ``channels`` are the ones glTF reads for that slot, ``colorspace`` ``srgb_texture`` for colour
  slots and ``none`` for data, ``scale`` the factor that multiplies it (its default when not
  authored: an ``emissiveTexture`` without ``emissiveFactor`` has scale (0, 0, 0)), ``texcoord``
  the UV set (``None`` for set 0), ``uv`` the KHR_texture_transform as ``place2d`` parameters
  (:mod:`.uv`), ``wrap`` the sampler's wrap modes as MaterialX address modes;
* ``normalTexture.scale`` is ``Texture.normal_map``; occlusion is ``1 + strength (r - 1)``, i.e.
  ``scale = strength`` and ``bias = 1 - strength``;
* iridescence thickness is ``mix(iridescenceThicknessMinimum, iridescenceThicknessMaximum, g)``
  with a texture (``scale = max - min``, ``bias = min``) and the maximum without one;
* the anisotropy texture's B channel is ``anisotropy_strength``'s texture; its RG direction has no
  gltf_pbr input of its own (MaterialX's ``gltf_anisotropy_image`` adds ``atan2`` of it to
  ``anisotropy_rotation``), so it is kept as a :class:`Texture` in ``extra["gltf"]["anisotropy_direction"]``.

Texture files are the image URI, percent-decoded, relative to the asset; an image inside the asset
(data URI, GLB buffer view) is ``"#/images/<index>"`` with ``packaged=True``. What gltf_pbr cannot
hold goes to ``Material.extra["gltf"]`` as raw JSON for a translator: ``doubleSided``, ``extras``,
and the extensions the node does not carry (``KHR_materials_diffuse_transmission``,
``KHR_materials_unlit`` (converted as emission by the translation), ``KHR_materials_pbrSpecularGlossiness``
(its factors and textures also read, by specular-workflow names, into ``extra["gltf"]["spec_gloss"]`` for
the translation; reported as archived), unknown ones). Every value's :class:`Location` is the file, a JSON pointer to
the object holding the property and the glTF property name.

Facts for the glTF rules (extensions, images, each primitive's UV sets, attribute formats, extent and tangent signs, the
values of primitives with a material: :mod:`.accessors`, and their vertex colour and UV layout: :mod:`.geometry`;
variants; repeated JSON names; animation pointers to undefined material properties: :mod:`.animation_pointers`) are in
``Asset.extra["gltf"]``; broken references and resources are :class:`Observation` s, each reported once.
Only a file that is not glTF at all raises :class:`ReadError` (the container's limits are :mod:`.document`'s).

Nothing outside the asset is opened: an image or buffer URI that is a URL, absolute, climbs out with
``..`` or resolves outside the asset's folder through a symbolic link is never read (the image's
``outside`` fact says why, for the rules), and an embedded image is measured (width, height,
format) from its header through a view, never copied. Every step is linear in the size of the
document, so thousands of materials, textures or primitives cost milliseconds each.

This module reads the document, its resources and materials (factors, which slot lives where);
images, textures and samplers are :mod:`.textures`'s. One module because the reading is one pass over the document
whose order matters (resources and layout before the materials that sample them, variants after the materials).
"""

from __future__ import annotations

import re

from ... import tables, versioning
from ...model import Asset, Constant, Input, Location, Material, Texture
from .. import ReadError
from . import accessors, animation_pointers, drafts, geometry, json_schema, layout, references, schema, slots
from .document import GltfDocument, ResourceError, load_document
from .extension_reader import ExtensionReading, thin_diffuse_transmission
from .textures import TextureReading, json_float, json_index, json_numbers, json_text

MODEL, VERSION = "gltf_pbr", "2.0.1"
SCENE_LENGTH_UNIT = "meter"  # glTF is metres (specification 3.4)


def read_gltf(path: str, allow_outside: tuple[str, ...] = ()) -> Asset:
    """Read the glTF or GLB file at ``path``; :class:`~openpbr_tools.io.ReadError` if it is not glTF.
    Buffers and images may come from the asset's folder or one in ``allow_outside``."""
    try:
        import pygltflib  # noqa: F401  (slots takes the glTF enums from it)
    except ImportError:
        raise ReadError("unsupported", "reading glTF needs pygltflib: pip install pygltflib",
                        Location(path)) from None
    document = load_document(path)
    document.allow_outside = tuple(allow_outside)
    asset = Asset(path=path, format="gltf", format_version=document.json["asset"]["version"],
                  colorspace="lin_rec709", colorspace_location=Location(path, path="/asset"), meters_per_unit=1.0)
    _Reader(asset, document).run()
    return asset


class _Reader(TextureReading, ExtensionReading):
    def __init__(self, asset: Asset, document: GltfDocument) -> None:
        self.asset, self.document, self.path = asset, document, asset.path
        header = document.json.get("asset") if isinstance(document.json.get("asset"), dict) else {}
        self.toolkit_written = str(header.get("generator", "")).startswith("openpbr-tools")  # (translate.gltf)
        self.table = tables.table(MODEL, VERSION)
        self.wrap_modes = slots.wrap_to_address()
        self.filters = slots.sampler_filters()
        self.bad_samplers: set = set()
        self.observed: set = set()  # (kind, pointer, message): the same problem reached twice is reported once
        self.texture_pointers: set[str] = set()
        self.reading, self.reading_name = {}, ""  # the state of the material being read (read_material), its name
        self.tangent_cache: dict[int, dict | None] = {}
        self.data_cache: dict = {}  # the accessors whose values accessors.primitive_problems and geometry judged
        self.package_files: set[str] = set()  # embedded images that decode: the textures rule looks them up here
        self.facts: dict = {"extensions_used": _names(document.json.get("extensionsUsed")),
                            "extensions_required": _names(document.json.get("extensionsRequired")),
                            "extension_uses": [], "images": [], "texture_uses": [], "primitives": [],
                            "glb": document.is_glb, "repeated_names": document.duplicates,  # each texture's image:
                            "texture_sources": [t.get("source") if isinstance(t, dict) and json_index(t.get("source"))
                                                else None for t in document.array("textures")]}
        asset.extra["gltf"] = self.facts

    def location(self, pointer: str, name: str | None = None) -> Location:
        return Location(self.path, None, pointer, name)

    def invalid(self, pointer: str, message: str, name: str | None = None) -> None:
        self.observe_once("gltf_invalid", pointer, message, name)

    def broken(self, error: ResourceError) -> None:
        self.observe_once("gltf_resource", error.pointer, error.message)

    def observe_once(self, kind: str, pointer: str, message: str, name: str | None = None) -> None:
        key = (kind, pointer, name, message)
        if key not in self.observed:
            self.observed.add(key)
            self.asset.observe(kind, self.location(pointer, name), message=message)

    def run(self) -> None:
        for pointer, message in self.document.repairs:
            self.invalid(pointer, message)
        _extension_uses(self.document.json, self.facts["extension_uses"])
        for pointer, name in self.facts["extension_uses"]:
            if not _extension_in_place(pointer, name):
                where = (f"{name} belongs in the root's extensions (its variants) and in mesh primitives' (their "
                         "mappings)") if name == slots.VARIANTS else ("a material extension belongs in a material's "
                                                                       "extensions, KHR_texture_transform in a textureInfo's, "
                                                                       "an image format's in a texture's")
                self.invalid(pointer, f"{name} is not defined on this object ({where}); viewers ignore it")
        for key in ("extensionsUsed", "extensionsRequired"):
            names, seen = self.document.json.get(key), set()
            for index, name in enumerate(names if isinstance(names, list) else ()):
                if isinstance(name, str) and name in seen:
                    self.invalid(f"/{key}/{index}", f"{name!r} is listed twice in {key} (its items must be unique)")
                seen.add(name if isinstance(name, str) else None)
        self.images = [self.read_image(i) for i in range(len(self.document.array("images")))]
        self.facts["images"] = self.images
        self.asset.extra["package_files"] = frozenset(self.package_files)
        self.check_layout()
        self.read_primitives()
        materials = self.document.json.get("materials", [])
        if not isinstance(materials, list):
            self.invalid("/materials", "materials is not an array")
            return
        for index, raw in enumerate(materials):
            if not isinstance(raw, dict):
                self.invalid(f"/materials/{index}", "material is not an object")
                continue
            self.asset.materials.append(self.read_material(index, raw))
        self.read_variants()

    # -- resources and layout ------------------------------------------------------------------
    def check_layout(self) -> None:
        """Buffers, GLB chunks, Draco objects, the default scene, accessor and texture-source facts (:mod:`.layout`);
        the root's arrays and images in bufferViews of mesh data (:mod:`.schema`); texture objects' properties."""
        for kind, pointer, message, name in (*layout.buffer_problems(self.document), *layout.compression_problems(self.document),
                                             *schema.root_problems(self.document), *schema.image_view_problems(self.document),
                                             *references.invalid(self.document)):
            self.observe_once(kind, pointer, message, name)
        self.unexpected_texture_properties()
        for pointer, name, index, why in references.dangling(self.document):  # (the root's scene: name None)
            self.asset.observe("dangling_reference", self.location(pointer, name), attribute=name or "scene",
                               target=index, ends=why)
        self.facts["accessor_problems"], self.facts["schema_errors"] = (layout.accessor_problems(self.document),
                                                                        json_schema.errors(self.document.json))
        self.facts["extension_sources"] = layout.extension_sources(self.document)
        self.facts["animation_pointers"] = animation_pointers.material_pointer_problems(self.document)

    def read_primitives(self) -> None:
        for where, primitive in self.document.primitives():
            attributes = primitive.get("attributes") if isinstance(primitive.get("attributes"), dict) else {}
            sets = sorted(n for n in (_set_of(name, "TEXCOORD_") for name in attributes) if n is not None)
            formats = {name: self.accessor_format(accessor) for name, accessor in attributes.items()  # (rules.gltf_meshes)
                       if name in ("NORMAL", "TANGENT") or any(_set_of(name, s) is not None for s in ("TEXCOORD_", "COLOR_"))}
            material = primitive.get("material")
            self.facts["primitives"].append({"pointer": where, "material": material, "texcoords": sets,
                                             "tangents": "TANGENT" in attributes, "normals": "NORMAL" in attributes,
                                             "attribute_formats": {n: f for n, f in formats.items() if f},
                                             "extent": accessors.position_extent(self.document, attributes.get("POSITION")),
                                             "tangent_signs": accessors.tangent_signs(self.document, attributes.get("TANGENT"),
                                                                                      self.tangent_cache)})
            if material is not None and self.document.item("materials", material) is None:
                self.asset.observe("dangling_reference", self.location(where, "material"), attribute="material",
                                   target=material)
            elif material is not None:  # the data of the primitives the file's materials shade
                self.facts["accessor_problems"] += accessors.primitive_problems(self.document, where, primitive, self.data_cache)
                self.facts["primitives"][-1]["geometry"] = geometry.primitive_geometry(self.document, primitive, self.data_cache)

    def accessor_format(self, index) -> tuple | None:
        """``(type, componentType, normalized)`` of accessor ``index``, or ``None`` (a dangling index is judged elsewhere)."""
        accessor = self.document.item("accessors", index)
        if accessor is None:
            return None
        kind, component = accessor.get("type"), accessor.get("componentType")
        if not isinstance(kind, str) or not isinstance(component, int) or isinstance(component, bool):
            return None  # a malformed accessor: not a texture-coordinate format to judge
        return kind, component, accessor.get("normalized") is True

    # -- materials ---------------------------------------------------------------------------
    def read_material(self, index: int, raw: dict) -> Material:
        pointer = f"/materials/{index}"
        name = raw.get("name") if isinstance(raw.get("name"), str) and raw.get("name") else f"material_{index}"
        material = Material(name=name, model=MODEL, location=self.location(pointer), material_name=name,
                            material_location=self.location(pointer))
        extensions = raw.get("extensions") if isinstance(raw.get("extensions"), dict) else {}
        extra = {"index": index, "material_extensions": sorted(extensions), "toolkit_written": self.toolkit_written}
        for key in ("doubleSided", "extras"):
            if key in raw:
                extra[key] = raw[key]
        for key, kind, what in (("name", str, "a string"), ("doubleSided", bool, "a boolean")):
            if key in raw and not isinstance(raw[key], kind):
                self.invalid(pointer, f"{key} must be {what}, not {json_text(raw[key])}", key)
        if raw.get("alphaMode") == "MASK":  # OpenPBR keeps the cut-out, not the mode: gltf_state carries it
            extra["alphaMode"] = "MASK"
            cutoff = raw.get("alphaCutoff", 0.5)
            extra["alphaCutoff"] = float(cutoff) if json_numbers([cutoff], 1) else 0.5
        volume = extensions.get(slots.VOLUME)
        if isinstance(volume, dict) and json_numbers([volume.get("thicknessFactor")], 1) and \
                json_float(volume["thicknessFactor"]) > 0:  # OpenPBR has no thickness: gltf_state carries it
            extra["thickness"] = json_float(volume["thicknessFactor"])
        kept = {n: v for n, v in extensions.items()
                if n not in slots.INTERPRETED_MATERIAL_EXTENSIONS and n not in drafts.MATERIAL_DRAFTS}
        if kept:
            extra["extensions"] = kept
        material.extra["gltf"] = extra
        for recorded in sorted(kept):
            if recorded == slots.DIFFUSE_TRANSMISSION and thin_diffuse_transmission(extensions):
                continue  # read as OpenPBR's thin-walled subsurface by the translation
            if recorded == slots.UNLIT:
                continue  # read as emission of the base colour over a black base by the translation
            if recorded == slots.SPECULAR_GLOSSINESS and isinstance(kept[recorded], dict):
                # read by the spec-gloss -> metal-rough solve (translate/spec_gloss.py); archived: reported
                fallback = isinstance(raw.get(slots.PBR), dict) and bool(raw[slots.PBR]) and \
                    recorded not in self.facts["extensions_required"]
                self.asset.observe("gltf_archived", self.location(f"{pointer}/extensions/{recorded}"),
                                   extension=recorded, material=name, fallback=fallback)
                continue
            if recorded not in slots.NEUTRAL_EXTENSIONS:  # e.g. slots.VARIANTS lives elsewhere
                self.asset.observe("gltf_not_converted", self.location(f"{pointer}/extensions/{recorded}"),
                                   extension=recorded, material=name)
        self.unknown_sub_extensions(extensions, pointer, name, extra)
        self.unexpected_properties(raw, extensions, pointer)
        self.index, self.reported, self.reading, self.reading_name = index, set(), extra, name
        # glTF ignores alpha in OPAQUE mode (specification 3.9.4): only MASK and BLEND read the
        # base colour texture's A channel, so only they get an alpha texture input.
        self.reads_alpha = raw.get("alphaMode") in ("MASK", "BLEND")
        for slot in slots.SLOTS:
            container, container_pointer = self.container(raw, extensions, slot, pointer)
            if container is not None:
                self.read_slot(material, slot, container, container_pointer)
        self.read_drafts(material, extensions, pointer)
        iridescence = extensions.get(slots.IRIDESCENCE)
        low_name = slots.IRIDESCENCE_THICKNESS_MINIMUM[0]
        if isinstance(iridescence, dict) and json_numbers([iridescence.get(low_name)], 1) and \
                json_float(iridescence[low_name]) < 0:  # (no gltf_pbr parameter holds it: checked here)
            self.invalid(f"{pointer}/extensions/{slots.IRIDESCENCE}",
                         f"{low_name} must be at least 0, not {json_text(iridescence[low_name])}", low_name)
        if isinstance(extensions.get(slots.SPECULAR_GLOSSINESS), dict):
            self.read_specular_glossiness(material, extensions[slots.SPECULAR_GLOSSINESS],
                                          f"{pointer}/extensions/{slots.SPECULAR_GLOSSINESS}")
        versioning.settle(material)
        if material.version == VERSION and material.version_basis.startswith("default"):
            material.version_basis = "glTF 2.0 material"
        return material

    def container(self, raw: dict, extensions: dict, slot: slots.Slot, pointer: str) -> tuple[dict | None, str]:
        if slot.container == slots.CORE:
            return raw, pointer
        if slot.container == slots.PBR:
            found, where = raw.get(slots.PBR), f"{pointer}/{slots.PBR}"
        else:
            found, where = extensions.get(slot.container), f"{pointer}/extensions/{slot.container}"
        present = slots.PBR in raw if slot.container == slots.PBR else slot.container in extensions
        if present and not isinstance(found, dict):  # (null too: the Khronos glTF-Validator's TYPE_MISMATCH)
            if where not in self.reported:
                self.reported.add(where)
                self.invalid(where, f"{where.rsplit('/', 1)[-1]} is not an object")
            return None, where
        return found, where

    def read_slot(self, material: Material, slot: slots.Slot, container: dict, pointer: str) -> None:
        parameter = self.table[slot.parameter]
        factor, factor_error = self.factor(slot, container)
        texture_info = container.get(slot.texture) if slot.texture else None
        if slot.parameter == "alpha" and not self.reads_alpha:
            texture_info = None
        if texture_info is not None:
            if factor_error:
                if (pointer, slot.factor) not in self.reported:  # baseColorFactor feeds two parameters
                    self.reported.add((pointer, slot.factor))
                    self.invalid(pointer, factor_error, slot.factor)
                factor = None
            value = self.texture(slot, texture_info, f"{pointer}/{slot.texture}", factor, container)
            entry = Input(slot.parameter, parameter.type, value, self.location(pointer, slot.texture))
        elif slot.factor is not None and slot.factor in container:
            entry = Input(slot.parameter, parameter.type, None, self.location(pointer, slot.factor))
            if slot.parameter == "alpha_mode" and isinstance(container[slot.factor], str) and factor_error:
                entry.raw, entry.allowed = json_text(container[slot.factor]), slots.ALPHA_MODES  # OPBR303
            elif factor_error:
                entry.raw, entry.error = json_text(container[slot.factor]), factor_error
            else:
                entry.value = Constant(factor)
        elif slot.factor is not None and slot.container not in (slots.CORE, slots.PBR) and \
                not _same(slot.default, parameter.default):
            # an extension present without this factor means glTF's default, which gltf_pbr's node
            # definition does not share (iridescenceThicknessMaximum: 400 nm in glTF, 100 in MaterialX)
            entry = Input(slot.parameter, parameter.type, Constant(slot.default), self.location(pointer))
        else:
            return
        if parameter.unit == "scene_length":
            entry.unit, entry.unittype = SCENE_LENGTH_UNIT, "distance"
        if parameter.role == "color" and isinstance(entry.value, Constant):
            entry.colorspace = "lin_rec709"  # glTF factors are linear Rec.709 (specification 3.9.2)
        material.inputs[slot.parameter] = entry
        if slot.parameter == "anisotropy_strength" and isinstance(entry.value, Texture):
            strength = entry.value
            material.extra["gltf"]["anisotropy_direction"] = Texture(
                file=strength.file, image_type="color3", channels=(0, 1), colorspace=slots.DATA, uv=strength.uv,
                texcoord=strength.texcoord, wrap=strength.wrap, node=strength.node, node_category=strength.node_category,
                location=strength.location, packaged=strength.packaged)

    def read_specular_glossiness(self, material: Material, container: dict, pointer: str) -> None:
        """KHR_materials_pbrSpecularGlossiness's factors and textures, checked and read as the gltf_pbr slots
        of the same kind are, into the glTF state by their specular-workflow names
        (:data:`~.slots.SPECULAR_GLOSSINESS_SLOTS`); the material's own inputs stay the metal-rough fallback's."""
        scratch = Material(name=material.name, model=MODEL, location=material.location)
        found = {}
        for name, slot in slots.SPECULAR_GLOSSINESS_SLOTS:
            self.read_slot(scratch, slot, container, pointer)
            entry = scratch.inputs.pop(slot.parameter, None)
            if entry is not None:
                entry.name = name
                found[name] = entry
        material.extra["gltf"]["spec_gloss"] = found

    def factor(self, slot: slots.Slot, container: dict):
        """(value, error): the authored factor converted to gltf_pbr's value, or its default."""
        if slot.factor is None or slot.factor not in container:
            return slot.default, None
        raw = container[slot.factor]
        if slot.parameter == "alpha_mode":
            if raw in slots.ALPHA_MODES:
                return slots.ALPHA_MODES.index(raw), None
            return None, f"alphaMode must be one of {', '.join(slots.ALPHA_MODES)}, not {json_text(raw)}"
        if slot.factor_components is not None:  # baseColorFactor: RGB for base_color, A for alpha
            if not json_numbers(raw, 4):
                return None, f"{slot.factor} must be an array of 4 numbers, not {json_text(raw)}"
            part = tuple(json_float(v) for v in raw[slot.factor_components])
            return (part if len(part) > 1 else part[0]), None
        width = len(slot.default) if isinstance(slot.default, tuple) else 1
        if width > 1:
            if not json_numbers(raw, width):
                return None, f"{slot.factor} must be an array of {width} numbers, not {json_text(raw)}"
            return tuple(json_float(v) for v in raw), None
        if not json_numbers([raw], 1):
            return None, f"{slot.factor} must be a number, not {json_text(raw)}"
        return json_float(raw), None

def _extension_uses(document, found: list) -> None:
    """Every (JSON pointer, extension name) under an ``extensions`` object anywhere in the document,
    in document order (a pre-order walk, iterative: the document may be deep)."""
    stack = [(document, "", False)]
    while stack:
        value, pointer, is_extensions = stack.pop()
        if is_extensions:
            found.extend((f"{pointer}/{_escape(name)}", name) for name in value)
        children = value.items() if isinstance(value, dict) else enumerate(value)
        nested = [(child, f"{pointer}/{_escape(key)}", key == "extensions" and isinstance(child, dict) and isinstance(value, dict))
                  for key, child in children if isinstance(child, (dict, list))]
        stack.extend(reversed(nested))


_MATERIAL_EXTENSION = re.compile(r"/materials/\d+/extensions/[^/]+")
_VARIANTS_PLACES = re.compile(rf"(/meshes/\d+/primitives/\d+)?/extensions/{slots.VARIANTS}")
_TEXTURE_SOURCE = re.compile(r"/textures/\d+/extensions/[^/]+")
_TEXTURE_TRANSFORM = re.compile(r"/materials/\d+(/[^/]+)*/[^/]*[tT]exture/extensions/KHR_texture_transform")


def _extension_in_place(pointer: str, name: str) -> bool:
    """Whether a KHR_materials_* extension sits on a material, KHR_texture_transform on a textureInfo, an image format's
    on a texture (the Khronos glTF-Validator's UNEXPECTED_EXTENSION_OBJECT; other extensions are not judged here)."""
    if name == slots.TEXTURE_TRANSFORM:
        return _TEXTURE_TRANSFORM.fullmatch(pointer) is not None
    if name == slots.VARIANTS:  # (despite its name no material extension: the validator's UNEXPECTED_EXTENSION_OBJECT)
        return _VARIANTS_PLACES.fullmatch(pointer) is not None
    if name.startswith("KHR_materials_"):
        return _MATERIAL_EXTENSION.fullmatch(pointer) is not None
    return name not in slots.EXTENSION_MIME_TYPES.values() or _TEXTURE_SOURCE.fullmatch(pointer) is not None


def _set_of(name: str, semantic: str) -> int | None:
    """n of an indexed attribute ``<semantic>n`` as glTF spells it (no leading zero), else ``None``."""
    number = name[len(semantic):] if name.startswith(semantic) and len(name) < 40 else ""
    return int(number) if number.isascii() and number.isdigit() and number == str(int(number)) else None


def _escape(token: str) -> str:
    return str(token).replace("~", "~0").replace("/", "~1")


def _names(value) -> list[str]:
    return [v for v in value if isinstance(v, str)] if isinstance(value, list) else []


def _same(a, b) -> bool:
    return a == b or (isinstance(a, (tuple, list)) and isinstance(b, (tuple, list)) and tuple(a) == tuple(b))
