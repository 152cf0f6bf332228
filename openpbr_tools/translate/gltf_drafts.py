"""The draft glTF extensions in a glTF <-> OpenPBR translation (the texts and versions implemented
are :mod:`openpbr_tools.io.gltf.drafts`'s).

Reading: the glTF reader records each draft's properties (``extra["gltf"]["drafts"]``);
:func:`apply_drafts` sets the OpenPBR parameters they give, exactly, in place of what the ratified
fallbacks (KHR_materials_clearcoat, KHR_materials_sheen) would give, and :func:`with_draft_coat`
makes KHR_materials_coat's weight, roughness and IOR the ones the base's roughness and specular
inverses read. Coat anisotropy uses glTF's convention (:mod:`.gltf_anisotropy`); ``coatIor`` 0 (the
draft's undefined "backwards compatibility mode") is read as 1.5 and reported;
``coatAnisotropyRotation`` is reported (OpenPBR rotates through the coat tangent).

Writing (``Settings.gltf_drafts``): :func:`draft_record` gives the values the writer turns into the
draft extensions' JSON: OpenPBR's coat (roughness and anisotropy in glTF's convention), fuzz and
diffuse roughness, and a marker for EXT_materials_specular_openpbr (the translation then writes
OpenPBR's specular weight and colour, and a metal's F0, as KHR_materials_specular and the base colour).
"""

from __future__ import annotations

import copy

import numpy as np

from .. import tables
from ..evaluate.microfacet import openpbr_alphas
from ..io.gltf import drafts
from ..model import Constant, Input, Material, Texture
from ..rules.translation import APPROXIMATED, CONVERTED, NOT_CARRIED
from .common import Settings
from .gltf_anisotropy import gltf_anisotropy_strength, gltf_roughness, openpbr_anisotropy, openpbr_roughness
from .target import inside

#: KHR_materials_clearcoat's fixed IOR (its F0 is 0.04), and KHR_materials_coat's default.
GLTF_CLEARCOAT_IOR = 1.5

#: OpenPBR parameters each draft extension gives exactly (their mappings from the ratified
#: extensions are then not used).
DRAFT_TARGETS = {
    drafts.COAT: ("coat_weight", "coat_roughness", "coat_roughness_anisotropy", "coat_ior", "coat_color",
                  "coat_darkening", "geometry_coat_normal"),
    drafts.FUZZ: ("fuzz_weight", "fuzz_color", "fuzz_roughness"),
    drafts.DIFFUSE_ROUGHNESS: ("base_diffuse_roughness",),
    drafts.CLEARCOAT_DARKENING: ("coat_darkening",),
    drafts.CLEARCOAT_IOR: ("coat_ior",),
    drafts.SPECULAR_OPENPBR: (),
    drafts.ANISOTROPY_OPENPBR: (),
}


def _constant(entry):
    return entry.value.value if entry is not None and isinstance(entry.value, Constant) else None


def with_draft_coat(material: Material, coat: dict | None, ior_only: bool = False) -> tuple[Material, float]:
    """``material`` with KHR_materials_coat's weight and roughness standing for clearcoat's (the base's
    roughness and specular inverses read them), and the coat's IOR (1.5 without the draft).
    ``ior_only``: ``coat`` is KHR_materials_clearcoat_ior's record (the clearcoat is read as it is)."""
    if coat is None:
        return material, GLTF_CLEARCOAT_IOR
    ior = _constant(coat.get("coat_ior"))
    ior = float(ior) if isinstance(ior, (int, float)) and ior >= 1.0 else GLTF_CLEARCOAT_IOR
    if ior_only:
        return material, ior
    source = copy.copy(material)
    source.inputs = dict(material.inputs)
    weight = coat.get("coat_weight")
    if weight is None:
        source.inputs.pop("clearcoat", None)  # the draft's default (0) replaces the fallback's value
    else:
        source.inputs["clearcoat"] = copy.copy(weight)
        source.inputs["clearcoat"].name = "clearcoat"
    # the coat roughens the base by OpenPBR's coat roughness (the writer's convention), which the
    # coat's anisotropy changes even at coatRoughnessFactor 0 (alpha_t = mix(0, 1, s^2))
    rough, strength = coat.get("coat_roughness"), coat.get("coat_anisotropy_strength")
    r = 0.0 if rough is None else _constant(rough)
    s = 0.0 if strength is None else _constant(strength)
    if isinstance(r, float) and isinstance(s, float):
        value = float(openpbr_roughness(np.float64(r), np.float64(s)))
        anchor = rough if rough is not None else strength
        if value == 0.0 or anchor is None:
            source.inputs.pop("clearcoat_roughness", None)
        else:
            source.inputs["clearcoat_roughness"] = Input("clearcoat_roughness", "float", Constant(value), anchor.location)
    elif rough is not None:  # a textured roughness: read isotropic (apply_drafts reports the anisotropy)
        source.inputs["clearcoat_roughness"] = copy.copy(rough)
        source.inputs["clearcoat_roughness"].name = "clearcoat_roughness"
    else:
        source.inputs.pop("clearcoat_roughness", None)
    return source, ior


