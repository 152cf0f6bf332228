"""Resolve a :class:`~openpbr_tools.model.Material` into the numbers an evaluator needs.

For every parameter of the model's table (``schemas/models/``, latest version of the model):

* an authored constant is used as is (colours converted to linear Rec.709 from the input's, or
  else the material's, colour space);
* a texture, given a :class:`~.textures.TextureSampler` and the shading points' UVs, is read per
  point (an array with one value per point; the main normal map becomes ``normal``, a
  tangent-space vector per point); without a sampler, or where the sampler cannot read it, it
  contributes its ``fallback`` value when it has one, otherwise the table default, and the
  parameter is listed under ``textured`` ("textured (not evaluated)", with the reason);
* a connection the reader could not interpret, or an unparsable value, falls back to the
  table default and is listed under ``not_evaluated``;
* anything unset takes the table default.

Of the geometric inputs the main normal map tilts the shading frame and the coat's normal map the
coat's (without one the coat keeps the geometric normal); a textured tangent (OpenPBR
geometry_tangent / geometry_coat_tangent, Standard Surface tangent) turns the frame's tangent:
read through a ``normalmap`` decode it is a tangent-space direction, otherwise a world-space
vector, as MaterialX passes it to the BSDF.
Defaults are never retyped here; they come from the tables.

One module because resolving is one pass over a material's inputs (constants, textures, stand-ins, lengths and their
unit, glTF's extension reads), which every evaluator model, the comparison and the candidate search share.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from .. import tables
from ..colorspaces import to_lin_rec709_as_materialx
from ..io.gltf.slots import DIFFUSE_TRANSMISSION, UNLIT
from ..model import Connection, Constant, Material, Texture
from . import procedural

#: Parameter roles the evaluator does not consume.
_GEOMETRIC_ROLES = ("normal", "tangent", "filename", "string")


@dataclass
class ResolvedParameters:
    """Evaluator inputs of one material.

    ``values`` maps parameter names to NumPy arrays (floats and integers 0-d, colours shape
    ``(3,)``, booleans as ``bool``). ``textured`` lists textured parameters evaluated at their
    fallback or default, ``not_evaluated`` those whose authored value could not be used,
    ``ignored`` authored names the model's table does not know.
    """

    model: str
    version: str
    values: dict[str, object]
    textured: list[str] = field(default_factory=list)
    not_evaluated: list[str] = field(default_factory=list)
    ignored: list[str] = field(default_factory=list)
    sampled: list[str] = field(default_factory=list)  # textured parameters read per shading point
    normal: object = None  # (N, 3) tangent-space normals from the main normal map, or None
    coat_normal: object = None  # (N, 3) tangent-space normals from the coat's normal map, or None
    tangents: dict = field(default_factory=dict)  # tangent input -> ((N, 3) vectors, in tangent space?)
    approximated: list[tuple[str, str]] = field(default_factory=list)  # (parameter, why)
    why_not: dict = field(default_factory=dict)  # textured parameter -> why it was not sampled
    stand_ins: list[str] = field(default_factory=list)  # parameters rendered by a stand-in for their graph
    tangent_graphs: list[str] = field(default_factory=list)  # tangents from a node graph, not rendered

    def notes(self) -> list[str]:
        out = [f"{name}: textured (not evaluated{': ' + self.why_not[name] if name in self.why_not else ''})"
               for name in self.textured]
        out += [f"{name}: {why}" for name, why in self.approximated]
        out += [f"{name}: not evaluated (connection or invalid value), default used" for name in self.not_evaluated]
        out += [f"{name}: not a parameter of {self.model} {self.version}, ignored" for name in self.ignored]
        return out


_NUMERIC_TYPES = {"float": ((),), "integer": ((),), "color3": ((3,),), "color4": ((3,), (4,)), "vector2": ((2,),),
                  "vector3": ((3,),), "vector4": ((4,),)}  # and the shapes their values take here (_convert)


def _convert(value, ptype: str, role: str, colorspace: str | None):
    if ptype == "boolean":
        if isinstance(value, str):
            return value.strip().lower() in ("true", "1")
        return bool(value)
    if ptype == "integer":
        return np.asarray(int(value))
    array = np.asarray(value, dtype=float)
    if ptype in ("color3", "color4") and array.ndim == 0:
        array = np.full(3, float(array))
    if ptype in ("color3", "color4") and role == "color":
        array = to_lin_rec709_as_materialx(array[..., :3], colorspace)
    return array


def _fallback_for(texture: Texture, ptype: str):
    """A texture's fallback in the parameter's width: UsdUVTexture's is a float4, of which a float
    parameter reads the channel the texture delivers and a colour the first three."""
    fallback = texture.fallback
    if not isinstance(fallback, (tuple, list)):
        return fallback
    if ptype in ("color3", "vector3"):
        return tuple(fallback[:3]) if len(fallback) >= 3 else fallback
    if ptype in ("float", "integer"):
        channel = texture.channels[0] if texture.channels else 0
        return fallback[channel] if channel < len(fallback) else fallback[0]
    return fallback


def _sampled(values: np.ndarray, kind: str) -> np.ndarray:
    """A sampler's values shaped for the evaluator: (N,) for floats, (N, 3) for colours (a single
    channel read for a colour is grey); ``kind`` the parameter's type."""
    if kind in ("color3", "color4", "vector3"):
        return values if values.ndim == 2 else np.repeat(values[:, None], 3, axis=1)
    return values if values.ndim == 1 else values[:, 0]


