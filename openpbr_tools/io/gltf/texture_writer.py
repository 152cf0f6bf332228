"""The texture half of writing a glTF material: one textureInfo per glTF texture property, its
image (passed through or baked), sampler, UV set and KHR_texture_transform, and the factors that
multiply it.

glTF reads fixed channels of one image per property (:mod:`.slots`). An image passes through
unchanged when every parameter sharing the property reads its own channel from it in the encoding
glTF expects (sRGB for colour, linear for data) and nothing unintended sits in the channels no
parameter feeds (a metallicRoughness image whose G would scale a constant roughness, an alpha
channel under a blended base colour). Otherwise a PNG is baked (:mod:`.gltf_bake`) with each
channel from its source, re-encoded where needed, and ``1.0`` in the channels nothing feeds, so the
factor alone applies there.
"""

from __future__ import annotations

import os
import re

from ... import colorspaces
from ...model import Texture, normal_decode, normal_encoding
from ...rules.translation import APPROXIMATED, CONVERTED, NOT_CARRIED
from ..images import ImageUndecodable
from ..usd.types import WRAP_TO_ADDRESS_MODE
from . import slots
from .bake import ChannelSource, pack
from .uv import to_texture_transform

#: A USD UV primvar named as the USD writer names glTF UV set n (io/usd/texture_networks.py: "st1"), read back
#: as that set; "st" itself is the default set (texcoord None).
_NUMBERED_PRIMVAR = re.compile(r"st(\d{1,2})")


