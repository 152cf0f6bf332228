"""The model-neutral material representation every reader produces and every rule reads.

An :class:`Asset` is one file: the materials found in it plus what the reader observed about the
file's structure (document colour space, unit information, nodes it could not place). A
:class:`Material` is one surface shader of a known shading model (``open_pbr_surface``,
``standard_surface``, ``gltf_pbr``, ``UsdPreviewSurface``) with one :class:`Input` per authored
parameter. An input's value is a :class:`Constant`, a :class:`Texture` reference, or a
:class:`Connection` the reader could not interpret (kept and reported, never dropped).

Everything carries a :class:`Location` so a diagnostic can point at the file, line, element path
(MaterialX), prim path (USD) or JSON pointer (glTF), and input name.

Readers only record what they see; judging it is the rules' job.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field
from typing import Any, Union

# MaterialX type names are the lingua franca for parameter types (USD and glTF readers map theirs).
ScalarValue = Union[float, int, bool, str]
Value = Union[ScalarValue, tuple]


@dataclass(frozen=True, slots=True)
class Location:
    """Where something is: ``file``, ``line`` (1-based) where the format has lines, ``path``
    (MaterialX element name path, USD prim path or glTF JSON pointer), ``input`` name, and the
    ``material`` it belongs to where that is not obvious from ``path`` (translation notes name the
    source material they concern)."""

    file: str
    line: int | None = None
    path: str | None = None
    input: str | None = None
    material: str | None = None

    def with_input(self, name: str | None) -> "Location":
        return Location(self.file, self.line, self.path, name, self.material)

    def with_material(self, name: str | None) -> "Location":
        return Location(self.file, self.line, self.path, self.input, name)

    def __str__(self) -> str:
        text = self.file
        if self.line is not None:
            text += f":{self.line}"
        if self.path:
            text += f" {self.path}"
        if self.input:
            text += f".{self.input}"
        return text


@dataclass(slots=True)
class UVTransform:
    """A 2D texture-coordinate transform (MaterialX ``place2d``, ``KHR_texture_transform``,
    ``UsdTransform2d``). ``rotate`` is in degrees, counter-clockwise as MaterialX ``place2d``
    defines it; ``pivot`` is the rotation/scale centre."""

    scale: tuple[float, float] = (1.0, 1.0)
    rotate: float = 0.0
    offset: tuple[float, float] = (0.0, 0.0)
    pivot: tuple[float, float] = (0.0, 0.0)

    @property
    def is_identity(self) -> bool:
        return self.scale == (1.0, 1.0) and self.rotate == 0.0 and self.offset == (0.0, 0.0)


@dataclass(slots=True)
class Constant:
    """A literal value, already parsed into Python numbers (tuples for vectors/colours)."""

    value: Value


def normal_map_decode(strength: float) -> tuple[tuple[float, float, float], tuple[float, float, float]]:
    """The scale and bias that take a normal map's texels to a tangent-space vector of ``strength``
    (x and y scaled, as MaterialX's ``normalmap`` and glTF's ``normalTexture.scale`` do): the decode a
    UsdUVTexture feeding UsdPreviewSurface's ``normal`` applies (UsdPreviewSurface spec, "normal")."""
    return (2.0 * strength, 2.0 * strength, 2.0), (-strength, -strength, -1.0)


def rgb_components(value, default: float) -> tuple[float, float, float]:
    """A texture's scale or bias for its red, green and blue (a UsdUVTexture's float4, a colour, a scalar for all
    three, or unauthored: ``default``); a short sequence is padded with ``default``."""
    if value is None:
        return (default,) * 3
    if not isinstance(value, (tuple, list)):
        return (float(value),) * 3
    return tuple(float(v) for v in (tuple(value) + (default,) * 3)[:3])


