"""Headless OpenGL for the tests that compare the evaluator with MaterialX's GLSL renderer.

``gl_display()`` makes sure an X display is available: it uses ``$DISPLAY`` when set, otherwise
starts ``Xvfb`` (if installed) on a free display number for the rest of the process and sets
``DISPLAY``. ``gl_status()`` then checks, in a subprocess (a failing GL context can abort the
process), that MaterialX's ``GlslRenderer`` can create a context. Tests call
``require_gl()`` (or use the ``materialx_renderer`` helper), which skips with a reason naming what
is missing; skips are listed by ``pytest -ra``.

:class:`MaterialXRenderer` renders a material node of any of the four models on the same sphere,
camera and lighting as :func:`openpbr_tools.evaluate.preview.shade_sphere` (its ``Rig``): a
tessellated UV sphere of radius 1 (OBJ written to a temporary folder, 256 x 128 quads),
orthographic camera looking down -z over [-extent, extent]^2, one MaterialX
``directional_light`` (direction = -rig.key, intensity = rig.key_irradiance) and uniform
radiance/irradiance environment maps of value rig.environment_radiance (FIS environment
sampling, MaterialX's default), float framebuffer, no sRGB encoding. One shader is compiled per
model; materials set its uniforms.
"""

from __future__ import annotations

import atexit
import ctypes
import os
import shutil
import subprocess
import sys
import tempfile
import time
from functools import lru_cache
from pathlib import Path

import numpy as np

NODEDEFS = {
    "open_pbr_surface": "ND_open_pbr_surface_surfaceshader",
    "standard_surface": "ND_standard_surface_surfaceshader",
    "gltf_pbr": "ND_gltf_pbr_surfaceshader",
    "UsdPreviewSurface": "ND_UsdPreviewSurface_surfaceshader",
}

_xvfb: subprocess.Popen | None = None


def _stop_xvfb() -> None:
    global _xvfb
    if _xvfb is not None and _xvfb.poll() is None:
        _xvfb.terminate()
        try:
            _xvfb.wait(timeout=5)
        except subprocess.TimeoutExpired:
            _xvfb.kill()
    _xvfb = None


@lru_cache(maxsize=1)
def gl_display() -> tuple[str | None, str]:
    """``(display, how)``: the X display to use and how it was obtained, or ``(None, reason)``."""
    global _xvfb
    if os.environ.get("DISPLAY"):
        return os.environ["DISPLAY"], "DISPLAY from the environment"
    xvfb = shutil.which("Xvfb")
    if xvfb is None:
        return None, "DISPLAY is unset and Xvfb is not installed (apt-get install xvfb xauth libgl1-mesa-dri)"
    for number in range(91, 200):
        if Path(f"/tmp/.X{number}-lock").exists() or Path(f"/tmp/.X11-unix/X{number}").exists():
            continue
        proc = subprocess.Popen(
            [xvfb, f":{number}", "-screen", "0", "640x480x24", "-nolisten", "tcp"],
            stdout=subprocess.DEVNULL,
            stderr=subprocess.DEVNULL,
        )
        for _ in range(100):
            if Path(f"/tmp/.X11-unix/X{number}").exists() or proc.poll() is not None:
                break
            time.sleep(0.05)
        if proc.poll() is None:
            _xvfb = proc
            atexit.register(_stop_xvfb)
            os.environ["DISPLAY"] = f":{number}"
            return os.environ["DISPLAY"], f"Xvfb started on :{number}"
    return None, "could not start Xvfb on any display :91-:199"


_PROBE = (
    "import MaterialX.PyMaterialXRender as mr, MaterialX.PyMaterialXRenderGlsl as rg\n"
    "r = rg.GlslRenderer.create(8, 8, mr.BaseType.FLOAT)\n"
    "r.initialize()\n"
    "print('ok')\n"
)


@lru_cache(maxsize=1)
def gl_status() -> tuple[bool, str]:
    """``(available, reason)`` for an OpenGL context usable by MaterialX's GLSL renderer."""
    display, how = gl_display()
    if display is None:
        return False, how
    try:
        import MaterialX.PyMaterialXRenderGlsl  # noqa: F401
    except ImportError as error:
        return False, f"MaterialX GLSL renderer bindings missing: {error}"
    try:
        proc = subprocess.run([sys.executable, "-c", _PROBE], capture_output=True, text=True, timeout=60, env=os.environ.copy())
    except subprocess.TimeoutExpired:
        return False, f"creating a GL context timed out ({how})"
    if proc.returncode != 0 or "ok" not in proc.stdout:
        detail = (proc.stderr or proc.stdout).strip().splitlines()[-1:] or ["no output"]
        return False, f"no OpenGL context on {display} ({how}): {detail[0]}"
    return True, f"OpenGL context on {display} ({how})"