class TextureWriting:
    """Mixed into the material writer, which provides ``material``, ``extra``, ``images``,
    ``builder``, ``note``, ``container`` and ``clamped``."""

    def texture_group(self, prop: str, members: list[slots.Slot]) -> None:
        """One textureInfo ``prop`` fed by the textures of ``members`` (the parameters sharing it)."""
        inputs = self.material.inputs
        textures = {s.parameter: inputs[s.parameter].value for s in members}
        sources = {}
        for slot in members:
            located = self.images.locate(textures[slot.parameter], f"{self.material.name}.{slot.parameter}",
                                         (self.where(slot.parameter), self.output))
            if located is not None:
                sources[slot.parameter] = located
        members = [s for s in members if s.parameter in sources]
        if not members:
            return
        first = textures[members[0].parameter]
        for slot in members[1:]:
            other = textures[slot.parameter]
            if (other.uv, other.texcoord, other.wrap) != (first.uv, first.texcoord, first.wrap):
                self.note(APPROXIMATED, f"{slot.parameter} shares {prop} with {members[0].parameter} but has another UV "
                                        f"transform, UV set or wrap; {members[0].parameter}'s is used", slot.parameter)
        try:
            image_index = self.image_for(prop, members, textures, sources)
        except ImageUndecodable as error:  # an EXR cut short, NaN texels: left out (a defect still raises)
            for slot in members:
                self.note(NOT_CARRIED, f"{slot.parameter}: {error}; texture not written", slot.parameter)
            return
        info = {"index": self.builder.add_texture(image_index, self.sampler(first, members[0].parameter))}
        self.uv(info, first, members[0].parameter)
        slot = members[0]
        if slot.texture_kind == "normalTextureInfo":
            if first.normal_map is None:
                self.note(CONVERTED, f"{slot.parameter}: texture without a normal-map decode written as a glTF normal map",
                          slot.parameter)
            else:
                remap_scale, _, strength = normal_encoding(first)
                if strength != 1.0:
                    info["scale"] = strength
                if remap_scale is not None:  # (bake_plan remapped the texels: glTF's decode is 2 t - 1)
                    decoded_scale, decoded_bias = normal_decode(first)
                    self.note(CONVERTED, f"{slot.parameter}: the normal map's decode (scale {_listed(decoded_scale)}, bias "
                                         f"{_listed(decoded_bias)}: a flipped green channel, say) baked into its texels "
                                         "for glTF's 2 t - 1", slot.parameter)
        elif slot.texture_kind == "occlusionTextureInfo":
            strength = 1.0 if first.scale is None else float(first.scale)
            expected_bias = 1.0 - strength
            if abs((first.bias or 0.0) - expected_bias) > 1e-9 and not (first.bias is None and strength == 1.0):
                self.note(APPROXIMATED, f"occlusion: scale {strength:g} / bias {first.bias} is not glTF's 1 + strength (r - 1); "
                                        f"strength {strength:g} used", slot.parameter)
            if strength != 1.0:
                info["strength"] = strength
        self.container(slot)[prop] = info
        for member in members:
            self.texture_factor(member, textures[member.parameter])

    def texture_factor(self, slot: slots.Slot, texture: Texture) -> None:
        if slot.parameter == "iridescence_thickness":
            low = 0.0 if texture.bias is None else float(texture.bias)
            span = 1.0 if texture.scale is None else float(texture.scale)
            self.container(slot)["iridescenceThicknessMinimum"] = low
            self.container(slot)["iridescenceThicknessMaximum"] = low + span
            return
        if slot.factor is None:
            return
        affine = _affine(slot, texture)
        if affine is not None:  # baked into the texels (bake_plan): the factor's default, 1
            if slot.colour:
                self.note(CONVERTED, f"{slot.parameter}: texture scale {_listed(affine[0])} and bias {_listed(affine[1])} "
                                     "(which no glTF factor holds) baked into its texels, on the linear colour",
                          slot.parameter)
            return
        if texture.bias not in (None, 0.0, (0.0, 0.0, 0.0)) and slot.texture_kind == "textureInfo":
            self.note(NOT_CARRIED, f"{slot.parameter}: texture bias {texture.bias} has no glTF equivalent; dropped", slot.parameter)
        scale = texture.scale
        if slot.parameter in ("base_color", "alpha"):
            pbr = self.containers[slots.PBR]
            factor = list(pbr.get("baseColorFactor", [1.0, 1.0, 1.0, 1.0]))
            if slot.parameter == "base_color" and scale is not None:
                factor[:3] = self.clamped(slot, list(scale) if isinstance(scale, tuple) else [float(scale)] * 3)
            elif scale is not None:
                factor[3] = self.clamped(slot, float(scale))
            if factor != [1.0, 1.0, 1.0, 1.0] or "baseColorFactor" in pbr:
                pbr["baseColorFactor"] = factor
            return
        if scale is None:
            # glTF multiplies the texture by the factor's default: say 1 where that default is not 1
            if slot.default not in (1.0, (1.0, 1.0, 1.0)):
                self.container(slot)[slot.factor] = [1.0, 1.0, 1.0] if isinstance(slot.default, tuple) else 1.0
            return
        if isinstance(slot.default, tuple):
            scale = list(scale) if isinstance(scale, tuple) else [float(scale)] * len(slot.default)
        elif isinstance(scale, tuple):
            self.note(APPROXIMATED, f"{slot.parameter}: a {len(scale)}-component texture scale on a float; its first component "
                                    "is used", slot.parameter)
            scale = float(scale[0])
        self.container(slot)[slot.factor] = self.clamped(slot, scale if isinstance(scale, list) else float(scale))

    def sampler(self, texture: Texture, parameter: str) -> int | None:
        filters = {}
        if texture.filter == "closest":  # MaterialX's closest: glTF's NEAREST both ways (9728)
            filters = {"magFilter": 9728, "minFilter": 9728}
        elif texture.filter == "linear" or texture.filter == "cubic":
            filters = {"magFilter": 9729}
            if texture.filter == "cubic":
                self.note(APPROXIMATED, "filter type 'cubic' has no glTF equivalent; LINEAR used", parameter)
        if texture.minification is not None:  # a glTF source's minFilter, as it was
            filters["minFilter"] = texture.minification
        if texture.wrap is None and not filters:
            return None
        table = slots.address_to_wrap()
        modes = []
        for mode in texture.wrap or ("periodic", "periodic"):
            # a UsdUVTexture's wrap token in MaterialX's words (useMetadata: the image's default, periodic)
            mode = "periodic" if mode == "useMetadata" else WRAP_TO_ADDRESS_MODE.get(mode, mode)
            if mode not in table:
                self.note(APPROXIMATED, f"address mode {mode!r} is unknown; REPEAT used", parameter)
            elif mode == "constant":
                self.note(APPROXIMATED, "address mode 'constant' (border colour) has no glTF equivalent; CLAMP_TO_EDGE used",
                          parameter)
            modes.append(table.get(mode, table["periodic"]))
        return self.builder.add_sampler(modes[0], modes[1], filters)

    def uv(self, info: dict, texture: Texture, parameter: str) -> None:
        if texture.texcoord:
            numbered = _NUMBERED_PRIMVAR.fullmatch(texture.texcoord) if isinstance(texture.texcoord, str) else None
            try:
                info["texCoord"] = int(numbered.group(1) if numbered else texture.texcoord)
            except (TypeError, ValueError):
                self.note(APPROXIMATED, f"UV set {texture.texcoord!r} is not a glTF TEXCOORD index; set 0 used", parameter)
            else:
                if numbered:
                    self.note(CONVERTED, f"UV primvar {texture.texcoord!r} written as TEXCOORD_{info['texCoord']} "
                                         "(the USD writer's name for that glTF UV set)", parameter)
        if texture.uv is None or texture.uv.is_identity and tuple(texture.uv.pivot) in ((0.0, 0.0), (0.0, 1.0)):
            return
        try:
            offset, rotation, scale = to_texture_transform(texture.uv)
        except ZeroDivisionError:
            self.note(NOT_CARRIED, "a UV transform with scale 0 has no KHR_texture_transform equivalent; dropped", parameter)
            return
        transform = {}
        if offset != (0.0, 0.0):
            transform["offset"] = [_round(offset[0]), _round(offset[1])]
        if rotation != 0.0:
            transform["rotation"] = _round(rotation)
        if scale != (1.0, 1.0):
            transform["scale"] = [_round(scale[0]), _round(scale[1])]
        if transform:
            info.setdefault("extensions", {})[slots.TEXTURE_TRANSFORM] = transform

    def image_for(self, prop, members, textures, sources) -> int:
        """The image index for ``prop``: a source image unchanged when it already has glTF's shape, else a baked PNG."""
        source = sources[members[0].parameter]
        same_image = len({sources[s.parameter].key for s in members}) == 1
        fitting = all(self.fits(s, textures[s.parameter], sources[s.parameter]) for s in members)
        covered = self.covers(prop, members, source)
        if same_image and fitting and covered and source.gltf_ready(any(s.colour for s in members)):
            return self.builder.add_image(source.key, source.data, source.mime, source.name)
        plan = self.bake_plan(prop, members, textures, sources)
        label = f"{self.material.name}.{prop}"
        where = self.where(members[0].parameter)
        data = pack(plan, lambda message: self.notes.append(APPROXIMATED.note(message, where, self.output)), label)
        why = "re-encoded as PNG" if same_image and fitting and covered else "baked: channels packed as glTF reads them"
        name = f"{_safe(self.material.material_name or self.material.name)}_{prop}.png"
        index = self.builder.add_image(("baked", data), data, "image/png", name)
        read = ", ".join(sorted({os.path.basename(sources[s.parameter].name) for s in members}))
        self.note(CONVERTED, f"{prop}: {why}, from {read} into {self.builder.image_name(index)}", members[0].parameter)
        return index

    @property
    def untagged_linear(self) -> bool:
        """Whether a colour texture without a colour space holds linear texels: in a MaterialX document (no colour
        space on the image or the document: no transform), not in USD, whose renderers decode an untagged 8-bit
        image as sRGB (UsdUVTexture's sourceColorSpace auto)."""
        location = self.material.location
        return bool(location and location.file and str(location.file).lower().endswith(".mtlx"))

    def conversion(self, slot: slots.Slot, space: str | None) -> tuple[str | None, bool]:
        """(colour space to decode from, whether to encode sRGB) so texels reach glTF's encoding:
        sRGB for colour slots, linear for data; a colour texture without a colour space (nor its document) is linear
        where MaterialX reads it (:attr:`untagged_linear`). An unknown name is taken as already right (noted). A name
        of another scheme (a UsdUVTexture's ``raw``, a USD colour space) is read as its MaterialX equivalent; a colour
        texture tagged as data (``raw``, ``none``) holds linear colour, as its renderers read it."""
        space = colorspaces.materialx_name(space)
        if slot.colour and (space is None and self.untagged_linear or space is not None and colorspaces.is_data(space)):
            # MaterialX reads such texels as they are, and a UsdUVTexture's raw as they are: linear colour in the
            # renderer's working space, which glTF's colour slots hold sRGB-encoded (the red team's P-F3: a raw
            # base colour was copied as it was, and read 15.7 mean CIEDE2000 off)
            return "lin_rec709", True
        if space is None or colorspaces.is_data(space) or (slot.colour and space == slots.SRGB):
            return None, False
        if space not in colorspaces.materialx_names():
            self.note(NOT_CARRIED, f"{slot.parameter}: unknown colour space {space!r}; texels used as they are", slot.parameter)
            return None, False
        if slot.colour:
            return space, True
        return (space, False) if colorspaces.encoded(space) else (None, False)

    def fits(self, slot: slots.Slot, texture: Texture, source) -> bool:
        """Does the texture read ``slot``'s channels of its image, in the encoding glTF expects (and
        without a scale and bias that only baking carries)?"""
        if _affine(slot, texture) is not None:
            return False
        space = colorspaces.materialx_name(texture.colorspace)
        if slot.colour:
            if space not in ((slots.SRGB,) if self.untagged_linear else (None, slots.SRGB)):
                return False  # (untagged in a MaterialX document without a colour space: linear texels, re-encoded)
        elif colorspaces.encoded(space):
            return False
        if slot.texture_kind == "normalTextureInfo":
            return texture.channels in (None, (0, 1, 2)) and _normal_remap(slot, texture, 0) is None
        channels = texture.channels
        if channels is None:  # the whole image: RGB for colour slots, the first channel for single ones
            return slot.channels in ((0, 1, 2), (0,)) or (source.channels in (1, 2) and slot.channels[0] < 3)
        return tuple(channels) == slot.channels

    def covers(self, prop: str, members, source) -> bool:
        """Does the image leave nothing unintended in the channels no member feeds?"""
        present = {s.parameter for s in members}
        if prop == "metallicRoughnessTexture":
            return present == {"metallic", "roughness"}
        if prop == "baseColorTexture" and present == {"base_color"}:
            mode = self.material.inputs.get("alpha_mode")
            opaque = mode is None or mode.constant in (0, None)
            return opaque or source.channels in (1, 3)
        if prop == "baseColorTexture" and present == {"alpha"}:
            return False
        if prop == "anisotropyTexture":
            direction = self.extra.get("anisotropy_direction")
            return isinstance(direction, Texture) and direction.file == self.material.inputs["anisotropy_strength"].value.file \
                and tuple(direction.channels or ()) == (0, 1)
        return True

    def bake_plan(self, prop, members, textures, sources) -> list:
        """The channels of the image to bake for ``prop``."""
        def channel(slot: slots.Slot, index: int):
            """Channel ``index`` of what feeds ``slot`` (a single-channel read of a whole image is
            its first channel, as MaterialX reads a float image)."""
            texture, source = textures[slot.parameter], sources[slot.parameter]
            if texture.channels:
                picked = texture.channels[min(index, len(texture.channels) - 1)]
            else:
                picked = index if slot.channels in (None, (0, 1, 2)) else 0
            decode, encode = self.conversion(slot, texture.colorspace)
            affine = _affine(slot, texture)
            if slot.colour and affine is not None:  # scale and bias act on linear colour: decode, map, encode
                scale, bias = affine[0][min(index, 2)], affine[1][min(index, 2)]
                if decode is None and not encode:  # (texels already sRGB-encoded, as glTF holds them)
                    decode, encode = slots.SRGB, True
            else:
                scale, bias = affine or _normal_remap(slot, texture, index) or (1.0, 0.0)
            return ChannelSource(source.image, picked, decode=decode, encode_srgb=encode, scale=scale, bias=bias)

        by_name = {s.parameter: s for s in members}
        if prop == "baseColorTexture":
            rgb = [channel(by_name["base_color"], i) for i in range(3)] if "base_color" in by_name else [1.0, 1.0, 1.0]
            if "alpha" in by_name:
                return rgb + [channel(by_name["alpha"], 0)]
            return rgb
        if prop == "metallicRoughnessTexture":
            roughness = channel(by_name["roughness"], 0) if "roughness" in by_name else 1.0
            metallic = channel(by_name["metallic"], 0) if "metallic" in by_name else 1.0
            return [1.0, roughness, metallic]
        if prop == "anisotropyTexture":
            direction = self.extra.get("anisotropy_direction")
            strength = channel(by_name["anisotropy_strength"], 0)
            if isinstance(direction, Texture):
                located = self.images.locate(direction, f"{self.material.name}.anisotropy direction",
                                             (self.where("anisotropy_strength"), self.output))
                if located is not None:
                    return [ChannelSource(located.image, (direction.channels or (0, 1))[0]),
                            ChannelSource(located.image, (direction.channels or (0, 1))[1]), strength]
            return [slots.ANISOTROPY_DIRECTION_DEFAULT[0], slots.ANISOTROPY_DIRECTION_DEFAULT[1], strength]
        slot = members[0]
        if slot.texture_kind == "normalTextureInfo" or slot.channels == (0, 1, 2):
            return [channel(slot, i) for i in range(3)]
        if slot.channels == (3,):
            return [1.0, channel(slot, 0)]  # grey + alpha: the value in A
        return [channel(slot, 0)]  # grey: R = G = B = the value