def normal_decode(texture: "Texture") -> tuple[tuple[float, float, float], tuple[float, float, float]] | None:
    """(scale, bias) with which a normal map's texels t become its tangent-space vector n = scale t + bias
    (before normalisation), whichever way it was authored: a UsdUVTexture's scale and bias (or MaterialX
    multiply/add nodes feeding a preview's normal) are the whole decode (UsdPreviewSurface spec, "normal");
    otherwise the texture's scale and bias come before a normalmap node's 2 t - 1 and its strength k on x and
    y (MaterialX's ND_normalmap). ``None`` for a texture that is no normal map."""
    if texture.normal_map is None:
        return None
    scale, bias = rgb_components(texture.scale, 1.0), rgb_components(texture.bias, 0.0)
    if texture.node_category == "UsdUVTexture" or texture.decoded_by_scale_bias:
        return scale, bias
    k = float(texture.normal_map)
    strength = (k, k, 1.0)
    return (tuple(2.0 * s * w for s, w in zip(scale, strength)),
            tuple((2.0 * b - 1.0) * w for b, w in zip(bias, strength)))


def decode_strength(scale, bias, tolerance: float = 1e-6) -> float | None:
    """k where (scale, bias) is :func:`normal_map_decode` (k), a plain normal map of one strength; ``None`` for
    any other decode (a flipped green channel: a DirectX normal map read as OpenGL's, a per-axis strength)."""
    k = -bias[0]
    expected_scale, expected_bias = normal_map_decode(k)
    if all(abs(a - b) <= tolerance for a, b in zip(tuple(scale) + tuple(bias), expected_scale + expected_bias)):
        return k
    return None


def normal_encoding(texture: "Texture") -> tuple[tuple | None, tuple | None, float] | None:
    """(scale, bias, strength) that give :func:`normal_decode` as an affine map on the texels followed by a
    normalmap node (2 t - 1, x and y times strength), as the MaterialX writers write it: scale and bias
    ``None`` where the decode is a plain one of some strength; else strength 1 and the texels remapped,
    scale / 2 and (bias + 1) / 2. ``None`` for a texture that is no normal map."""
    decode = normal_decode(texture)
    if decode is None:
        return None
    k = decode_strength(*decode)
    if k is not None:
        return None, None, k
    scale, bias = decode
    return tuple(s / 2.0 for s in scale), tuple((b + 1.0) / 2.0 for b in bias), 1.0


def normal_strength(scale) -> float | None:
    """The strength of a ``normalmap`` node's ``scale`` as authored: a float (``ND_normalmap_float``),
    or a vector2 whose x and y are equal (``ND_normalmap_vector2`` scales x and y by its components);
    ``None`` for a vector2 with different components, which one strength cannot hold, and for
    anything else. An unauthored scale is 1 (both nodedefs' default)."""
    if scale is None:
        return 1.0
    if isinstance(scale, bool):
        return None
    if isinstance(scale, (int, float)):
        return float(scale)
    try:
        components = tuple(float(component) for component in scale)
    except (TypeError, ValueError):
        return None
    if len(components) == 2 and components[0] == components[1]:
        return components[0]
    return None


