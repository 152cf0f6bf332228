"""What a primitive's vertex data does to the material drawn on it: its vertex colour and its texture coordinates.

glTF 2.0, 3.7.2.1 Meshes: "if a primitive specifies a vertex color using the attribute semantic property COLOR_0,
then this value acts as an additional linear multiplier to base color", so a COLOR_0 that is black on every vertex
draws the material black whatever its base colour (:func:`primitive_geometry`'s ``black_colour``). Texture
coordinates are float32 (or normalised integers in [0, 1]); two facts of each UV set a texture reads are kept:

* ``largest``: the largest magnitude of u and of v, which fixes the coarsest step float32 can take there
  (``numpy.spacing``): far from 0, neighbouring texels can no longer be told apart;
* ``udim_tiles``: for a *tile-per-triangle* layout, ``{"tiles", "tiles_with_own_islands"}``, else ``None``: every
  triangle lies within one unit square of UV space and the triangles lie in two or more of them, all in UDIM's ten
  columns; ``tiles`` are those squares as UDIM numbers (1001 + u + 10 v', v' = -floor(v), glTF's V pointing down the
  image), ``tiles_with_own_islands`` those holding a UV island confined to them (islands: triangles joined by edges
  whose ends share position and coordinates). A mapping continuous across squares, a floor repeated 0..4 with
  REPEAT wrap, is one island over many squares; UDIM islands keep to their tiles. glTF has no UDIM: a texture
  repeats, so every tile shows the one image.

Only triangle lists (mode 4, the default) are laid out; an accessor that is sparse or not FLOAT or normalised is
not read (:mod:`.accessors`, bounded to its first :data:`~.accessors.MAX_ELEMENTS` elements), nor one without a
bufferView (zeros by 3.6.2.2, but in practice a stub: no verdict on data that is not there). Each accessor's facts are
computed once (``cache``).
"""

from __future__ import annotations

from . import accessors, surfaces
from .surfaces import components as _components
from .document import GltfDocument
from .textures import json_index

_TRIANGLES = 4
_TILE_SLACK = 1e-6  # a vertex on a tile's far edge (u = 2.0 for tile 1001 + 1) still lies in that tile
_WELD = 1e5  # positions and coordinates equal to 1e-5 are one vertex when edges are matched
UDIM_COLUMNS = 10


def primitive_geometry(document: GltfDocument, primitive: dict, cache: dict) -> dict:
    """``{"black_colour": {"accessor", "count"} or None, "uv_sets": {n: {"accessor", "largest", "udim_tiles"}},
    "surface": ...}`` for one mesh primitive (see the module docstring; ``surface``: :mod:`.surfaces`, for a primitive
    with a material)."""
    attributes = primitive.get("attributes") if isinstance(primitive.get("attributes"), dict) else {}
    colour = attributes.get("COLOR_0")
    found = {"black_colour": _cached(cache, ("black", _ref(colour)), lambda: _black(document, colour)), "uv_sets": {}}
    mode = primitive.get("mode", _TRIANGLES)
    # (cache keys: an index that is no JSON index, e.g. a list, keys as None, as the readers take it as absent)
    position, index = _ref(attributes.get("POSITION")), _ref(primitive.get("indices"))
    for name, accessor in attributes.items():
        if not name.startswith("TEXCOORD_") or not name[9:].isdigit() or not json_index(accessor):
            continue
        key = ("uv", accessor, position, index, _ref(mode))
        facts = _cached(cache, key, lambda: _uv_set(document, accessor, position, index, mode))
        if facts is not None:
            found["uv_sets"][int(name[9:])] = facts
    material = document.item("materials", primitive.get("material")) if json_index(primitive.get("material")) else None
    if isinstance(material, dict):
        key = ("surface", primitive.get("material"), position, index, _ref(mode), _ref(attributes.get("NORMAL")),
               _ref(attributes.get("TANGENT")), tuple(_ref(attributes.get(f"TEXCOORD_{n}")) for n in _normal_sets(material)))
        found["surface"] = _cached(cache, key, lambda: surfaces.primitive_surface(
            document, primitive, _volume_thickness(material), _normal_sets(material)))
    return found


def _volume_thickness(material: dict) -> bool:
    """A KHR_materials_volume with a thickness above 0 (a volume boundary, not a thin wall)."""
    extensions = material.get("extensions") if isinstance(material.get("extensions"), dict) else {}
    volume = extensions.get("KHR_materials_volume")
    thickness = volume.get("thicknessFactor", 0.0) if isinstance(volume, dict) else 0.0
    return isinstance(thickness, (int, float)) and not isinstance(thickness, bool) and thickness > 0


