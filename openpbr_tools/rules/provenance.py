"""Why each rule exists: the renderer or tool behaviour it protects against, and where that
behaviour is specified or implemented.

One module because it is one table, read whole by ``openpbr rules``, the SARIF catalogue and the provenance test:
split by family, each part would repeat the source constants.

``PROVENANCE[code] = (protects, sources)``. ``protects`` says what goes wrong, and where, when the
finding is ignored (for a style or policy rule: what it protects instead). ``sources`` are
citations separated by ``"; "``, each an ``https://`` URL or ``owner/repository:path`` in a public
GitHub repository (the specification or the code that behaves so). ``openpbr rules CODE`` and the
SARIF rule help show both; a test checks that every rule has them.
"""

from __future__ import annotations

_MX = "AcademySoftwareFoundation/MaterialX:"
MX_SPEC = _MX + "documents/Specification/MaterialX.Specification.md"
MX_PBR = _MX + "documents/Specification/MaterialX.PBRSpec.md"
MX_NODES = _MX + "documents/Specification/MaterialX.StandardNodes.md"
MX_VALIDATE = _MX + "source/MaterialXCore/Document.cpp"
MX_NODE = _MX + "source/MaterialXCore/Node.cpp"
MX_XML = _MX + "source/MaterialXFormat/XmlIo.cpp"
MX_VERSION = _MX + "source/MaterialXCore/Version.cpp"
MX_UNITS = _MX + "source/MaterialXCore/Unit.cpp"
MX_CMS = _MX + "source/MaterialXGenShader/DefaultColorManagementSystem.cpp"
MX_CMLIB = _MX + "libraries/cmlib/cmlib_defs.mtlx"
MX_STDLIB = _MX + "libraries/stdlib/stdlib_defs.mtlx"
MX_OPENPBR = _MX + "libraries/bxdf/open_pbr_surface.mtlx"
MX_PREVIEW = _MX + "libraries/bxdf/usd_preview_surface.mtlx"
OPENPBR = "https://academysoftwarefoundation.github.io/OpenPBR/"
OPENPBR_SRC = "AcademySoftwareFoundation/OpenPBR:index.html"
_USD = "PixarAnimationStudios/OpenUSD:"
USD_PREVIEW = "https://openusd.org/release/spec_usdpreviewsurface.html"
USDZ = "https://openusd.org/release/spec_usdz.html"
USD_SHADER = _USD + "pxr/usd/usdShade/shader.h"
USD_CONNECT = _USD + "pxr/usd/usdShade/connectableAPI.h"
USD_MTLX = _USD + "pxr/usd/usdMtlx/reader.cpp"
HD_MTLX = _USD + "pxr/imaging/hdMtlx/hdMtlx.cpp"
HD_ST = _USD + "pxr/imaging/hdSt/materialNetwork.cpp"
HIO_STB = _USD + "pxr/imaging/hio/stbImage.cpp"
GF_COLOR = _USD + "pxr/base/gf/colorSpace.h"
USD_METRICS = _USD + "pxr/usd/usdGeom/metrics.h"
USD_COMPLIANCE = _USD + "pxr/usd/usdUtils/complianceChecker.py"
USDZ_FORMAT = _USD + "pxr/usd/usd/usdzFileFormat.cpp"
_GLTF = "KhronosGroup/glTF:"
GLTF = _GLTF + "specification/2.0/Specification.adoc"
GLTF_MATERIAL_SCHEMA = _GLTF + "specification/2.0/schema/material.schema.json"


def khr(name: str) -> str:
    return f"{_GLTF}extensions/2.0/Khronos/{name}/README.md"


FILAMENT = "https://google.github.io/filament/Filament.html"

