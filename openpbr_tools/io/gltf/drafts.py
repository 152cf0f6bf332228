"""The draft glTF material extensions that align glTF with OpenPBR: where each property lives and
which OpenPBR parameter it stands for. Shared by the glTF reader, the glTF translation and the writer.

Implemented from these texts (KhronosGroup/glTF, read on 2026-11-25; all are drafts and may change):

* ``KHR_materials_coat`` (pull request #2534; ``extensions/2.0/Khronos/KHR_materials_coat/README.md``
  at commit ac989f7a): ``coatFactor`` (R of ``coatTexture``), ``coatRoughnessFactor`` (G of
  ``coatRoughnessTexture``), ``coatNormalTexture``, ``coatIor`` (default 1.5; 0 is a
  "backwards compatibility mode" the text does not define), ``coatColorFactor`` (sRGB
  ``coatColorTexture``; the square of the coat's transmittance at normal incidence, as OpenPBR's
  ``coat_color``), ``coatDarkeningFactor`` (default 1, OpenPBR's ``coat_darkening``),
  ``coatAnisotropyStrength`` / ``coatAnisotropyRotation`` / ``coatAnisotropyTexture`` with
  KHR_materials_anisotropy's convention (alpha_t = mix(r^2, 1, s^2), alpha_b = r^2). It takes
  precedence over ``KHR_materials_clearcoat``, which stays as the fallback.
* ``KHR_materials_fuzz`` (#2538; README at commit b714616c): ``fuzzFactor`` (R of
  ``fuzzTexture``), ``fuzzColorFactor`` (default white; sRGB ``fuzzColorTexture``),
  ``fuzzRoughnessFactor`` (default 0.5; A of ``fuzzRoughnessTexture``): OpenPBR's fuzz weight,
  colour and roughness, on top of the coat. Takes precedence over ``KHR_materials_sheen``.
* ``KHR_materials_diffuse_roughness`` (#2481; README at commit 95c4f0db): ``diffuseRoughnessFactor``
  (R of ``diffuseRoughnessTexture``), OpenPBR's energy-conserving Oren-Nayar roughness.
* ``EXT_materials_specular_openpbr`` (#2488; README at commit dbf52b38), a sub-extension of
  ``KHR_materials_specular`` without properties: ``specularFactor`` and ``specularColorFactor``
  then mean OpenPBR's ``specular_weight`` and ``specular_color`` (the colour tints the whole
  dielectric lobe, and a metal's F82 edge), and the base colour is a metal's F0.
* ``EXT_materials_clearcoat_darkening`` (#2518), a sub-extension of ``KHR_materials_clearcoat``:
  ``clearcoatDarkeningFactor`` (default 1), OpenPBR's ``coat_darkening``.
* ``KHR_materials_clearcoat_ior`` (draft; README in KhronosGroup/glTF ``extensions/2.0/Khronos/``), a
  sub-extension of ``KHR_materials_clearcoat``: ``clearcoatIor`` (default 1.5), OpenPBR's ``coat_ior``.
* ``EXT_materials_anisotropy_openpbr`` (#2521), a sub-extension of ``KHR_materials_anisotropy``:
  with ``openPbrAnisotropyEnabled`` true, ``anisotropyStrength`` is OpenPBR's
  ``specular_roughness_anisotropy`` and ``roughnessFactor`` OpenPBR's ``specular_roughness``.
"""

from __future__ import annotations

from .slots import Slot

COAT = "KHR_materials_coat"
FUZZ = "KHR_materials_fuzz"
DIFFUSE_ROUGHNESS = "KHR_materials_diffuse_roughness"
SPECULAR_OPENPBR = "EXT_materials_specular_openpbr"
CLEARCOAT_DARKENING = "EXT_materials_clearcoat_darkening"
ANISOTROPY_OPENPBR = "EXT_materials_anisotropy_openpbr"
CLEARCOAT_IOR = "KHR_materials_clearcoat_ior"

