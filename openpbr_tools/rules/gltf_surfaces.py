"""glTF surfaces that light a material from the wrong side, turn its normal map the wrong way on mirrored UVs, or give
a volume no inside, while the Khronos glTF-Validator passes them (it reads accessor formats and unit lengths, not
facing, closure or handedness).

* NORMAL against winding (OPBR1246): glTF 2.0 makes counter-clockwise winding the front face, and for a
  double-sided material "the back-face MUST have its normals reversed before the lighting equation is evaluated":
  the authored normal belongs on the front side. Where it points to the back on (nearly) the whole primitive, the
  side the viewer sees is lit from behind, culled or not (a double-sided back face gets the reversed normal, which
  then points away from the viewer);
* tangent handedness on mirrored UVs (OPBR1247): the bitangent is ``cross(normal, tangent.xyz) * w`` (3.7.2.1),
  so on a mirrored UV island ``w`` must flip, or the normal map's green axis reads inverted there;
* a volume on an open surface (OPBR1248): KHR_materials_volume: "A non-zero thickness switches from thin-walled to
  volumetric behavior. This requires a manifold/closed mesh."

Not judged: an occlusion texture on a UV set whose islands overlap. A copy of TEXCOORD_0 in TEXCOORD_1 shares one
bake between faces, which is wrong for a unique bake and right for a shared trim (a crate's six equal faces); the
red teams' good files have that layout as often as their broken ones.

The facts are :mod:`openpbr_tools.io.gltf.surfaces`'.
"""

from __future__ import annotations

from ..diagnostics import Severity
from ..model import Location
from . import Rule
from .gltf_geometry import _QUAD, _QUAD_INDICES, _document

#: Normals facing the back of at least this share of a primitive's area are reversed (OPBR1246).
REVERSED_SHARE = 0.9
#: Triangles whose tangent frame turns against the rest, as a share of those counted (OPBR1247), and at least:
MIXED_SHARE, MIXED_TRIANGLES = 0.1, 2
#: A 4 x 4 flat normal map (128, 128, 255) for the examples.
_FLAT_NORMAL = ("data:image/png;base64,iVBORw0KGgoAAAANSUhEUgAAAAQAAAAECAIAAAAmkwkpAAAAFElEQVR42mNsaPjPAANMDEgANwcA"
                "ZFMCBygXkuMAAAAASUVORK5CYII=")


def _facing(z: float) -> str:
    return _document({"POSITION": ("VEC3", _QUAD), "NORMAL": ("VEC3", (0, 0, z) * 4)}, {"name": "M"})


NORMALS_REVERSED = Rule(
    "OPBR1246", "gltf-normals-against-winding", Severity.ERROR,
    "A primitive's NORMALs point to the back of its triangles (against their counter-clockwise winding) on nearly "
    "all of its surface, so the material is lit from behind.",
    "glTF 2.0: a triangle's front face is its counter-clockwise side (3.7.2.1), and for a double-sided material "
    "\"the back-face MUST have its normals reversed before the lighting equation is evaluated\" (material."
    "doubleSided), so the authored NORMAL belongs on the front side. "
    "When the normals point away from the front on (nearly) every triangle, light, Fresnel and the normal map are "
    "computed for the far side: a lit surface renders dark and a dark one lit, single- or double-sided (a back face "
    "seen gets the reversed normal, which then points away from the viewer). On a closed mesh the winding's signed "
    "volume says which is reversed: normals pointing in (flipped in the DCC, winding not), or triangles wound "
    "inside out. Reported when at least 90% of the primitive's area (triangles weighted by area) has normals behind "
    "the front face; smooth normals over sharp edges disagree on a few triangles, not on all. The Khronos "
    "glTF-Validator checks that normals have unit length, not which way they face.",
    passing=_facing(1.0), failing=_facing(-1.0),
    passing_name="example.gltf", failing_name="example.gltf", formats=("gltf",),
)


