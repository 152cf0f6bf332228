"""What the red-team rounds' tests share (tests/test_red_team_*.py): a validation report of one file, its
codes (or findings) at warning and error, a small MaterialX document written from a body, a small PNG, and the
Khronos glTF-Validator's error codes for a file when OPENPBR_GLTF_VALIDATOR is set."""

from __future__ import annotations

import os
import textwrap
from pathlib import Path

from PIL import Image

from openpbr_tools.validate import Options, validate_paths


def report(path):
    """The validation report of ``path``, without the project's configuration."""
    return validate_paths([str(path)], options=Options(use_config=False))


def codes(path, severities=("error", "warning")) -> dict[str, int]:
    """Code -> count of the findings at ``severities``."""
    found: dict[str, int] = {}
    for d in report(path).diagnostics:
        if str(d.severity) in severities:
            found[d.code] = found.get(d.code, 0) + 1
    return found


def findings(path) -> list[tuple[str, str, str | None, str | None]]:
    """(code, severity, JSON pointer, property) of every warning or error."""
    return [(d.code, str(d.severity), d.location.path, d.location.input) for d in report(path).diagnostics
            if str(d.severity) in ("error", "warning")]


def khronos_errors(path, tmp_path, severity: int = 0) -> set[str] | None:
    """The Khronos glTF-Validator's error codes (or those of another ``severity``: 1 warnings) for ``path``, or
    ``None`` when OPENPBR_GLTF_VALIDATOR is not set."""
    if not os.environ.get("OPENPBR_GLTF_VALIDATOR"):
        return None
    from gltf_support import validate_with_khronos

    return {m["code"] for m in validate_with_khronos(path, tmp_path)["issues"]["messages"] if m["severity"] == severity}


def khronos_warnings(path, tmp_path) -> set[str] | None:
    """The Khronos glTF-Validator's warning codes for ``path`` (``None`` as :func:`khronos_errors`)."""
    return khronos_errors(path, tmp_path, severity=1)


def messages(path, code: str) -> list[str]:
    return [d.message for d in report(path).diagnostics if d.code == code]


def mtlx(tmp_path, body: str, name: str = "m.mtlx", version: str = "1.39",
         attributes: str = 'colorspace="lin_rec709"') -> Path:
    """A MaterialX document ``name`` in ``tmp_path`` holding ``body`` (dedented, indented under the root)."""
    path = tmp_path / name
    path.write_text(f'<?xml version="1.0"?>\n<materialx version="{version}" {attributes}>\n'
                    + textwrap.indent(textwrap.dedent(body).strip("\n"), "  ") + "\n</materialx>\n", encoding="utf-8")
    return path


def png(path: Path, mode: str = "RGB", size=(4, 4), colour=(200, 120, 40)) -> Path:
    """A plain image (RGBA: alpha 128), its folders made."""
    path.parent.mkdir(parents=True, exist_ok=True)
    Image.new(mode, size, colour if mode != "RGBA" else colour + (128,)).save(path)
    return path


def textured_openpbr(file: str) -> str:
    """A body for :func:`mtlx`: an OpenPBR material whose base colour reads the image ``file`` (srgb_texture)."""
    return f'''
        <image name="albedo" type="color3">
          <input name="file" type="filename" value="{file}" colorspace="srgb_texture" />
        </image>
        <open_pbr_surface name="S" type="surfaceshader">
          <input name="base_color" type="color3" nodename="albedo" />
        </open_pbr_surface>
        <surfacematerial name="M" type="material">
          <input name="surfaceshader" type="surfaceshader" nodename="S" />
        </surfacematerial>
        '''


def textured_preview(file: str) -> str:
    """A USD layer: a UsdPreviewSurface Material ``/M`` whose diffuseColor reads the image ``file``."""
    return textwrap.dedent(f"""\
        #usda 1.0
        def Material "M"
        {{
            token outputs:surface.connect = </M/S.outputs:surface>
            def Shader "S"
            {{
                uniform token info:id = "UsdPreviewSurface"
                color3f inputs:diffuseColor.connect = </M/T.outputs:rgb>
                token outputs:surface
            }}
            def Shader "T"
            {{
                uniform token info:id = "UsdUVTexture"
                asset inputs:file = @{file}@
                float3 outputs:rgb
            }}
        }}
        """)


STAGE_METADATA = 'defaultPrim = "M"\n    metersPerUnit = 1\n    upAxis = "Y"'


def preview_stage(folder: Path, *lines: str, extra: str = "", metadata: str = STAGE_METADATA,
                  name: str = "stage.usda") -> Path:
    """A USD layer ``name`` in ``folder``: a Material ``/M`` whose UsdPreviewSurface ``/M/S`` authors ``lines``, and
    ``extra`` prims inside the Material (:func:`uv_texture`'s, say)."""
    body = "".join(f"        {line}\n" for line in lines)
    path = folder / name
    path.write_text(f"#usda 1.0\n(\n    {metadata}\n)\ndef Material \"M\"\n{{\n"
                    "    token outputs:surface.connect = </M/S.outputs:surface>\n"
                    f"    def Shader \"S\"\n    {{\n        uniform token info:id = \"UsdPreviewSurface\"\n{body}"
                    f"        token outputs:surface\n    }}\n{extra}}}\n", encoding="utf-8")
    return path


def uv_texture(name: str, file: str, output: str = "rgb", output_type: str = "float3", *lines: str) -> str:
    """A UsdUVTexture shader ``name`` inside :func:`preview_stage`'s Material, reading ``file``, with ``lines``."""
    body = "".join(f"        {line}\n" for line in lines)
    return (f"    def Shader \"{name}\"\n    {{\n        uniform token info:id = \"UsdUVTexture\"\n"
            f"        asset inputs:file = @{file}@\n{body}        {output_type} outputs:{output}\n    }}\n")
