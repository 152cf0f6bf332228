"""What a run shares between conversions (see :class:`RunCache`): the baker decodes image files and
encodes baked images through :data:`RUN`, one per process (a batch worker's life)."""

from __future__ import annotations

import os

import numpy as np

from .io.images import load_pixels


class RunCache:
    """What a run (a batch worker's life) shares between conversions, so an image used by many
    materials or files is decoded once and a baked image that comes out the same is encoded once:
    decoded files by real path, size and modification time, encoded images by a digest of their
    texels and how they are encoded. Bounded (least recently used first out) by texel bytes."""

    def __init__(self, limit_bytes: int = 512 << 20):
        from collections import OrderedDict  # lazy: only bakes need it

        self.limit = limit_bytes
        self._decoded_lru: OrderedDict = OrderedDict()
        self._encoded_lru: OrderedDict = OrderedDict()
        self.size = 0

    def _stamp(self, path: str):
        info = os.stat(path)
        return path, info.st_size, info.st_mtime_ns

    def pixels(self, path: str, levels: bool):
        key = self._stamp(path) + (levels,)
        if key in self._decoded_lru:
            self._decoded_lru.move_to_end(key)
            return self._decoded_lru[key]
        pixels = load_pixels(path, levels)
        pixels.flags.writeable = False  # shared by every conversion of the run: nobody may edit it
        self._decoded_lru[key] = pixels
        self.size += pixels.nbytes
        while self.size > self.limit and len(self._decoded_lru) > 1:
            _, dropped = self._decoded_lru.popitem(last=False)
            self.size -= dropped.nbytes
        return pixels

    def encoded(self, values, how: tuple, encode):
        import hashlib  # lazy: only bakes need it

        key = (hashlib.blake2b(np.ascontiguousarray(values).tobytes(), digest_size=20).digest(), values.shape, how)
        if key not in self._encoded_lru:
            self._encoded_lru[key] = encode()
            while len(self._encoded_lru) > 64:
                self._encoded_lru.popitem(last=False)
        self._encoded_lru.move_to_end(key)
        return self._encoded_lru[key]


RUN = RunCache()


def decoded(located, levels: bool):
    """A located image's pixels: files through the run's cache, packaged images decoded here."""
    if isinstance(located.image, str):
        return RUN.pixels(located.image, levels)
    return load_pixels(located.image, levels)
