"""An independent MaterialX reference for each material of a glTF file, built straight from the glTF
JSON (no openpbr_tools code), for bench_glsl_gltf_samples.py: a ``gltf_pbr`` surface shader with
the core and KHR_materials_* parameters wired as MaterialX's glTF nodes read them (``gltf_image``,
``gltf_iridescence_thickness`` and ``gltf_anisotropy_image`` with the sampler's wrap modes and
KHR_texture_transform), or a ``surface_unlit`` emitting the base colour for KHR_materials_unlit.

Occlusion is left out (gltf_pbr's graph does not use it). What the reference cannot express (an
extension gltf_pbr has no input for, such as KHR_materials_diffuse_transmission; unlit alpha; a
second UV set) is returned as a note, never approximated.
"""

from __future__ import annotations

import json
import math
import os
import urllib.parse

import MaterialX as mx

WRAP = {10497: "periodic", 33071: "clamp", 33648: "mirror"}
HANDLED = frozenset((
    "KHR_materials_ior", "KHR_materials_specular", "KHR_materials_clearcoat", "KHR_materials_transmission",
    "KHR_materials_volume", "KHR_materials_iridescence", "KHR_materials_sheen", "KHR_materials_anisotropy",
    "KHR_materials_dispersion", "KHR_materials_emissive_strength",
))


