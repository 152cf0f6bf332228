"""Write ``gltf_pbr`` :class:`~openpbr_tools.model.Material` objects as glTF 2.0 (``.gltf`` or ``.glb``).

Each material becomes a glTF material: constants become factors (colours converted to linear
Rec.709 from the colour space they were authored in; an emissive colour above 1 is normalised into
``KHR_materials_emissive_strength``), textures become textureInfos with ``KHR_texture_transform``
for UV transforms (:mod:`.gltf_uv`), ``texCoord`` for UV sets and a sampler for wrap modes. Every
``KHR_*`` extension written is declared in ``extensionsUsed``. ``Material.extra["gltf"]`` (from the
glTF reader or a translator) adds ``doubleSided``, ``extras`` and extensions the node does not carry,
when they reference no texture.

glTF reads fixed channels of one image per texture property: images already in that shape pass
through unchanged, others are baked into a new PNG (:mod:`.gltf_texture_writer`, :mod:`.gltf_bake`).

Images: a ``.glb`` carries them in its binary chunk; a ``.gltf`` references files copied beside it
(keeping their path relative to the source asset's folder), or data URIs with ``embed=True``.
Source images are only ever read from the source asset's folder (``source``: the :class:`Asset`
or file the materials came from; else the folder of the file a texture was read from; else the
output's folder) or a folder listed in ``allow_outside``; anything else raises
:class:`GltfWriteError`. Images inside a source glTF (``#/images/N``) are extracted from it.

``mesh="sphere"`` adds a UV sphere (:mod:`.gltf_mesh`) per material, in a row along +X, so the file
shows something in any viewer. Output is deterministic (no timestamps, fixed key order, Python's
shortest round-trip float text) and written atomically. Returns notes on anything not carried exactly.
"""

from __future__ import annotations

import dataclasses
import os

from ... import colorspaces, tables
from ...atomic import write_bytes
from ...diagnostics import Diagnostic
from ...model import Asset, Connection, Constant, Location, Material, Texture
from ...rules.translation import APPROXIMATED, CONVERTED, NOT_CARRIED
from . import slots
from .document_writer import DocumentBuilder
from .draft_writer import DraftWriting
from .writer_values import clamp, finite as _finite, json_finite, json_value as _json_value
from .images import GltfWriteError, ImageResolver
from .texture_writer import TextureWriting


def write_gltf(materials: list[Material], path, *, mesh: str | None = None, embed: bool | None = None,
               allow_outside=None, source: Asset | str | None = None) -> list[Diagnostic]:
    """Write ``materials`` (``gltf_pbr``) to ``path`` (``.gltf`` or ``.glb``); returns the notes
    (OPBR11xx diagnostics at each material's source location, with the glTF material as ``output``).

    ``embed`` defaults to ``True`` for ``.glb`` (images in the binary chunk) and ``False`` for
    ``.gltf`` (image files beside the output); ``embed=True`` with ``.gltf`` writes data URIs.
    ``allow_outside`` lists folders outside the source asset's folder images may be read from.
    """
    try:
        import PIL  # noqa: F401  (baking and image inspection)
        import pygltflib  # noqa: F401  (glTF enums)
    except ImportError as error:
        raise GltfWriteError(f"writing glTF needs {error.name}: pip install 'openpbr-tools[gltf,images]'") from None
    path = os.fspath(path)
    suffix = os.path.splitext(path)[1].lower()
    if suffix not in (".gltf", ".glb"):
        raise GltfWriteError(f"cannot write {suffix or 'a file without suffix'} as glTF: use .gltf or .glb")
    if mesh not in (None, "sphere"):
        raise GltfWriteError(f"unknown mesh {mesh!r}: use None or 'sphere'")
    glb = suffix == ".glb"
    embed = glb if embed is None else bool(embed)
    source_path = source.path if isinstance(source, Asset) else (os.fspath(source) if source else None)
    notes: list[Diagnostic] = []
    builder = DocumentBuilder(path, glb=glb, embed=embed)
    images = ImageResolver(source_path, path, tuple(allow_outside or ()), notes)
    written = []
    for material in materials:
        if material.model != "gltf_pbr":
            notes.append(NOT_CARRIED.note(f"{material.name}: a {material.model} material is not written (translate it to "
                                          "gltf_pbr first)", material.location.with_material(_display_name(material))))
            continue
        written.append(builder.add_material(_MaterialWriter(material, images, builder, notes, len(builder.materials)).write()))
    if mesh == "sphere" and written:
        builder.add_spheres(written, [_texcoords_of(builder.materials[i]) for i in written])
    files = builder.finish()
    for file_path, data in files[1:]:
        os.makedirs(os.path.dirname(file_path), exist_ok=True)
        write_bytes(file_path, data)
    write_bytes(files[0][0], files[0][1])
    return notes