def _normal_sets(material: dict) -> tuple:
    """The UV sets the material's normal textures read (normalTexture, KHR_materials_clearcoat's
    clearcoatNormalTexture)."""
    extensions = material.get("extensions") if isinstance(material.get("extensions"), dict) else {}
    coat = extensions.get("KHR_materials_clearcoat")
    coat = coat if isinstance(coat, dict) else {}
    sets = set()
    for info in (material.get("normalTexture"), coat.get("clearcoatNormalTexture")):
        if isinstance(info, dict) and json_index(info.get("index")):
            texcoord = info.get("texCoord", 0)
            if json_index(texcoord):
                sets.add(texcoord)
    return tuple(sorted(sets))


def _ref(value):
    """``value`` where it is a JSON index (or a plain number: a mode), else None: hashable for the caches."""
    return value if isinstance(value, (int, float, str)) or value is None else None


def _cached(cache: dict, key, compute):
    if key not in cache:
        cache[key] = compute()
    return cache[key]


def _black(document: GltfDocument, index) -> dict | None:
    accessor = document.item("accessors", index) if json_index(index) else None
    if accessor is None or accessor.get("type") not in ("VEC3", "VEC4") or not json_index(accessor.get("count")):
        return None
    values = accessors.vectors(document, index)
    if values is None or values.shape[0] < accessor["count"] or not values.size:  # (not read whole: no verdict)
        return None
    return {"accessor": index, "count": accessor["count"]} if not values[:, :3].any() else None


def _uv_set(document: GltfDocument, index, position, indices, mode) -> dict | None:
    import numpy  # lazy: only for a file with mesh data

    uv = accessors.vectors(document, index)
    if uv is None or uv.shape[1] != 2:
        return None
    finite = numpy.isfinite(uv).all(axis=1)
    largest = numpy.abs(uv[finite]).max(axis=0).tolist() if finite.any() else [0.0, 0.0]
    tiles = _udim_tiles(document, uv, position, indices) if mode == _TRIANGLES and finite.all() else None
    return {"accessor": index, "largest": largest, "udim_tiles": tiles}


def _udim_tiles(document: GltfDocument, uv, position, index) -> dict | None:
    import numpy  # lazy: as in _uv_set

    if numpy.floor(uv.min(axis=0)).tolist() == numpy.floor(uv.max(axis=0) - _TILE_SLACK).tolist():
        return None  # one unit square holds all: no layout across tiles (the common case, decided without indices)
    triangles = surfaces.triangle_list(document, index, uv.shape[0])
    if triangles is None or not len(triangles):
        return None
    coordinates = uv[triangles]  # (triangles, 3 corners, u v)
    low = numpy.floor(coordinates.min(axis=1))
    if (coordinates.max(axis=1) > low + 1.0 + _TILE_SLACK).any():
        return None  # a triangle crosses a tile's edge: a continuous (tiling) mapping
    squares = numpy.unique(low, axis=0)
    if len(squares) < 2 or not ((squares[:, 0] >= 0) & (squares[:, 0] < UDIM_COLUMNS) & (squares[:, 1] <= 0)).all():
        return None
    positions = accessors.vectors(document, position) if json_index(position) else None
    if positions is None or positions.shape[0] != uv.shape[0] or positions.shape[1] != 3:
        return None
    welded = numpy.round(numpy.hstack([positions, uv]) * _WELD)
    _, vertex = numpy.unique(welded, axis=0, return_inverse=True)
    vertex = vertex.reshape(-1)[triangles]
    island = _components(numpy.concatenate([vertex[:, :2], vertex[:, 1:]]), int(vertex.max()) + 1)[vertex[:, 0]]
    tile = (low[:, 0] - UDIM_COLUMNS * low[:, 1]).astype("int64")  # (u, -v) -> u + 10 v'
    pairs = numpy.unique(numpy.column_stack([island, tile]), axis=0)
    islands, spans = numpy.unique(pairs[:, 0], return_counts=True)
    confined = pairs[numpy.isin(pairs[:, 0], islands[spans == 1]), 1]
    return {"tiles": sorted(int(1001 + t) for t in numpy.unique(tile)),
            "tiles_with_own_islands": sorted(int(1001 + t) for t in numpy.unique(confined))}