@dataclass(slots=True)
class Texture:
    """A reference to an image file feeding a parameter.

    ``channels`` names which channels of the image feed the parameter (``(0,)`` for the red channel,
    ``(0, 1, 2)`` for RGB); ``None`` means the image's output is used as is. ``colorspace`` is the
    effective colour-space name as authored (after inheritance), in the naming scheme of the source
    format. ``scale``/``bias`` apply after the lookup (``value * scale + bias``), as UsdUVTexture
    and glTF factors do, in the width of what the texture delivers (three components for RGB, one
    for a single channel; readers select UsdUVTexture's per-RGBA float4 by channel). ``normal_map`` is set when the texture reaches the parameter through a
    normal-map decode (MaterialX ``normalmap``, glTF ``normalTexture``), with its strength.
    """

    file: str
    image_type: str = "color3"
    channels: tuple[int, ...] | None = None
    colorspace: str | None = None
    uv: UVTransform | None = None
    texcoord: str | int | None = None
    scale: Value | None = None
    bias: Value | None = None
    wrap: tuple[str, str] | None = None
    fallback: Value | None = None
    normal_map: float | None = None
    node: str | None = None
    node_category: str | None = None
    location: Location | None = None
    packaged: bool = False  # ``file`` is a path inside the asset's own package (USDZ), not on disk
    constant_uv: bool = False  # a MaterialX place2d whose texcoord is unconnected: ND_place2d_vector2 defaults it to (0, 0)
    # a normal map's scale and bias are its whole decode (a UsdPreviewSurface's normal fed by MaterialX
    # multiply/add nodes, as a UsdUVTexture's are), not followed by a normalmap node's 2 t - 1
    decoded_by_scale_bias: bool = False
    layer: str | None = None  # a MaterialX image's layer: the OpenEXR layer (part) its channels are read from
    filter: str | None = None  # MaterialX filtertype (closest, linear, cubic), a glTF sampler's magFilter as one
    minification: int | None = None  # a glTF sampler's minFilter (9728-9987), which only glTF has a place for
    # whether ``colorspace`` is written on the image itself (its file input or node), not inherited from an
    # enclosing node graph or the document; None where the format has no inheritance
    colorspace_on_image: bool | None = None
    # the source's node graph the image was read through, whole, as for Connection.kept_graph (kept_for: the
    # texture_key of the texture as read)
    kept_graph: str | None = None
    kept_output: str | None = None
    kept_for: str | None = None

    @property
    def reads_alpha(self) -> bool:
        """Whether the parameter reads the image's alpha channel alone, which no colour management
        transforms (MaterialX's color4 transforms, sRGB decoding in Storm: RGB only)."""
        return self.channels == (3,)

    @property
    def is_udim(self) -> bool:
        """Whether ``file`` names a UDIM set. The token is case-sensitive, as MaterialX (``UDIM_TOKEN``)
        and OpenUSD (``UsdShadeUdimUtils``) substitute it: ``<udim>`` is part of a file name."""
        return "<UDIM>" in self.file

    def selected_channels(self, width: int) -> list[int]:
        """The image channels a parameter of ``width`` components (1 or 3) reads: ``channels`` (one
        channel read by a three-component parameter is repeated, as grey), else R or RGB. A channel
        beyond the image's reads 1 (an absent alpha), which the readers of texels apply."""
        channels = list(self.channels) if self.channels else ([0, 1, 2] if width == 3 else [0])
        return (channels * 3)[:3] if width == 3 and len(channels) == 1 else channels[:width]


@dataclass(slots=True)
class Connection:
    """A connection the reader could not interpret as a constant or a texture (a procedural
    graph, an unsupported node) or could not follow at all (``dangling``). ``graph_xml`` holds the
    upstream nodes as a MaterialX document when the reader could capture them, and ``output`` the
    name of the node in it that feeds the input, so a writer can put the graph back. ``varying`` is False
    where the reader found the graph constant over the surface (no image, geometric property or input that
    defaults to one, on the path to the output read)."""

    target: str
    category: str | None = None
    reason: str = ""
    dangling: bool = False
    graph_xml: str | None = None
    output: str | None = None
    varying: bool = True  # the graph may change over the surface (False: constants and arithmetic only)
    # an image whose coordinates only the graph holds: the image with the placement read up to it, for an output
    # that holds no graph (glTF: convert_textures.graph_fallbacks)
    fallback: "Texture | None" = None
    # the source's node graph the input read, whole (its interface, every output; capture.capture_nodegraph), the
    # output read, and the capture it stands for (graph_key): a .mtlx writer puts the graph back as it was
    # while ``graph_xml`` and ``output`` are still that capture (a mapping that changed them wrote its own nodes)
    kept_graph: str | None = None
    kept_output: str | None = None
    kept_for: str | None = None


def graph_key(graph_xml: str | None, output: str | None) -> str:
    """What identifies a capture (:attr:`Connection.kept_for`): its output and text."""
    return f"{output}\n{graph_xml}"


def texture_key(texture: "Texture") -> str:
    """What identifies a texture as read (:attr:`Texture.kept_for`): every field but the kept graph's."""
    return repr(dataclasses.replace(texture, kept_graph=None, kept_output=None, kept_for=None))


