"""Real published assets (tests/data/published, sources and licences in its SOURCES.md): MaterialX's
example library, OpenUSD's and the USD working group's test assets, factor-only derivatives of
Khronos' glTF sample models, and 110 materials of the CC0 physically-based database (and 198 more as another
published generator exports it, kwokcb/materialxMaterials).

A finding on a published, working asset is a false alarm until the asset is shown broken. Every
error the validator reports on this corpus is listed below with its verdict: a defect of the asset
(shown), a test fixture that is not meant to render, a policy, or a false alarm still to remove.
The test fails when an error appears that is not listed (a new false alarm) and when a listed one
disappears (shrink the list)."""

from __future__ import annotations

import collections
import os
from pathlib import Path

from openpbr_tools.validate import Options, validate_paths

CORPUS = Path(__file__).resolve().parent / "data" / "published"
USDMTLX = "usd/openusd/pxr/usd/usdMtlx/testenv/testUsdMtlxFileFormat.testenv"
TESTSUITE = "materialx/resources/Materials/TestSuite"
HARNESS_IMAGES = ("fixture: names resources/Images/... from the MaterialX repository root, which MaterialX's test "
                  "harness puts on its search path; nothing is there beside the file")

# (file, code): (count, verdict)
EXPECTED_ERRORS = {
    (f"{USDMTLX}/ExpandFilePrefix.mtlx", "OPBR701"):
        (2, "fixture: tests fileprefix expansion; the .tif files do not exist in OpenUSD either"),
    (f"{USDMTLX}/Looks.mtlx", "OPBR004"):
        (14, "fixture: MaterialX's Document.validate() rejects it too (custom nodes without definitions)"),
    (f"{USDMTLX}/NodeGraphs.mtlx", "OPBR004"):
        (4, "fixture: MaterialX's Document.validate() rejects it too (invalid port connections)"),
    (f"{USDMTLX}/baseline/NodeGraphs.usda", "OPBR701"):
        (4, "fixture: UsdMtlx's generated baseline names layer1.tif, layer2.tif, mask1.tif and multilayer.tif, which do "
            "not exist in OpenUSD either; usd-core's MissingReferenceValidator calls them errors (a usd-core OPBR1010 "
            "warning until session 26)"),
    (f"{USDMTLX}/baseline/Looks.usda", "OPBR1003"):
        (16, "fixture: UsdMtlx's generated baseline; its custom nodedefs exist only in Looks.mtlx"),
    # (testPreviewSurfaceConnectedScalar.usda connects roughness to a UsdPrimvarReader_float whose result is authored
    # float2: an OPBR1005 error until session 20; Storm reads the node's definition, float: OPBR1030, an info)
    ("usd/usd-wg/test_assets/MaterialXTest/standard_surface_brass_tiled.mtlx", "OPBR701"):
        (2, "defect: fileprefix './textures/' plus file './textures/brass_color.jpg' names ./textures/./textures/..."),
    # (usd-wg's MaterialXTest/basicTextured.usda references ../_common/teapot.usda: an OPBR1011 policy error until
    # session 20; the corpus is validated as a folder, which is the tree its files may read from)
    (f"{TESTSUITE}/pbrlib/surfaceshader/network_surfaceshader.mtlx", "OPBR701"): (1, HARNESS_IMAGES),
    # (an image behind a computed texcoord: its file was not looked for until session 20)
    (f"{TESTSUITE}/pbrlib/surfaceshader/usd_normal_map.mtlx", "OPBR701"): (1, HARNESS_IMAGES),
    (f"{TESTSUITE}/pbrlib/surfaceshader/normalmapped_surfaceshader.mtlx", "OPBR701"): (2, HARNESS_IMAGES),
    (f"{TESTSUITE}/stdlib/nodegraphs/cascade_nodegraphs.mtlx", "OPBR701"): (1, HARNESS_IMAGES),
    (f"{TESTSUITE}/stdlib/nodegraphs/nodegraph_nodegraph.mtlx", "OPBR701"): (3, HARNESS_IMAGES),
    (f"{TESTSUITE}/stdlib/color_management/color_management.mtlx", "OPBR701"): (11, HARNESS_IMAGES),
    # (its gamma18, gamma22 and gamma24 were OPBR502 errors until session 19: MaterialX's colour management remaps
    # them itself, schemas/colorspaces.json materialx_remapped)
    (f"{TESTSUITE}/stdlib/definition/definition_reduced_interface.mtlx", "OPBR104"):
        (1, "defect: its nodedef says nodename=\"pattern_shader\" where node= declares a category, so no nodedef "
            "declares the pattern_shader node it instantiates (MaterialX's validate() does not check categories)"),
    ("materialx_materials/PhysicallyBasedMaterialX_OPBR.mtlx", "OPBR202"):
        (12, "defect: subsurface_radius, a float in OpenPBR 1.1.1's nodedef, holds the database's three-channel radius "
             "(\"10,5,1\" for coffee): MaterialX cannot read it as a float and renders the default (the per-channel "
             "radius is subsurface_radius_scale)"),
    ("materialx_materials/PhysicallyBasedMaterialX_OPBR.mtlx", "OPBR301"):
        (5, "defect: transmission_dispersion_scale, in [0, 1], holds the Abbe number (55.3 diamond, 64 glass, 72.2 "
            "sapphire); the Abbe number's input is transmission_dispersion_abbe_number"),
    ("usd/openusd/pxr/usdImaging/usdImagingGL/testenv/testUsdImagingGLPreviewSurface/"
     "testPreviewSurfaceOpacityThreshold.usda", "OPBR1034"):
        (2, "fixture: the threshold test's Material_0_4 and _0_5 read an alpha of 128/255 everywhere under thresholds "
            "0.9 and 1, so Storm draws nothing of them (its baseline shows the other four planes)"),
    ("gltf_samples/Avocado_SpecGloss/Avocado_SpecGloss.gltf", "OPBR1210"):
        (1, "defect: glossinessFactor is [20.0], an array where the schema wants a number in [0, 1] (the Khronos "
            "validator's TYPE_MISMATCH)"),
}