def _mirrored(second_w: float) -> str:
    """Two quads, the second's UV island mirrored in u, both with tangents along +u; ``second_w`` its handedness."""
    positions = _QUAD + tuple(c + (3 if i % 3 == 0 else 0) for i, c in enumerate(_QUAD))
    uvs = (0, 1, 1, 1, 1, 0, 0, 0) + (1, 1, 0, 1, 0, 0, 1, 0)
    tangents = (1, 0, 0, 1) * 4 + (-1, 0, 0, second_w) * 4
    return _document({"POSITION": ("VEC3", positions), "NORMAL": ("VEC3", (0, 0, 1) * 8),
                      "TANGENT": ("VEC4", tangents), "TEXCOORD_0": ("VEC2", uvs)},
                     {"name": "M", "normalTexture": {"index": 0}},
                     indices=_QUAD_INDICES + tuple(i + 4 for i in _QUAD_INDICES), images=[{"uri": _FLAT_NORMAL}])


HANDEDNESS_MIXED = Rule(
    "OPBR1247", "gltf-tangent-handedness-mirrored", Severity.ERROR,
    "A normal-mapped primitive's TANGENT frame turns one way on some triangles and the other way on the rest, against "
    "its texture coordinates: mirrored UV islands exported without flipping the tangent's w.",
    "glTF 2.0 (3.7.2.1): the bitangent \"MUST be computed by taking the cross product of the normal and tangent XYZ "
    "vectors and multiplying it against the W component\", w being \"a sign value (-1 or +1) indicating handedness "
    "of the tangent basis\". Where a UV island is mirrored (u running the other way, the usual way to paint one half "
    "of a symmetric model), the texture's v axis turns the other way against the tangent, so w must flip there "
    "(MikkTSpace does). With w the same everywhere, the normal map's green channel is read inverted on the mirrored "
    "triangles: bumps look dented and light comes from the wrong side on half the model. Compared per triangle: the "
    "authored bitangent against the derivative of position along v from the triangle's UVs; the exporter's "
    "convention does not matter, only that it is one convention. Reported when at least 10% of the triangles "
    "counted (and two or more) turn against the rest; degenerate UV triangles, seams and near-perpendicular frames "
    "are not counted. The Khronos glTF-Validator checks that w is +1 or -1, not which. Regenerate the tangents "
    "(MikkTSpace) from the normal map's UV set.",
    passing=_mirrored(-1.0), failing=_mirrored(1.0),
    passing_name="example.gltf", failing_name="example.gltf", formats=("gltf",),
)

_TETRAHEDRON = (0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1)
_TETRAHEDRON_INDICES = (0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3)


def _volume(closed: bool) -> str:
    material = {"name": "Glass", "pbrMetallicRoughness": {"metallicFactor": 0.0},
                "extensions": {"KHR_materials_transmission": {"transmissionFactor": 1.0},
                               "KHR_materials_volume": {"thicknessFactor": 0.01}}}
    used = ["KHR_materials_transmission", "KHR_materials_volume"]
    if closed:
        return _document({"POSITION": ("VEC3", _TETRAHEDRON)}, material, indices=_TETRAHEDRON_INDICES,
                         extensionsUsed=used)
    return _document({"POSITION": ("VEC3", _QUAD)}, material, extensionsUsed=used)


VOLUME_OPEN = Rule(
    "OPBR1248", "gltf-volume-open-surface", Severity.WARNING,
    "A material with KHR_materials_volume and a thickness above 0 is drawn on a primitive whose surface is open (edges "
    "used by one triangle only): the volume has no inside.",
    "KHR_materials_volume: \"A non-zero thickness switches from thin-walled to volumetric behavior. This requires a "
    "manifold/closed mesh\"; refraction and attenuation are defined for light entering through one side of the "
    "boundary and leaving through another. A window pane or liquid surface modelled as one open sheet has no back "
    "wall: ray tracers refract into it and never leave (or leave through the environment), raster viewers thicken "
    "it by the thickness texture. Make the material thin-walled (thickness 0) or close the mesh. Corners at one "
    "position are welded first (split UV seams and hard edges do not open a mesh); judged per primitive, as each is "
    "one material's surface. The Khronos glTF-Validator does not check closure.",
    passing=_volume(True), failing=_volume(False),
    passing_name="example.gltf", failing_name="example.gltf", formats=("gltf",),
)

