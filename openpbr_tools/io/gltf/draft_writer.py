"""The parts of a glTF material that exist for the sake of other extensions: the draft extensions a
translation asked for (``Material.extra["gltf_drafts"]``, :mod:`.drafts`) beside their ratified
fallbacks, and the exclusions KHR_materials_unlit and KHR_materials_pbrSpecularGlossiness impose when
a side channel restores them. A mixin of the material writer (:mod:`.writer`), which provides
``containers``, ``out``, ``note``, ``linear``.
"""

from __future__ import annotations

from ...model import Constant, Texture
from ...rules.translation import CONVERTED, NOT_CARRIED
from . import drafts, slots
from .writer_values import clamp, finite as _finite, json_value as _json_value


class DraftWriting:
    def honour_exclusions(self) -> None:
        """KHR_materials_unlit and KHR_materials_pbrSpecularGlossiness (restored from a side channel)
        must not be used with the other material extensions (their Exclusions sections; the Khronos
        validator warns MULTIPLE_EXTENSIONS): those the translation derived are omitted, noted."""
        for exclusive, excluded in ((slots.UNLIT, slots.EXCLUDED_WITH_UNLIT + drafts.MATERIAL_DRAFTS),
                                    (slots.SPECULAR_GLOSSINESS, slots.EXCLUDED_WITH_SPECULAR_GLOSSINESS + drafts.MATERIAL_DRAFTS)):
            if exclusive not in self.containers:
                continue
            for name in sorted(set(self.containers) & set(excluded)):
                removed = self.containers.pop(name)
                if name == slots.EMISSIVE_STRENGTH:
                    self.fold_strength(removed.get("emissiveStrength", 1.0), exclusive)
                    continue
                self.note(CONVERTED, f"{name} omitted: it must not be used with {exclusive}, which the source material "
                                     "uses (its look is that extension's)")

    def fold_strength(self, strength: float, exclusive: str) -> None:
        """KHR_materials_emissive_strength cannot stay beside ``exclusive``: its strength goes into
        emissiveFactor, exactly while the product stays within glTF's [0, 1]."""
        factor = self.out.get("emissiveFactor")
        if not factor:
            return
        product = [c * strength for c in factor]
        folded = [min(c, 1.0) for c in product]
        self.out["emissiveFactor"] = folded
        if folded != product:
            self.note(NOT_CARRIED, f"emissive strength {strength:g} cannot be written beside {exclusive} (its Exclusions); "
                                   f"emissiveFactor {product} clamped to {folded}", "emissive")
        else:
            self.note(CONVERTED, f"emissive strength {strength:g} folded into emissiveFactor ({exclusive} excludes "
                                 "KHR_materials_emissive_strength)", "emissive")

    def write_derived(self) -> None:
        """Ratified extensions a translation derived from OpenPBR parameters the gltf_pbr node has no
        input for (``Material.extra["gltf_extensions"]``: KHR_materials_diffuse_transmission from a
        thin-walled subsurface), factors only; they replace a side channel's copy."""
        record = self.material.extra.get("gltf_extensions")
        for name, properties in sorted(record.items()) if isinstance(record, dict) else ():
            container = {}
            for prop, entry in sorted(properties.items()):
                value = entry.value.value
                if not _finite(value):
                    continue
                if entry.type == "color3":
                    value = [min(max(c, 0.0), 1.0) for c in self.linear(value, entry)]
                value = _json_value(value)
                if value != [1.0, 1.0, 1.0]:  # a white colour is the extensions' default
                    container[prop] = value
            self.containers[name] = container

    def write_drafts(self) -> None:
        """The draft extensions a translation asked for (``Material.extra["gltf_drafts"]``, see
        :mod:`.drafts`) beside the ratified fallbacks already written."""
        record = self.material.extra.get("gltf_drafts")
        if not isinstance(record, dict):
            return
        for name in drafts.MATERIAL_DRAFTS:
            if name not in record:
                continue
            container = {}
            for slot in drafts.SLOTS[name]:
                entry = record[name].get(slot.parameter)
                if entry is None:
                    continue
                if isinstance(entry.value, Constant) and slot.factor is not None:
                    value = entry.value.value
                    if not _finite(value):
                        continue
                    if slot.parameter in drafts.COLOUR_KEYS:
                        value = self.linear(value, entry)
                    value = self.draft_clamped(name, slot, _json_value(value))
                    if value != _json_value(slot.default):
                        container[slot.factor] = value
                elif isinstance(entry.value, Texture) and slot.texture is not None:
                    shared = drafts.SHARED_TEXTURES.get((slot.parameter, name))
                    ratified = self.containers.get(shared[0], {}) if shared else {}
                    if shared and shared[1] in ratified:
                        container[slot.texture] = dict(ratified[shared[1]])
                        factor = {"clearcoatTexture": "clearcoatFactor"}.get(shared[1])
                        if factor and factor in ratified:
                            container[slot.factor] = ratified[factor]
                    else:
                        self.note(NOT_CARRIED, f"{slot.parameter} is textured; {name} (draft) gets its default for it "
                                               "(only textures a ratified fallback shares are written)", slot.parameter)
            self.containers[name] = container
        if drafts.SPECULAR_OPENPBR in record:
            # the factors were written with OpenPBR's meaning (even at their defaults, which a coat or a
            # metal reads differently in glTF's): the sub-extension says so
            specular = self.containers.setdefault(slots.SPECULAR, {})
            specular.setdefault("extensions", {})[drafts.SPECULAR_OPENPBR] = {}

    def draft_clamped(self, name: str, slot: slots.Slot, value):
        low, high = drafts.RANGES.get(slot.parameter, (None, None))
        count = len(value) if isinstance(value, list) else 1
        fixed = clamp(value, (low,) * count, (high,) * count)
        if fixed != value:
            self.note(NOT_CARRIED, f"{name} {slot.factor} {value} is outside the draft's range; clamped to {fixed}",
                      slot.parameter)
        return fixed

