"""USD stages (``.usda``, ``.usdc``, ``.usdz``): the reader (``reader``, ``network`` for shader
networks, ``texture_nodes`` for the texture lookups in them, ``attributes`` for attribute values),
the writer (``writer``, ``texture_networks`` for the texture networks it writes), type mapping
(``types``), the guard that decides whether a stage may be opened by usd-core at all and which layers
it may compose (``guard``, with the byte checks of ``crate``, ``package`` and ``text_layer``),
usd-core's diagnostics (``errors``), Sdr registration of the MaterialX node definitions (``sdr``) and
usd-core's own validators (``validators``)."""
