"""Whether a mesh's UV primvar gives texture coordinates a renderer uses (io/usd/reader.py reads them for
OPBR1015): its interpolation, and its element count for that interpolation (UsdGeomPrimvar's documentation)."""

from __future__ import annotations


def primvar_problem(UsdGeom, mesh, primvar) -> str | None:
    """Why a mesh's own primvar has the wrong number of elements for its interpolation (constant 1, uniform one per
    face, vertex and varying one per point, faceVarying one per face-vertex; an indexed primvar's indices count,
    and each must name a value), as UsdGeomPrimvar documents them; ``None`` when it fits or cannot be judged (no
    topology authored, a primvar inherited from an ancestor)."""
    if not primvar or not primvar.HasAuthoredValue() or primvar.GetAttr().GetPrim() != mesh:
        return None
    geometry = UsdGeom.Mesh(mesh)
    counts, points = geometry.GetFaceVertexCountsAttr().Get(), geometry.GetPointsAttr().Get()
    if counts is None or points is None:
        return None
    interpolation = str(primvar.GetInterpolation())
    if interpolation in ("constant", "uniform"):  # one UV for the mesh, or per face: no texture coordinates
        return (f"is {interpolation}: one UV per {'mesh' if interpolation == 'constant' else 'face'}, so each "
                f"{'mesh' if interpolation == 'constant' else 'face'} shows a single texel")
    needed = {"constant": 1, "uniform": len(counts), "vertex": len(points), "varying": len(points),
              "faceVarying": int(sum(counts))}.get(interpolation)
    values = primvar.Get()
    if needed is None or values is None:
        return None
    element = max(1, primvar.GetElementSize())
    if primvar.IsIndexed():
        indices = primvar.GetIndices() or ()
        if len(indices) != needed * element:
            return f"has {len(indices)} indices where {interpolation} interpolation needs {needed * element}, so renderers drop it"
        if len(indices) and (min(indices) < 0 or max(indices) >= len(values)):
            return f"has indices outside its {len(values)} values, so renderers drop it"
        return None
    if len(values) != needed * element:
        return f"has {len(values)} values where {interpolation} interpolation needs {needed * element}, so renderers drop it"
    return None