def require_gl() -> None:
    """Skip the calling test with the reason when no GL context can be created."""
    import pytest

    ok, reason = gl_status()
    if not ok:
        pytest.skip(f"MaterialX GLSL reference unavailable: {reason}")


def write_sphere_obj(path: Path, segments_u: int = 256, segments_v: int = 128) -> Path:
    """A UV sphere of radius 1 with normals and texture coordinates (u = 1/2 + atan2(x, z) / 2 pi
    along the longitude, the seam at the back; v from the south pole), as a Wavefront OBJ: the
    evaluator's preview sphere (openpbr_tools.evaluate.preview.sphere_geometry)."""
    lines = []
    for j in range(segments_v + 1):
        theta = np.pi * j / segments_v
        for i in range(segments_u + 1):
            phi = 2.0 * np.pi * i / segments_u - np.pi  # from the back seam (u = 0) round to it (u = 1)
            x, y, z = np.sin(theta) * np.sin(phi), np.cos(theta), np.sin(theta) * np.cos(phi)
            lines.append(f"v {x:.8f} {y:.8f} {z:.8f}")
            lines.append(f"vn {x:.8f} {y:.8f} {z:.8f}")
            lines.append(f"vt {i / segments_u:.8f} {1.0 - j / segments_v:.8f}")
    for j in range(segments_v):
        for i in range(segments_u):
            a = j * (segments_u + 1) + i + 1
            b, c = a + 1, a + segments_u + 1
            d = c + 1
            lines.append(f"f {a}/{a}/{a} {c}/{c}/{c} {d}/{d}/{d}")
            lines.append(f"f {a}/{a}/{a} {d}/{d}/{d} {b}/{b}/{b}")
    path.write_text("\n".join(lines) + "\n")
    return path


def uniforms(values: dict) -> dict:
    """Resolved values (NumPy arrays and numbers) as :meth:`MaterialXRenderer.render` takes them: booleans, integers,
    floats and lists of floats."""
    out = {}
    for name, value in values.items():
        array = np.asarray(value)
        if array.dtype.kind == "b":
            out[name] = bool(array)
        elif array.ndim == 0:
            out[name] = int(array) if array.dtype.kind in "iu" else float(array)
        else:
            out[name] = [float(v) for v in array]
    return out


def studio_environment(width: int = 256, height: int = 128) -> np.ndarray:
    """A structured latitude-longitude environment (linear RGB, row 0 at one pole): a sky whose radiance falls
    from 0.45 to 0.25 towards the horizon, striped (12 bands of +0.06), a dark ground (0.04) and two bright
    windows (6 and 3), slightly warm. Unlike the rig's uniform environment it shows how sharply a surface
    reflects or refracts: a mirror shows the windows and the horizon, a rough lobe blurs them."""
    v = (np.arange(height) + 0.5) / height
    u = (np.arange(width) + 0.5) / width
    uu, vv = np.meshgrid(u, v)
    sky = vv < 0.5
    radiance = np.where(sky, 0.25 + 0.4 * (0.5 - vv), 0.04) + 0.06 * (np.sin(uu * 24.0 * np.pi) > 0) * sky
    radiance = np.where((np.abs(uu - 0.62) < 0.05) & (np.abs(vv - 0.35) < 0.07), 6.0, radiance)
    radiance = np.where((np.abs(uu - 0.2) < 0.08) & (np.abs(vv - 0.42) < 0.03), 3.0, radiance)
    return np.stack([radiance, radiance * 0.97, radiance * 0.9], axis=-1)