def apply_drafts(result: Material, source: Material, found: dict, settings: Settings) -> list:
    """Set the OpenPBR parameters the drafts give; the loss report for what they cannot."""
    context = settings.context
    table = tables.table("open_pbr_surface")
    notes = []

    def say(rule, message, entry=None):
        location = entry.location if entry is not None else source.location
        notes.append(context.diagnostic(rule, f"{source.name} (glTF -> OpenPBR): {message}", location))

    def put(name, entry, value=None):
        parameter = table[name]
        if value is not None:
            entry = Input(name, parameter.type, Constant(value), entry.location, colorspace=entry.colorspace)
        else:
            entry = copy.deepcopy(entry)
            entry.name, entry.type = name, parameter.type
        if isinstance(entry.value, Constant):
            typed, clamped = inside(entry.value.value, parameter)
            if clamped:
                say(APPROXIMATED, f"{name}: {clamped}", entry)
            if typed == parameter.default or (isinstance(typed, tuple) and tuple(typed) == tuple(parameter.default or ())):
                result.inputs.pop(name, None)
                return
            entry.value = Constant(typed)
        result.inputs[name] = entry

    for name in sorted(found):
        record = found[name]
        fallback = {drafts.COAT: "KHR_materials_clearcoat", drafts.FUZZ: "KHR_materials_sheen"}.get(name)
        if name == drafts.COAT:
            _coat_from_draft(record, put, say)
        elif name == drafts.CLEARCOAT_IOR and "coat_ior" not in record:  # present, empty: its default 1.5
            put("coat_ior", Input("coat_ior", "float", None, source.location), GLTF_CLEARCOAT_IOR)
        else:
            for key, entry in sorted(record.items()):
                put(key, entry)
        where = next(iter(record.values()), None)
        read = ", ".join(DRAFT_TARGETS[name]) or {drafts.SPECULAR_OPENPBR: "specular_weight, specular_color and a metal's "
                                                                          "base colour as OpenPBR's",
                                                  drafts.ANISOTROPY_OPENPBR: "specular_roughness and "
                                                                             "specular_roughness_anisotropy as OpenPBR's"}[name]
        say(CONVERTED, f"{name} (draft) read exactly: {read}"
                       + (f"; its fallback {fallback} is not read" if fallback and fallback in source.extra["gltf"].get(
                           "material_extensions", ()) else ""), where)
    return notes


def _coat_from_draft(record: dict, put, say) -> None:
    for key in ("coat_weight", "coat_ior", "coat_color", "coat_darkening", "geometry_coat_normal"):
        entry = record.get(key)
        if entry is None:
            continue
        if key == "coat_ior" and _constant(entry) == 0.0:
            say(APPROXIMATED, "coatIor 0 (the draft's backwards-compatibility mode, which it does not define) is "
                              "read as 1.5", entry)
            put(key, entry, GLTF_CLEARCOAT_IOR)
            continue
        put(key, entry)
    if "coat_ior" not in record and record:  # the draft's default, 1.5, is not OpenPBR's (1.6)
        put("coat_ior", next(iter(record.values())), GLTF_CLEARCOAT_IOR)
    roughness, strength = record.get("coat_roughness"), record.get("coat_anisotropy_strength")
    r = _constant(roughness) if roughness is not None else 0.0
    s = _constant(strength) if strength is not None else 0.0
    if r is not None and s is not None:
        anchor = roughness or strength
        if anchor is not None:
            put("coat_roughness", anchor, float(openpbr_roughness(np.float64(r), np.float64(s))))
            put("coat_roughness_anisotropy", anchor, float(openpbr_anisotropy(np.float64(r), np.float64(s))))
    elif roughness is not None and isinstance(roughness.value, Texture) and s == 0.0:
        put("coat_roughness", roughness)
    else:
        say(NOT_CARRIED, "a textured coat roughness with coat anisotropy (or a coatAnisotropyTexture) needs "
                         "OpenPBR's roughness solved per texel; not carried", roughness or strength)
    rotation = record.get("coat_anisotropy_rotation")
    if rotation is not None and _constant(rotation) not in (0.0, None):
        say(NOT_CARRIED, "coatAnisotropyRotation has no equivalent: OpenPBR rotates anisotropy through the "
                         "coat tangent", rotation)