#: Evaluator inputs a model's MaterialX node has no parameter for, with their defaults: glTF's
#: KHR_materials_diffuse_transmission (the gltf_pbr node has none; a glTF material carries it in
#: ``extra``, see :func:`_gltf_diffuse_transmission`).
EVALUATOR_EXTRAS = {"gltf_pbr": {"diffuse_transmission": 0.0, "diffuse_transmission_color": (1.0, 1.0, 1.0)}}


def defaults(model: str) -> ResolvedParameters:
    """Every parameter of ``model`` (latest table) at its default, and its :data:`EVALUATOR_EXTRAS`."""
    table = tables.table(model)
    values = {}
    for name, p in table.parameters.items():
        if p.role in _GEOMETRIC_ROLES or p.default is None:
            continue
        values[name] = _convert(p.default, p.type, p.role, None)
    values.update((name, np.asarray(default, dtype=float)) for name, default in EVALUATOR_EXTRAS.get(model, {}).items())
    return ResolvedParameters(model=model, version=table.version, values=values)


def with_values(model: str, overrides: dict) -> ResolvedParameters:
    """Defaults of ``model`` with ``overrides`` (linear Rec.709 numbers or arrays, which may carry
    leading batch axes) applied; unknown names raise ``KeyError``."""
    resolved = defaults(model)
    table = tables.table(model)
    for name, value in overrides.items():
        if name in EVALUATOR_EXTRAS.get(model, {}):
            resolved.values[name] = np.asarray(value, dtype=float)
            continue
        if name not in table.parameters:
            raise KeyError(f"{name!r} is not a parameter of {model} {table.version}")
        p = table.parameters[name]
        resolved.values[name] = value if p.type == "boolean" else np.asarray(value, dtype=float)
    return resolved


#: The normal input whose map tilts the shading frame, per model.
MAIN_NORMAL = {"open_pbr_surface": "geometry_normal", "standard_surface": "normal", "gltf_pbr": "normal",
               "UsdPreviewSurface": "normal"}
#: The coat's own normal input: its map tilts the coat's frame; without one the coat keeps the
#: geometric normal, not the base's map (MaterialX defaultgeomprop Nworld for geometry_coat_normal
#: and coat_normal; glTF: "no normal mapping is applied to the clear coat layer").
COAT_NORMAL = {"open_pbr_surface": "geometry_coat_normal", "standard_surface": "coat_normal",
               "gltf_pbr": "clearcoat_normal"}


