"""Which way a primitive's surface faces, whether it closes, and which way its tangent frame turns: three facts of the
vertex data that decide how a material is lit and that no glTF validator reads.

* ``facing``: glTF 2.0 makes a triangle's counter-clockwise winding its front face, and for a double-sided material
  "the back-face MUST have its normals reversed before the lighting equation is evaluated", so an authored NORMAL
  belongs on the front side. ``agree`` is the share of the primitive's surface area (triangles weighted by area)
  whose winding normal ``(p1 - p0) x (p2 - p0)`` points the same way as the sum of its three corners' NORMALs
  (triangles whose normals sum to zero, or lie at right angles to them, are not counted). Near 0: normals and
  winding disagree, and whichever side the viewer sees is lit from behind.
* ``closed``: whether the primitive's triangles close a volume: every edge, after welding corners at one position
  (within :data:`WELD` of the primitive's extent, so UV seams and hard edges that split vertices do not open it), is shared
  by exactly two triangles; ``boundary`` counts the edges used once. ``volume``: the signed volume the winding
  encloses (the divergence theorem, the sum of ``p0 . (p1 x p2) / 6``): positive when the front faces look out.
  Read only when asked for (a volume material, KHR_materials_volume: "a non-zero thickness ... requires a
  manifold/closed mesh") or when the facing is in doubt.
* ``handedness``: per UV set of a normal texture, the tangent frame the TANGENT attribute gives (bitangent
  ``cross(NORMAL, TANGENT.xyz) * w``, 3.7.2.1) against the one the texture coordinates give (the derivative of
  position along v, from the triangle's edges in UV space), and the TANGENT against the derivative along u. A
  correct frame turns the same way on every triangle, whichever way the exporter's convention turns it; ``mixed`` is
  the share of the checked triangles that turn the other way (mirrored UV islands exported with ``w = +1``
  everywhere, or with tangents that do not follow u), the worse of the two axes. Triangles whose UV area is degenerate, whose
  corners carry different ``w`` (a seam) or whose two bitangents are near perpendicular (|cos| < :data:`TURN_COSINE`)
  are not counted.

Only triangle lists are read, within :mod:`.accessors`' bound; a primitive whose data cannot be read gives ``None``.
"""

from __future__ import annotations

from . import accessors
from .document import GltfDocument
from .textures import json_index

_TRIANGLES = 4
#: Corners closer than this fraction of the primitive's largest side are one vertex when edges are matched.
WELD = 1e-5
#: A triangle's two bitangents must agree or disagree at least this clearly (|cos|) to count for ``handedness``.
TURN_COSINE = 0.5


def primitive_surface(document: GltfDocument, primitive: dict, wants_closed: bool, normal_sets: tuple) -> dict | None:
    """``{"triangles", "facing": {"agree", "area"} or None, "closed": {...} or None, "handedness": {set: {...}}}``
    for one primitive (see the module docstring); ``wants_closed`` reads closure whatever the facing,
    ``normal_sets`` are the UV sets a normal texture of its material reads."""
    import numpy  # lazy: only for a file with mesh data

    attributes = primitive.get("attributes") if isinstance(primitive.get("attributes"), dict) else {}
    if primitive.get("mode", _TRIANGLES) != _TRIANGLES or not json_index(attributes.get("POSITION")):
        return None
    positions = accessors.vectors(document, attributes["POSITION"])
    if positions is None or positions.shape[1] != 3 or not numpy.isfinite(positions).all():
        return None
    triangles = triangle_list(document, primitive.get("indices"), positions.shape[0])
    if triangles is None or not len(triangles):
        return None
    corners = positions.astype("float32")[triangles]  # (triangles, 3, xyz); float32 as stored: signs are asked
    winding = numpy.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0])
    area = numpy.linalg.norm(winding, axis=1) / 2.0
    found = {"triangles": int(len(triangles)), "facing": None, "closed": None, "handedness": {}}
    normals = _vertex_vectors(document, attributes.get("NORMAL"), positions.shape[0], 3)
    if normals is not None:
        dot = numpy.einsum("ij,ij->i", winding, normals[triangles].sum(axis=1))
        judged = float(area[dot != 0].sum())  # (zero normals face no way: another rule's)
        if judged > 0:
            found["facing"] = {"agree": float(area[dot > 0].sum()) / judged, "area": judged}
    if wants_closed or (found["facing"] is not None and found["facing"]["agree"] < 0.5):
        found["closed"] = _closure(positions, triangles, corners)
    tangents = _vertex_vectors(document, attributes.get("TANGENT"), positions.shape[0], 4)
    for number in normal_sets if normals is not None and tangents is not None else ():
        uv = _vertex_vectors(document, attributes.get(f"TEXCOORD_{number}"), positions.shape[0], 2)
        if uv is not None:
            found["handedness"][number] = _handedness(corners, normals[triangles], tangents[triangles], uv[triangles])
    return found


def triangle_list(document: GltfDocument, index, count: int):
    """The corners of a triangle list of ``count`` vertices as a ``(triangles, 3)`` index array (every vertex in
    order without ``index``), ``None`` when the indices cannot be read or name a vertex past ``count``."""
    import numpy  # lazy: as in primitive_surface

    corners = numpy.arange(count) if index is None else accessors.indices(document, index) if json_index(index) else None
    if corners is None or (corners.size and corners.max() >= count):
        return None
    return corners[: corners.size - corners.size % 3].reshape(-1, 3)


def _vertex_vectors(document: GltfDocument, index, count: int, width: int):
    import numpy  # lazy: as in primitive_surface

    values = accessors.vectors(document, index) if json_index(index) else None
    if values is None or values.shape != (count, width) or not numpy.isfinite(values).all():
        return None
    return values.astype("float32")


