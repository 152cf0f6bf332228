"""Following USD shading connections: from a shader input to a constant (through Material and
NodeGraph interfaces, and MaterialX ``dot`` and ``constant`` nodes, which hand their input on), a texture lookup,
or a node the toolkit does not interpret.

Part of the USD reader (:mod:`.reader`), kept apart because it is its own idea: how UsdShade
networks encode what the model calls a :class:`~openpbr_tools.model.Texture`. This module walks
connections (through node-graph and material interfaces, checking that connected types line up),
reads colour spaces and locates texture files; which nodes make a texture lookup (MaterialX image
chains, ``UsdUVTexture``) is :mod:`.texture_nodes`'s, and attribute values as plain Python are
:mod:`.attributes`'.
"""

from __future__ import annotations

import os
import posixpath

from ...model import Connection, Input, Texture
from ..paths import Kind, classify
from .attributes import MAX_SAMPLES, input_name, read_constant, read_constant_at, value_shape
from .sdr import defined_output_type
from .texture_nodes import TextureNodeReader

MAX_DEPTH = 32


class NetworkReader(TextureNodeReader):
    """Connection-following half of the USD reader. Expects ``stage``, ``asset``, ``path``,
    ``root_layer``, ``root_dir``, ``UsdShade``, ``Usd``, ``colorspace_of_prim``,
    ``observed_colorspaces`` and ``location()``."""

    # -- colour spaces ----------------------------------------------------------------------
    def authored_prim_colorspace(self, prim) -> str | None:
        attribute = prim.GetAttribute("colorSpace:name")
        if attribute and attribute.HasAuthoredValue():
            return str(attribute.Get())
        return None

    def inherited_colorspace(self, prim) -> str | None:
        """The ``Usd.ColorSpaceAPI`` name in effect at ``prim`` (its own or the nearest ancestor's).
        Walks up without recursion: prims may nest deeper than Python's stack."""
        walked = []
        name = None
        while prim and not prim.IsPseudoRoot():
            key = prim.GetPath()
            if key in self.colorspace_of_prim:
                name = self.colorspace_of_prim[key]
                break
            walked.append(key)
            if prim.HasAPI(self.Usd.ColorSpaceAPI):
                name = self.authored_prim_colorspace(prim)
                if name is not None:
                    break
            prim = prim.GetParent()
        for key in walked:
            self.colorspace_of_prim[key] = name
        return name

    def attribute_colorspace(self, attribute, scheme: str, colour_output: bool | None = None) -> str | None:
        """The attribute's ``colorSpace`` metadata, observed for the naming-scheme check.
        ``colour_output``: whether the node's output is a colour (MaterialX converts only those)."""
        if not attribute.HasColorSpace():
            return None
        name = str(attribute.GetColorSpace())
        self.observe_colorspace(self.location(attribute.GetPrim().GetPath(), input_name(attribute)), name, scheme,
                                "colorSpace metadata", colour_output)
        return name

    def observe_colorspace(self, where, name: str, scheme: str, owner: str, colour_output: bool | None = None) -> None:
        """Record a colour-space name and the scheme its place wants, once per place (a texture
        node read by two inputs is one place)."""
        key = (where.path, where.input, name)
        if key not in self.observed_colorspaces:
            self.observed_colorspaces.add(key)
            self.asset.observe("usd_colorspace", where, name=name, scheme=scheme, owner=owner,
                               colour_output=colour_output)

    # -- connections ------------------------------------------------------------------------
    def source(self, attribute):
        """Follow ``attribute``'s connection through node-graph and material interfaces.

        Returns ``("shader", prim, output_name, interface_name)``, ``("value", attribute,
        interface_name)`` for an attribute that is not connected (its own value, if any, applies),
        or ``("dangling", target, reason)``.
        """
        interface = None
        for _ in range(MAX_DEPTH):
            targets = attribute.GetConnections()
            if not targets:
                return ("value", attribute, interface)
            target = targets[0]
            prim = self.stage.GetPrimAtPath(target.GetPrimPath())
            if not prim:
                return ("dangling", str(target), f"no prim at {target.GetPrimPath()}")
            property_name = str(target.name)
            if prim.IsA(self.UsdShade.Shader):
                if not property_name.startswith("outputs:"):
                    return ("dangling", str(target), "a connection must name a shader output")
                passed = _passed_through(prim, property_name, self.UsdShade)
                if passed:  # a MaterialX dot or constant node hands its input on unchanged
                    attribute = passed
                    continue
                return ("shader", prim, property_name[len("outputs:"):], interface)
            if prim.IsA(self.UsdShade.NodeGraph):
                upstream = prim.GetAttribute(property_name)
                if not upstream:
                    return ("dangling", str(target), f"{prim.GetPath()} has no {property_name}")
                if property_name.startswith("inputs:") and interface is None:
                    interface = property_name[len("inputs:"):]
                attribute = upstream
                continue
            return ("dangling", str(target), f"{prim.GetPath()} is a {prim.GetTypeName() or 'typeless prim'}, not a shader or node graph")
        return ("dangling", str(attribute.GetPath()), "connection cycle")

    def interpret(self, attribute, entry: Input, consumer):
        kind, *found = self.source(attribute)
        if kind == "dangling":
            target, reason = found
            return Connection(target, None, reason, dangling=True)
        if kind == "value":
            origin, interface = found
            entry.interface_name = interface
            if origin is not attribute:
                if not self.check_connection_type(entry, origin, str(origin.GetTypeName())):
                    return None  # OPBR1005: the value cannot be read as the input's type
                if origin.HasColorSpace() and not entry.authored_colorspace:
                    entry.authored_colorspace = self.attribute_colorspace(
                        origin, "materialx" if consumer[1] == "mtlx" else "usd")
                    entry.colorspace = entry.authored_colorspace
            constant = read_constant(origin)
            if origin.GetNumTimeSamples() > 1 and consumer[2] is not None:  # animated: every sample is a value
                samples = [(float(time), read_constant_at(origin, time)) for time in origin.GetTimeSamples()[:MAX_SAMPLES]]
                self.asset.observe("usd_time_samples", entry.location, input=entry.name, model=consumer[0],
                                   samples=[s for s in samples if constant is None or s[1] != constant.value])
            return constant
        prim, output_name, interface = found
        entry.interface_name = interface
        value = self.texture_chain(prim, output_name, entry, consumer)
        if not isinstance(value, Texture):
            self.check_connection_type(entry, prim.GetAttribute(f"outputs:{output_name}"),
                                       self.declared_output_type(prim, output_name))
        return value

    def check_connection_type(self, entry: Input, origin, origin_type: str | None) -> bool:
        """Record a connection between attributes whose values cannot line up (a ``float`` source
        for a ``color3f`` input): USD does not convert, renderers read garbage or the default.
        Returns whether the types line up."""
        if origin_type is None:
            return True
        if value_shape(origin_type) == value_shape(entry.source_type):
            return True
        self.asset.observe(
            "usd_connection_type_mismatch", entry.location, input=entry.name,
            source=str(origin.GetPath()) if origin else None, source_type=origin_type, input_type=entry.source_type,
        )
        return False

    def declared_output_type(self, prim, output_name: str) -> str | None:
        """The type of a shader's output as renderers take it: the node definition's where the id names one
        (Storm builds the network from Sdr's definition, hdMtlx from MaterialX's; OpenUSD's
        testUsdImagingGLGeomSubsets authors a UsdPrimvarReader_float3's result as float2 and renders its colours),
        else the type authored on the prim. An authored type of another shape than the definition's is observed."""
        attribute = prim.GetAttribute(f"outputs:{output_name}")
        authored = str(attribute.GetTypeName()) if attribute else None
        shader_id = str(self.UsdShade.Shader(prim).GetShaderId() or "")
        defined = defined_output_type(shader_id, output_name)
        if defined is None:
            return authored
        key = str(prim.GetPath()), output_name
        if authored and value_shape(authored) != value_shape(defined) and key not in self.mistyped_outputs:
            self.mistyped_outputs.add(key)
            self.asset.observe("usd_output_type_differs", self.location(prim.GetPath(), f"outputs:{output_name}"),
                               output=str(attribute.GetPath()), id=shader_id, authored=authored, defined=defined)
        return defined

    def upstream(self, prim, input_name: str):
        attribute = prim.GetAttribute(f"inputs:{input_name}")
        if not attribute:
            return ("value", None, None)
        return self.source(attribute)

    def file_of(self, attribute) -> tuple[str, bool]:
        """The texture path relative to the asset's folder (or inside its package), and whether it
        is packaged. A path authored in another layer is re-anchored at the root layer's folder; a file input
        connected to an interface input reads that input's path (where it was authored)."""
        if not attribute:
            return "", False
        if attribute.HasAuthoredConnections():  # a file from a Material or NodeGraph interface input: its value
            kind, *found = self.source(attribute)
            if kind != "value" or found[0] is None:
                return "", False
            attribute = found[0]
        value = attribute.Get()
        if value is None and attribute.GetNumTimeSamples():  # an animated texture: its first file
            from pxr import Usd  # lazy: pxr only once the reader has required it and opened a stage

            value = attribute.Get(Usd.TimeCode.EarliestTime())
        authored = getattr(value, "path", None) if value is not None else None
        if not authored:
            return "", False
        # No file name holds a NUL, and path functions raise on one: shown as U+FFFD (still not found)
        authored = authored.replace("\0", "\ufffd")
        layer = self.root_layer
        for spec in attribute.GetPropertyStack():
            if spec.HasDefaultValue() or spec.HasInfo("timeSamples"):
                layer = spec.layer
                break
        packaged = ".usdz" in layer.identifier.lower()
        if packaged and classify(authored) is Kind.RELATIVE and "[" not in authored:
            # a member of the package: relative to the packaged layer's own folder inside it ("./a.png" of
            # the package's first layer is the member "a.png"); one that climbs out of the package stays as authored
            packages, inner = _package_chain(layer.identifier)
            member = posixpath.normpath(posixpath.join(posixpath.dirname(inner), authored.replace("\\", "/")))
            if member.startswith(".."):
                return authored, True
            for package in reversed(packages):  # a nested package's member: "parts/bolt.usdz[textures/a.png]"
                member = f"{package}[{member}]"
            if not packages and member not in self.asset.extra.get("package_files", ()):
                outside = self.resolved_beside_package(value, authored, layer)
                if outside is not None:  # not in the package, but usd-core finds it on disk: a file, not a member
                    return os.path.relpath(outside, self.root_dir).replace(os.sep, "/"), False
            return member, True
        if packaged or layer.identifier == self.root_layer.identifier or classify(authored) is not Kind.RELATIVE:
            return authored, packaged  # as authored: a URL, an absolute, drive or UNC path is not re-anchored
        if not layer.realPath:
            return authored, False
        # USD's resolver looks a relative path up beside the layer that authored it first; spelled
        # relative to the root layer's folder (whether that stays inside is the texture rules' call)
        anchored = os.path.normpath(os.path.join(os.path.dirname(layer.realPath), authored))
        return os.path.relpath(anchored, self.root_dir).replace(os.sep, "/"), False

    def resolved_beside_package(self, value, authored: str, layer) -> str | None:
        """Where usd-core resolves a packaged layer's relative asset path that the package does not hold, when
        that is a file on disk: a search-path style name (``texture.png``, not ``./texture.png``) is looked up in
        the package first, then beside it (ArDefaultResolver), and UDIM tiles likewise
        (UsdShade.UdimUtils.ResolveUdimTilePaths). ``None`` where usd-core finds nothing or a package member."""
        if self.UsdShade.UdimUtils.IsUdimIdentifier(authored):
            tiles = self.UsdShade.UdimUtils.ResolveUdimTilePaths(authored, layer)
            found = os.path.join(os.path.dirname(tiles[0][0]), os.path.basename(authored)) if tiles else ""
        else:
            found = getattr(value, "resolvedPath", "") or ""
        return found if found and "[" not in found and os.path.isabs(found) else None