def kept(value) -> tuple[str, str] | None:
    """(the source's node graph, the output read) a value still stands for: a Connection whose capture, or a
    Texture which, no mapping or rebasing changed since it was read; else None."""
    if isinstance(value, Connection) and value.kept_graph and value.kept_for == graph_key(value.graph_xml, value.output):
        return value.kept_graph, value.kept_output
    if isinstance(value, Texture) and value.kept_graph and value.kept_for == texture_key(value):
        return value.kept_graph, value.kept_output
    return None


ParameterValue = Union[Constant, Texture, Connection]


@dataclass(slots=True)
class Input:
    """One authored parameter of a shader.

    ``type`` is the type as authored (MaterialX type names; USD/glTF readers translate theirs and
    keep the original in ``source_type``). ``value`` is ``None`` when the text could not be parsed,
    in which case ``error`` says why and ``raw`` holds the text.
    """

    name: str
    type: str | None
    value: ParameterValue | None
    location: Location
    raw: str | None = None
    error: str | None = None
    colorspace: str | None = None
    unit: str | None = None
    unittype: str | None = None
    source_type: str | None = None
    authored_colorspace: str | None = None
    interface_name: str | None = None  # the material/node-graph interface input the value comes through
    allowed: tuple[str, ...] | None = None  # the format's names the raw text had to be one of (an enum)

    @property
    def constant(self) -> Value | None:
        return self.value.value if isinstance(self.value, Constant) else None

    @property
    def texture(self) -> Texture | None:
        return self.value if isinstance(self.value, Texture) else None


@dataclass(slots=True)
class Material:
    """One surface shader of a known shading model, with its authored inputs.

    ``version`` is the model version the toolkit settled on and ``version_basis`` says how
    (``"node version attribute"``, ``"nodedef ND_..."``, ``"inferred from input names"``,
    ``"default"``); ``declared_version`` is what the file itself stated, if anything.
    """

    name: str
    model: str
    location: Location
    inputs: dict[str, Input] = field(default_factory=dict)
    version: str | None = None
    version_basis: str = "default"
    version_candidates: tuple[str, ...] = ()
    declared_version: str | None = None
    nodedef: str | None = None
    material_name: str | None = None
    material_location: Location | None = None
    colorspace: str | None = None
    duplicates: list[Input] = field(default_factory=list)
    extra: dict[str, Any] = field(default_factory=dict)

    def authored(self, name: str) -> Value | None:
        """The constant authored for ``name``, or ``None`` when unset or not a constant."""
        entry = self.inputs.get(name)
        return entry.constant if entry is not None else None

    def textures(self) -> list[tuple[str, Texture]]:
        return [(n, i.value) for n, i in self.inputs.items() if isinstance(i.value, Texture)]

    def gltf_state(self) -> dict:
        """What the glTF reader recorded beside the inputs (``extra["gltf"]``: gltf_state), or an empty dict."""
        state = self.extra.get("gltf")
        return state if isinstance(state, dict) else {}


@dataclass(slots=True)
class Observation:
    """Something structural a reader saw that is not a material parameter: a node of an unknown
    category, a material with no surface shader, an element the format does not allow. ``kind`` is
    a short stable key the rules match on; ``detail`` carries kind-specific facts."""

    kind: str
    location: Location
    detail: dict[str, Any] = field(default_factory=dict)


@dataclass(slots=True)
class Asset:
    """One file as read: its materials and the structural facts around them."""

    path: str
    format: str
    materials: list[Material] = field(default_factory=list)
    format_version: str | None = None
    colorspace: str | None = None
    colorspace_location: Location | None = None
    meters_per_unit: float | None = None
    observations: list[Observation] = field(default_factory=list)
    line_of: dict[str, int] = field(default_factory=dict)
    extra: dict[str, Any] = field(default_factory=dict)
    suppressions: dict[str, frozenset[str]] = field(default_factory=dict)

    def observe(self, kind: str, location: Location, **detail: Any) -> None:
        self.observations.append(Observation(kind, location, detail))