def _closure(positions, triangles, corners) -> dict:
    """Welded edges used once (``boundary``), more than twice (``non_manifold``), and the signed volume. Corners weld
    on their positions quantised to :data:`WELD` of the extent, each packed into one integer key (17 bits an axis),
    and edges on their two welded ends packed likewise: one-dimensional sorts, not row sorts."""
    import numpy  # lazy: as in primitive_surface

    vertex = _welded(positions)
    welded = vertex[triangles]
    kept = (welded[:, 0] != welded[:, 1]) & (welded[:, 1] != welded[:, 2]) & (welded[:, 0] != welded[:, 2])
    welded = welded[kept]
    ends = numpy.concatenate([welded[:, [0, 1]], welded[:, [1, 2]], welded[:, [2, 0]]])
    ends.sort(axis=1)
    _, uses = numpy.unique(ends[:, 0] * (int(vertex.max()) + 1) + ends[:, 1], return_counts=True)
    volume = float(numpy.einsum("ij,ij->i", corners[:, 0], numpy.cross(corners[:, 1], corners[:, 2]),
                                dtype="float64").sum() / 6.0)
    return {"edges": int(uses.size), "boundary": int((uses == 1).sum()), "non_manifold": int((uses > 2).sum()),
            "volume": volume}


def _welded(positions):
    """The welded vertex of each corner: corners closer than :data:`WELD` of the extent on every axis are one.
    Snapping to one grid would split two copies a float32 step apart that straddle a cell's edge; so corners are
    joined when they share a cell in any of the 8 grids offset by half a cell along each axis (two corners under a
    quarter cell apart per axis share one of them), each key packed into one integer (17 bits an axis)."""
    import numpy  # lazy: as in primitive_surface

    low = positions.min(axis=0)
    extent = float((positions.max(axis=0) - low).max()) or 1.0
    scaled = (positions - low) / (extent * WELD * 4.0)  # (cells of 4 x WELD: corners within WELD share one)
    edges = []
    for offset in ((x, y, z) for x in (0.0, 0.5) for y in (0.0, 0.5) for z in (0.0, 0.5)):
        cells = numpy.floor(scaled + offset).astype("int64")
        keys = (cells[:, 0] << 34) | (cells[:, 1] << 17) | cells[:, 2]
        order = numpy.argsort(keys, kind="stable")
        same = keys[order[1:]] == keys[order[:-1]]
        edges.append(numpy.column_stack([order[:-1][same], order[1:][same]]))
    joined = numpy.concatenate(edges)
    if not joined.size:
        return numpy.arange(len(positions))
    return components(joined, len(positions))


def _handedness(corners, normals, tangents, uv) -> dict:
    """``{"checked", "mixed", "minority"}``: triangles counted, and how many turn against the majority, for the
    worse of the frame's two axes: the authored bitangent against dP/dv (mirrored islands with w not flipped) and the
    authored tangent against dP/du (mirrored islands whose tangents do not follow u)."""
    import numpy  # lazy: as in primitive_surface

    du1, dv1 = (uv[:, 1] - uv[:, 0]).T
    du2, dv2 = (uv[:, 2] - uv[:, 0]).T
    determinant = du1 * dv2 - du2 * dv1
    scale = numpy.abs(uv.reshape(-1, 2).max(axis=0) - uv.reshape(-1, 2).min(axis=0)).max() or 1.0
    usable = numpy.abs(determinant) > 1e-12 * scale * scale
    safe = numpy.where(usable, determinant, 1.0)[:, None]
    edge1, edge2 = corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0]
    along_v = (du1[:, None] * edge2 - du2[:, None] * edge1) / safe  # dP/dv
    along_u = (dv2[:, None] * edge1 - dv1[:, None] * edge2) / safe  # dP/du
    signs = numpy.sign(tangents[:, :, 3])
    usable &= (signs[:, 0] == signs[:, 1]) & (signs[:, 1] == signs[:, 2]) & (signs[:, 0] != 0)
    tangent = tangents[:, :, :3].sum(axis=1)
    bitangent = numpy.cross(normals.sum(axis=1), tangent) * signs[:, :1]
    worst = {"checked": 0, "minority": 0, "mixed": 0.0}
    for derived, authored in ((along_v, bitangent), (along_u, tangent)):
        lengths = numpy.linalg.norm(derived, axis=1) * numpy.linalg.norm(authored, axis=1)
        cosine = numpy.einsum("ij,ij->i", derived, authored) / numpy.where(lengths > 0, lengths, 1.0)
        counted = usable & (lengths > 0) & (numpy.abs(cosine) >= TURN_COSINE)
        turns = numpy.sign(cosine[counted])
        checked = int(turns.size)
        minority = int(min((turns > 0).sum(), (turns < 0).sum())) if checked else 0
        if checked and minority / checked > worst["mixed"]:
            worst = {"checked": checked, "minority": minority, "mixed": minority / checked}
        elif not worst["checked"]:
            worst["checked"] = checked
    return worst


def components(edges, count: int):
    """The connected component of each of ``count`` vertices joined by ``edges`` (pairs), as the smallest vertex of
    each: hooking every vertex to its smallest neighbour's label, then pointer jumping, until nothing changes."""
    import numpy  # lazy: as in primitive_surface

    label = numpy.arange(count)
    while True:
        a, b = label[edges[:, 0]], label[edges[:, 1]]
        hooked = label.copy()
        numpy.minimum.at(hooked, a, numpy.minimum(a, b))
        numpy.minimum.at(hooked, b, numpy.minimum(a, b))
        while True:
            jumped = hooked[hooked]
            if (jumped == hooked).all():
                break
            hooked = jumped
        if (hooked == label).all():
            return label
        label = hooked