def resolve(material: Material, sampler=None, uvs=None, length_scale: float = 1.0) -> ResolvedParameters:
    """Resolve ``material`` (see the module docstring); with ``sampler`` and ``uvs`` (a
    :class:`~.textures.UVs` of N shading points) textures are read per point. Lengths in scene units are the
    material's own (the rig's sphere is one scene unit across the volume, glTF's thickness its own), times
    ``length_scale`` where a comparison reads them in another material's unit (:func:`scene_unit`)."""
    from .textures import TextureUnavailable  # lazy: circular (textures is a sibling only samplers need)

    resolved = defaults(material.model)
    table = tables.table(material.model)
    for name, entry in material.inputs.items():
        p = table.get(name)
        if p is None:
            resolved.ignored.append(name)
            continue
        value = entry.value
        if sampler is not None and uvs is not None and isinstance(value, Texture) and p.type not in ("boolean", "integer") \
                and p.role not in ("filename", "string"):
            owner = f"{material.name}.{name}"
            if p.role == "normal" and name not in (MAIN_NORMAL.get(material.model), COAT_NORMAL.get(material.model)):
                resolved.approximated.append((name, "textured; not evaluated"))
                continue
            if p.role == "normal" and value.normal_map is None:
                resolved.approximated.append((name, "an image without a normal-map decode; the surface normal is used"))
                continue
            try:
                sampled = sampler.sample(value, p.type, uvs, owner)
            except TextureUnavailable as error:
                resolved.why_not[name] = str(error).removeprefix(owner + ": ")
            else:
                resolved.sampled.append(name)
                if p.role == "tangent":
                    resolved.tangents[name] = (sampled, value.normal_map is not None)
                elif p.role == "normal" and name == COAT_NORMAL.get(material.model):
                    resolved.coat_normal = sampled
                elif p.role == "normal":
                    resolved.normal = sampled
                else:
                    resolved.values[name] = _sampled(sampled, p.type)
                continue
        if p.role in _GEOMETRIC_ROLES:
            if isinstance(value, Texture):
                resolved.textured.append(name)
            elif p.role == "tangent" and isinstance(value, Connection) and value.graph_xml:
                # (a rotated tangent written as MaterialX nodes, say: not rendered, the geometric tangent is used)
                resolved.tangent_graphs.append(name)
                resolved.stand_ins.append(name)
                resolved.approximated.append((name, "procedural: a tangent graph, not rendered (the surface's own "
                                                    "tangent is used)"))
            continue
        colorspace = entry.colorspace or material.colorspace
        try:
            if isinstance(value, Constant):
                converted = _convert(value.value, p.type, p.role, colorspace)
                if p.unit == "scene_length" and length_scale != 1.0:
                    converted = converted * length_scale
                if p.type in _NUMERIC_TYPES and (np.shape(converted) not in _NUMERIC_TYPES[p.type] or
                                                 not np.all(np.isfinite(np.asarray(converted, dtype=float)))):
                    # NaN or infinity (OPBR203), or a colour where a float belongs (OPBR201): the default
                    resolved.not_evaluated.append(name)
                else:
                    resolved.values[name] = converted
            elif isinstance(value, Texture):
                resolved.textured.append(name)
                if value.fallback is not None:
                    space = value.colorspace or colorspace
                    resolved.values[name] = _convert(_fallback_for(value, p.type), p.type, p.role, space)
            elif isinstance(value, Connection) and value.graph_xml and p.type in ("float", "color3") \
                    and (stand_in := procedural.value(value.graph_xml, value.output, p.type, colorspace)) is not None:
                resolved.values[name] = _convert(stand_in, p.type, p.role, None)  # already linear Rec.709
                resolved.stand_ins.append(name)
                resolved.approximated.append((name, f"procedural: its graph's closing arithmetic evaluated, every other "
                                                    f"node at {procedural.STAND_IN} (a stand-in)"))
            elif isinstance(value, Connection) or value is None:
                resolved.not_evaluated.append(name)
        except (TypeError, ValueError):
            resolved.not_evaluated.append(name)
    _open_bounds(table, resolved)
    if material.model == "gltf_pbr":
        _gltf_diffuse_transmission(material, resolved)
        _gltf_unlit(material, resolved)
        _gltf_specular_glossiness(material, resolved, sampler, uvs)
    if sampler is not None and uvs is not None and material.model == "gltf_pbr":
        _gltf_anisotropy_direction(material, resolved, sampler, uvs)
    return resolved


#: The anisotropy each tangent input turns (OpenPBR's base and coat, Standard Surface's one tangent): a tangent turns
#: nothing isotropic.
TANGENT_ANISOTROPY = {"geometry_tangent": ("specular_roughness_anisotropy",),
                      "geometry_coat_tangent": ("coat_roughness_anisotropy",),
                      "tangent": ("specular_anisotropy", "coat_anisotropy")}


def scene_unit(material: Material) -> float:
    """Metres per scene unit of ``material``'s lengths: a MaterialX ``unit`` on one of them, else its USD stage's
    (``extra["meters_per_unit"]``, the USD reader's), else 1 (an untagged MaterialX length is taken as metres, as the
    converters take it; glTF's are metres). A comparison reads the second material's lengths in the first's unit, so
    MaterialX's honey (a depth of 2, metres) and its .usda in a centimetre stage (200) are the same (the red team's
    E#3: 17 mean CIEDE2000 apart)."""
    units = _distance_units()
    table = tables.table(material.model)
    for name, entry in material.inputs.items():
        parameter = table.get(name)
        if parameter is not None and parameter.unit == "scene_length" and entry.unit in units:
            return float(units[entry.unit])
    scale = material.extra.get("meters_per_unit")
    return float(scale) if isinstance(scale, (int, float)) and scale > 0 else 1.0