PROVENANCE: dict[str, tuple[str, str]] = {
    # -- document ------------------------------------------------------------------------------
    "OPBR001": ("Nothing can be rendered or checked: every renderer's loader fails on the file, usually at "
                "render time on a farm rather than at check-in.", MX_XML),
    "OPBR002": ("MaterialX (pugixml), usd-core (Sdf/Usd layer readers) and glTF loaders refuse malformed files: the "
                "asset loads nowhere, or loads truncated in lenient readers.", f"{MX_XML}; {GLTF}"),
    "OPBR003": ("Nothing renders wrong; it tells a reviewer the file was checked and held no material (a library, a "
                "geometry layer), so a clean report is not mistaken for a verified material.", MX_SPEC),
    "OPBR004": ("MaterialX's own Document.validate() rejects the document: its shader generators (GLSL, OSL, MDL) "
                "skip or fail on invalid elements, so what renders is not what was authored.", MX_VALIDATE),
    "OPBR005": ("MaterialX upgrades documents older than its version on load (Document::upgradeVersion), renaming "
                "and re-wiring nodes; open_pbr_surface exists from 1.39 only, so older documents hold something "
                "else than the author believes.", MX_VERSION),
    "OPBR006": ("No renderer in the pipeline reads the file as a material; it protects a CI gate from passing a "
                "file it never looked at.", MX_SPEC),
    "OPBR007": ("MaterialX's pugixml parser accepts malformed XML that standard XML tools, DCC importers and "
                "linters reject: the file works in one tool and fails in the next.", f"{MX_XML}; "
                "https://www.w3.org/TR/xml/#sec-well-formed"),
    "OPBR008": ("A misspelt configuration key would silently disable a project's policy; the gate refuses to run "
                "rather than pass everything.", "https://toml.io/en/v1.0.0"),
    "OPBR009": ("An include that is not followed leaves its definitions out: MaterialX reports missing nodedefs "
                "and renderers see an incomplete look; an include outside the asset breaks when the asset is "
                "moved.", MX_XML),
    "OPBR010": ("MaterialX cannot follow a missing, unreadable or circular XInclude: readXIncludes fails, and the "
                "document loads without the definitions it relies on.", MX_XML),
    # -- names ---------------------------------------------------------------------------------
    "OPBR011": ("Without it, one file that trips a defect of the toolkit would stop a folder's whole report (or "
                "pass unchecked): every other file is still checked, and the exit code says this one was not.",
                "https://docs.python.org/3/tutorial/errors.html"),
    "OPBR012": ("A version header older than the content misleads tools that branch on it; nothing renders "
                "differently when MaterialX's upgrade leaves the document as written (info).", MX_VERSION),
    "OPBR101": ("MaterialX shader generation ignores an input that matches no nodedef input (Document.validate "
                "flags it): the value silently renders as the default.", f"{MX_NODE}; {MX_OPENPBR}"),
    "OPBR102": ("An input of another OpenPBR version matches no input of the installed nodedef: renderers drop it "
                "and render the default.", f"{MX_OPENPBR}; {OPENPBR}"),
    "OPBR103": ("MaterialX keeps only one of two same-named children (which one depends on the reader), so the "
                "value that renders differs between tools.", f"{MX_XML}; {MX_SPEC}"),
    "OPBR104": ("A node of a category no nodedef declares cannot be generated: MaterialX's code generators fail "
                "or drop the node and everything downstream.", f"{MX_VALIDATE}; {MX_NODE}"),
    "OPBR105": ("A shader naming a nodedef that does not exist cannot bind: MaterialX falls back to no "
                "implementation and the material does not render.", f"{MX_NODE}; {MX_SPEC}"),
    "OPBR106": ("MaterialX binds a node to the nodedef of its version attribute; a disagreeing version binds "
                "another definition (other inputs and defaults) or none.", f"{MX_NODE}; {MX_SPEC}"),
    "OPBR107": ("UsdShade and every UsdPreviewSurface reader ignore an input the shader's definition lacks: one an "
                "exporter writes on every material renders nothing, as its exporter meant.",
                f"{USD_PREVIEW}; {USD_SHADER}"),
    # -- values --------------------------------------------------------------------------------
    "OPBR201": ("MaterialX reports a type mismatch and code generators either reject the input or reinterpret "
                "its components (a float read as a colour), so the value renders differently or not at all.",
                f"{MX_VALIDATE}; {MX_OPENPBR}"),
    "OPBR202": ("MaterialX parses an unparsable value as empty and renders the default (a decimal comma becomes "
                "two components); the authored value never reaches the renderer.", f"{MX_SPEC}; {GLTF}"),
    "OPBR203": ("NaN and infinity propagate through shading: black or white pixels, fireflies, and NaN pixels "
                "that poison denoisers and compositing.", f"{MX_SPEC}; {GLTF}"),
    "OPBR204": ("Uniform inputs must be constant; shading languages reject a varying connection (OSL) or ignore "
                "it (GLSL), so geometry_thin_walled from a texture renders inconsistently.", f"{MX_OPENPBR}; {OPENPBR}"),
    "OPBR205": ("MaterialX ignores a constant on an input with a defaultgeomprop (it connects Nworld anyway), "
                "readers that honour it shade every point as facing one direction: the asset renders differently "
                "between them (info: it renders right in MaterialX).",
                f"{MX_OPENPBR}; {_MX}source/MaterialXGenShader/ShaderGraph.cpp"),
    # -- ranges --------------------------------------------------------------------------------
    "OPBR301": ("Outside the physically meaningful range renderers clamp differently (or not at all): energy "
                "gain, negative lobes, black or glowing surfaces that differ between renderers.",
                f"{OPENPBR}; {GLTF_MATERIAL_SCHEMA}; {USD_PREVIEW}"),
    "OPBR302": ("Legal but unusual values that some exporters and renderers clamp to the UI range (uimin/uimax of "
                "the nodedef), so the look can change on export.", f"{MX_OPENPBR}; {OPENPBR}"),
    "OPBR303": ("An enum outside its list has no defined behaviour: glTF loaders reject the file, MaterialX's "
                "switch nodes fall through to a default branch.", f"{GLTF_MATERIAL_SCHEMA}; {MX_PREVIEW}; {USD_PREVIEW}"),
    "OPBR304": ("A renderer working in the document's colour space reflects more than 100% in the channel above "
                "1 (energy gain); OpenPBR assumes in-gamut albedos.", f"{OPENPBR_SRC}; {MX_CMLIB}"),
    # -- version -------------------------------------------------------------------------------
    "OPBR401": ("Nothing renders wrong; it records which OpenPBR version the material was read as, the basis of "
                "every other check and of the translation.", f"{OPENPBR}; {MX_OPENPBR}"),
    "OPBR402": ("Renderers bind the current open_pbr_surface nodedef: inputs renamed or reinterpreted since the "
                "material's version render differently or not at all.", f"{MX_OPENPBR}; {OPENPBR}"),
    "OPBR403": ("No single nodedef declares all the inputs: whichever version a renderer binds, part of the "
                "material is dropped.", f"{MX_OPENPBR}; {OPENPBR}"),
    "OPBR404": ("One file binding several OpenPBR versions renders as two looks in one pipeline; libraries drift "
                "apart.", MX_OPENPBR),
    "OPBR405": ("A project pins the OpenPBR version its renderers implement; another version renders differently "
                "there.", f"{OPENPBR}; {MX_OPENPBR}"),
    "OPBR406": ("The installed MaterialX has no nodedef for the legacy inputs or node version: validate rejects "
                "the file and generators render defaults (openpbr upgrade rewrites it).", f"{MX_OPENPBR}; {MX_VALIDATE}"),
    # -- colour spaces -------------------------------------------------------------------------
    "OPBR501": ("OpenPBR's specification assumes ACEScg, MaterialX's default colour management lin_rec709: the "
                "same numbers render as two different colours.", f"{OPENPBR}; {MX_CMS}; {MX_SPEC}"),
    "OPBR502": ("MaterialX's colour management finds no transform for an unknown name and applies none: the "
                "texture or colour renders in the wrong space (sRGB albedo rendered as linear).",
                f"{MX_CMS}; {MX_CMLIB}"),
    "OPBR503": ("A colour texture read as raw skips the sRGB decode: albedo renders washed out (too bright in the "
                "mid-tones).", f"{MX_CMS}; {MX_SPEC}"),
    "OPBR504": ("A colour transform bends data: an sRGB-decoded roughness of 0.5 renders as 0.21, metalness and "
                "normals likewise; Storm decodes UsdUVTexture 'auto' 8-bit RGB(A) as sRGB.",
                f"{MX_CMS}; {HIO_STB}; {USD_PREVIEW}"),
    "OPBR505": ("A project renders in one working space; a document in another converts differently per tool.",
                f"{MX_CMS}; {OPENPBR}"),
    "OPBR506": ("A texture in a colour space the pipeline's renderers or OCIO config lack renders unconverted.",
                MX_CMS),
    "OPBR507": ("MaterialX colour-manages color3/color4 images only, UsdMtlx drops the attribute, other renderers "
                "apply it: one file, different roughness or normals per renderer.", f"{MX_CMS}; {USD_MTLX}"),
    "OPBR508": ("MaterialX's shader generation reads an image's colour space from its own file input, not from the "
                "interface input the file name comes through: an sRGB texture renders undecoded there, decoded "
                "where the specification's reading is followed.",
                f"{MX_SPEC}; {_MX}source/MaterialXGenShader/ShaderGraph.cpp"),
    # -- units ---------------------------------------------------------------------------------
    "OPBR509": ("MaterialX applies an input's colorspace to the input's own value: on a connected input it converts "
                "nothing, and the texture behind it is read unconverted.", f"{MX_SPEC}; {MX_CMS}"),
    "OPBR601": ("MaterialX converts lengths through the unittype's converter; a wrong unittype converts with the "
                "wrong table or not at all.", f"{MX_UNITS}; {MX_STDLIB}"),
    "OPBR602": ("MaterialX's distance converter has no factor for an unknown unit and leaves the value as is: a "
                "depth in inches renders as metres.", f"{MX_UNITS}; {MX_STDLIB}"),
    "OPBR603": ("Nothing renders wrong in one scene; without a unit a length means the scene unit, so the same "
                "file renders differently in scenes of other scales (style choice: info).", f"{MX_UNITS}; {USD_METRICS}"),
    "OPBR604": ("A unit on an input with no or a fixed unit is ignored by MaterialX: the author believes a "
                "conversion happens that does not.", f"{MX_UNITS}; {MX_OPENPBR}"),
    "OPBR607": ("Renders as meant in MaterialX, whose unit system converts the value into range (metres); a "
                "renderer without unit conversion reads the number as written.",
                f"{MX_UNITS}; {_MX}resources/Materials/TestSuite/stdlib/units/standard_surface_unit.mtlx"),
    "OPBR605": ("OpenPBR's thin_film_thickness is in micrometres: a value in nanometres (500) is a 0.5 mm film, "
                "whose interference washes out to no iridescence.", f"{OPENPBR}; {MX_OPENPBR}"),
    "OPBR606": ("OpenPBR's thin_film_thickness is in micrometres: a value in metres (4.5e-07) is a film of a "
                "fraction of an atom, whose interference phase is zero: no iridescence.", f"{OPENPBR}; {MX_OPENPBR}"),
    # -- textures ------------------------------------------------------------------------------
    "OPBR701": ("A missing image renders as the image node's default (usually black or magenta) or fails the "
                "render on a farm.", f"{MX_NODES}; {USD_PREVIEW}"),
    "OPBR702": ("MaterialX rejects a connection whose types differ, or the generator converts with a default "
                "channel rule: the wrong channel drives the input.", f"{MX_VALIDATE}; {MX_NODES}"),
    "OPBR703": ("A tangent-space normal map read without normalmap is used as a raw vector in [0, 1]: every "
                "normal tilts towards +X+Y+Z.", f"{MX_NODES}; {MX_OPENPBR}"),
    "OPBR711": ("tiledimage multiplies by uvtiling and place2d divides by scale (MaterialX's stdlib node "
                "definitions): a 0 collapses the texture or divides by zero.", MX_NODES),
    "OPBR712": ("A colour image's red, green or blue channel is a colour component, not a roughness or mask; "
                "data packed beside a colour lives in alpha.", MX_NODES),
    "OPBR713": ("Direct3D 11/12 and Metal on Apple GPUs load textures of at most 16384 pixels a side.",
                "https://learn.microsoft.com/windows/win32/direct3d11/overviews-direct3d-11-resources-limits"),
    "OPBR710": ("A floating-point image read straight into a world-space normal input is right only if it holds "
                "world-space normals; a tangent-space map read so shades every point wrongly.", f"{MX_NODES}; {MX_OPENPBR}"),
    "OPBR704": ("Absolute paths, '..' and URLs break when the asset is moved, packaged (USDZ, glTF) or rendered "
                "on a farm; a symlink out of the folder breaks on copy.", f"{USD_COMPLIANCE}; {GLTF}"),
    "OPBR723": ("Nothing renders wrong: a relative path into a shared folder resolves wherever the tree is checked "
                "out (MaterialX's examples read ../../../Images); the validator only declines to read outside the "
                "asset's folder.", f"{MX_SPEC}; {_MX}resources/Materials/Examples/StandardSurface/standard_surface_brass_tiled.mtlx"),
    "OPBR705": ("An image node without a file renders its default: the texture silently vanishes.",
                f"{MX_NODES}; {USD_PREVIEW}"),
    "OPBR706": ("A place2d whose texcoord is unconnected transforms the constant (0, 0): MaterialX's renderers "
                "read one texel everywhere and the texture shows as a flat colour (the node definition gives "
                "texcoord no default geometric property, where image's defaults to UV0).",
                _MX + "libraries/stdlib/stdlib_defs.mtlx"),
    "OPBR707": ("A texture that is empty, a Git LFS pointer, an HTML page or a PNG/JPEG cut short renders black, "
                "magenta or half grey (libjpeg fills a truncated JPEG with grey), or is skipped with only a log "
                "line: the asset renders wrong without failing.",
                "https://www.w3.org/TR/png-3/; https://www.w3.org/Graphics/JPEG/itu-t81.pdf; git-lfs/git-lfs:docs/spec.md; "
                "KhronosGroup/glTF-Validator:lib/src/data_access/image_decoder.dart"),
    "OPBR708": ("Bytes in no known image format are skipped by renderers and viewers: the texture is missing "
                "where the asset is shown (the Khronos glTF-Validator's IMAGE_UNRECOGNIZED_FORMAT).",
                "KhronosGroup/glTF-Validator:lib/src/errors.dart; " + MX_NODES),
    "OPBR709": ("A greyscale image read as a normal map gives every texel the same direction: the surface "
                "detail is lost or the whole surface tilts (a height map belongs in heighttonormal or bump).",
                f"{MX_NODES}; {GLTF}"),
    # -- structure -----------------------------------------------------------------------------
    "OPBR720": ("ND_normalmap_float multiplies x and y by its scale: -1 inverts the relief instead of converting a "
                "DirectX map, which needs green flipped only (ND_normalmap_vector2 scale (1, -1)).", f"{MX_STDLIB}; {MX_NODES}"),
    "OPBR721": ("Unity HDRP's mask map holds smoothness in its alpha and glossiness maps hold 1 - roughness: read as "
                "roughness without an inversion, polished parts render matte.",
                f"https://docs.unity3d.com/Packages/com.unity.render-pipelines.high-definition@17.0/manual/Mask-Map-and-Detail-Map.html; {MX_OPENPBR}"),
    "OPBR722": ("A PNG's sRGB chunk declares sRGB-encoded values; MaterialX applies the authored tag, so a linear tag "
                "never removes the sRGB curve and the albedo renders washed out.",
                f"https://www.w3.org/TR/png-3/#11sRGB; {MX_CMS}"),
    "OPBR724": ("Decoded, the normals face into the surface: the shading is lit from behind.",
                f"{MX_STDLIB}; {GLTF}; {GLTF_MATERIAL_SCHEMA}"),
    "OPBR725": ("8-bit values in a 16-bit file read 257 times too small: a roughness of 0.99 reads 0.004.",
                "https://www.w3.org/TR/png-3/#11IHDR"),
    "OPBR726": ("NaN and infinite texels spread through filtering and shading into speckles and fireflies.",
                "https://openexr.com/en/latest/TechnicalIntroduction.html"),
    "OPBR727": ("Loaders place or stretch an OpenEXR data-window crop differently: the texture moves per renderer.",
                "https://openexr.com/en/latest/TechnicalIntroduction.html#data-window"),
    "OPBR801": ("A material without a surface shader renders black or with the renderer's fallback shader.",
                f"{MX_SPEC}; {USD_SHADER}"),
    "OPBR802": ("A dangling reference is dropped by MaterialX and USD: the input falls back to its default or "
                "the material to nothing; a glTF index that names nothing (a texture, a variant, the default scene) "
                "leaves loaders nothing to show (the glTF-Validator's UNRESOLVED_REFERENCE).",
                f"{MX_VALIDATE}; {USD_CONNECT}; {GLTF}"),
    "OPBR803": ("Nothing renders wrong; the toolkit cannot check (or translate without baking) a procedural "
                "graph, and says so.", MX_NODES),
    "OPBR804": ("Nothing renders wrong; an unbound shader is usually left over and never reaches a renderer.",
                MX_SPEC),
    "OPBR805": ("Nothing renders wrong (info: published files use other shaders); a shader the toolkit does not "
                "read is not checked and cannot be converted, and without the report the material would vanish "
                "from a converted file.", f"{MX_SPEC}; {USD_SHADER}"),
    # -- plausibility --------------------------------------------------------------------------
    "OPBR806": ("MaterialX's specification: the output attribute names the output of a node with several; MaterialX "
                "connects the first where it is missing.", _MX + "documents/Specification/MaterialX.Specification.md"),
    "OPBR807": ("ND_extract_color3 takes index 0 to 2; MaterialX's GLSL indexes the vector past its end, which GLSL "
                "leaves undefined.", f"{MX_STDLIB}; {MX_NODES}"),
    "OPBR808": ("MaterialX's shader generation reads a custom node's implementation file: without it generation "
                "fails and no MaterialX renderer shows the material.", f"{_MX}source/MaterialXGenShader/SourceCodeNode.cpp; {MX_SPEC}"),
    "OPBR809": ("The MaterialX specification allows one default version per node and signature; with two, an "
                "unversioned node binds one of them silently.", f"{MX_SPEC}; {MX_NODE}"),
    "OPBR810": ("MaterialX geometry names are '/'-separated paths: a Maya DAG path matches no geometry, so the look "
                "assigns the material to nothing.", MX_SPEC),
    "OPBR811": ("MaterialX connects a multi-output graph's first output where the input names none: the input reads "
                "another map than meant, silently.", MX_SPEC),
    "OPBR812": ("The shading models take world-space normals and tangents (nodedef defaults Nworld, Tworld): an "
                "object-space vector shades right only while the object is untransformed.", f"{MX_STDLIB}; {MX_OPENPBR}"),
    "OPBR813": ("hextiledimage rotates each tile's lookup, not the tangent-space vectors in it: the bumps of each tile "
                "light from another direction; hextilednormalmap rotates both.", MX_STDLIB),
    "OPBR814": ("A geometry assignment names geom or a collection; with both, applications pick differently.", MX_SPEC),
    "OPBR815": ("normalmap's default tangent frame follows UV set 0; a map baked in another set's layout decodes in "
                "the wrong frame.", MX_STDLIB),
    "OPBR901": ("Real metals reflect at least ~50% at normal incidence; a darker metal reads as plastic under "
                "image-based light (info: heuristic, some measured alloys come close).",
                f"{FILAMENT}; https://physicallybased.info/"),
    "OPBR902": ("Diffuse albedos of real materials lie roughly in [0.02, 0.9]; outside, lighting and exposure "
                "look wrong (info: heuristic, Spectralon and the darkest paints exist).",
                f"{FILAMENT}; https://physicallybased.info/"),
    "OPBR903": ("OpenPBR's metal is opaque: transmission under base_metalness 1 has no effect in any renderer, "
                "so the author's intent is lost.", f"{OPENPBR}; {khr('KHR_materials_transmission')}"),
    "OPBR904": ("A thin film of zero thickness has no interference: the iridescence the author set does not "
                "render.", f"{OPENPBR}; {khr('KHR_materials_iridescence')}"),
    "OPBR905": ("An IOR below 1 inverts the Fresnel behaviour (total internal reflection from outside); rare "
                "outside metamaterials and usually a typo.", f"{OPENPBR}; {khr('KHR_materials_ior')}"),
    "OPBR906": ("Partial metalness is a blend of metal and dielectric that rarely exists in nature; usually an "
                "anti-aliasing value painted as a constant (info).", f"{OPENPBR}; {FILAMENT}"),
    "OPBR907": ("The emission set does not render (luminance 0, or a black colour): intent lost, or a leftover "
                "that a later edit will make glow.", f"{OPENPBR}; {khr('KHR_materials_emissive_strength')}"),
    "OPBR908": ("A fully transparent surface renders nothing, not even reflections (OpenPBR's geometry_opacity "
                "mixes the whole surface with nothing; glTF's BLEND alpha 0 or MASK below the cutoff draws nothing); "
                "cut-outs are textured opacity, which this does not flag.", f"{OPENPBR}; {GLTF}"),
    # -- usd -----------------------------------------------------------------------------------
    "OPBR909": ("OpenPBR's metal reflects base_weight * base_color at normal incidence; no measured metal reflects "
                "under 2% (physicallybased.info).", "AntonPalmqvist/physically-based-api:deploy/v2/materials.json"),
    "OPBR714": ("MaterialX's stb_image loader, browsers and engines choose the decoder by the file's suffix: a "
                "TIFF named .png fails there and loads only where the content is sniffed (OpenImageIO).",
                f"{_MX}source/MaterialXRender/StbImageLoader.cpp; {_MX}source/MaterialXRender/ImageHandler.cpp"),
    "OPBR715": ("MaterialX applies a texture's colour space as authored: an sRGB tag on an OpenEXR or Radiance "
                "image (scene-linear by convention) runs the sRGB decode on linear values (its GLSL's "
                "NG_srgb_texture_to_lin_rec709).", f"{MX_CMS}; https://openexr.com/en/latest/TechnicalIntroduction.html"),
    "OPBR716": ("MaterialX and USD resolve <UDIM> per point: UVs in [0, 1] read tile 1001; without it they read "
                "the image's default.", f"{MX_SPEC}; {_USD}pxr/usd/usdShade/udimUtils.h"),
    "OPBR717": ("MaterialX's image layer selects the OpenEXR channels '<layer>.R', '.G', '.B': a layer the file "
                "does not have reads nothing and renders the default.", f"{MX_NODES}; {MX_SPEC}"),
    "OPBR718": ("A tangent is a signed direction; an 8-bit image holds [0, 1], so without a 2t - 1 decode every "
                "anisotropic highlight runs along the positive octant.", f"{MX_OPENPBR}; {MX_NODES}"),
    "OPBR719": ("place2d's rotate and UsdTransform2d's rotation are in degrees (MaterialX's GLSL converts with "
                "mx_radians); glTF's is in radians, so a value copied across turns the texture by 1/57 of what "
                "was meant, and a degree value typed into a glTF file (90) by 57 times it; KHR_materials_anisotropy's "
                "anisotropyRotation is in radians too, so 90 turns the brushed highlight by 14.3 turns.",
                f"{MX_NODES}; {USD_PREVIEW}; {GLTF}; {_GLTF}extensions/2.0/Khronos/KHR_texture_transform/README.md; "
                f"{khr('KHR_materials_anisotropy')}"),
    "OPBR910": ("An 8-bit image read as a luminance in nits emits at most 1 nit: the surface looks unlit.",
                f"{OPENPBR}; {MX_OPENPBR}"),
    "OPBR911": ("A dielectric whose scaled reflectivity reaches 1 is a mirror at every angle: its base, subsurface and "
                "transmission vanish, and the weight beyond 1 / F0 changes nothing.", f"{OPENPBR}; {MX_OPENPBR}"),
    "OPBR1001": ("Without info:id (or a source asset/code) Sdr cannot find the shader's definition: Hydra "
                 "renders the material with its fallback.", f"{USD_SHADER}; {_USD}pxr/usd/sdr/shaderNode.h"),
    "OPBR1002": ("Hydra and UsdMtlx type MaterialX inputs from the USD type (role and precision): a wrong role "
                 "or a double can make hdMtlx drop or mis-convert the input.", f"{HD_MTLX}; {USD_MTLX}"),
    "OPBR1003": ("An info:id that names no Sdr node is not found in the registry: Storm and other delegates "
                 "render the fallback material.", f"{USD_SHADER}; {HD_MTLX}"),
    "OPBR1004": ("USD colour-space names and MaterialX names are different schemes: a name from the wrong one is "
                 "unknown where it is read, and no conversion happens.", f"{GF_COLOR}; {HD_MTLX}; {MX_CMS}"),
    "OPBR1005": ("UsdShade connects attributes whose types differ, but Hydra drops or reinterprets the value "
                 "(a float into a colour): the input renders its default.", f"{USD_CONNECT}; {HD_ST}"),
    "OPBR1006": ("UsdPreviewSurface expects tangent-space normals in [-1, 1]; an 8-bit image stores (n + 1) / 2 "
                 "and must be decoded by scale and bias, or every normal tilts.", f"{USD_PREVIEW}; {HD_ST}"),
    "OPBR1007": ("A non-zero opacityThreshold makes opacity a cut-out in Storm and MaterialX's "
                 "ND_UsdPreviewSurface, overriding opacityMode; with opacity 1 it cuts nothing.",
                 f"{USD_PREVIEW}; {MX_PREVIEW}"),
    "OPBR1034": ("Storm and MaterialX's ND_UsdPreviewSurface discard every fragment whose opacity is below "
                 "opacityThreshold: when no texel of the mask reaches it, the whole surface disappears; usd-core's "
                 "validators read no texels.", f"{USD_PREVIEW}; {MX_PREVIEW}"),
    "OPBR1008": ("UsdPreviewSurface's specular workflow ignores metallic: the authored metal renders as a "
                 "dielectric.", f"{USD_PREVIEW}; {MX_PREVIEW}"),
    "OPBR1035": ("UsdPreviewSurface's metalness workflow ignores specularColor: the authored value does not render.",
                 f"{USD_PREVIEW}; {MX_PREVIEW}"),
    "OPBR1009": ("Viewports and clients without MaterialX render the UsdPreviewSurface fallback: a fallback far "
                 "from the OpenPBR look shows another material there.", f"{USD_PREVIEW}; {HD_MTLX}"),
    "OPBR1010": ("usd-core's own validators (the anchor) flag stages that load or render wrongly in USD tools "
                 "(composition errors, missing stage metrics).", f"{USD_COMPLIANCE}; {USD_METRICS}"),
    "OPBR1040": ("usd-core's validators (the anchor) flag missing stage metadata and the pre-21.11 token varname; "
                 "neither changes how a bound material renders.", f"{USD_COMPLIANCE}; {USD_METRICS}"),
    "OPBR1025": ("usd-core's validators (the anchor): SubsetMaterialBindFamilyName, SubsetFamilies and "
                 "MaterialBindingCollectionValidator report these as errors; UsdShadeMaterialBindingAPI.ComputeBoundMaterial "
                 "then finds another material, or none (checked on the red team's round-five files ub01, ub06, ub07).",
                 f"{_USD}pxr/usd/usdShade/materialBindingAPI.h; {_USD}pxr/usd/usdGeom/subset.h"),
    "OPBR1026": ("Usd.CollectionAPI's explicitOnly includes exactly the listed prims; UsdShade binds a collection's "
                 "material to its members only, so a collection of the group binds nothing that renders "
                 "(ComputeBoundMaterial on the meshes, checked on the red team's round-five ub13).",
                 f"{_USD}pxr/usd/usd/collectionAPI.h; {_USD}pxr/usd/usdShade/materialBindingAPI.h"),
    "OPBR1027": ("usd-core composes the prims below an instance from its prototype and ignores the stage's own "
                 "opinions there: an override of one instance does nothing (ComputeBoundMaterial, checked on the red "
                 "team's round-five ub02).", f"{_USD}pxr/usd/usd/instancing.dox; {_USD}pxr/usd/usd/prim.h"),
    "OPBR1028": ("UsdUVTexture's scale multiplies the texel values: a tiling written into it brightens an albedo "
                 "past 1 instead of repeating the texture.", USD_PREVIEW),
    "OPBR1029": ("The mtlx render context is read through MaterialX's node definitions, where the preview surface "
                 "is ND_UsdPreviewSurface_surfaceshader; the glslfx id UsdPreviewSurface names none there.",
                 f"{MX_PREVIEW}; {HD_MTLX}"),
    "OPBR1030": ("Storm builds a shading network from Sdr's node definitions and hdMtlx from MaterialX's, not from "
                 "the type authored on a shader's output: a mistyped output renders as its definition says (OpenUSD's "
                 "testUsdImagingGLGeomSubsets baseline), and only tools reading authored types see it wrong.",
                 f"{_USD}pxr/usdImaging/usdImagingGL/testenv/testUsdImagingGLGeomSubsets/testUsdImagingGLGeomSubsets.usda; "
                 f"{_USD}pxr/usdImaging/plugin/usdShaders/shaders/shaderDefs.usda; {HD_MTLX}"),
    "OPBR1031": ("Only constant primvars inherit (UsdGeomPrimvarsAPI.FindPrimvarWithInheritance): a faceVarying UV set "
                 "on the transform above a mesh belongs to no geometry, and the mesh's textures read the fallback "
                 "coordinate (checked on the red team's session-20 ub05).", _USD + "pxr/usd/usdGeom/primvarsAPI.h"),
    "OPBR1032": ("UsdGeomPrimvar reads indices as int[]: authored as uint[] the primvar is indexed with no readable "
                 "indices and ComputeFlattened fails, so its UVs are dropped (checked on the red team's session-20 "
                 "ub14).", _USD + "pxr/usd/usdGeom/primvar.h"),
    "OPBR1033": ("UsdGeomMesh's faceVaryingLinearInterpolation \"none\" smooths faceVarying data everywhere (OpenSubdiv's "
                 "FVAR_LINEAR_NONE): UV corners and borders move under subdivision and the texture shrinks and swims "
                 "there (the red team's session-20 ub13).",
                 f"{_USD}pxr/usd/usdGeom/schema.usda; https://graphics.pixar.com/opensubdiv/docs/subdivision_surfaces.html"),
    "OPBR1011": ("An arc outside the asset breaks when the asset moves or is packaged, and reads files the "
                 "asset's owner did not ship; the toolkit never opens it.", f"{USDZ}; {USD_COMPLIANCE}"),
    "OPBR1039": ("Nothing renders wrong: a relative arc into a shared folder resolves wherever the tree is checked out "
                 "(usd-wg's ../_common); the validator only declines to open outside the asset's folder.",
                 "usd-wg/assets:full_assets/Vehicles; " + USD_COMPLIANCE),
    "OPBR1012": ("The USDZ specification requires stored (uncompressed), relative, aligned entries; ARKit and "
                 "usd-core refuse or mis-read others, and '..' names can write outside on extraction.",
                 f"{USDZ}; {USDZ_FORMAT}"),
    "OPBR1013": ("usd-core without the usdMtlx plugin cannot open a referenced .mtlx: those materials are "
                 "absent in builds without it (the toolkit validates the .mtlx with the stage).", USD_MTLX),
    "OPBR1014": ("hdMtlx passes a Gf colour-space name to MaterialX unchanged; MaterialX 1.39.4+ maps it to its "
                 "own, older versions do not (no conversion there).", f"{HD_MTLX}; {MX_CMS}; {GF_COLOR}"),
    # -- translation ---------------------------------------------------------------------------
    "OPBR1015": ("A primvar reader whose primvar the mesh lacks returns (0, 0): the texture renders as one flat "
                 "colour on that mesh (Storm, and every renderer that follows the preview specification).",
                 f"{USD_PREVIEW}; {HD_ST}; " + _USD + "pxr/usd/usdShade/materialBindingAPI.h"),
    "OPBR1016": ("A UsdUVTexture whose st is unconnected samples (0, 0) everywhere: the texture renders as one "
                 "flat colour.", f"{USD_PREVIEW}; {HD_ST}"),
    "OPBR1017": ("A direct binding to a missing, inactive or non-Material prim resolves to no material: the "
                 "geometry renders with the renderer's fallback.", _USD + "pxr/usd/usdShade/materialBindingAPI.h"),
    "OPBR1018": ("A UsdShade input is an attribute: a relationship named inputs:x is no input and is never "
                 "connected.", _USD + "pxr/usd/usdShade/input.h"),
    "OPBR1019": ("UsdShade's connectability (interfaceOnly) and encapsulation rules, as "
                 "UsdShadeConnectableAPI::CanConnect applies them.", _USD + "pxr/usd/usdShade/connectableAPI.h"),
    "OPBR1020": ("UsdGeom's metersPerUnit is the root layer's metadata; composition does not rescale the values of "
                 "a layer authored in another unit.", _USD + "pxr/usd/usdGeom/metrics.h"),
    "OPBR1041": ("Every length in scene units is read through metersPerUnit: 0 or a negative unit makes them "
                 "meaningless, and usd-core's StageMetadataChecker only asks that it be authored.",
                 _USD + "pxr/usd/usdGeom/metrics.h"),
    "OPBR1042": ("usd-core composes a stage without a sublayer, reference or payload it cannot find (a composition "
                 "error): whatever that layer held is missing from every renderer.",
                 _USD + "pxr/usd/pcp/errors.h"),
    "OPBR1021": ("UsdShade's material purposes are allPurpose, preview and full (UsdShadeTokens); a binding under "
                 "another purpose name is computed for no renderer.", _USD + "pxr/usd/usdShade/materialBindingAPI.h"),
    "OPBR1022": ("bindMaterialAs takes UsdShadeTokens weakerThanDescendants or strongerThanDescendants; any other "
                 "token is read as the fallback strength.", _USD + "pxr/usd/usdShade/materialBindingAPI.h"),
    "OPBR1023": ("Usd.CollectionAPI includes are paths: a path that names no prim matches nothing, so a collection "
                 "binding of only such paths binds nothing.", _USD + "pxr/usd/usd/collectionAPI.h"),
    "OPBR1024": ("UsdShadeMaterial::ComputeSurfaceSource looks up outputs:<renderContext>:surface for the renderer's "
                 "context (mtlx, glslfx, ri) and the universal outputs:surface.", _USD + "pxr/usd/usdShade/material.h"),
    "OPBR1101": ("Nothing is lost; a rename recorded so a reviewer can follow a value across models and "
                 "versions.", f"{OPENPBR}; {MX_OPENPBR}"),
    "OPBR1102": ("Nothing is lost; the value changed form exactly (units, folded parameters) and the report says "
                 "how.", f"{OPENPBR}; {GLTF}"),
    "OPBR1103": ("The target renders a close but different look; without the note the difference would be "
                 "discovered in review or never.", f"{OPENPBR}; {GLTF}; {USD_PREVIEW}"),
    "OPBR1104": ("The target cannot hold the value: without the note a converted asset silently loses "
                 "a feature (a coat, a texture, a tint).", f"{OPENPBR}; {GLTF}; {USD_PREVIEW}"),
    "OPBR1105": ("A default changed between versions: writing it explicitly keeps the look when the file is "
                 "read with the new defaults.", f"{OPENPBR}; {MX_OPENPBR}"),
    "OPBR1106": ("Nothing is lost; a node graph now carries the value, which some viewers evaluate differently "
                 "than a constant.", MX_NODES),
    "OPBR1107": ("The target version reads the input differently with no known compensation: the look shifts.",
                 f"{OPENPBR}; {MX_OPENPBR}"),
    "OPBR1108": ("Nothing is wrong; the measured difference between original and conversion, the evidence "
                 "behind 'converted'.", "https://www.ece.rochester.edu/~gsharma/ciede2000/"),
    "OPBR1109": ("The converted material differs visibly (mean CIEDE2000 above the threshold) in the lobe "
                 "evaluator's render.", "https://www.ece.rochester.edu/~gsharma/ciede2000/"),
    # -- gltf ----------------------------------------------------------------------------------
    "OPBR1232": ("Browsers apply a JPEG's EXIF Orientation when they decode it (HTML's image decoding, "
                 "createImageBitmap's imageOrientation default); engines and native loaders mostly ignore it, so the "
                 "texture is oriented differently per viewer.",
                 f"{GLTF}; https://html.spec.whatwg.org/multipage/imagebitmap-and-animations.html#dom-imagebitmapoptions-imageorientation"),
    "OPBR1233": ("glTF clients must ignore a PNG's ICC profile and pixel aspect; web viewers that decode "
                 "through the browser without turning colour conversion off apply the profile to data textures.",
                 f"{GLTF}; https://github.com/KhronosGroup/glTF-Validator/blob/main/ISSUES.md"),
    "OPBR1234": ("glTF reads each data texture from fixed channels; an image packed for another engine renders its "
                 "flat channel (a mirror coat, a dielectric where the mask says metal), and no validator reads texels.",
                 f"{GLTF}; {khr('KHR_materials_clearcoat')}"),
    "OPBR1235": ("A normal map read in a tangent space the viewer generates shades as baked only where the baker used "
                 "the same (MikkTSpace on the same mesh); viewers without MikkTSpace differ (the glTF-Validator's "
                 "MESH_PRIMITIVE_GENERATED_TANGENT_SPACE, a warning). Legal and common: most Khronos samples do it.",
                 f"{GLTF}; mmikk/MikkTSpace:mikktspace.h; KhronosGroup/glTF-Validator:lib/src/errors.dart"),
    "OPBR1236": ("The anisotropy direction and a clear-coat normal map are read in the tangent space of the normal "
                 "texture's UV set; painted on another set they point the wrong way where the layouts differ (the "
                 "glTF-Validator's KHR_MATERIALS_ANISOTROPY_ANISOTROPY_TEXTURE_TEXCOORD, "
                 "KHR_MATERIALS_CLEARCOAT_CLEARCOAT_NORMAL_TEXTURE_TEXCOORD, warnings).",
                 f"{GLTF}; {khr('KHR_materials_anisotropy')}; {khr('KHR_materials_clearcoat')}"),
    "OPBR1237": ("Bytes a GLB carries for nothing (an unknown chunk, which loaders must ignore; a BIN chunk beyond "
                 "buffer 0; base64 data URIs a third larger than the bytes in a binary container): no wrong render, but "
                 "dead weight or a tool that lost track of its buffer (the glTF-Validator's GLB_UNKNOWN_CHUNK_TYPE, "
                 "BUFFER_GLB_CHUNK_TOO_BIG, DATA_URI_GLB, warnings).",
                 f"{GLTF}; KhronosGroup/glTF-Validator:lib/src/errors.dart"),
    "OPBR1238": ("A greyscale roughness map in the packed metallicRoughnessTexture is read as metalness (B) too: the "
                 "surface renders metallic wherever it is rough, a dielectric as patchy rough metal; no validator "
                 "reads texels.", GLTF),
    "OPBR1239": ("An occlusion texture black in R removes all indirect light: under image-based lighting, the usual "
                 "glTF viewer set-up, the object renders near black (a failed bake); no validator reads texels.", GLTF),
    "OPBR1240": ("An untextured white emission on a textured material adds full white at every texel: the surface "
                 "renders flat white and its texture never shows (an exporter's default emission colour); the "
                 "glTF-Validator does not judge values.", GLTF),
    "OPBR1253": ("Khronos' JSON schema for glTF 2.0 and for each Khronos extension defines every property's type, "
                 "range and list; the glTF-Validator rejects a file that breaks it (TYPE_MISMATCH, UNDEFINED_PROPERTY, "
                 "VALUE_NOT_IN_RANGE).", f"{_GLTF}specification/2.0/schema; {GLTF}"),
    "OPBR1252": ("glTF scales a normal map's x and y by normalTexture.scale: -1 inverts the relief instead of "
                 "converting a DirectX map (green only); the glTF-Validator checks no sign.", GLTF),
    "OPBR1241": ("COLOR_0 multiplies the base colour in every glTF viewer: all zeros (an empty vertex-colour layer "
                 "exported by default) renders the material black; the glTF-Validator does not read vertex colours.", GLTF),
    "OPBR1242": ("A KHR_animation_pointer channel whose pointer names no defined property animates nothing (the "
                 "extension's MUST); the glTF-Validator does not resolve material pointers.",
                 f"{khr('KHR_animation_pointer')}; {_GLTF}specification/2.0/ObjectModel.adoc"),
    "OPBR1243": ("A texture transform is per textureInfo: tiling the base colour alone slides it off the normal, "
                 "metallic-roughness and occlusion maps of its texture set; no validator compares transforms.",
                 f"{khr('KHR_texture_transform')}; {GLTF}"),
    "OPBR1244": ("glTF samples one image per texture and wraps or clamps coordinates: a UDIM layout shows tile 1001's "
                 "image on every tile's islands; no validator reads UV layouts.", f"{GLTF}; {khr('KHR_texture_transform')}"),
    "OPBR1245": ("float32 texture coordinates far from 0 are quantised coarser than a texel: the texture renders blocky "
                 "and swims; no validator judges magnitudes.", GLTF),
    "OPBR1246": ("Normals on the back of the triangles light the material from behind (glTF renders back faces with "
                 "reversed normals, so neither side is right); the glTF-Validator checks unit length only.", GLTF),
    "OPBR1247": ("A tangent frame that does not flip on mirrored UV islands reads the normal map's green axis inverted "
                 "there; the glTF-Validator checks that w is a sign, not which sign.",
                 f"{GLTF}; https://github.com/mmikk/MikkTSpace"),
    "OPBR1248": ("A volume (thickness above 0) on an open surface has no inside: refraction and attenuation are "
                 "undefined; the glTF-Validator does not check closure.", f"{khr('KHR_materials_volume')}"),
    "OPBR1249": ("Every viewer discards a MASK fragment whose alpha is below alphaCutoff (and BLEND draws alpha 0 as "
                 "nothing): when no texel of the base colour texture reaches it, the whole surface disappears, in "
                 "every viewer; the glTF-Validator reads no texels.", f"{GLTF}; {GLTF_MATERIAL_SCHEMA}"),
    "OPBR1250": ("Every viewer reads alpha 1 from an image without alpha: a MASK material whose base colour texture "
                 "has none keeps every fragment, and its cut-out renders as solid geometry; the glTF-Validator reads "
                 "no texels.", f"{GLTF}; {GLTF_MATERIAL_SCHEMA}"),
    "OPBR1201": ("glTF loaders ignore extensions not listed in extensionsUsed (and the Khronos validator "
                 "errors): the extension's look is lost. A loader without KHR_mesh_quantization, listed as optional, "
                 "misreads the quantised attributes instead of refusing the file (NON_REQUIRED_EXTENSION).", f"{GLTF}; https://github.com/KhronosGroup/glTF-Validator"),
    "OPBR1202": ("A loader that does not support a required extension must refuse the whole asset; the toolkit "
                 "cannot check what that extension does.", GLTF),
    "OPBR1203": ("The glTF specification forbids combining these extensions (pbrSpecularGlossiness with the PBR "
                 "extensions, unlit with others): loaders pick one.", f"{GLTF}; {khr('KHR_materials_pbrSpecularGlossiness')}"),
    "OPBR1204": ("The material's look is defined by the archived specular-glossiness extension, which gltf_pbr (and "
                 "OpenPBR) cannot hold: viewers that dropped it show the fallback, and a conversion approximates it "
                 "by the spec-gloss -> metal-rough solve.",
                 f"{khr('KHR_materials_pbrSpecularGlossiness')}; {_MX}libraries/bxdf/gltf_pbr.mtlx"),
    "OPBR1205": ("A texture reading a UV set the mesh does not have samples nothing (or set 0) in loaders: the "
                 "texture renders wrong or as its factor. UV sets with a gap break the specification's MUST, and "
                 "loaders that count or bind the sets by position read the later ones as others (the glTF-Validator's "
                 "MESH_PRIMITIVE_INDEXED_SEMANTIC_CONTINUITY).", GLTF),
    "OPBR1206": ("WebGL 1 cannot mipmap or wrap non-power-of-two images; older loaders resample (info).", GLTF),
    "OPBR1207": ("Core glTF allows PNG and JPEG only; other images need their texture extension or loaders "
                 "skip them.", f"{GLTF}; {khr('KHR_texture_basisu')}"),
    "OPBR1208": ("emissive_strength multiplies emissiveFactor; with nothing emitted it has no effect (a likely "
                 "authoring slip).", khr("KHR_materials_emissive_strength")),
    "OPBR1209": ("A buffer or image that cannot be loaded fails the asset in glTF loaders and the Khronos "
                 "validator; a buffer shorter than its byteLength leaves the data at its end undefined, and an "
                 "unaligned GLB chunk breaks loaders that map the binary data in place; a buffer data URI of another "
                 "media type is refused by loaders that check it (the glTF-Validator's BUFFER_BYTE_LENGTH_MISMATCH, "
                 "GLB_CHUNK_LENGTH_UNALIGNED, BUFFER_DATA_URI_MIME_TYPE_INVALID).",
                 f"{GLTF}; https://github.com/KhronosGroup/glTF-Validator; KhronosGroup/glTF-Validator:lib/src/errors.dart"),
    "OPBR1210": ("A property of the wrong JSON type violates the schema: loaders ignore it or refuse the file, and a "
                 "null textureInfo is dereferenced by loaders that test only for the property's presence (the "
                 "glTF-Validator's TYPE_MISMATCH). A variants object on a material, a mapping without variants, or a "
                 "variant that is no object with a name never switches a material (UNEXPECTED_EXTENSION_OBJECT, "
                 "EMPTY_ENTITY, ARRAY_TYPE_MISMATCH). An image in a strided bufferView breaks a MUST NOT "
                 "(IMAGE_BUFFER_VIEW_WITH_BYTESTRIDE); a Draco object without its bufferView leaves a required "
                 "decoder nothing to decode, so the mesh is not drawn.",
                 f"{GLTF_MATERIAL_SCHEMA}; {GLTF}; {khr('KHR_materials_variants')}; "
                 f"{_GLTF}extensions/2.0/Khronos/KHR_materials_variants/schema/mesh.primitive.KHR_materials_variants.schema.json; "
                 f"{_GLTF}extensions/2.0/Khronos/KHR_draco_mesh_compression/schema/"
                 "mesh.primitive.KHR_draco_mesh_compression.schema.json"),
    "OPBR1211": ("The extension texts say these settings do nothing (transmission on a metal, a volume without "
                 "transmission, dispersion without a volume, a texture "
                 "without the channel its slot reads): intent lost, and viewers differ.",
                 f"{khr('KHR_materials_volume')}; {khr('KHR_materials_dispersion')}; {khr('KHR_materials_iridescence')}; "
                 f"{khr('KHR_materials_transmission')}; {khr('KHR_materials_diffuse_transmission')}; "
                 f"{khr('KHR_materials_sheen')}; {khr('KHR_materials_specular')}; {khr('KHR_materials_anisotropy')}; {GLTF}"),
    "OPBR1251": ("Each extension's factor defaults to 0, so an empty object switches nothing on; valid glTF that the "
                 "Khronos glTF-Validator passes, written by exporters for a lobe at 0.",
                 f"{khr('KHR_materials_sheen')}; {khr('KHR_materials_transmission')}; {khr('KHR_materials_clearcoat')}; "
                 f"{khr('KHR_materials_iridescence')}; {khr('KHR_materials_anisotropy')}; "
                 f"{khr('KHR_materials_diffuse_transmission')}"),
    "OPBR1213": ("A property the schema does not define is ignored by every viewer: a misspelt factor renders as its "
                 "default, silently. The Khronos glTF-Validator warns (UNEXPECTED_PROPERTY).",
                 f"{GLTF_MATERIAL_SCHEMA}; {khr('KHR_materials_iridescence')}; https://github.com/KhronosGroup/glTF-Validator"),
    "OPBR1214": ("A loader that picks the image decoder by the declared MIME type fails on bytes of another "
                 "format: the material shows without its texture (the glTF-Validator's IMAGE_MIME_TYPE_INVALID).",
                 f"{GLTF}; KhronosGroup/glTF-Validator:lib/src/errors.dart"),
    "OPBR1215": ("Nothing renders wrong: viewers without spec-gloss show the authored metallic-roughness fallback "
                 "(info, so a carefully exported legacy asset is not reported as at risk).",
                 f"{_GLTF}extensions/2.0/Archived/KHR_materials_pbrSpecularGlossiness/README.md"),
    "OPBR1216": ("Viewers ignore an extension they do not know: a misspelt name silently drops the effect it was "
                 "meant to add (the glTF-Validator only notes it cannot validate the extension).",
                 f"{GLTF}; KhronosGroup/glTF-Validator:lib/src/errors.dart"),
    "OPBR1217": ("Vertex attributes in a format glTF does not allow are rejected or misread by loaders: unsigned "
                 "bytes without normalized read as 0-255, so every texture samples far outside [0, 1] and vertex "
                 "colours multiply the base colour by up to 255; a VEC3 tangent has no handedness for the normal map "
                 "(the glTF-Validator's MESH_PRIMITIVE_ATTRIBUTES_ACCESSOR_INVALID_FORMAT, ACCESSOR_NORMALIZED_INVALID).",
                 f"{GLTF}; {_GLTF}extensions/2.0/Khronos/KHR_mesh_quantization/README.md; "
                 f"{_GLTF}specification/2.0/schema/accessor.schema.json"),
    "OPBR1218": ("Without a tangent space a clear-coat normal map or an anisotropy direction has no orientation: "
                 "viewers generate different tangents or none (the glTF-Validator's MESH_PRIMITIVE_NO_TANGENT_SPACE). "
                 "Tangents without normals MUST be ignored by loaders, which shade with flat normals and generated "
                 "tangents (MESH_PRIMITIVE_TANGENT_WITHOUT_NORMAL).",
                 f"{_GLTF}extensions/2.0/Khronos/KHR_materials_clearcoat/README.md; "
                 f"{_GLTF}extensions/2.0/Khronos/KHR_materials_anisotropy/README.md; {GLTF}"),
    "OPBR1219": ("A 16-bit base colour or emissive image, or a CMYK JPEG, breaks glTF's MUSTs (8-bit sRGB colour "
                 "textures; JFIF JPEGs): loaders truncate, reject or miscolour it (the glTF-Validator's "
                 "IMAGE_DATA_INVALID for the JPEG).", f"{GLTF}; https://www.w3.org/Graphics/JPEG/jfif3.pdf"),
    "OPBR1220": ("A WebP or KTX2 image named by a texture's core source fails in viewers without the extension, and "
                 "viewers with it never look there (the glTF-Validator's TEXTURE_INVALID_IMAGE_MIME_TYPE); a "
                 "KHR_texture_basisu source that is no Basis Universal KTX2 (a legacy .basis file, raw texels) fails "
                 "in the Basis transcoders of the viewers that read the extension.",
                 f"{GLTF}; {khr('KHR_texture_basisu')}; {_GLTF}extensions/2.0/Vendor/EXT_texture_webp/README.md; "
                 "KhronosGroup/glTF-Validator:lib/src/errors.dart"),
    "OPBR1221": ("Glass blended by a uniform alpha is transparent twice: its reflections and tint fade, and it almost "
                 "disappears; the extension asks for OPAQUE when alpha is not coverage.", khr("KHR_materials_transmission")),
    "OPBR1222": ("A length in the wrong unit (micrometres for nanometres, centimetres for metres) renders no thin-film "
                 "colour, or refraction and absorption through an object hundreds of times too thick.",
                 f"{khr('KHR_materials_iridescence')}; {khr('KHR_materials_volume')}; {GLTF}"),
    "OPBR1223": ("A volume whose attenuation keeps no light over its thickness renders black glass (Beer-Lambert with the "
                 "extension's attenuationColor and attenuationDistance).", khr("KHR_materials_volume")),
    "OPBR1224": ("A thickness range whose minimum exceeds its maximum inverts the thickness texture: thin where it was "
                 "painted thick.", khr("KHR_materials_iridescence")),
    "OPBR1225": ("A variant mapped twice on one primitive gives the primitive two materials for one selection: viewers "
                 "pick either (the glTF-Validator's KHR_MATERIALS_VARIANTS_NON_UNIQUE_VARIANT).",
                 f"{khr('KHR_materials_variants')}; KhronosGroup/glTF-Validator:lib/src/errors.dart"),
    "OPBR1226": ("Two variants of one name cannot both be selected by name in a configurator or API.",
                 khr("KHR_materials_variants")),
    "OPBR1227": ("A tangent w that is not a sign collapses or flips the bitangent, so normal maps (and clear-coat "
                 "normals, anisotropy) shade wrong (the glTF-Validator's ACCESSOR_INVALID_SIGN).",
                 f"{GLTF}; KhronosGroup/glTF-Validator:lib/src/errors.dart"),
    "OPBR1228": ("An unaligned accessor is refused by GPU APIs (WebGL: INVALID_OPERATION) or read misaligned; a stride "
                 "smaller than an element overlaps vertices, one that is no multiple of 4 (or outside 4-252) starts every "
                 "other vertex off a 4-byte boundary; unsorted or out-of-range sparse indices substitute UVs at "
                 "the wrong vertices or past the end; attributes of unequal count leave vertices without UVs, an "
                 "accessor longer than its view reads its last elements from elsewhere, indices past the vertex count "
                 "name vertices that do not exist: the texture is misplaced or the mesh is not drawn (the "
                 "glTF-Validator's ACCESSOR_OFFSET_ALIGNMENT, ACCESSOR_SMALL_BYTESTRIDE, VALUE_MULTIPLE_OF, "
                 "BUFFER_VIEW_TOO_BIG_BYTE_STRIDE, MESH_PRIMITIVE_ACCESSOR_UNALIGNED, ACCESSOR_TOO_LONG, "
                 "ACCESSOR_SPARSE_INDICES_NON_INCREASING, ACCESSOR_SPARSE_INDEX_OOB, ACCESSOR_INDEX_OOB, "
                 "MESH_PRIMITIVE_UNEQUAL_ACCESSOR_COUNT, all errors).",
                 f"{GLTF}; {_GLTF}specification/2.0/schema/bufferView.schema.json; "
                 "KhronosGroup/glTF-Validator:lib/src/errors.dart; KhronosGroup/glTF-Validator:lib/src/base/accessor.dart"),
    "OPBR1229": ("A texture whose only image needs WebP or KTX2 support, with the extension optional, renders as a plain "
                 "factor in every viewer without that support instead of the asset being refused (the extensions' "
                 "\"Using Without a Fallback\"; the glTF-Validator does not check it).",
                 f"{_GLTF}extensions/2.0/Vendor/EXT_texture_webp/README.md; {khr('KHR_texture_basisu')}"),
    "OPBR1230": ("A property written twice in one object is read as the last value by JavaScript and Python parsers "
                 "and as the first by others: one file, two materials, depending on the viewer (the glTF-Validator, "
                 "parsing with JSON.parse, keeps the last and says nothing).",
                 f"{GLTF}; https://www.rfc-editor.org/rfc/rfc8259#section-4"),
    "OPBR1231": ("A NaN texture coordinate samples garbage, a NaN normal or position drops or blackens triangles, and a "
                 "normal not of unit length scales the lighting and tilts normal maps in viewers that do not "
                 "renormalise (the glTF-Validator's ACCESSOR_INVALID_FLOAT, ACCESSOR_VECTOR3_NON_UNIT, errors).",
                 f"{GLTF}; KhronosGroup/glTF-Validator:lib/src/errors.dart; "
                 "KhronosGroup/glTF-Validator:lib/src/base/accessor.dart"),
    "OPBR1212": ("Nothing renders wrong (info: Khronos' own samples use these); checks and conversions see the "
                 "material without the extension, and a conversion reports what it keeps or loses.",
                 f"{khr('KHR_materials_diffuse_transmission')}; {GLTF}"),
}