class GltfReference:
    """The glTF file at ``gltf_path``; :meth:`write` makes one material's reference document."""

    def __init__(self, gltf_path: str):
        self.path = gltf_path
        with open(gltf_path, encoding="utf-8") as handle:
            self.gltf = json.load(handle)
        self.materials = self.gltf.get("materials", [])
        self._doc = mx.createDocument()
        self._notes: list[str] = []
        self._out_dir = ""

    def write(self, index: int, out_path: str) -> list[str]:
        """Write material ``index``'s reference to ``out_path`` (texture paths relative to its
        folder); returns notes on what the reference leaves out."""
        material = self.materials[index]
        self._doc = mx.createDocument()
        self._doc.setColorSpace("lin_rec709")
        self._notes = []
        self._out_dir = os.path.dirname(out_path)
        if "KHR_materials_unlit" in material.get("extensions", {}):
            shader = self._unlit(material)
        else:
            shader = self._gltf_pbr(material)
        self._doc.addMaterialNode("M_ref", shader)
        mx.writeToXmlFile(self._doc, out_path)
        return self._notes

    def _unlit(self, material: dict):
        shader = self._doc.addNode("surface_unlit", "SR_ref", "surfaceshader")
        pbr = material.get("pbrMetallicRoughness", {})
        factor = pbr.get("baseColorFactor", [1.0, 1.0, 1.0, 1.0])
        self._colour(shader, "emission_color", pbr.get("baseColorTexture"), factor[:3])
        if factor[3] != 1.0 or material.get("alphaMode", "OPAQUE") != "OPAQUE":
            self._notes.append("unlit alpha not shown")
        return shader

    def _gltf_pbr(self, material: dict):
        shader = self._doc.addNode("gltf_pbr", "SR_ref", "surfaceshader")
        pbr = material.get("pbrMetallicRoughness", {})
        factor = pbr.get("baseColorFactor", [1.0, 1.0, 1.0, 1.0])
        if "baseColorTexture" in pbr:
            multiply = self._doc.addNode("multiply", "base_factor", "color4")
            multiply.setConnectedNode("in1", self._image("base_img", pbr["baseColorTexture"], "color4", "srgb_texture"))
            multiply.setInputValue("in2", mx.Color4(*[float(f) for f in factor]))
            rgb = self._doc.addNode("convert", "base_rgb", "color3")
            rgb.setConnectedNode("in", multiply)
            alpha = self._doc.addNode("extract", "base_alpha", "float")
            alpha.setConnectedNode("in", multiply)
            alpha.setInputValue("index", 3)
            shader.setConnectedNode("base_color", rgb)
            shader.setConnectedNode("alpha", alpha)
        else:
            shader.setInputValue("base_color", mx.Color3(*[float(f) for f in factor[:3]]))
            shader.setInputValue("alpha", float(factor[3]))
        texture = pbr.get("metallicRoughnessTexture")
        self._float(shader, "metallic", pbr.get("metallicFactor", 1.0), texture, 2)
        self._float(shader, "roughness", pbr.get("roughnessFactor", 1.0), texture, 1)
        if "normalTexture" in material:
            shader.setConnectedNode("normal", self._normal("normal", material["normalTexture"]))
        self._colour(shader, "emissive", material.get("emissiveTexture"), material.get("emissiveFactor", [0.0] * 3))
        shader.setInputValue("alpha_mode", {"OPAQUE": 0, "MASK": 1, "BLEND": 2}[material.get("alphaMode", "OPAQUE")])
        shader.setInputValue("alpha_cutoff", float(material.get("alphaCutoff", 0.5)))
        extensions = material.get("extensions", {})
        for name in sorted(set(extensions) - HANDLED):
            self._notes.append(f"{name} not in the reference")
        if "KHR_materials_emissive_strength" in extensions:
            shader.setInputValue("emissive_strength",
                                 float(extensions["KHR_materials_emissive_strength"].get("emissiveStrength", 1.0)))
        if "KHR_materials_ior" in extensions:
            shader.setInputValue("ior", float(extensions["KHR_materials_ior"].get("ior", 1.5)))
        if "KHR_materials_dispersion" in extensions:
            shader.setInputValue("dispersion", float(extensions["KHR_materials_dispersion"].get("dispersion", 0.0)))
        e = extensions.get("KHR_materials_specular")
        if e is not None:
            self._float(shader, "specular", e.get("specularFactor", 1.0), e.get("specularTexture"), 3)
            self._colour(shader, "specular_color", e.get("specularColorTexture"), e.get("specularColorFactor", [1.0] * 3))
        e = extensions.get("KHR_materials_clearcoat")
        if e is not None:
            self._float(shader, "clearcoat", e.get("clearcoatFactor", 0.0), e.get("clearcoatTexture"), 0)
            self._float(shader, "clearcoat_roughness", e.get("clearcoatRoughnessFactor", 0.0),
                        e.get("clearcoatRoughnessTexture"), 1)
            if "clearcoatNormalTexture" in e:
                shader.setConnectedNode("clearcoat_normal", self._normal("clearcoat_normal", e["clearcoatNormalTexture"]))
        e = extensions.get("KHR_materials_transmission")
        if e is not None:
            self._float(shader, "transmission", e.get("transmissionFactor", 0.0), e.get("transmissionTexture"), 0)
        e = extensions.get("KHR_materials_volume")
        if e is not None:
            self._float(shader, "thickness", e.get("thicknessFactor", 0.0), e.get("thicknessTexture"), 1)
            if "attenuationDistance" in e:
                shader.setInputValue("attenuation_distance", float(e["attenuationDistance"]))
            shader.setInputValue("attenuation_color", mx.Color3(*[float(f) for f in e.get("attenuationColor", [1.0] * 3)]))
        e = extensions.get("KHR_materials_iridescence")
        if e is not None:
            self._iridescence(shader, e)
        e = extensions.get("KHR_materials_sheen")
        if e is not None:
            self._colour(shader, "sheen_color", e.get("sheenColorTexture"), e.get("sheenColorFactor", [0.0] * 3))
            self._float(shader, "sheen_roughness", e.get("sheenRoughnessFactor", 0.0), e.get("sheenRoughnessTexture"), 3)
        e = extensions.get("KHR_materials_anisotropy")
        if e is not None:
            self._anisotropy(shader, e)
        return shader

    def _iridescence(self, shader, extension: dict) -> None:
        self._float(shader, "iridescence", extension.get("iridescenceFactor", 0.0), extension.get("iridescenceTexture"), 0)
        shader.setInputValue("iridescence_ior", float(extension.get("iridescenceIor", 1.3)))
        thickest = float(extension.get("iridescenceThicknessMaximum", 400.0))
        if "iridescenceThicknessTexture" in extension:
            node = self._image("iridescence_thickness_img", extension["iridescenceThicknessTexture"], "float",
                               category="gltf_iridescence_thickness")
            node.setInputValue("thicknessMin", float(extension.get("iridescenceThicknessMinimum", 100.0)))
            node.setInputValue("thicknessMax", thickest)
            shader.setConnectedNode("iridescence_thickness", node)
        else:
            shader.setInputValue("iridescence_thickness", thickest)

    def _anisotropy(self, shader, extension: dict) -> None:
        strength = float(extension.get("anisotropyStrength", 0.0))
        rotation = float(extension.get("anisotropyRotation", 0.0))
        if "anisotropyTexture" not in extension:
            shader.setInputValue("anisotropy_strength", strength)
            shader.setInputValue("anisotropy_rotation", rotation)
            return
        node = self._image("anisotropy_img", extension["anisotropyTexture"], "multioutput", category="gltf_anisotropy_image")
        node.setInputValue("anisotropy_strength", strength)
        node.setInputValue("anisotropy_rotation", rotation)
        for name in ("anisotropy_strength", "anisotropy_rotation"):
            port = shader.addInput(name, "float")
            port.setConnectedNode(node)
            port.setOutputString(name + "_out")

    def _image(self, name: str, info: dict, kind: str, colorspace: str | None = None, category: str = "gltf_image"):
        """A glTF image node reading the texture with its sampler's wrap modes and texture transform."""
        texture = self.gltf["textures"][info["index"]]
        source = texture.get("source")
        for key in ("KHR_texture_basisu", "EXT_texture_webp"):
            if key in texture.get("extensions", {}):
                source = texture["extensions"][key]["source"]
        uri = urllib.parse.unquote(self.gltf["images"][source]["uri"])
        node = self._doc.addNode(category, name, kind)
        node.setInputValue("file", os.path.relpath(os.path.join(os.path.dirname(self.path), uri), self._out_dir), "filename")
        if colorspace:
            node.getInput("file").setColorSpace(colorspace)
        sampler = self.gltf["samplers"][texture["sampler"]] if "sampler" in texture else {}
        node.setInputValue("uaddressmode", WRAP[sampler.get("wrapS", 10497)])
        node.setInputValue("vaddressmode", WRAP[sampler.get("wrapT", 10497)])
        transform = info.get("extensions", {}).get("KHR_texture_transform", {})
        if "offset" in transform:
            node.setInputValue("offset", mx.Vector2(*transform["offset"]))
        if "scale" in transform:
            node.setInputValue("scale", mx.Vector2(*transform["scale"]))
        if "rotation" in transform:
            node.setInputValue("rotate", float(math.degrees(transform["rotation"])))
        if transform.get("texCoord", info.get("texCoord", 0)):
            self._notes.append("texCoord > 0 read from the sphere's one UV set")
        return node

    def _float(self, shader, name: str, factor: float, info: dict | None, channel: int) -> None:
        """factor, or factor * one channel of a linear texture (3: alpha)."""
        if info is None:
            shader.setInputValue(name, float(factor))
            return
        extract = self._doc.addNode("extract", name + "_channel", "float")
        extract.setConnectedNode("in", self._image(name + "_img", info, "color4" if channel == 3 else "vector3"))
        extract.setInputValue("index", channel)
        multiply = self._doc.addNode("multiply", name + "_factor", "float")
        multiply.setConnectedNode("in1", extract)
        multiply.setInputValue("in2", float(factor))
        shader.setConnectedNode(name, multiply)

    def _colour(self, shader, name: str, info: dict | None, factor) -> None:
        """factor, or factor * an sRGB texture. The factor multiplies the decoded texel: MaterialX
        applies a colour-managed gltf_image's colour transform after the node's own ``factor``."""
        colour = mx.Color3(*[float(f) for f in factor])
        if info is None:
            shader.setInputValue(name, colour)
            return
        image = self._image(name + "_img", info, "color3", "srgb_texture")
        if colour == mx.Color3(1.0, 1.0, 1.0):
            shader.setConnectedNode(name, image)
            return
        multiply = self._doc.addNode("multiply", name + "_factor", "color3")
        multiply.setConnectedNode("in1", image)
        multiply.setInputValue("in2", colour)
        shader.setConnectedNode(name, multiply)

    def _normal(self, name: str, info: dict):
        normal = self._doc.addNode("normalmap", name, "vector3")
        normal.setConnectedNode("in", self._image(name + "_img", info, "vector3"))
        normal.setInputValue("scale", float(info.get("scale", 1.0)))
        return normal
