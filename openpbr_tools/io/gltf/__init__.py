"""glTF 2.0 (``.gltf``, ``.glb``): the reader (``reader``, ``textures`` for its images, textures and
samplers, ``document`` for the bounded JSON/GLB loader), the parameter slots of glTF PBR and its
extensions (``slots``), the writer (``writer``, ``texture_writer``, ``document_writer``, ``images``,
``bake`` for channel packing, ``mesh``, ``uv``)."""