def _distance_units() -> dict:
    from ..resources import load_json  # lazy: the tables are loaded already; units only where a length is authored

    return load_json("units.json")["distance"]


def _open_bounds(table: dict, resolved: ResolvedParameters) -> None:
    """A value on or below an open lower bound (an IOR of 0 or less, which the validator reports as OPBR301)
    evaluated just inside it (:meth:`~openpbr_tools.tables.Parameter.inside_low`), as the translation's target
    clamp writes one (the formulas divide by it)."""
    for name, value in list(resolved.values.items()):
        p = table.get(name)
        if p is None or not p.hard_min_exclusive or not isinstance(p.hard_min, (int, float)):
            continue
        inside = p.inside_low()
        if np.any(np.asarray(value, dtype=float) < inside):
            resolved.values[name] = np.maximum(value, inside)
            resolved.approximated.append((name, f"outside its valid range: evaluated as {inside:g} where below it"))


def _gltf_diffuse_transmission(material: Material, resolved: ResolvedParameters) -> None:
    """KHR_materials_diffuse_transmission's factors: from a translation's record
    (``extra["gltf_extensions"]``, :class:`~openpbr_tools.model.Input` s in their colour space) or a
    read glTF's JSON (``extra["gltf"]["extensions"]``, linear Rec.709). Its textures are not read
    (listed as approximated): the factors apply."""
    record = (material.extra.get("gltf_extensions") or {}).get(DIFFUSE_TRANSMISSION)
    if isinstance(record, dict):
        for key, name in (("diffuseTransmissionFactor", "diffuse_transmission"),
                          ("diffuseTransmissionColorFactor", "diffuse_transmission_color")):
            entry = record.get(key)
            if entry is not None and isinstance(entry.value, Constant):
                value = np.asarray(entry.value.value, dtype=float)
                resolved.values[name] = value if value.ndim == 0 else \
                    to_lin_rec709_as_materialx(value, entry.colorspace or material.colorspace)
        return
    found = ((material.extra.get("gltf") or {}).get("extensions") or {}).get(DIFFUSE_TRANSMISSION)
    if not isinstance(found, dict):
        return
    try:
        factor = float(found.get("diffuseTransmissionFactor", 0.0))
        colour = np.atleast_1d(np.asarray(found.get("diffuseTransmissionColorFactor", (1.0, 1.0, 1.0)), dtype=float))
    except (TypeError, ValueError):
        resolved.not_evaluated.append("diffuse_transmission")
        return
    resolved.values["diffuse_transmission"] = np.asarray(factor)
    if colour.shape == (3,):
        resolved.values["diffuse_transmission_color"] = colour
    else:  # malformed (the validator reports it): the default colour
        resolved.not_evaluated.append("diffuse_transmission_color")
    for key in ("diffuseTransmissionTexture", "diffuseTransmissionColorTexture"):
        if key in found:
            resolved.approximated.append(("diffuse_transmission", f"{key} not read; its factor applies"))


def _gltf_unlit(material: Material, resolved: ResolvedParameters) -> None:
    """A glTF file's KHR_materials_unlit material shows its base colour whatever the lighting (the
    extension's README: the colour is the output): rendered as that colour emitted (glTF's emissive 1)
    by a black base that does not reflect. Only for a material read from a glTF file: a .mtlx
    ``gltf_pbr`` node keeps the extension as data only, and MaterialX renders the node lit."""
    state = material.gltf_state()
    extensions = state.get("extensions") if isinstance(state.get("extensions"), dict) else {}
    if UNLIT not in extensions or not str(material.location.file).lower().endswith((".gltf", ".glb")):
        return
    values = resolved.values
    values["emissive"] = values.get("base_color", np.ones(3))
    values["emissive_strength"] = np.asarray(1.0)
    values["base_color"] = np.zeros(3)
    values["metallic"] = np.asarray(0.0)
    values["specular"] = np.asarray(0.0)
    resolved.approximated.append(("base_color", "KHR_materials_unlit: rendered as its colour emitted by a black base "
                                                "that does not reflect"))


