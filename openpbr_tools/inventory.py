"""What a file holds, for ``openpbr info``: materials, models, versions and textures."""

from __future__ import annotations

from .model import Asset, Connection


def describe(asset: Asset) -> dict:
    not_converted = _not_converted(asset) if asset.format == "gltf" else set()  # (once: linear in the materials)
    return {
        "file": asset.path,
        "format": asset.format,
        "format_version": asset.format_version,
        "colorspace": asset.colorspace,
        "meters_per_unit": asset.meters_per_unit,
        "materials": [
            {
                "name": m.name,
                "material": m.material_location.path if asset.format == "usd" and m.material_location else m.material_name,
                "fallback_of": m.extra.get("fallback_of"),
                "model": m.model,
                "version": m.version,
                "version_basis": m.version_basis,
                "location": str(m.location),
                "inputs": len(m.inputs),
                "textures": [
                    {"input": name, "file": t.file, "colorspace": t.colorspace, "channels": list(t.channels) if t.channels else None,
                     "normal_map": t.normal_map is not None, "udim": t.is_udim}
                    for name, t in m.textures()
                ],
                "procedural_inputs": sorted(n for n, i in m.inputs.items() if isinstance(i.value, Connection)),
                "extensions": _extensions(m, not_converted) if asset.format == "gltf" else [],
            }
            for m in asset.materials
        ],
    }


def _not_converted(asset: Asset) -> set:
    """(material name, extension) for each extension the glTF reader reported as not converted."""
    return {(o.detail.get("material"), o.detail.get("extension")) for o in asset.observations
            if o.kind == "gltf_not_converted"}


def _extensions(material, not_converted: set) -> list[dict]:
    """The glTF material extensions ``material`` uses (nested ones as ``parent/name``), each with how
    the toolkit treats it: ``ratified`` (read), ``draft`` (read, see io.gltf.drafts), ``read as emission``
    (KHR_materials_unlit: its base colour emitted over a black base, translate/gltf.py), ``read as thin-walled
    subsurface`` (KHR_materials_diffuse_transmission with factors only, no volume), ``read as metal-rough
    (spec-gloss solve)`` (KHR_materials_pbrSpecularGlossiness, translate/spec_gloss.py) or ``not converted`` (as
    the reader reported it: ``not_converted``, from :func:`_not_converted`)."""
    from .io.gltf import drafts, slots  # lazy: info on a .mtlx file does not need the glTF tables

    state = material.gltf_state()
    read_as = {slots.UNLIT: "read as emission", slots.DIFFUSE_TRANSMISSION: "read as thin-walled subsurface",
               slots.SPECULAR_GLOSSINESS: "read as metal-rough (spec-gloss solve)"}
    found = []
    for name in state.get("material_extensions") or ():
        status = "ratified" if name in slots.INTERPRETED_MATERIAL_EXTENSIONS else \
            "draft" if name in drafts.MATERIAL_DRAFTS else \
            read_as[name] if name in read_as and (material.material_name or material.name, name) not in not_converted \
            else "not converted"
        found.append({"name": name, "status": status})
    for parent, name, read in state.get("nested_extensions") or ():
        found.append({"name": f"{parent}/{name}", "status": "draft" if read else "not converted"})
    return found


def describe_text(entries: list[dict]) -> str:
    lines = []
    for entry in entries:
        header = f"{entry['file']} ({entry['format']}"
        if entry["format_version"]:
            header += f" {entry['format_version']}"
        if entry["colorspace"]:
            header += f", colorspace {entry['colorspace']}"
        lines.append(header + ")")
        if not entry["materials"]:
            lines.append("  no materials")
        for m in entry["materials"]:
            bound = f" -> material {m['material']}" if m["material"] else " (not bound to a material)"
            lines.append(f"  {m['name']}{bound}: {m['model']} {m['version'] or '?'} ({m['version_basis']}), {m['inputs']} inputs")
            for t in m["textures"]:
                extra = []
                if t["channels"]:
                    extra.append("channel " + ",".join(str(c) for c in t["channels"]))
                if t["normal_map"]:
                    extra.append("normal map")
                if t["udim"]:
                    extra.append("UDIM")
                suffix = f" [{'; '.join(extra)}]" if extra else ""
                lines.append(f"    {t['input']}: {t['file']} ({t['colorspace'] or 'no colour space'}){suffix}")
            for name in m["procedural_inputs"]:
                lines.append(f"    {name}: procedural (not interpreted)")
            if m.get("extensions"):
                lines.append("    extensions: " + ", ".join(f"{e['name']} ({e['status']})" for e in m["extensions"]))
    from .reports import printable  # lazy: the text form only (names from the asset keep to their line)

    return "\n".join(printable(line) for line in lines) + "\n"
