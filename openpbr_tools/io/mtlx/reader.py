"""Read MaterialX documents into :class:`~openpbr_tools.model.Asset` objects.

Parsing is MaterialX's (``MaterialX.readFromXmlString``, XInclude disabled so a document can never
make the reader open another file); line numbers and duplicate children come from the expat
pre-pass in :mod:`.xmlscan`. Every ``open_pbr_surface``, ``standard_surface``, ``gltf_pbr`` and
``UsdPreviewSurface`` node is read wherever it sits (top level or inside a node graph), whether or
not a ``surfacematerial`` or a look reaches it, except inside a node graph that implements a node
definition (a definition, not a material). A material whose shader is a custom node defined by such
a graph around one of those shaders is read as that shader with the node's values bound to its
interface (:meth:`_Reader.expand_custom_shader`); any other shader is an ``unsupported_shader``
observation (OPBR805; a conversion reports it). A shader of an XIncluded document that a material here
binds is read with that material (it converts with it) and checked in its own document, where the
includer's material binds it (:meth:`_Reader.included_shader`, :meth:`_Reader.bound_by_includer`).

One module because one walk over the composed document reads shaders, materials, looks and the bindings
between them, which refer to one another; the graph walk behind an input is :mod:`.graph`'s.

Each shader input becomes an :class:`~openpbr_tools.model.Input` whose value is

* a :class:`Constant` parsed strictly from the value string (see :mod:`openpbr_tools.values`), or
  from a ``constant`` node (through ``dot`` nodes) that feeds the input;
* a :class:`Texture` when the upstream chain is an ``image``/``tiledimage`` node, optionally through
  ``extract``, ``convert``, ``normalmap``, ``multiply``/``add`` by constants (its scale and bias; a
  UsdPreviewSurface's ``normal`` is then a tangent-space vector, decoded by them, as in USD) and, on
  the texture coordinates, ``place2d`` and ``texcoord``; through ``nodegraph``/``output`` and
  ``interfacename`` indirections;
* a :class:`Connection` otherwise: a procedural graph (kept and reported) or a reference that does
  not resolve (``dangling``).
"""

from __future__ import annotations

import os

from ... import colorspaces, gltf_state, versioning
from ...model import Asset, Connection, Constant, Input, Location, Material
from ...values import ValueSyntaxError, parse_value
from .. import ReadError, read_bytes
from ..paths import PathGuard
from . import library
from .capture import capture_graph
from .graph import GraphFollower, in_definition, interface_colorspace
from .looks import record_looks
from .includes import follow_includes, import_includer
from .document_checks import observe_document
from .xmlscan import (XmlSyntaxError, decode_document, message_sites, parse_suppression, scan, scan_with_materialx,
                      upgrade_changes_nothing)

SHADER_CATEGORIES = ("open_pbr_surface", "standard_surface", "gltf_pbr", "UsdPreviewSurface")
MATERIAL_CATEGORIES = ("surfacematerial",)


def known_categories(complete: bool = False) -> frozenset[str]:
    """The node categories MaterialX's standard libraries define (``complete``: with those only
    their implementation files declare), from the cached library index (:mod:`.library`)."""
    return library.known_categories(complete)


def is_known_category(category: str) -> bool:
    return category in known_categories() or category in known_categories(complete=True)