def irradiance_environment(radiance: np.ndarray) -> np.ndarray:
    """The cosine-weighted convolution of a latitude-longitude ``radiance`` map divided by pi (what MaterialX's
    irradiance map holds: a uniform radiance L gives L), by nine spherical harmonics (Ramamoorthi and Hanrahan,
    "An efficient representation for irradiance environment maps", SIGGRAPH 2001: the order-2 projection, its
    cosine-lobe factors pi, 2 pi / 3, pi / 4). Rows are polar angle, columns azimuth; the same parameterisation
    is used to project and to evaluate, so the map agrees with the radiance map whatever MaterialX's orientation."""
    height, width, _ = radiance.shape
    theta = np.pi * (np.arange(height) + 0.5) / height
    phi = 2.0 * np.pi * (np.arange(width) + 0.5) / width
    th, ph = np.meshgrid(theta, phi, indexing="ij")
    x, y, z = np.sin(th) * np.cos(ph), np.sin(th) * np.sin(ph), np.cos(th)
    basis = np.stack([0.282095 * np.ones_like(x), 0.488603 * y, 0.488603 * z, 0.488603 * x, 1.092548 * x * y,
                      1.092548 * y * z, 0.315392 * (3.0 * z * z - 1.0), 1.092548 * x * z,
                      0.546274 * (x * x - y * y)], axis=-1)
    weight = np.sin(th) * (np.pi / height) * (2.0 * np.pi / width)
    coefficients = np.einsum("hwk,hwc,hw->kc", basis, radiance, weight)
    bands = np.array([np.pi] + [2.0 * np.pi / 3.0] * 3 + [np.pi / 4.0] * 5)
    return np.einsum("hwk,kc->hwc", basis, coefficients * bands[:, None]) / np.pi


