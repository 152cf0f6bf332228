"""The parts of reading a glTF material that concern its extensions beyond the gltf_pbr node's: the
draft extensions (:mod:`.drafts`) into ``extra["gltf"]["drafts"]``, extensions nested in an
interpreted one that the toolkit does not read (reported), and the KHR_materials_variants names
selecting each material. A mixin of the glTF reader (:mod:`.reader`), which provides ``asset``,
``document``, ``location``, ``invalid``, ``factor`` and ``texture``.
"""

from __future__ import annotations

from ...model import Constant, Input, Material
from . import drafts, slots
from .textures import json_float, json_numbers, json_text


def thin_diffuse_transmission(extensions: dict) -> bool:
    """KHR_materials_diffuse_transmission with factors only on a material without a volume: what the
    glTF -> OpenPBR translation reads as a thin-walled subsurface."""
    found, volume = extensions.get(slots.DIFFUSE_TRANSMISSION), extensions.get(slots.VOLUME)
    thick = isinstance(volume, dict) and json_numbers([volume.get("thicknessFactor")], 1) and \
        json_float(volume["thicknessFactor"]) > 0
    return isinstance(found, dict) and not thick and not any(key.endswith("Texture") for key in found)


class ExtensionReading:
    def unknown_sub_extensions(self, extensions: dict, pointer: str, name: str, extra: dict) -> None:
        """Extensions nested in an interpreted extension object (KHR_materials_clearcoat_ior inside
        KHR_materials_clearcoat, say) that the toolkit does not read are reported, never ignored;
        ``extra["gltf"]["nested_extensions"]`` lists every nested one as ``[parent, name, read]``."""
        nested = []
        for parent in slots.INTERPRETED_MATERIAL_EXTENSIONS + drafts.MATERIAL_DRAFTS:
            inner = extensions.get(parent)
            subs = inner.get("extensions") if isinstance(inner, dict) else None
            for sub in sorted(subs) if isinstance(subs, dict) else ():
                read = (parent, sub) in drafts.SUB_DRAFTS
                nested.append([parent, sub, read])
                if not read:
                    self.asset.observe("gltf_not_converted", self.location(f"{pointer}/extensions/{parent}/extensions/{sub}"),
                                       extension=sub, material=name)
        if nested:
            extra["nested_extensions"] = nested

    def unexpected_properties(self, raw: dict, extensions: dict, pointer: str) -> None:
        """Properties the schemas of the material's objects do not define (:func:`.slots.object_properties`):
        in the material, its pbrMetallicRoughness, each known material extension, their textureInfos and
        those's KHR_texture_transform. Observed as ``gltf_unexpected_property``, as the Khronos
        glTF-Validator's UNEXPECTED_PROPERTY."""
        known = slots.object_properties()
        objects = [(slots.CORE, raw, pointer), (slots.PBR, raw.get(slots.PBR), f"{pointer}/{slots.PBR}")]
        objects += [(name, extensions.get(name), f"{pointer}/extensions/{name}") for name in known
                    if name not in (slots.CORE, slots.PBR)]
        for container, found, where in objects:
            if not isinstance(found, dict):
                continue
            names, textures = known[container]
            self.unexpected(found, names, where, container or "material")
            for name, kind in textures.items():
                info = found.get(name)
                if info is None and name in found:  # (the schema's type is object: null is no "no texture")
                    self.invalid(f"{where}/{name}", f"{name} is null, not a {kind} object: viewers that test for the "
                                 "property's presence read a texture that is not there (omit it when there is none)")
                if not isinstance(info, dict):
                    continue
                self.unexpected(info, slots.TEXTURE_INFO_PROPERTIES[kind] + slots.COMMON_PROPERTIES, f"{where}/{name}", kind)
                inner = info.get("extensions")
                transform = inner.get(slots.TEXTURE_TRANSFORM) if isinstance(inner, dict) else None
                if isinstance(transform, dict):
                    self.unexpected(transform, slots.TEXTURE_TRANSFORM_PROPERTIES + slots.COMMON_PROPERTIES,
                                    f"{where}/{name}/extensions/{slots.TEXTURE_TRANSFORM}", slots.TEXTURE_TRANSFORM)

    def unexpected(self, found: dict, names, where: str, what: str) -> None:
        for key in found:
            if key not in names:
                self.asset.observe("gltf_unexpected_property", self.location(where, key), property=key, object=what,
                                   expected=sorted(names))

    def read_drafts(self, material: Material, extensions: dict, pointer: str) -> None:
        """The draft extensions (:mod:`.drafts`) into ``extra["gltf"]["drafts"]``: per extension, its
        properties as :class:`Input` s keyed by the draft record's names (OpenPBR's where one to one)."""
        found: dict = {}
        containers = [(name, extensions.get(name), f"{pointer}/extensions/{name}") for name in drafts.MATERIAL_DRAFTS]
        for parent, sub in drafts.SUB_DRAFTS:
            inner = extensions.get(parent)
            subs = inner.get("extensions") if isinstance(inner, dict) else None
            containers.append((sub, subs.get(sub) if isinstance(subs, dict) else None,
                               f"{pointer}/extensions/{parent}/extensions/{sub}"))
        for name, container, where in containers:
            if container is None:
                continue
            if not isinstance(container, dict):
                self.invalid(where, f"{name} is not an object")
                continue
            if name == drafts.ANISOTROPY_OPENPBR and container.get("openPbrAnisotropyEnabled") is not True:
                continue  # present but off: glTF's own anisotropy convention
            record: dict = {}
            for slot in drafts.SLOTS.get(name, ()):
                entry = self.draft_property(slot, container, where)
                if entry is not None:
                    record[slot.parameter] = entry
            found[name] = record
        if found:
            material.extra["gltf"]["drafts"] = found

    def draft_property(self, slot: slots.Slot, container: dict, pointer: str) -> Input | None:
        kind = "vector3" if slot.texture_kind == "normalTextureInfo" else \
            ("color3" if isinstance(slot.default, tuple) else "float")
        factor, error = self.factor(slot, container)
        if slot.texture and slot.texture in container:
            value = self.texture(slot, container[slot.texture], f"{pointer}/{slot.texture}", None if error else factor,
                                 container)
            return Input(slot.parameter, kind, value, self.location(pointer, slot.texture))
        if slot.factor is None or slot.factor not in container:
            return None
        if error:
            self.invalid(pointer, error, slot.factor)
            return None
        entry = Input(slot.parameter, kind, Constant(factor), self.location(pointer, slot.factor))
        if kind == "color3":
            entry.colorspace = "lin_rec709"
        return entry

    def read_variants(self) -> None:
        """KHR_materials_variants: the names of the variants that select each material (the root's
        ``variants`` list, indexed by each primitive's ``mappings``), as ``extra["gltf"]["variants"]``,
        which travels in the side channel (gltf_state). A mapping's material or variant index that names
        nothing is a dangling reference, one that lists no variant an invalid property; the variant names
        and, per primitive, the variant indices of each mapping are facts for the rules
        (``facts["variants"]``: ``names``, ``mappings``)."""
        root = self.document.json.get("extensions")
        declared = root.get(slots.VARIANTS) if isinstance(root, dict) else None
        listed = declared.get("variants") if isinstance(declared, dict) else None
        if isinstance(declared, dict) and (not isinstance(listed, list) or not listed):
            # the root object's schema: variants required, at least one (the validator's UNDEFINED_PROPERTY, EMPTY_ENTITY)
            self.invalid(f"/extensions/{slots.VARIANTS}", "the root's KHR_materials_variants object lists no variant "
                         "(its schema requires a variants array of at least one): no mapping can select a material",
                         "variants")
        listed = listed if isinstance(listed, list) else []
        names = [v.get("name") if isinstance(v, dict) and isinstance(v.get("name"), str) else f"variant_{i}"
                 for i, v in enumerate(listed)]
        for i, variant in enumerate(listed):  # (the schema: objects with a required string name)
            where = f"/extensions/{slots.VARIANTS}/variants/{i}"
            if not isinstance(variant, dict):
                self.invalid(where, f"variant {i} is {json_text(variant)}, not an object with a name ({{\"name\": ...}}): "
                             "viewers cannot list it, and the mappings that name it select nothing")
            elif not isinstance(variant.get("name"), str):
                self.invalid(where, f"variant {i} has no string name (the schema requires one), so viewers cannot list it",
                             "name")
        facts = {"names": [(f"/extensions/{slots.VARIANTS}/variants/{i}", v.get("name"))
                           for i, v in enumerate(listed) if isinstance(v, dict) and isinstance(v.get("name"), str)],
                 "mappings": []}
        by_index = {m.extra["gltf"]["index"]: m for m in self.asset.materials}
        for primitive_pointer, primitive in self.document.primitives():
            extensions = primitive.get("extensions")
            extension = extensions.get(slots.VARIANTS) if isinstance(extensions, dict) else None
            mappings = extension.get("mappings") if isinstance(extension, dict) else None
            pointer = f"{primitive_pointer}/extensions/{slots.VARIANTS}/mappings"
            used = []  # (mapping pointer, variant index) in order, for the rules
            if isinstance(extension, dict) and not isinstance(mappings, list):  # (required: the validator's
                self.invalid(pointer.rsplit("/", 1)[0], f"this primitive's {slots.VARIANTS} mappings are "  # TYPE_MISMATCH)
                             f"{json_text(mappings)}, not an array of mappings: no variant selects a material here",
                             "mappings")
            for number, mapping in enumerate(mappings if isinstance(mappings, list) else []):
                if not isinstance(mapping, dict):
                    continue
                where = f"{pointer}/{number}"
                target = mapping.get("material")
                if _index(target) and self.document.item("materials", target) is None:
                    self.asset.observe("dangling_reference", self.location(where, "material"),
                                       attribute="material", target=target)
                elif not _index(target):  # (required, a glTFid: the validator's INVALID_INDEX / UNDEFINED_PROPERTY)
                    self.invalid(where, f"this KHR_materials_variants mapping's material is {json_text(target)}, no "
                                 "material index: its variants select no material", "material")
                variants = mapping.get("variants") if isinstance(mapping.get("variants"), list) else []
                if mapping.get("variants") == []:  # (the schema's minItems 1: the validator's EMPTY_ENTITY)
                    self.invalid(f"{where}/variants", "this KHR_materials_variants mapping lists no variant, so no "
                                 "selection ever shows its material (the schema requires at least one variant "
                                 "index): remove the mapping, or name the variants that should select it")
                for position, variant in enumerate(variants):
                    if not _index(variant):  # (the validator's INVALID_INDEX)
                        self.invalid(f"{where}/variants/{position}", f"variant index {json_text(variant)} names no "
                                     "variant (an index is a whole number from 0): it selects nothing")
                        continue
                    if variant >= len(listed):
                        self.asset.observe("dangling_reference", self.location(f"{where}/variants/{position}"),
                                           attribute="variant", target=variant)
                        continue
                    used.append((where, variant))
                    material = by_index.get(target) if _index(target) else None
                    chosen = material.extra["gltf"].setdefault("variants", []) if material is not None else None
                    if chosen is not None and names[variant] not in chosen:
                        chosen.append(names[variant])
            if used:
                facts["mappings"].append({"pointer": pointer, "variants": used})
        if facts["names"] or facts["mappings"]:
            self.facts["variants"] = facts


def _index(value) -> bool:
    return isinstance(value, int) and not isinstance(value, bool) and value >= 0
