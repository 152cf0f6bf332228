"""Whether a mesh's UV primvar gives texture coordinates a renderer uses (io/usd/reader.py reads them for
OPBR1015): its interpolation, and its element count for that interpolation (UsdGeomPrimvar's documentation);
and, for the meshes a textured Material is bound to, what UsdGeom makes of the UVs as authored
(:func:`observe_textured_uvs`: not inherited, unreadable indices, smoothed by subdivision)."""

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
    if not (_array(counts) and _array(points)):  # (none authored, or a value of another type: the validators')
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


#: primvar types that hold texture coordinates (the texCoord role, or plain two-component floats)
UV_TYPES = frozenset(("texCoord2f[]", "texCoord2d[]", "texCoord2h[]", "float2[]", "double2[]", "half2[]"))


def observe_textured_uvs(UsdGeom, meshes, observe, location) -> None:
    """What UsdGeom makes of the UVs of ``meshes`` (those bound to a Material that reads a texture):

    - ``usd_uv_not_inherited``: an ancestor (an Xform) authors a UV primvar of another interpolation than
      constant, which the mesh does not author itself: only constant primvars inherit
      (UsdGeomPrimvarsAPI.FindPrimvarWithInheritance), so the mesh has no such UVs;
    - ``usd_uv_indices_type``: the mesh's UV primvar has ``:indices`` authored as another type than int[]
      (uint[]): IsIndexed is true but GetIndices reads nothing, and ComputeFlattened fails;
    - ``usd_uv_smoothed``: a subdivided mesh (subdivisionScheme other than none; catmullClark is the fallback)
      with faceVarying UVs and faceVaryingLinearInterpolation "none" ("No linear constraints or sharpening, smooth
      everywhere"), so the UV borders and corners are smoothed like positions. Not where meshes of the same
      stage show several faceVaryingLinearInterpolation values side by side (a comparison of the settings, as
      OpenUSD's testUsdImagingGLFaceVarying scenes are)."""
    ancestors: dict = {}
    uninherited: dict[tuple[str, str, str], list[str]] = {}  # (owner, primvar, interpolation) -> meshes without it
    smoothed = []
    settings = set()
    for mesh in meshes:
        api = UsdGeom.PrimvarsAPI(mesh)
        own = {str(p.GetPrimvarName()): p for p in api.GetPrimvarsWithAuthoredValues() if str(p.GetTypeName()) in UV_TYPES}
        for name, (owner, interpolation) in _ancestor_uvs(UsdGeom, mesh.GetParent(), ancestors).items():
            if name not in own and not api.FindPrimvarWithInheritance(name):
                uninherited.setdefault((owner, name, interpolation), []).append(str(mesh.GetPath()))
        for name, primvar in own.items():
            indices = mesh.GetAttribute(f"{primvar.GetAttr().GetName()}:indices")
            if indices and indices.HasAuthoredValue() and str(indices.GetTypeName()) != "int[]":
                observe("usd_uv_indices_type", location(mesh.GetPath(), f"primvars:{name}:indices"),
                        mesh=str(mesh.GetPath()), primvar=name, type=str(indices.GetTypeName()))
        geometry = UsdGeom.Mesh(mesh)
        linear = str(geometry.GetFaceVaryingLinearInterpolationAttr().Get() or "")
        settings.add(linear)
        face_varying = sorted(n for n, p in own.items() if p.GetInterpolation() == UsdGeom.Tokens.faceVarying)
        if linear == "none" and face_varying and str(geometry.GetSubdivisionSchemeAttr().Get() or "") != "none":
            smoothed.append((mesh, face_varying[0], str(geometry.GetSubdivisionSchemeAttr().Get())))
    for (owner, name, interpolation), without in uninherited.items():  # once per primvar, naming its meshes
        observe("usd_uv_not_inherited", location(owner, f"primvars:{name}"), meshes=without, primvar=name, owner=owner,
                interpolation=interpolation)
    if len(settings) > 1:
        return  # the stage compares the settings side by side
    for mesh, name, scheme in smoothed:
        observe("usd_uv_smoothed", location(mesh.GetPath(), "faceVaryingLinearInterpolation"), mesh=str(mesh.GetPath()),
                primvar=name, scheme=scheme)


def _ancestor_uvs(UsdGeom, prim, cache: dict) -> dict[str, tuple[str, str]]:
    """UV primvar name -> (the nearest ancestor authoring it, its interpolation) of the primvars ``prim`` and its
    ancestors author with an interpolation other than constant (those no descendant inherits)."""
    chain = []
    while prim and not prim.IsPseudoRoot() and prim.GetPath() not in cache:
        chain.append(prim)
        prim = prim.GetParent()
    found = dict(cache.get(prim.GetPath(), {})) if prim else {}
    for ancestor in reversed(chain):  # outermost first: a nearer ancestor's primvar replaces a farther one's
        found = dict(found)
        for primvar in UsdGeom.PrimvarsAPI(ancestor).GetPrimvarsWithAuthoredValues():
            name = str(primvar.GetPrimvarName())
            if str(primvar.GetTypeName()) in UV_TYPES and primvar.GetInterpolation() != UsdGeom.Tokens.constant:
                found[name] = (str(ancestor.GetPath()), str(primvar.GetInterpolation()))
            else:
                found.pop(name, None)  # a constant one of that name is inherited instead
        cache[ancestor.GetPath()] = found
    return cache.get(chain[0].GetPath(), found) if chain else found


def primvar_type_problem(primvar) -> str | None:
    """Why a primvar a UsdPrimvarReader_float2 reads as texture coordinates cannot give them: its type has
    other than two components (a ``color3f[] primvars:st``), so the reader finds no float2 primvar of that name
    and returns its fallback; ``None`` for a two-component type (texCoord2f, float2, double2, half2)."""
    if not primvar:
        return None
    type_name = primvar.GetTypeName()
    try:
        components = len(type_name.scalarType.defaultValue)
    except TypeError:  # a scalar (float, int, token)
        components = 1
    if components == 2:
        return None
    return f"is {type_name}, not a two-component type (texCoord2f[]), so a float2 reader does not find it"


def _array(value) -> bool:
    """Whether a topology attribute's value is an array (not None, nor a path or token authored in its place)."""
    return value is not None and not isinstance(value, (str, bytes)) and hasattr(value, "__len__")