def read_mtlx(path: str, data: bytes | None = None, allow_outside: tuple[str, ...] = (),
              included_by: str | None = None) -> Asset:
    """Read the MaterialX document at ``path`` (or ``data``, named ``path``). XIncludes are followed inside its folder
    or one in ``allow_outside``; ``included_by`` (:func:`.includes.import_includer`) is the document including it."""
    import MaterialX as mx  # lazy: as in library.standard_library

    if data is None:
        data = read_bytes(path)
    try:
        text = decode_document(data)
    except UnicodeDecodeError as error:
        raise ReadError(
            "unreadable", f"not text in its declared encoding ({error.encoding}; UTF-8 where none is declared): "
                          f"{error.reason} at byte {error.start}", Location(path),
        ) from None
    except LookupError:  # (expat refuses it as malformed: "unknown encoding")
        raise ReadError("not_materialx", "not well-formed XML: the XML declaration names an encoding no XML parser "
                        "knows", Location(path, line=1)) from None
    lenient_error = None
    try:
        structure = scan(data)
    except XmlSyntaxError as error:
        if error.fatal:
            raise ReadError("not_materialx", str(error), Location(path, line=error.line)) from None
        # MaterialX's parser (pugixml) accepts some documents expat rejects; judge by MaterialX,
        # and report the malformation as a finding instead of refusing the file.
        structure = scan_with_materialx(text)
        if structure is None:
            raise ReadError(
                "not_materialx", f"not well-formed XML: {error} (line {error.line}, column {error.column})",
                Location(path, line=error.line),
            ) from None
        lenient_error = error
    if structure.root_tag != "materialx":
        raise ReadError(
            "not_materialx",
            f"root element is <{structure.root_tag}>, not <materialx>",
            Location(path, line=1),
        )
    document = mx.createDocument()
    options = mx.XmlReadOptions()
    options.readXIncludeFunction = None
    try:
        mx.readFromXmlString(document, text, mx.FileSearchPath(), options)
    except Exception as error:  # MaterialX raises its own exception types for parse failures
        raise ReadError("not_materialx", f"MaterialX cannot read the document: {error}", Location(path)) from None
    guard = PathGuard.for_asset(path, allow_outside)
    shadowed: list[tuple[str, str]] = []  # (the document's own element, the include that defines it too)
    followed: list[str] = []  # every file the includes read: validated as files of their own too
    not_followed = follow_includes(document, path, structure.xincludes, guard,
                                   {guard.resolve(os.path.abspath(path)).real}, shadowed=shadowed, followed=followed)

    asset = Asset(path=path, format="mtlx", line_of=structure.lines, suppressions=dict(structure.suppressions))
    if included_by is not None and import_includer(document, included_by, allow_outside):
        asset.extra["included_by"] = included_by
    asset.format_version = structure.root_attributes.get("version")
    asset.extra["upgrade_changes_nothing"] = lenient_error is None and upgrade_changes_nothing(data, document, asset.format_version)
    asset.colorspace = structure.root_attributes.get("colorspace") or None
    asset.colorspace_location = Location(path, line=1, path="", input=None)
    asset.extra["included_documents"] = tuple(dict.fromkeys(followed))
    if lenient_error is not None:
        asset.observe("malformed_xml", Location(path, lenient_error.line),
                      message=f"{lenient_error} (line {lenient_error.line}, column {lenient_error.column})")
    _Reader(asset, document, structure).run()
    observe_document(document, asset, path, guard)
    for line, href, reason, broken in not_followed:
        asset.observe("xinclude_broken" if broken else "xinclude", Location(path, line), href=href, reason=reason)
    for name, href in shadowed:  # MaterialX reads the include's first and drops the document's own
        asset.observe("duplicate_element", Location(path, structure.lines.get(name), name), first_in=href, name=name)
    _remapped_colorspaces(asset)
    return asset


def _remapped_colorspaces(asset: Asset) -> None:
    """Colour-space names MaterialX's colour management maps itself (lin_ap1, gamma22, lin_p3d65_scene) read as
    the cmlib names they stand for, as MaterialX reads them: known, and converted by them."""
    asset.colorspace = colorspaces.materialx_remapped(asset.colorspace)
    for material in asset.materials:
        for entry in material.inputs.values():
            entry.colorspace = colorspaces.materialx_remapped(entry.colorspace)
            entry.authored_colorspace = colorspaces.materialx_remapped(entry.authored_colorspace)
            if entry.texture is not None:
                entry.texture.colorspace = colorspaces.materialx_remapped(entry.texture.colorspace)