#: ior 1.5's normal-incidence reflectance, by which the specular colour that gives F0 = S is S / 0.04
_F0_OF_1_5 = ((1.5 - 1.0) / (1.5 + 1.0)) ** 2


def _gltf_specular_glossiness(material: Material, resolved: ResolvedParameters, sampler, uvs) -> None:
    """A glTF file's KHR_materials_pbrSpecularGlossiness material (the reader's
    ``extra["gltf"]["spec_gloss"]``) is rendered as the extension defines its BRDF inputs, ``c_diff = D (1 -
    max(S))``, ``F0 = S``, ``alpha = (1 - g)^2``, not as its metallic-roughness fallback, which a viewer of
    the extension does not show: in gltf_pbr's terms a dielectric (metallic 0) of base colour c_diff, of F0
    S (ior 1.5 with KHR_materials_specular's colour S / 0.04, F90 1), roughness 1 - g, alpha the diffuse
    alpha. Textures are read with ``sampler``; without one their factors apply (listed as textured)."""
    from .textures import TextureUnavailable  # lazy: as in resolve

    state = material.gltf_state()
    found = state.get("spec_gloss")
    extensions = state.get("extensions") if isinstance(state.get("extensions"), dict) else {}
    if not isinstance(found, dict) or not str(material.location.file).lower().endswith((".gltf", ".glb")) \
            or UNLIT in extensions:  # (the two together: read as unlit, as conversions do)
        return
    values = resolved.values

    def read(name: str, kind: str, default):
        entry = found.get(name)
        value = entry.value if entry is not None else None
        if isinstance(value, Constant) and np.all(np.isfinite(np.asarray(value.value, dtype=float))):
            return np.asarray(value.value, dtype=float)
        if isinstance(value, Texture) and sampler is not None and uvs is not None:
            try:
                sampled = sampler.sample(value, kind, uvs, f"{material.name}.{name}")
            except TextureUnavailable as error:
                resolved.why_not[name] = str(error)
            else:
                resolved.sampled.append(name)
                return _sampled(sampled, kind)
        if isinstance(value, Texture):
            resolved.textured.append(name)
            return np.asarray(value.scale if value.scale is not None else default, dtype=float)
        return np.asarray(default, dtype=float)

    diffuse, specular = read("diffuseColor", "color3", (1.0, 1.0, 1.0)), read("specularColor", "color3", (1.0, 1.0, 1.0))
    values["base_color"] = diffuse * (1.0 - np.max(specular, axis=-1, keepdims=True))
    values["specular_color"] = specular / _F0_OF_1_5
    values["metallic"], values["ior"], values["specular"] = np.asarray(0.0), np.asarray(1.5), np.asarray(1.0)
    values["roughness"] = 1.0 - read("glossiness", "float", 1.0)
    values["alpha"] = read("opacity", "float", 1.0)  # (the extension's coverage, 1 unauthored; not the fallback's)
    resolved.approximated.append(("base_color", "KHR_materials_pbrSpecularGlossiness: rendered by the extension's "
                                                "BRDF inputs, not the metallic-roughness fallback"))


def _gltf_anisotropy_direction(material: Material, resolved: ResolvedParameters, sampler, uvs) -> None:
    """KHR_materials_anisotropy's texture carries a tangent-space direction in R, G (``2 t - 1``),
    rotated by ``anisotropyRotation`` (the extension's README): the evaluator's per-point rotation is
    ``anisotropy_rotation + atan2(d_y, d_x)``. The glTF reader keeps that texture beside the strength
    it also feeds (``extra["gltf"]["anisotropy_direction"]``)."""
    from .textures import TextureUnavailable  # lazy: as in resolve

    direction = (material.extra.get("gltf") or {}).get("anisotropy_direction")
    if not isinstance(direction, Texture):
        return
    owner = f"{material.name}.anisotropy_direction"
    try:
        rg = sampler.sample(direction, "vector3", uvs, owner)
    except TextureUnavailable as error:
        resolved.approximated.append(("anisotropy_rotation", f"direction texture not read ({error}); "
                                                             "the factor's rotation is used"))
        return
    d = 2.0 * rg[:, :2] - 1.0
    rotation = np.asarray(resolved.values["anisotropy_rotation"], dtype=float)
    resolved.values["anisotropy_rotation"] = rotation + np.arctan2(d[:, 1], d[:, 0])
    resolved.sampled.append("anisotropy_rotation")