#: Material-level draft extensions (beside the ratified ones in a material's ``extensions``).
MATERIAL_DRAFTS = (COAT, FUZZ, DIFFUSE_ROUGHNESS)
#: Sub-extensions: (parent extension, draft) pairs.
SUB_DRAFTS = (("KHR_materials_specular", SPECULAR_OPENPBR), ("KHR_materials_clearcoat", CLEARCOAT_DARKENING),
              ("KHR_materials_anisotropy", ANISOTROPY_OPENPBR), ("KHR_materials_clearcoat", CLEARCOAT_IOR))
ALL_DRAFTS = MATERIAL_DRAFTS + tuple(draft for _, draft in SUB_DRAFTS)

#: Each draft property as a :class:`Slot` whose ``parameter`` names the property's key in the
#: material's draft record (its OpenPBR parameter where the mapping is one to one).
SLOTS: dict[str, tuple[Slot, ...]] = {
    COAT: (
        Slot("coat_weight", COAT, "coatFactor", 0.0, "coatTexture", (0,)),
        Slot("coat_roughness", COAT, "coatRoughnessFactor", 0.0, "coatRoughnessTexture", (1,)),
        Slot("geometry_coat_normal", COAT, None, None, "coatNormalTexture", None, texture_kind="normalTextureInfo"),
        Slot("coat_ior", COAT, "coatIor", 1.5),
        Slot("coat_color", COAT, "coatColorFactor", (1.0, 1.0, 1.0), "coatColorTexture", (0, 1, 2), True),
        Slot("coat_darkening", COAT, "coatDarkeningFactor", 1.0),
        Slot("coat_anisotropy_strength", COAT, "coatAnisotropyStrength", 0.0, "coatAnisotropyTexture", (2,)),
        Slot("coat_anisotropy_rotation", COAT, "coatAnisotropyRotation", 0.0),
    ),
    FUZZ: (
        Slot("fuzz_weight", FUZZ, "fuzzFactor", 0.0, "fuzzTexture", (0,)),
        Slot("fuzz_color", FUZZ, "fuzzColorFactor", (1.0, 1.0, 1.0), "fuzzColorTexture", (0, 1, 2), True),
        Slot("fuzz_roughness", FUZZ, "fuzzRoughnessFactor", 0.5, "fuzzRoughnessTexture", (3,)),
    ),
    DIFFUSE_ROUGHNESS: (
        Slot("base_diffuse_roughness", DIFFUSE_ROUGHNESS, "diffuseRoughnessFactor", 0.0, "diffuseRoughnessTexture", (0,)),
    ),
    CLEARCOAT_DARKENING: (
        Slot("coat_darkening", CLEARCOAT_DARKENING, "clearcoatDarkeningFactor", 1.0),
    ),
    CLEARCOAT_IOR: (
        Slot("coat_ior", CLEARCOAT_IOR, "clearcoatIor", 1.5),
    ),
}

#: Properties whose value is a colour (sRGB-encoded in a texture, linear Rec.709 as a factor).
COLOUR_KEYS = frozenset({"coat_color", "fuzz_color"})
#: Hard ranges the drafts' schemas and texts give ([low, high]; None: unbounded).
RANGES = {"coat_weight": (0.0, 1.0), "coat_roughness": (0.0, 1.0), "coat_color": (0.0, 1.0),
          "coat_darkening": (0.0, 1.0), "coat_anisotropy_strength": (0.0, 1.0), "coat_ior": (1.0, None),
          "fuzz_weight": (0.0, 1.0), "fuzz_color": (0.0, 1.0), "fuzz_roughness": (0.0, 1.0),
          "base_diffuse_roughness": (0.0, 1.0)}

#: Which ratified fallback texture a draft texture can share when written (same data, same channel).
SHARED_TEXTURES = {("coat_weight", COAT): ("KHR_materials_clearcoat", "clearcoatTexture"),
                   ("geometry_coat_normal", COAT): ("KHR_materials_clearcoat", "clearcoatNormalTexture")}