class _Reader(GraphFollower):
    def __init__(self, asset: Asset, document, structure) -> None:
        self.asset = asset
        self.document = document
        self.structure = structure
        self.path = asset.path

    def location(self, element, input_name: str | None = None) -> Location:
        name_path = element.getNamePath()
        return Location(self.path, self.asset.line_of.get(name_path), name_path, input_name)

    def run(self) -> None:
        import MaterialX as mx  # lazy: as in library.standard_library

        used = {element.getCategory() for element in self.document.traverseTree() if element.isA(mx.Node)}
        self.document.setDataLibrary(library.library_for(used))
        valid, message = self.document.validate() if "included_by" not in self.asset.extra else (True, "")
        if not valid:
            self.asset.extra["materialx_validate"] = message.strip()
            self.asset.extra["materialx_validate_sites"] = message_sites(self.document, message)
        shaders: dict[str, Material] = {}
        root_doc = self.document.getDocString()
        if root_doc:
            self._doc_suppression("", root_doc)
        for element in self.document.traverseTree():
            if element.getActiveSourceUri():
                continue  # included (XInclude): resolves references here, validated as its own file
            if element.getCategory() in ("input", "output") and element.getNodeName() and not element.getOutputString():
                node = element.getConnectedNode()  # a multi-output node named without output=: its first output
                if node is not None and node.getType() == "multioutput" and element.getType() != "multioutput":
                    self.asset.observe("multioutput_unnamed", self.location(element.getParent(), element.getName())
                                       if element.getCategory() == "input" else self.location(element),
                                       node=node.getNamePath(), category=node.getCategory())
            if element.hasAttribute("doc"):
                self._doc_suppression(element.getNamePath(), element.getDocString())
            if not element.isA(mx.Node):
                if element.getCategory() == "nodegraph" and element.hasAttribute("colorspace"):
                    self.asset.observe("node_colorspace", self.location(element), name=element.getAttribute("colorspace"))
                continue
            category = element.getCategory()
            if category in SHADER_CATEGORIES and in_definition(element):
                continue  # part of a nodedef's implementation graph: a definition, not a material
            if category in SHADER_CATEGORIES:
                material = self.read_shader(element)
                shaders[element.getNamePath()] = material
                self.asset.materials.append(material)
            elif category not in MATERIAL_CATEGORIES and not is_known_category(category):
                if not self.document.getMatchingNodeDefs(category) and not (  # (a node of a namespaced definition
                        element.hasNamespace()  # names its namespace: the red team's P-F1, OpenUSD's custom nodes)
                        and self.document.getMatchingNodeDefs(f"{element.getNamespace()}:{category}")):
                    self.asset.observe("unknown_category", self.location(element), category=category, type=element.getType())
            elif category not in MATERIAL_CATEGORIES:
                for port in element.getInputs():  # a graph's colour spaces: checked by name as a shader's are
                    if port.hasAttribute("colorspace"):
                        self.asset.observe("node_colorspace", self.location(element, port.getName()),
                                           name=port.getAttribute("colorspace"))
                for name, value, allowed in library.enum_violations(element):
                    self.asset.observe("node_enum_value", self.location(element, name), value=value, allowed=allowed)
                tagged = interface_colorspace(element)
                if tagged is not None:
                    self.asset.observe("interface_colorspace", self.location(element, "file"), interface=tagged[0],
                                       colorspace=tagged[1], applied=tagged[2])
        for duplicate_path, entries in self.structure.duplicates.items():
            parent, _, child = duplicate_path.rpartition("/")
            for line, attributes in entries:
                self.asset.observe(
                    "duplicate_element", Location(self.path, line, parent or child, child if parent else None),
                    first_line=self.asset.line_of.get(duplicate_path), attributes=attributes, name=child,
                )
        for material_node in self.document.getMaterialNodes():
            if material_node.getActiveSourceUri():
                self.asset.extra["included_materials"] = self.asset.extra.get("included_materials", 0) + 1
                self.bound_by_includer(material_node, shaders)
                continue
            self.read_material(material_node, shaders)
        for look in self.document.getLooks():
            for assign in look.getMaterialAssigns():
                target = assign.getMaterial()
                named = self.document.getChild(target) if target else None
                binds = named is not None and (named.getType() == "material" or any(  # a shader node binds nothing
                    port.getType() == "material" for port in getattr(named, "getOutputs", list)()))
                if target and not binds:
                    self.asset.observe("dangling_reference", self.location(assign), attribute="material", target=target,
                                       ends=None if named is None else f"is a {named.getType()} node, not a material")
            for assign in look.getVariantAssigns():  # a variant that names nothing selects nothing
                named = self.document.getVariantSet(assign.getVariantSetString())
                if named is None or named.getVariant(assign.getVariantString()) is None:
                    self.asset.observe("dangling_reference", self.location(assign), attribute="variant", target=
                                       f"{assign.getVariantSetString()}/{assign.getVariantString()}")
        record_looks(self.asset, self.document, self.location)

    def _doc_suppression(self, path: str, text: str) -> None:
        found = parse_suppression(text)
        if found is not None:
            whole_file, codes = found
            key = "" if whole_file else path
            self.asset.suppressions[key] = self.asset.suppressions.get(key, frozenset()) | codes

    # -- materials -------------------------------------------------------------------------
    def read_material(self, node, shaders: dict[str, Material]) -> None:
        surface = node.getInput("surfaceshader")
        location = self.location(node)
        if surface is None:
            if node.getCategory() not in MATERIAL_CATEGORIES and node.getNodeDef() is not None:
                # a material node of its own definition (MaterialX 1.39's material nodedefs): its shader is in
                # the implementation, which the toolkit does not read as a material
                self.asset.observe("unsupported_shader", location, material=node.getName(), category=node.getCategory())
            elif not any(i.getType().endswith("shader") for i in node.getInputs()):  # a light or volume material is whole
                self.asset.observe("material_without_shader", location, material=node.getName())
            return
        shader = self.upstream_node(surface)
        if shader is None:
            if surface.getNodeName() or surface.getNodeGraphString() or surface.getOutputString():
                self.asset.observe(
                    "dangling_reference", self.location(surface, None), attribute="nodename",
                    target=surface.getNodeName() or surface.getNodeGraphString(),
                )
            else:
                self.asset.observe("material_without_shader", location, material=node.getName())
            return
        if not shader.getType().endswith("shader"):  # a colour or value, no shader (the red team's B18: "a constant
            self.asset.observe("material_without_shader", location, material=node.getName())  # shader")
            return
        material = shaders.get(shader.getNamePath()) or self.included_shader(shader, shaders) \
            or self.expand_custom_shader(shader)
        if material is None:
            self.asset.observe(
                "unsupported_shader", location, material=node.getName(), category=shader.getCategory()
            )
            return
        if material.material_name is None:
            material.material_name = node.getName()
            material.material_location = location
            displacement = node.getInput("displacementshader")
            if displacement is not None and (displacement.getNodeName() or displacement.getNodeGraphString()):
                # kept whole for a .mtlx output (the writer wires it to the material again); others note it
                material.extra["displacement"] = "displacementshader"
                upstream = self.upstream_node(displacement)
                graph = capture_graph(upstream) if upstream is not None else None
                if graph:
                    material.extra["displacement_graph"] = Connection(
                        upstream.getNamePath(), upstream.getCategory(), "a displacement shader", graph_xml=graph,
                        output=upstream.getName())
            state = gltf_state.decode(node.getAttribute(gltf_state.MTLX_ATTRIBUTE)) if node.hasAttribute(
                gltf_state.MTLX_ATTRIBUTE) else {}
            if state:
                material.extra["gltf"] = state

    def expand_custom_shader(self, instance) -> Material | None:
        """A shader node of a custom category whose node definition is implemented by a node graph
        around one shader the toolkit reads (OpenUSD's UsdMtlx test files are full of them): that
        shader, its interface inputs bound to the instance's values (the definition's defaults where
        the instance authors none), named and located as the instance. ``None`` otherwise."""
        import MaterialX as mx  # lazy: as in library.standard_library

        nodedef = instance.getNodeDef()
        graph = nodedef.getImplementation() if nodedef is not None else None
        if graph is None or not graph.isA(mx.NodeGraph) or len(graph.getOutputs()) != 1:
            return None
        inner = graph.getOutputs()[0].getConnectedNode()
        if inner is None or inner.getCategory() not in SHADER_CATEGORIES:
            return None
        self.binding = (instance, nodedef)  # (an exception ends the whole read: no finally needed)
        material = self.read_shader(inner)
        self.binding = None
        for port in inner.getInputs():
            name = port.getInterfaceName()
            bound = (instance.getInput(name) or nodedef.getActiveInput(name)) if name else None
            if bound is not None and instance.getInput(name) is None and bound.hasDefaultGeomPropString():
                material.inputs.pop(port.getName(), None)  # MaterialX connects the geometric property, not the value
                continue
            if bound is not None:  # the node's value, else the definition's default
                entry = self.read_input(bound)
                entry.name = port.getName()
                if bound.getParent() is nodedef or bound.getParent().getName() == nodedef.getName():
                    entry.location = material.inputs[port.getName()].location
                material.inputs[port.getName()] = entry
        material.name, material.location = instance.getName(), self.location(instance)
        material.extra["node_path"] = instance.getNamePath()
        material.extra["expanded_from"] = {"category": instance.getCategory(), "nodedef": nodedef.getName()}
        self.asset.materials.append(material)
        return material

    # -- shaders ---------------------------------------------------------------------------
    def included_shader(self, shader, shaders: dict[str, Material]) -> Material | None:
        """A shader of an XIncluded document that a material of this one binds (the red team's D2: a library of
        shaders, namespaced or not, bound here): read as this document's material, so that it converts with its
        material; marked ``included_from``, as it is checked in its own document (:func:`.rules.check_asset`)."""
        source = shader.getActiveSourceUri()
        if not source or shader.getCategory() not in SHADER_CATEGORIES or in_definition(shader):
            return None
        material = self.read_shader(shader)
        material.location = Location(source, None, shader.getNamePath())
        material.extra["included_from"] = source
        shaders[shader.getNamePath()] = material
        self.asset.materials.append(material)
        return material

    def bound_by_includer(self, node, shaders: dict[str, Material]) -> None:
        """A material of the document including this one (read in its composition) that binds one of this
        document's shaders: the shader is bound (a library of shaders is bound where it is included)."""
        surface = node.getInput("surfaceshader")
        shader = self.upstream_node(surface) if surface is not None and "included_by" in self.asset.extra else None
        if shader is None:
            return
        name, namespace = shader.getNamePath(), shader.getNamespace()
        if namespace and name.startswith(namespace + ":") and namespace == self.document.getNamespace():
            name = name[len(namespace) + 1:]  # (the includer's copy of this namespaced document's shader)
        material = shaders.get(name)
        if material is not None and material.material_name is None:
            material.material_name = node.getName()
            material.material_location = Location(node.getActiveSourceUri(), None, node.getNamePath())

    def read_shader(self, node) -> Material:
        category = node.getCategory()
        location = self.location(node)
        material = Material(
            name=node.getName(),
            model=category,
            location=location,
            declared_version=node.getVersionString() or None,
            nodedef=node.getNodeDefString() or None,
            colorspace=node.getActiveColorSpace() or None,
        )
        material.extra["type"] = node.getType()
        material.extra["node_path"] = node.getNamePath()
        for port in node.getInputs():
            if not self.default_geometry(port):  # (a world-space normal or tangent node: the default, unauthored)
                entry = self.read_input(port)
                material.inputs[entry.name] = entry
        prefix = node.getNamePath() + "/"
        for duplicate_path, entries in self.structure.duplicates.items():
            if duplicate_path.startswith(prefix) and "/" not in duplicate_path[len(prefix):]:
                name = duplicate_path[len(prefix):]
                for line, attributes in entries:
                    material.duplicates.append(Input(name=name, type=attributes.get("type"), value=None,
                                                     raw=attributes.get("value"),
                                                     location=Location(self.path, line, node.getNamePath(), name)))
        versioning.settle(material)
        return material

    def read_input(self, port) -> Input:
        name = port.getName()
        location = Location(self.path, self.asset.line_of.get(port.getNamePath()), port.getParent().getNamePath(), name)
        entry = Input(
            name=name,
            type=port.getType() or None,
            value=None,
            location=location,
            colorspace=port.getActiveColorSpace() or None,
            unit=port.getUnit() or None,
            unittype=port.getUnitType() or None,
        )
        entry.authored_colorspace = port.getColorSpace() or None
        if port.hasAttribute("nodename") or port.hasAttribute("nodegraph") or port.hasAttribute("interfacename") \
                or port.hasAttribute("output"):
            entry.value = self.follow_shader_input(port)
            if isinstance(entry.value, Constant) and self.followed_space and self.followed_space != entry.colorspace:
                entry.colorspace = entry.authored_colorspace = self.followed_space
            if isinstance(entry.value, Constant) and self.followed_unit and self.followed_unit[1] and not entry.unit:
                entry.unittype, entry.unit = self.followed_unit
            return entry
        text = port.getValueString()
        entry.raw = text
        if not port.hasAttribute("value"):
            entry.error = "input has neither a value nor a connection"
            return entry
        try:
            entry.value = Constant(parse_value(text, entry.type or "float"))
        except ValueSyntaxError as error:
            entry.error = str(error)
        return entry