class MaterialXRenderer:
    """MaterialX GLSL rendering of single materials under a preview ``Rig`` (``environment``: the rig's
    uniform environment, or a latitude-longitude radiance map such as :func:`studio_environment`)."""

    def __init__(self, rig, environment: np.ndarray | None = None):
        import MaterialX as mx
        import MaterialX.PyMaterialXGenGlsl as gg
        import MaterialX.PyMaterialXGenShader as gs
        import MaterialX.PyMaterialXRender as mr
        import MaterialX.PyMaterialXRenderGlsl as rg

        self.mx, self.mr = mx, mr
        self.rig = rig
        self.library = mx.createDocument()
        search_path = mx.getDefaultDataSearchPath()
        mx.loadLibraries(mx.getDefaultDataLibraryFolders(), search_path, self.library)
        self.generator = gg.GlslShaderGenerator.create()
        self.context = gs.GenContext(self.generator)
        self.context.registerSourceCodeSearchPath(search_path)
        options = self.context.getOptions()
        options.hwMaxActiveLightSources = 1
        options.hwSrgbEncodeOutput = False
        options.hwSpecularEnvironmentMethod = gs.HwSpecularEnvironmentMethod.SPECULAR_ENVIRONMENT_FIS
        self.renderer = rg.GlslRenderer.create(rig.size, rig.size, mr.BaseType.FLOAT)
        self.renderer.initialize()
        self.renderer.setImageHandler(rg.GLTextureHandler.create(mr.StbImageLoader.create()))
        self._light_doc = mx.createDocument()
        self._light_doc.importLibrary(self.library)
        light = self._light_doc.addNode("directional_light", "key", "lightshader")
        d = -np.asarray(rig.key, dtype=float)
        light.setInputValue("direction", mx.Vector3(float(d[0]), float(d[1]), float(d[2])))
        light.setInputValue("color", mx.Color3(1.0, 1.0, 1.0))
        light.setInputValue("intensity", float(rig.key_irradiance))
        handler = mr.LightHandler.create()
        handler.registerLights(self._light_doc, [light], self.context)
        handler.setLightSources([light])
        self._handler = handler
        self.use_environment(environment)
        handler.setDirectLighting(True)
        handler.setIndirectLighting(True)
        self.renderer.setLightHandler(handler)
        self._tmp = Path(tempfile.mkdtemp(prefix="openpbr-gl-"))
        atexit.register(shutil.rmtree, self._tmp, True)
        geometry = self.renderer.getGeometryHandler()
        geometry.addLoader(mr.TinyObjLoader.create())
        geometry.clearGeometry()
        geometry.loadGeometry(mx.FilePath(str(write_sphere_obj(self._tmp / "sphere.obj"))), False)
        camera = self.renderer.getCamera()
        camera.setWorldMatrix(mx.Matrix44.IDENTITY)
        camera.setViewMatrix(mr.Camera.createViewMatrix(mx.Vector3(0, 0, 50), mx.Vector3(0, 0, 0), mx.Vector3(0, 1, 0)))
        ex = float(rig.extent)
        camera.setProjectionMatrix(mr.Camera.createOrthographicMatrix(-ex, ex, -ex, ex, 1.0, 100.0))
        self._documents = {}
        self._current = None

    def use_environment(self, environment: np.ndarray | None) -> None:
        """Light the following renders with the rig's uniform environment (None) or the latitude-longitude
        radiance map ``environment`` (and its irradiance: :func:`irradiance_environment`)."""
        mx, mr = self.mx, self.mr
        if environment is None:
            e = float(self.rig.environment_radiance)
            self._environment = mr.createUniformImage(64, 32, 4, mr.BaseType.FLOAT, mx.Color4(e, e, e, 1.0))
            self._irradiance = self._environment
        else:
            self._environment = self._image(environment)
            self._irradiance = self._image(irradiance_environment(environment))
        self._handler.setEnvRadianceMap(self._environment)
        self._handler.setEnvIrradianceMap(self._irradiance)

    def _image(self, pixels: np.ndarray):
        """A float RGBA MaterialX image of linear RGB ``pixels`` (row 0 first)."""
        mx, mr = self.mx, self.mr
        height, width, _ = pixels.shape
        image = mr.Image.create(width, height, 4, mr.BaseType.FLOAT)
        image.createResourceBuffer()
        for row in range(height):
            for column in range(width):
                r, g, b = (float(c) for c in pixels[row, column])
                image.setTexelColor(column, row, mx.Color4(r, g, b, 1.0))
        return image

    def _program(self, model: str):
        mx = self.mx
        if self._current == model:
            return self._documents[model][1]
        if model not in self._documents:
            doc = mx.createDocument()
            doc.importLibrary(self.library)
            node = doc.addNodeInstance(doc.getNodeDef(NODEDEFS[model]), "SR_preview")
            self._documents[model] = (doc, node, self.generator.generate(f"preview_{model}", node, self.context))
        doc, node, shader = self._documents[model]
        self.renderer.createProgram(shader)
        self._current = model
        return node

    def _uniform(self, nodedef, name, value):
        mx = self.mx
        kind = nodedef.getActiveInput(name).getType()
        if kind == "color3":
            v = [float(x) for x in np.broadcast_to(np.asarray(value, dtype=float), (3,))]
            return mx.TypedValue_color3.createValue(mx.Color3(*v))
        if kind == "float":
            return mx.TypedValue_float.createValue(float(value))
        if kind == "integer":
            return mx.TypedValue_integer.createValue(int(value))
        if kind == "boolean":
            return mx.TypedValue_boolean.createValue(bool(value))
        raise TypeError(f"unsupported uniform type {kind} for {name}")

    def render(self, model: str, values: dict) -> np.ndarray:
        """Render ``model`` with ``values`` (linear numbers; unset inputs keep the nodedef
        defaults); returns linear RGB, shape (size, size, 3), row 0 at the top."""
        self._program(model)
        nodedef = self.library.getNodeDef(NODEDEFS[model])
        for inp in nodedef.getActiveInputs():
            if inp.hasDefaultGeomPropString() or inp.getType() not in ("float", "color3", "integer", "boolean"):
                continue
            value = values[inp.getName()] if inp.getName() in values else inp.getValue()
            if value is None:
                continue
            if inp.getType() == "color3" and hasattr(value, "asTuple"):
                value = value.asTuple()
            self.renderer.updateUniform(inp.getName(), self._uniform(nodedef, inp.getName(), value))
        return self._capture()


    def _capture(self) -> np.ndarray:
        """Render and read back the framebuffer: linear RGB, row 0 at the top."""
        self.renderer.render()
        image = self.renderer.captureImage(None)
        h, w, c = image.getHeight(), image.getWidth(), image.getChannelCount()
        buffer = (ctypes.c_float * (h * w * c)).from_address(image.getResourceBuffer())
        pixels = np.ctypeslib.as_array(buffer).reshape(h, w, c).copy()
        return pixels[::-1, :, :3].astype(float)

    def render_document(self, path) -> np.ndarray:
        """Render the first surface shader of the MaterialX document at ``path`` with its own node
        graph (images, place2d, normal maps: MaterialX's GLSL samples the textures; file paths
        resolve against the document's folder; V is flipped for OpenGL's bottom-up texture rows,
        as MaterialXView does). Returns linear RGB (size, size, 3), row 0 at the top."""
        mx = self.mx
        import MaterialX.PyMaterialXGenShader as gs

        doc = mx.createDocument()
        mx.readFromXmlFile(doc, str(path))
        doc.importLibrary(self.library)
        elements = gs.findRenderableElements(doc)
        if not elements:
            raise ValueError(f"{path}: nothing to render")
        if not getattr(self, "_colour_managed", False):  # MaterialX's own colour management (cmlib transforms)
            cms = gs.DefaultColorManagementSystem.create(self.generator.getTarget())
            cms.loadLibrary(self.library)
            self.generator.setColorManagementSystem(cms)
            self._colour_managed = True
        options = self.context.getOptions()
        options.targetColorSpaceOverride = "lin_rec709"
        flip = options.fileTextureVerticalFlip
        options.fileTextureVerticalFlip = True
        try:
            shader = self.generator.generate("textured", elements[0], self.context)
        finally:
            options.fileTextureVerticalFlip = flip
        self.renderer.getImageHandler().setSearchPath(mx.FileSearchPath(str(Path(path).parent)))
        self.renderer.createProgram(shader)
        self._current = None
        return self._capture()