def _texcoords_of(material: dict) -> set[int]:
    found = {0}

    def walk(value):
        if isinstance(value, dict):
            if "index" in value and isinstance(value.get("texCoord"), int):
                found.add(value["texCoord"])
            transform = (value.get("extensions") or {}).get(slots.TEXTURE_TRANSFORM) if isinstance(value.get("extensions"), dict) else None
            if isinstance(transform, dict) and isinstance(transform.get("texCoord"), int):
                found.add(transform["texCoord"])
            for child in value.values():
                walk(child)

    walk(material)
    return found


# -- one material ------------------------------------------------------------------------------

#: How far past a factor's range a value may lie before its clamp is a loss to report (round trips through a
#: document colour space leave ~1e-16; 1e-6 is below what an 8- or 16-bit texel or a renderer resolves).
ROUNDING = 1e-6


class _MaterialWriter(TextureWriting, DraftWriting):
    def __init__(self, material: Material, images: ImageResolver, builder, notes: list[Diagnostic], index: int):
        self.material, self.images, self.builder, self.notes = material, images, builder, notes
        self.output = Location(builder.path, path=f"/materials/{index}")
        self.extra = material.gltf_state()
        # a glTF name another format had to make unique comes back as it was (gltf_state)
        name = self.extra.get("name") if isinstance(self.extra.get("name"), str) and self.extra.get("name") and \
            self.extra.get("renamed_to") == (material.material_name or material.name) else None
        self.out: dict = {"name": name or material.material_name or material.name}
        self.containers: dict[str, dict] = {slots.CORE: self.out, slots.PBR: {}}

    def note(self, rule, message: str, input: str | None = None) -> None:
        """A note of ``rule`` about the source of ``input`` (a parameter of this material)."""
        self.notes.append(rule.note(f"{self.material.name}: {message}", self.where(input), self.output))

    def where(self, input: str | None) -> Location:
        """The source location of ``input`` (the material's own without one), naming the material."""
        entry = self.material.inputs.get(input) if input else None
        location = entry.location if entry is not None else self.material.location.with_input(input)
        return location.with_material(_display_name(self.material))

    def container(self, slot: slots.Slot) -> dict:
        return self.containers.setdefault(slot.container, {})

    def write(self) -> dict:
        inputs = self.material.inputs
        for slot in slots.SLOTS:
            entry = inputs.get(slot.parameter)
            if entry is None or isinstance(entry.value, Texture):
                continue
            if isinstance(entry.value, Constant):
                self.constant(slot, entry)
            elif isinstance(entry.value, Connection):
                self.procedural(slot, entry)
            else:
                self.note(NOT_CARRIED, f"{slot.parameter} has no usable value ({entry.error or 'unset'}); not written",
                          slot.parameter)
        for name in sorted(set(inputs) - set(slots.SLOT_BY_PARAMETER)):
            self.note(NOT_CARRIED, f"{name} is not a glTF parameter; not written", name)
        self.pin_node_defaults()
        for prop in dict.fromkeys(s.texture for s in slots.SLOTS if s.texture):
            members = [s for s in slots.SLOTS if s.texture == prop and isinstance(getattr(inputs.get(s.parameter), "value", None), Texture)]
            if members:
                self.texture_group(prop, members)
        self.fold_emission()
        self.passthrough()
        self.write_derived()
        self.write_drafts()
        self.omit_inert()
        self.honour_exclusions()
        pbr = self.containers.pop(slots.PBR)
        extensions = {name: self.containers[name] for name in sorted(self.containers) if name != slots.CORE}
        ordered = {"name": self.out.pop("name")}
        if pbr:
            ordered[slots.PBR] = pbr
        ordered.update(self.out)
        if extensions:
            ordered.setdefault("extensions", {}).update(extensions)
        return ordered

    def procedural(self, slot: slots.Slot, entry) -> None:
        """A graph-driven input: its value at the graph's stand-in (evaluate.procedural.stand_in, linear Rec.709 as
        glTF holds colours), with a note; else not written, with a note."""
        from ...evaluate import procedural  # lazy: only for a graph-driven input

        connection = entry.value
        type_name = entry.type or ("color3" if isinstance(slot.default, tuple) else "float")
        written = procedural.stand_in(connection, type_name, self.material.colorspace)
        if written is None:
            self.note(NOT_CARRIED, f"{slot.parameter} is driven by {connection.category or connection.target!r}, "
                                   "which glTF cannot hold; not written", slot.parameter)
            return
        self.constant(slot, dataclasses.replace(entry, value=Constant(written), colorspace="lin_rec709"))
        self.note(APPROXIMATED, procedural.said(slot.parameter, connection.category, written), slot.parameter)

    # -- constants ---------------------------------------------------------------------------
    def constant(self, slot: slots.Slot, entry) -> None:
        value = entry.value.value
        if slot.parameter == "alpha_mode":
            if value in (0, 1, 2) and not isinstance(value, bool):
                self.out["alphaMode"] = slots.ALPHA_MODES[int(value)]
            else:
                self.note(NOT_CARRIED, f"alpha_mode {value!r} is not 0, 1 or 2; not written", slot.parameter)
            return
        if not _finite(value):
            self.note(NOT_CARRIED, f"{slot.parameter} = {value!r} is not a finite number; not written", slot.parameter)
            return
        if slot.parameter in ("base_color", "alpha"):
            self.base_color_factor(slot, value, entry)
            return
        if self.material.inputs[slot.parameter].type and isinstance(value, tuple) != isinstance(slot.default, tuple):
            self.note(NOT_CARRIED, f"{slot.parameter} = {value!r} does not have the parameter's type; not written",
                      slot.parameter)
            return
        if entry.type == "color3" or slot.parameter.endswith("color"):
            value = self.linear(value, entry)
        if slot.parameter == "attenuation_distance" and value == 0:  # MaterialX's gltf_pbr reads 0 where it is unset
            self.note(CONVERTED, "attenuation_distance 0 (MaterialX's gltf_pbr has no default: 0 is its unset value) "
                      "is not written: glTF's absent attenuationDistance (infinite)", slot.parameter)
            return
        if slot.parameter == "attenuation_distance" and value < 0:
            self.note(NOT_CARRIED, f"attenuation_distance {value:g} is not above 0 (glTF requires > 0; absent means infinite); "
                      "not written", slot.parameter)
            return
        if slot.factor is None:  # a texture-only slot (occlusion: glTF has no constant; 1 is no occlusion)
            if value != tables.table("gltf_pbr")[slot.parameter].default:
                self.note(NOT_CARRIED, f"{slot.parameter} {value!r}: glTF holds it only as a texture "
                          f"({slot.texture}); not written", slot.parameter)
            return
        self.container(slot)[slot.factor] = self.clamped(slot, _json_value(value))

    def pin_node_defaults(self) -> None:
        """An unset gltf_pbr input means the node definition's default; where glTF's own default for
        the factor differs (iridescenceThicknessMaximum: 400 nm in glTF, 100 in MaterialX), the node's
        is written, or a reader would take glTF's."""
        table = tables.table("gltf_pbr")
        for slot in slots.SLOTS:
            if slot.container in (slots.CORE, slots.PBR) or slot.container not in self.containers or slot.factor is None \
                    or slot.factor in self.containers[slot.container] or slot.parameter in self.material.inputs:
                continue
            default = table[slot.parameter].default
            if default is not None and default != slot.default and tuple([default]) != tuple([slot.default]):
                self.containers[slot.container][slot.factor] = _json_value(default)

    def clamped(self, slot: slots.Slot, value):
        """``value`` inside the parameter's hard range, which glTF's schema enforces (the Khronos
        validator rejects, and viewers clamp, a roughnessFactor of 1.5); noted when it moves."""
        parameter = tables.table("gltf_pbr").get(slot.parameter)
        if parameter is None or slot.parameter == "emissive":  # emissive above 1 is folded, not clamped
            return value
        count = len(value) if isinstance(value, list) else 1
        lows = parameter.hard_min if isinstance(parameter.hard_min, tuple) else (parameter.hard_min,) * count
        highs = parameter.hard_max if isinstance(parameter.hard_max, tuple) else (parameter.hard_max,) * count
        fixed = clamp(value, lows, highs)
        if parameter.type == "color3" and count == 3 and set(lows) == {0.0} and set(highs) == {1.0} and fixed != value:
            fixed = list(colorspaces.into_gamut(value))  # (a wide-gamut colour: its hue and lightness kept)
        moved = max(abs(a - b) for a, b in zip(fixed if isinstance(fixed, list) else [fixed],
                                                value if isinstance(value, list) else [value]))
        if moved > ROUNDING:  # (a colour taken through a document's colour space and back lands 1e-16 past 1)
            self.note(NOT_CARRIED, f"{slot.factor} {value} is outside glTF's range; clamped to {fixed}", slot.parameter)
        return fixed

    def linear(self, value, entry):
        """A colour constant in linear Rec.709, as glTF factors are (specification 3.9.2)."""
        # any scheme's name: a USD stage's colorSpace:name (lin_rec709_scene) is MaterialX's lin_rec709
        space = colorspaces.materialx_name(entry.colorspace or self.material.colorspace)
        if space in (None, "lin_rec709") or colorspaces.is_data(space):
            return value
        try:
            converted = colorspaces.to_lin_rec709(value, space)
        except KeyError:
            self.note(NOT_CARRIED, f"{entry.name}: unknown colour space {space!r}, written unconverted", entry.name)
            return value
        return tuple(float(c) for c in converted)

    def base_color_factor(self, slot: slots.Slot, value, entry) -> None:
        pbr = self.containers[slots.PBR]
        factor = list(pbr.get("baseColorFactor", [1.0, 1.0, 1.0, 1.0]))
        if slot.parameter == "base_color":
            factor[:3] = self.clamped(slot, _json_value(self.linear(value, entry)))
        else:
            factor[3] = self.clamped(slot, float(value))
        pbr["baseColorFactor"] = factor

    def fold_emission(self) -> None:
        """glTF's emissiveFactor is at most 1 (schema); the rest of a brighter colour becomes
        KHR_materials_emissive_strength (the product is what renders)."""
        factor = self.out.get("emissiveFactor")
        if factor and min(factor) < 0.0:  # an emission colour outside Rec.709's gamut (from acescg, P3)
            clipped = list(colorspaces.into_gamut(factor, high=None))
            self.note(NOT_CARRIED, f"emissiveFactor {factor} is outside glTF's range (negative in linear Rec.709); "
                                   f"clamped to {clipped}", "emissive")
            self.out["emissiveFactor"] = factor = clipped
        if not factor or max(factor) <= 1.0:
            return
        peak = max(factor)
        self.out["emissiveFactor"] = [c / peak for c in factor]
        strength = self.containers.setdefault(slots.EMISSIVE_STRENGTH, {})
        strength["emissiveStrength"] = strength.get("emissiveStrength", 1.0) * peak
        self.note(CONVERTED, f"emissive {factor} exceeds 1: written as emissiveFactor / {peak:g} with emissiveStrength x "
                             f"{peak:g}", "emissive")

    def omit_inert(self) -> None:
        """An extension whose weight is 0 with no texture does nothing (a clear coat of clearcoatFactor 0 with only
        its roughness written: the red team's G/F11, on every glTF output; the toolkit's own OPBR1211 on them);
        KHR_materials_emissive_strength of 0 leaves nothing of an untextured emissiveFactor (both omitted);
        KHR_materials_volume acts only through transmission (KHR_materials_transmission or
        diffuse_transmission), and KHR_materials_dispersion only through a volume (their READMEs; the
        Khronos validator warns VOLUME_NO_TRANSMISSION / DISPERSION_NO_VOLUME): inert ones are omitted."""
        for name, (factor, texture) in _WEIGHTS.items():
            found = self.containers.get(name)
            if not isinstance(found, dict):  # (absent, or a source's hostile value passed through: not judged here)
                continue
            weight = found.get(factor)
            if texture not in found and not (any(weight) if isinstance(weight, list) else weight):
                del self.containers[name]
                if any(key != factor for key in found):
                    self.note(CONVERTED, f"{name} omitted: its {factor} is 0 (no texture), so it has no effect "
                                         f"({', '.join(sorted(k for k in found if k != factor))} not written)")
        strength = self.containers.get(slots.EMISSIVE_STRENGTH)
        if isinstance(strength, dict) and strength.get("emissiveStrength", 1.0) == 0 and \
                "emissiveTexture" not in self.out:
            # (MaterialX's graphs give a non-emissive material emissive (1, 1, 1) at strength 0: a viewer without the
            # extension renders a white glow, the red team's I/F7)
            del self.containers[slots.EMISSIVE_STRENGTH]
            factor = self.out.pop("emissiveFactor", None)
            self.note(CONVERTED, f"{slots.EMISSIVE_STRENGTH} omitted: its emissiveStrength is 0, so the material emits "
                                 "nothing" + (f" (emissiveFactor {factor} not written: glTF's black)" if factor else ""),
                      "emissive")
        transmission = self.containers.get(slots.TRANSMISSION, {})
        transmits = transmission.get("transmissionFactor", 0.0) > 0 or "transmissionTexture" in transmission \
            or slots.DIFFUSE_TRANSMISSION in self.containers
        if slots.VOLUME in self.containers and not transmits:
            del self.containers[slots.VOLUME]
            self.note(CONVERTED, f"{slots.VOLUME} omitted: it has no effect on a material without transmission")
        volume = self.containers.get(slots.VOLUME, {})
        if slots.DISPERSION in self.containers and not (volume.get("thicknessFactor", 0.0) > 0 or "thicknessTexture" in volume):
            del self.containers[slots.DISPERSION]
            self.note(CONVERTED, f"{slots.DISPERSION} omitted: it has no effect without a volume (thickness > 0)")

    def passthrough(self) -> None:
        for key in ("doubleSided", "extras"):
            if key in self.extra:
                if not json_finite(self.extra[key]):
                    self.note(NOT_CARRIED, f"the source's {key} holds a number JSON cannot (NaN or infinity); not written")
                    continue
                self.out[key] = self.extra[key]
        if self.extra.get("alphaMode") == "MASK":
            # the source's cut-out came through OpenPBR as a (binary) opacity: its mode and threshold return (the
            # mapping writes a binary opacity as MASK at the default cutoff, 0.5: the source's cutoff is kept)
            self.out["alphaMode"], self.out["alphaCutoff"] = "MASK", self.extra.get("alphaCutoff", 0.5)
        for name, value in sorted((self.extra.get("extensions") or {}).items()):
            if name in slots.INTERPRETED_MATERIAL_EXTENSIONS:
                continue
            if _references_textures(value):
                self.note(NOT_CARRIED, f"{name} references textures of the source file; not written")
                continue
            if not json_finite(value):
                self.note(NOT_CARRIED, f"{name} holds a number JSON cannot (NaN or infinity); not written")
                continue
            self.containers[name] = value


#: The extensions a weight switches on, with that weight's factor and texture (their READMEs: default 0, the layer
#: absent). KHR_materials_sheen's weight is its colour (sheenColorFactor, default black).
_WEIGHTS = {slots.CLEARCOAT: ("clearcoatFactor", "clearcoatTexture"),
            slots.TRANSMISSION: ("transmissionFactor", "transmissionTexture"),
            slots.IRIDESCENCE: ("iridescenceFactor", "iridescenceTexture"),
            slots.ANISOTROPY: ("anisotropyStrength", "anisotropyTexture"),
            slots.DIFFUSE_TRANSMISSION: ("diffuseTransmissionFactor", "diffuseTransmissionTexture"),
            slots.SHEEN: ("sheenColorFactor", "sheenColorTexture")}


def _display_name(material: Material) -> str:
    return material.material_name or material.name


def _references_textures(value) -> bool:
    if isinstance(value, dict):
        return "index" in value and isinstance(value["index"], int) or any(_references_textures(v) for v in value.values())
    if isinstance(value, list):
        return any(_references_textures(v) for v in value)
    return False


__all__ = ["write_gltf", "GltfWriteError"]