#: MaterialX nodes whose output is their one input (stdlib_defs.mtlx: ND_dot_* "in", ND_constant_* "value").
_PASS_THROUGH = {"ND_dot_": "inputs:in", "ND_constant_": "inputs:value"}


def _passed_through(prim, output: str, usd_shade):
    """The input of a ``ND_dot_*`` or ``ND_constant_*`` shader whose ``out`` a connection reads, where it is
    authored (its value or its own connection); ``None`` for any other node."""
    if output != "outputs:out":
        return None
    shader_id = str(usd_shade.Shader(prim).GetShaderId() or "")
    for prefix, name in _PASS_THROUGH.items():
        if shader_id.startswith(prefix):
            attribute = prim.GetAttribute(name)
            return attribute if attribute and (attribute.HasAuthoredValue() or attribute.HasAuthoredConnections()) \
                else None
    return None


def _package_chain(identifier: str) -> tuple[list[str], str]:
    """The packages nested inside the root package, outermost first, and the layer's path inside the
    innermost: ``a.usdz[parts/b.usdz[b.usda]]`` gives (["parts/b.usdz"], "b.usda"), as does
    ``a.usdz[parts/b.usdz]`` (the nested package's first layer, as usd-core names it) with ""; a layer
    of the root package itself, ([], its path)."""
    if not identifier.endswith("]") or "[" not in identifier:
        return [], ""
    inside = identifier.split("[", 1)[1][:-1]
    packages = []
    while "[" in inside and inside.endswith("]"):
        package, inside = inside.split("[", 1)
        packages.append(package)
        inside = inside[:-1]
    if inside.lower().endswith(".usdz"):  # a nested package named alone: its first layer, at its root
        packages.append(inside)
        inside = ""
    return packages, inside
