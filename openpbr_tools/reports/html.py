"""The visual report of ``openpbr convert --report`` and ``openpbr compare --report``: one
self-contained HTML page (images embedded as ``data:`` URIs, CSS inline, no JavaScript) with, per
material, the original and the converted preview side by side on each shape, the ΔE2000 heat map,
the numbers, and the loss report grouped by severity (errors first).

Deterministic: the same comparisons and notes give the same bytes. Text is HTML-escaped.
"""

from __future__ import annotations

import base64
import html
from dataclasses import dataclass, field

from ..diagnostics import Severity

STYLE = """
body{font:14px/1.4 system-ui,sans-serif;margin:24px;background:#fafafa;color:#222}
h1{font-size:20px}h2{font-size:17px;margin-top:32px;border-top:1px solid #ccc;padding-top:12px}
table{border-collapse:collapse;margin:8px 0}td,th{border:1px solid #ccc;padding:3px 8px;text-align:right}
th{background:#eee}td.l,th.l{text-align:left}figure{display:inline-block;margin:4px 8px 4px 0;text-align:center}
figure img{image-rendering:pixelated;border:1px solid #999;width:192px;height:192px}figcaption{font-size:12px}
.error{color:#b00020}.warning{color:#8a5a00}.info{color:#555}.fail{background:#fde2e2}
ul{margin:4px 0 8px 20px;padding:0}
"""


@dataclass
class Entry:
    """One material of the report: names, models, the comparison's numbers and images (per shape,
    PNG bytes ``a``, ``b``, ``delta_e``), and its notes (diagnostics)."""

    name: str
    model_a: str
    model_b: str
    name_b: str | None = None
    numbers: dict = field(default_factory=dict)  # shape -> DeltaE, plus "albedo"
    images: dict = field(default_factory=dict)  # shape -> {"a": bytes, "b": bytes, "delta_e": bytes}
    diagnostics: list = field(default_factory=list)
    notes: list[str] = field(default_factory=list)
    exceeds: bool = False


def _image(data: bytes, alt: str) -> str:
    encoded = base64.b64encode(data).decode("ascii")
    return f'<img src="data:image/png;base64,{encoded}" alt="{html.escape(alt)}">'


def render_html(title: str, entries: list[Entry], threshold: float | None = None, legend: bytes | None = None,
                labels: tuple[str, str] = ("original", "converted")) -> str:
    """The page (see the module docstring)."""
    out = ["<!DOCTYPE html>", '<html lang="en"><head><meta charset="utf-8">',
           f"<title>{html.escape(title)}</title><style>{STYLE}</style></head><body>",
           f"<h1>{html.escape(title)}</h1>"]
    summary = ['<table id="summary"><tr><th class="l">material</th><th class="l">models</th><th>sphere mean</th>'
               '<th>sphere p95</th><th>sphere max</th><th>swatch mean</th><th>swatch p95</th><th>swatch max</th>'
               '<th>errors</th><th>warnings</th></tr>']
    for k, entry in enumerate(entries):
        sphere, flat = entry.numbers.get("sphere"), entry.numbers.get("swatch")
        cells = [_numbers(sphere), _numbers(flat)]
        errors = sum(1 for d in entry.diagnostics if d.severity == Severity.ERROR)
        warnings = sum(1 for d in entry.diagnostics if d.severity == Severity.WARNING)
        css = ' class="fail"' if entry.exceeds else ""
        summary.append(f'<tr{css}><td class="l"><a href="#m{k}">{html.escape(entry.name)}</a></td>'
                       f'<td class="l">{html.escape(entry.model_a)} &rarr; {html.escape(entry.model_b)}</td>'
                       f"{cells[0]}{cells[1]}<td>{errors}</td><td>{warnings}</td></tr>")
    summary.append("</table>")
    if threshold is not None:
        out.append(f"<p>Threshold: mean CIEDE2000 {threshold:g} (rows above it are highlighted).</p>")
    out += summary
    if legend is not None:
        out.append(f"<p>ΔE2000 heat map, 0 to 20: {_image(legend, 'heat-map scale 0 to 20')}</p>")
    for k, entry in enumerate(entries):
        heading = html.escape(entry.name) + (f" &rarr; {html.escape(entry.name_b)}" if entry.name_b else "")
        out.append(f'<h2 id="m{k}">{heading}</h2>')
        out.append(f"<p>{html.escape(entry.model_a)} &rarr; {html.escape(entry.model_b)}"
                   f"{' &mdash; <strong class=error>above the threshold</strong>' if entry.exceeds else ''}</p>")
        for shape, images in entry.images.items():
            out.append("<div>")
            for key, caption in (("a", f"{labels[0]} ({shape})"), ("b", f"{labels[1]} ({shape})"),
                                 ("delta_e", f"ΔE2000 ({shape})")):
                if key in images:
                    out.append(f"<figure>{_image(images[key], caption)}<figcaption>{html.escape(caption)}</figcaption></figure>")
            out.append("</div>")
        rows = ['<table><tr><th class="l">view</th><th>mean</th><th>p95</th><th>max</th><th>samples</th></tr>']
        for label, delta in entry.numbers.items():
            if delta is not None:
                rows.append(f'<tr><td class="l">{html.escape(label)}</td><td>{delta.mean:.2f}</td><td>{delta.p95:.2f}</td>'
                            f"<td>{delta.max:.2f}</td><td>{delta.samples}</td></tr>")
        rows.append("</table>")
        out += rows
        for severity in (Severity.ERROR, Severity.WARNING, Severity.INFO):
            found = [d for d in entry.diagnostics if d.severity == severity]
            if not found:
                continue
            out.append(f'<h3 class="{severity}">{str(severity).capitalize()}s ({len(found)})</h3><ul>')
            for d in found:
                where = f" <code>{html.escape(d.location.input)}</code>" if d.location.input else ""
                out.append(f'<li class="{severity}"><code>{html.escape(d.code)}</code>{where}: {html.escape(d.message)}</li>')
            out.append("</ul>")
        if entry.notes:
            out.append("<h3>Evaluator notes</h3><ul>" + "".join(f"<li>{html.escape(n)}</li>" for n in entry.notes) + "</ul>")
    out.append("</body></html>")
    return "\n".join(out) + "\n"


def _numbers(delta) -> str:
    if delta is None:
        return "<td>&ndash;</td><td>&ndash;</td><td>&ndash;</td>"
    return f"<td>{delta.mean:.2f}</td><td>{delta.p95:.2f}</td><td>{delta.max:.2f}</td>"


def entry_for(comparison, diagnostics=(), threshold: float | None = None, name: str | None = None) -> Entry:
    """An :class:`Entry` from a :class:`~openpbr_tools.evaluate.verify.MaterialComparison` (with its
    ``views`` kept) and the notes located at its material."""
    from ..evaluate.visual import view_images  # lazy: Pillow loads only when a report is written

    numbers = {"sphere": comparison.preview}
    if comparison.swatch is not None:
        numbers["swatch"] = comparison.swatch
    numbers["albedo"] = comparison.albedo
    images = {view.shape: view_images(view) for view in comparison.views}
    exceeds = threshold is not None and comparison.worst.exceeds(threshold)
    name_b = comparison.name_b if comparison.name_b not in (comparison.name_a, name) else None
    return Entry(name or comparison.name_a, comparison.model_a, comparison.model_b, name_b, numbers, images,
                 sorted(diagnostics, key=lambda d: (-int(d.severity), d.code, d.location.input or "", d.message)),
                 list(comparison.notes), exceeds)
