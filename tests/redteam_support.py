"""What the red-team rounds' tests share (tests/test_red_team_round_*.py): a validation report of one file, its
codes at warning and error, a small MaterialX document written from a body, a small PNG."""

from __future__ import annotations

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