# Warnings on the glTF sample models (gltf_samples/), each a fact about the file the Khronos validator shares or
# its extension text states: the older IridescenceSuzanne misspells iridescenceIor (UNEXPECTED_PROPERTY), and
# the Avocado spec-gloss variant uses the archived extension without a metallic-roughness fallback (BoomBox and
# WaterBottle author one: OPBR1215, an info).
EXPECTED_GLTF_SAMPLE_WARNINGS = {
    ("gltf_samples/IridescenceSuzanne/IridescenceSuzanne.gltf", "OPBR1213"): 3,
    ("gltf_samples/Avocado_SpecGloss/Avocado_SpecGloss.gltf", "OPBR1204"): 1,
}


def test_every_error_on_published_assets_is_accounted_for():
    report = validate_paths([str(CORPUS)], options=Options(use_config=False, jobs=1))
    assert not report.unreadable, [d for d in report.diagnostics if d.code in ("OPBR001", "OPBR002")]
    found = collections.Counter(
        (os.path.relpath(d.location.file, CORPUS).replace(os.sep, "/"), d.code)
        for d in report.diagnostics if str(d.severity) == "error")
    assert dict(found) == {key: count for key, (count, _) in EXPECTED_ERRORS.items()}


def test_the_gltf_samples_get_no_warning_but_the_listed_ones():
    report = validate_paths([str(CORPUS / "gltf_samples")], options=Options(use_config=False, jobs=1))
    found = collections.Counter(
        (os.path.relpath(d.location.file, CORPUS).replace(os.sep, "/"), d.code)
        for d in report.diagnostics if str(d.severity) == "warning")
    assert dict(found) == EXPECTED_GLTF_SAMPLE_WARNINGS


def test_the_corpus_covers_every_source():
    files = [p.relative_to(CORPUS).as_posix() for p in CORPUS.rglob("*") if p.is_file()]
    suffixes = collections.Counter(Path(f).suffix for f in files)
    assert suffixes[".mtlx"] >= 240 and suffixes[".gltf"] >= 75 and suffixes[".usda"] >= 10
    assert (CORPUS / "SOURCES.md").is_file()
