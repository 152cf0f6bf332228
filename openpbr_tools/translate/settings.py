"""The conventions a translation needs that no file states (:class:`Settings`), one object passed from the
CLI and the convert pipeline down to every mapping, candidate search and baker."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

from ..rules import Context


@dataclass(slots=True)
class Settings:
    """Conventions a translation needs that no file states.

    ``nits_per_unit``: how many nits one unit of a unitless emission weight stands for. The default,
    1, is MaterialX's reference implementation (``emission_luminance`` 1 renders as radiance 1).
    ``meters_per_unit``: the scene unit of lengths in the source (MaterialX ``unit`` attributes
    override it per input; USD's ``metersPerUnit``); glTF is always metres.
    ``gltf_drafts``: a glTF output also gets the draft extensions that carry what the ratified ones
    cannot (KHR_materials_coat, _fuzz, _diffuse_roughness, EXT_materials_specular_openpbr; see
    :mod:`openpbr_tools.io.gltf.drafts`), beside the ratified fallbacks. ``gltf_file``: the result is
    written to a glTF file (not a gltf_pbr node), so a translation may use glTF extensions the node
    has no input for (KHR_materials_diffuse_transmission for a thin-walled subsurface). ``node_graphs``: the
    output holds MaterialX node graphs (a .mtlx file, or a translation kept in memory), so a mapping of a
    procedural input is written as nodes after its graph (:mod:`.expressed`); USD and glTF writers do not.
    """

    nits_per_unit: float = 1.0
    meters_per_unit: float | None = None
    context: Context = field(default_factory=Context)
    baker: Any = None  # an openpbr_tools.bake.Baker: textures a formula transforms are baked per texel
    gltf_drafts: bool = False
    gltf_file: bool = False  # the result goes to a glTF file, which holds extensions the gltf_pbr node cannot
    candidates: bool = True  # weigh MaterialX's translation graphs against the mapping (translate.candidates)
    fit_films: bool = False  # also fit a thin film's thickness by rendering (translate.candidates; --verify)
    search: bool = False  # also search the target's parameters where the result is visibly off (translate.search; --verify)
    node_graphs: bool = True  # the output holds MaterialX node graphs (.mtlx): a mapping of a procedural input is written as nodes
    specular_split: bool = True  # a specular-workflow preview as metal + dielectric (translate.specular_workflow), else by luminance
    # a full metal's specular_weight as Standard Surface's coat tint (translate.ss_metal_weight), else in its base colour
    metal_weight_tint: bool = True
    # say (as infos) what is not carried but renders nothing (common.unread_notes); off for a USD output's preview
    # fallback, whose MaterialX shader holds those values
    unseen_notes: bool = True
    # a conversion's second step through the OpenPBR hub: where the report shows the notes at each OpenPBR input
    # the source does not hold (translate.convert.hub_sites), so that a note pointing at another names where it stands
    hub_sites: dict = field(default_factory=dict)