def _affine(slot: slots.Slot, texture: Texture) -> tuple | None:
    """(scale, bias) of a texture with a bias that glTF's factor cannot hold and the baked texels do: a
    one-channel data texture's as floats (a glossiness read as roughness: 1 - g), a colour texture's per
    channel as triples (a UsdUVTexture's bias on a diffuse colour, applied to the decoded, linear texels as
    its renderers apply it); None for the others."""
    def single(value):  # (a one-channel value, or the same in every channel)
        return value[0] if isinstance(value, tuple) and len(set(value)) == 1 else value

    if slot.texture_kind != "textureInfo" or slot.parameter == "iridescence_thickness":
        return None
    if slot.colour:
        bias, scale = texture.bias, texture.scale
        if bias is None or not any(float(b) != 0.0 for b in (bias if isinstance(bias, tuple) else (bias,))):
            return None
        triple = lambda v, default: tuple(float(x) for x in (v if isinstance(v, tuple) else (v,) * 3))[:3] \
            if v is not None else (default,) * 3  # noqa: E731
        return triple(scale, 1.0), triple(bias, 0.0)
    bias, scale = single(texture.bias), single(texture.scale)
    if not isinstance(bias, (int, float)) or bias == 0.0:
        return None
    if scale is not None and not isinstance(scale, (int, float)):
        return None
    return (1.0 if scale is None else float(scale)), float(bias)


def _listed(values) -> str:
    return "(" + ", ".join(f"{v:g}" for v in values) + ")"


def _normal_remap(slot: slots.Slot, texture: Texture, index: int) -> tuple[float, float] | None:
    """(scale, bias) of channel ``index`` of a normal map whose decode is no plain normal map of one strength
    (model.normal_encoding: a flipped green channel), remapped so that glTF's 2 t - 1 gives it; else None."""
    if slot.texture_kind != "normalTextureInfo" or texture.normal_map is None:
        return None
    scale, bias, _ = normal_encoding(texture)
    return None if scale is None else (scale[min(index, 2)], bias[min(index, 2)])



def _round(value: float) -> float:
    """Fifteen significant digits: the last-bit noise of the UV transform inversion (1 / (1 / x),
    degrees to radians and back) disappears, and the value is otherwise unchanged."""
    return float(f"{value:.15g}") + 0.0



def _safe(name: str) -> str:
    return re.sub(r"[^A-Za-z0-9_.-]+", "_", name).strip("._") or "material"