RULES = (NORMALS_REVERSED, HANDEDNESS_MIXED, VOLUME_OPEN)


def check(asset, context):
    """Runs on glTF assets only (rules.FAMILY_FORMATS)."""
    materials = {material.extra.get("gltf", {}).get("index"): material for material in asset.materials}
    for primitive in asset.extra.get("gltf", {}).get("primitives", ()):
        surface = (primitive.get("geometry") or {}).get("surface") or {}
        index = primitive.get("material")
        material = materials.get(index) if isinstance(index, int) and not isinstance(index, bool) else None
        if material is None:
            continue
        where = Location(asset.path, None, f"{primitive['pointer']}/attributes", "NORMAL")
        yield from _facing_check(primitive, surface, material, where, context)
        yield from _handedness_check(primitive, surface, material, context, asset)
        yield from _volume_check(primitive, surface, material, context, asset)


def _facing_check(primitive, surface, material, where, context):
    facing = surface.get("facing")
    if facing is None or facing["agree"] > 1.0 - REVERSED_SHARE:
        return
    closed = surface.get("closed")
    behind = f"{100 * (1 - facing['agree']):.0f}% of its area"
    if closed is not None and not closed["boundary"] and closed["volume"] > 0:
        which, hint = ("the mesh is closed and its triangles face out, so the normals point inward",
                       "flip the normals (not the faces) in the DCC and re-export")
    elif closed is not None and not closed["boundary"] and closed["volume"] < 0:
        which, hint = ("the mesh is closed and its triangles are wound inside out (front faces looking in) while the "
                       "normals point out", "flip the faces' winding (not the normals) in the DCC and re-export")
    else:
        which, hint = ("normals and winding disagree", "make the normals and the winding agree (recalculate normals "
                       "outside, or flip the faces) and re-export")
    yield context.diagnostic(
        NORMALS_REVERSED, f"NORMAL of primitive {primitive['pointer']} points to the back of its triangles on {behind}: "
        f"{which}; {material.name!r} is lit from behind", where, hint=hint)


def _handedness_check(primitive, surface, material, context, asset):
    for number, turns in sorted(surface.get("handedness", {}).items()):
        if turns["minority"] < MIXED_TRIANGLES or turns["mixed"] < MIXED_SHARE:
            continue
        yield context.diagnostic(
            HANDEDNESS_MIXED, f"TANGENT of primitive {primitive['pointer']} turns against TEXCOORD_{number} on "
            f"{turns['minority']} of {turns['checked']} triangles and with it on the rest: mirrored UV islands with the "
            f"tangent's w not flipped, so {material.name!r}'s normal map reads its green axis inverted there",
            Location(asset.path, None, f"{primitive['pointer']}/attributes", "TANGENT"),
            hint=f"regenerate the tangents (MikkTSpace) from TEXCOORD_{number}, which flips w on mirrored islands")


def _volume_check(primitive, surface, material, context, asset):
    closed = surface.get("closed")
    if closed is None or not closed["boundary"] or not _has_volume(material):
        return
    yield context.diagnostic(
        VOLUME_OPEN, f"{material.name!r} has KHR_materials_volume with a thickness above 0, but primitive "
        f"{primitive['pointer']} is open ({closed['boundary']} of its {closed['edges']} edges bound one triangle only): "
        "the volume has no inside",
        Location(material.location.file, None, f"{material.location.path}/extensions/KHR_materials_volume",
                 "thicknessFactor"),
        hint="set thicknessFactor to 0 (thin-walled) for a sheet, or close the mesh")


def _has_volume(material) -> bool:
    thickness = material.inputs.get("thickness")
    value = thickness.constant if thickness is not None else None
    return thickness is not None and (thickness.texture is not None or (isinstance(value, float) and value > 0))