def _authored_or_default(material: Material, name: str, table) -> Input:
    entry = material.inputs.get(name)
    if entry is not None:
        return entry
    parameter = table[name]
    return Input(name, parameter.type, Constant(parameter.default), material.location.with_input(name),
                 colorspace=material.colorspace)


def needs_specular_openpbr(material: Material) -> bool:
    """Whether ``material`` (OpenPBR) needs EXT_materials_specular_openpbr to be exact in glTF: a metal
    whose F82 edge tint or specular weight glTF's Schlick metal cannot hold (its ratified fit is
    approximate). Dielectrics keep glTF's own KHR_materials_specular, fitted and inverted exactly,
    which a viewer without the draft also reads right. A textured term counts as not at its default."""
    metalness = _constant(material.inputs.get("base_metalness"))
    if "base_metalness" not in material.inputs or metalness == 0:  # OpenPBR's default metalness is 0
        return False
    color = material.inputs.get("specular_color")
    weight = material.inputs.get("specular_weight")
    tinted = color is not None and (_constant(color) is None or tuple(_constant(color)) != (1.0, 1.0, 1.0))
    weighted = weight is not None and _constant(weight) != 1.0
    return tinted or weighted


def draft_record(material: Material, settings: Settings, specular_openpbr: bool = False) -> tuple[dict, list]:
    """What the draft extensions carry for ``material`` (OpenPBR), keyed as the reader keys them:
    {extension: {key: Input}}; the writer turns it into JSON (colours to linear Rec.709)."""
    table = tables.table("open_pbr_surface")
    context = settings.context
    notes = []
    record: dict = {}

    def active(name):
        entry = material.inputs.get(name)
        if entry is None:
            return False
        value = _constant(entry)
        return value is None or (isinstance(value, (int, float)) and value > 0)

    if active("coat_weight"):
        coat = {key: _authored_or_default(material, key, table)
                for key in ("coat_weight", "coat_ior", "coat_color", "coat_darkening")}
        if "geometry_coat_normal" in material.inputs:
            coat["geometry_coat_normal"] = material.inputs["geometry_coat_normal"]
        rough = _authored_or_default(material, "coat_roughness", table)
        aniso = _authored_or_default(material, "coat_roughness_anisotropy", table)
        r, a = _constant(rough), _constant(aniso)
        if r is not None and a is not None:
            coat["coat_roughness"] = Input("coat_roughness", "float", Constant(float(gltf_roughness(np.float64(r), np.float64(a)))),
                                           rough.location)
            if float(openpbr_alphas(np.float64(r), np.float64(a))[0]) > 1.0 + 1e-12:
                notes += [context.diagnostic(APPROXIMATED, f"{material.name} (OpenPBR -> glTF): {entry.name}: the coat's "
                                             "alpha_t exceeds 1, glTF's anisotropy cap: KHR_materials_coat (draft) holds "
                                             "it at 1", entry.location) for entry in (rough, aniso)]
            strength = float(gltf_anisotropy_strength(np.float64(r), np.float64(a)))
            if strength > 0:
                coat["coat_anisotropy_strength"] = Input("coat_anisotropy_strength", "float", Constant(strength),
                                                         aniso.location)
        elif a == 0.0:
            coat["coat_roughness"] = rough
        else:
            notes.append(context.diagnostic(NOT_CARRIED, f"{material.name} (OpenPBR -> glTF): a textured coat roughness "
                                            "or anisotropy needs glTF's anisotropy solved per texel; KHR_materials_coat "
                                            "(draft) gets none", aniso.location))
        record[drafts.COAT] = coat
    if active("fuzz_weight"):
        record[drafts.FUZZ] = {key: _authored_or_default(material, key, table)
                               for key in ("fuzz_weight", "fuzz_color", "fuzz_roughness")}
    if active("base_diffuse_roughness"):
        record[drafts.DIFFUSE_ROUGHNESS] = {"base_diffuse_roughness": material.inputs["base_diffuse_roughness"]}
    if specular_openpbr:
        record[drafts.SPECULAR_OPENPBR] = {}  # KHR_materials_specular holds OpenPBR's values
    return record, notes
