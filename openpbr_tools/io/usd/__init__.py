"""USD stages (``.usda``, ``.usdc``, ``.usdz``): the reader (``reader``, ``network`` for shader
networks), the writer (``writer``), type mapping (``types``) and the guards that decide whether a
file may be opened by usd-core at all (``stage``)."""