@lru_cache(maxsize=2)
def materialx_renderer(rig) -> MaterialXRenderer:
    """A shared renderer for ``rig`` (skips the calling test when GL is unavailable), lit by the rig's uniform
    environment (a test that calls :meth:`MaterialXRenderer.use_environment` puts it back)."""
    require_gl()
    return MaterialXRenderer(rig)


def comparison_mask(rig, radius: float = 0.96) -> np.ndarray:
    """Pixels whose centre lies within ``radius`` of the sphere's outline centre: the
    silhouette band is excluded because the tessellated outline differs from the analytic one."""
    n = rig.size
    c = -rig.extent + (np.arange(n) + 0.5) * (2.0 * rig.extent / n)
    x, y = np.meshgrid(c, -c)
    return x * x + y * y < radius * radius


@lru_cache(maxsize=1)
def shader_generator():
    """``(library, generator, context)``: MaterialX's standard libraries and a GLSL shader generator with
    its context, for tests that check an output generates a shader (no GL context needed)."""
    import MaterialX as mx  # lazy: only the tests that generate shaders need the generator modules
    import MaterialX.PyMaterialXGenGlsl as gg  # lazy: as above
    import MaterialX.PyMaterialXGenShader as gs  # lazy: as above

    library = mx.createDocument()
    mx.loadLibraries(mx.getDefaultDataLibraryFolders(), mx.getDefaultDataSearchPath(), library)
    glsl = gg.GlslShaderGenerator.create()
    context = gs.GenContext(glsl)
    context.registerSourceCodeSearchPath(mx.getDefaultDataSearchPath())
    return library, glsl, context


def validation(path):
    """(document, valid, message): the MaterialX document at ``path`` with MaterialX's standard libraries,
    and its own ``Document.validate()`` verdict."""
    import MaterialX as mx  # lazy: as in shader_generator

    document = mx.createDocument()
    mx.readFromXmlFile(document, str(path))
    document.setDataLibrary(shader_generator()[0])
    valid, message = document.validate()
    return document, valid, message


def validated(path):
    """The MaterialX document at ``path`` with MaterialX's standard libraries, asserted valid by its own
    ``Document.validate()`` (the message on failure)."""
    document, valid, message = validation(path)
    assert valid, message
    return document


def single_material(path: str, name: str, out_path: str) -> str:
    """Write the MaterialX document at ``path`` with only the surfacematerial ``name`` left (for
    ``render_document``, which renders a document's first), beside it so texture paths still resolve."""
    import MaterialX as mx  # lazy: as in shader_generator

    doc = mx.createDocument()
    mx.readFromXmlFile(doc, path)
    for material in doc.getMaterialNodes():
        if material.getName() != name:
            doc.removeNode(material.getName())
    mx.writeToXmlFile(doc, out_path)
    return out_path


def mean_delta_e(image: np.ndarray, reference: np.ndarray, mask: np.ndarray, white: float) -> float:
    """Mean CIEDE2000 over ``mask`` between two renders; NaN where either is not finite there."""
    from openpbr_tools.evaluate.difference import delta_e_2000  # lazy: the GL helpers above do not need it

    if not (np.isfinite(image[mask]).all() and np.isfinite(reference[mask]).all()):
        return float("nan")
    return float(delta_e_2000(image[mask], reference[mask], white).mean())
