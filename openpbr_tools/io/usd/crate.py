"""Crate (``.usdc``) bytes judged before usd-core parses them, and the LZ4 decoder that needs.

usd-core's crate reader checks every read against the file's end, but sizes its buffers from counts
and sizes the file declares before reading them: a 1 KiB file declaring a 6 GB token table makes it
allocate and touch 6 GB. :func:`crate_problem` checks every count and size of the table of contents,
the structural sections (tokens, strings, fields, field sets, paths, specs) and every field value
against the bytes that must hold it; :func:`crate_tokens` reads the token table (to know whether a
layer can hold value clips at all). Compressed sections are usd-core's TfFastCompression (a 0 byte,
then one LZ4 block) over its integer coding (``sdf/integerCoding.cpp``); the small LZ4 block
decoder here reads them without another dependency.

No ``pxr`` here: these are byte checks only (:class:`~.guard.StageGuard` calls them).
"""

from __future__ import annotations

import struct

CRATE_MAGIC = b"PXR-USDC"


def crate_problem(data: bytes) -> str | None:
    """Why usd-core must not be handed these crate (``.usdc``) bytes, or ``None``.

    usd-core's crate reader checks every read against the file's end, but sizes its buffers from
    counts and sizes the file declares before reading them: a 1 KiB file declaring a 6 GB token
    table makes it allocate and touch 6 GB, and compressed integers longer than their count
    allows overrun its buffer. So every count and size in the table of contents and the structural
    sections (tokens, strings, fields, field sets, paths, specs) is checked against the section
    that must hold it: a compressed block cannot expand more than LZ4 can (255 times), and no
    buffer may exceed 64 times the file's size (real files expand less than 10 times)."""
    if len(data) < 88 or data[8] != 0:
        return None  # usd-core reports a bootstrap or version it cannot read, without reading further
    version = (data[9], data[10])
    (toc,) = struct.unpack_from("<q", data, 16)
    if not 0 <= toc <= len(data) - 8:
        return "its table of contents lies outside the file"
    (count,) = struct.unpack_from("<Q", data, toc)
    if count > (len(data) - toc - 8) // 32:
        return f"its table of contents declares {count} sections, more than the file holds"
    sections = {}
    for index in range(count):
        name, start, size = struct.unpack_from("<16sqq", data, toc + 8 + 32 * index)
        if start < 0 or size < 0 or start + size > len(data):
            return f"section {name.rstrip(bytes(1)).decode('latin-1')!r} lies outside the file"
        sections.setdefault(name.rstrip(bytes(1)).decode("latin-1"), (start, size))
    budget = 64 * len(data) + (1 << 20)
    for name, (start, size) in sections.items():
        problem = _crate_section_problem(name, data[start:start + size], version >= (4,), budget)
        if problem:
            return f"section {name}: {problem}"
    if "SPECS" in sections and version >= (4,):
        problem = _spec_types_problem(data, *sections["SPECS"])
        if problem:
            return f"section SPECS: {problem}"
    if "FIELDS" in sections:
        return _CrateValues(data, version, budget).problem(*sections["FIELDS"])
    return None


def _spec_types_problem(data: bytes, start: int, size: int) -> str | None:
    """A spec type outside usd-core's enum (1-11): usd-core range-checks only the values above it,
    so a negative one passes and later indexes its tables out of bounds (a segmentation fault)."""
    try:
        (count,) = struct.unpack_from("<Q", data, start)
        offset = start + 8
        for _ in range(2):  # path indexes, field set indexes: skipped
            offset += 8 + struct.unpack_from("<Q", data, offset)[0]
        types = _compressed_ints(data, offset, count)
    except (struct.error, ValueError, IndexError):
        return None  # usd-core reports it
    if types is None:
        return None
    bad = next((t for t in types if not 1 <= t <= 11), None)
    return None if bad is None else f"a spec type {bad - (1 << 32) if bad >= 1 << 31 else bad} is not one usd-core defines"


def _compressed_ints(data: bytes, offset: int, count: int) -> list[int] | None:
    """usd-core's compressed 32-bit integers (sdf/integerCoding.cpp): LZ4 over the encoding of
    each integer's difference to the previous one, as the most common difference (code 0) or an
    8-, 16- or 32-bit value (codes 1-3), the 2-bit codes first. Returns them unsigned."""
    (stored,) = struct.unpack_from("<Q", data, offset)
    block = data[offset + 8: offset + 8 + stored]
    if block[:1] != b"\0":
        return None
    codes_size = (2 * count + 7) // 8
    raw = _lz4_block(block[1:], 4 + codes_size + 4 * count)
    (common,) = struct.unpack_from("<i", raw, 0)
    codes, position, previous, found = raw[4:4 + codes_size], 4 + codes_size, 0, []
    formats = {1: ("<b", 1), 2: ("<h", 2), 3: ("<i", 4)}
    for index in range(count):
        code = codes[index // 4] >> 2 * (index % 4) & 3
        if code == 0:
            delta = common
        else:
            form, width = formats[code]
            (delta,) = struct.unpack_from(form, raw, position)
            position += width
        previous = (previous + delta + (1 << 31)) % (1 << 32) - (1 << 31)  # int32 arithmetic
        found.append(previous % (1 << 32))
    return found


# Crate value types (usd-core sdf/crateDataTypes.h) whose unpacking sizes a buffer from a count in the
# file: element sizes as stored.
_ARRAY_ELEMENT_BYTES = {
    1: 1, 2: 1, 3: 4, 4: 4, 5: 8, 6: 8, 7: 2, 8: 4, 9: 8, 10: 4, 11: 4, 12: 4, 13: 32, 14: 72, 15: 128,
    16: 32, 17: 16, 18: 8, 19: 16, 20: 8, 21: 4, 22: 8, 23: 24, 24: 12, 25: 6, 26: 12, 27: 32, 28: 16,
    29: 8, 30: 16, 56: 8, 57: 4,
}
_VECTOR_ELEMENT_BYTES = {40: 4, 41: 4, 48: 8, 49: 16, 50: 4, 58: 8}  # path, token, double, offset, string...
_LIST_OP_ITEM_BYTES = {32: 4, 33: 4, 34: 4, 36: 4, 37: 8, 38: 4, 39: 8}  # token, string, path, int...
_REFERENCE_LIST_OP, _UNREGISTERED_LIST_OP, _PAYLOAD_LIST_OP = 35, 54, 55
_DICTIONARY, _TIME_SAMPLES, _VALUE, _SPLINE = 31, 46, 52, 59


class _CrateValues:
    """Walks the value of every field of a crate file as usd-core would unpack it (vectors, list
    ops, dictionaries, time samples, arrays, nested values), checking each count against the bytes
    that must hold its items before usd-core allocates them."""

    MAX_VISITS = 1_000_000

    def __init__(self, data: bytes, version: tuple[int, int], budget: int):
        self.data, self.version, self.budget = data, version, budget
        self.seen: set[int] = set()

    def u64(self, offset: int) -> int:
        if not 0 <= offset <= len(self.data) - 8:
            raise IndexError
        return struct.unpack_from("<Q", self.data, offset)[0]

    def problem(self, start: int, size: int) -> str | None:
        try:
            for rep in self.field_reps(start, size):
                self.check(rep, 0)
        except ValueError as error:
            return f"a field value: {error}"
        except (IndexError, struct.error, RecursionError):
            return None  # a read past the end: usd-core reports it without allocating
        return None

    def field_reps(self, start: int, size: int):
        if self.version < (4,):  # Field {u32 padding; u32 token; u64 rep}
            count = self.u64(start)
            return [self.u64(start + 8 + 16 * i + 8) for i in range(min(count, (size - 8) // 16))]
        count = self.u64(start)
        offset = start + 16 + self.u64(start + 8)  # past the compressed field names
        stored = self.u64(offset)
        block = self.data[offset + 9: offset + 8 + stored]  # TfFastCompression: a 0 byte, then LZ4
        if self.data[offset + 8: offset + 9] != b"\0":
            return []
        reps = _lz4_block(block, 8 * count)
        return struct.unpack_from(f"<{len(reps) // 8}Q", reps)

    def check(self, rep: int, depth: int) -> None:
        if rep >> 62 & 1 or rep in self.seen or depth > 64 or len(self.seen) > self.MAX_VISITS:
            return  # inlined, already checked, or absurdly nested (usd-core guards recursion itself)
        self.seen.add(rep)
        kind, at = rep >> 48 & 0xFF, rep & ((1 << 48) - 1)
        if rep >> 63 & 1:
            self.array(kind, at, compressed=bool(rep >> 61 & 1))
        elif kind in _VECTOR_ELEMENT_BYTES:
            self.items(at, _VECTOR_ELEMENT_BYTES[kind], "items")
        elif kind in _LIST_OP_ITEM_BYTES or kind in (_REFERENCE_LIST_OP, _UNREGISTERED_LIST_OP, _PAYLOAD_LIST_OP):
            self.list_op(kind, at, depth)
        elif kind == _DICTIONARY:
            self.dictionary(at, depth)
        elif kind == _VALUE:
            self.value(at, depth)
        elif kind == _TIME_SAMPLES:
            times_at = at + self.signed(at)
            self.check(self.u64(times_at), depth + 1)
            values_at = times_at + 8 + self.signed(times_at + 8)
            count = self.items(values_at, 8, "time samples")
            for index in range(min(count, 4096)):  # each is unpacked when asked for
                self.check(self.u64(values_at + 8 + 8 * index), depth + 1)
        elif kind == _SPLINE:
            self.items(at, 1, "spline bytes")

    def signed(self, offset: int) -> int:
        value = self.u64(offset)
        return value - (1 << 64) if value >= 1 << 63 else value

    def items(self, at: int, size: int, what: str) -> int:
        """A u64 count of ``size``-byte items at ``at``; returns the count."""
        count = self.u64(at)
        if count * size > len(self.data) - at - 8:
            raise ValueError(f"{count} {what} do not fit in the file")
        return count

    def array(self, kind: int, at: int, compressed: bool) -> None:
        size = _ARRAY_ELEMENT_BYTES.get(kind)
        if size is None:
            return
        if self.version >= (7,):
            count, header = self.u64(at), 8
        else:
            header = 8 if self.version < (5,) else 4  # (a rank before 0.5.0) and a u32 count
            count = struct.unpack_from("<I", self.data, at + header - 4)[0]
        room = len(self.data) - at - header
        if compressed and (count > 1020 * room + 64 or count * size > self.budget):
            raise ValueError(f"a compressed array of {count} values cannot come from {room} bytes")
        if not compressed and count * size > room:
            raise ValueError(f"an array of {count} values does not fit in the file")

    def list_op(self, kind: int, at: int, depth: int) -> None:
        header, offset = self.data[at], at + 1
        for bit in (1, 2, 5, 6, 3, 4):  # explicit, added, prepended, appended, deleted, ordered
            if not header >> bit & 1:
                continue
            if kind in _LIST_OP_ITEM_BYTES:
                offset += 8 + _LIST_OP_ITEM_BYTES[kind] * self.items(offset, _LIST_OP_ITEM_BYTES[kind], "list items")
                continue
            smallest = {_REFERENCE_LIST_OP: 32, _PAYLOAD_LIST_OP: 8, _UNREGISTERED_LIST_OP: 16}[kind]
            count = self.items(offset, smallest, "list items")
            offset += 8
            for _ in range(count):
                offset = self.list_item(kind, offset, depth)

    def list_item(self, kind: int, offset: int, depth: int) -> int:
        """Check one reference, payload or value of a list op; returns where the next one starts."""
        if kind == _UNREGISTERED_LIST_OP:
            return self.value(offset, depth)
        offset += 8  # asset path and prim path indexes
        if kind == _PAYLOAD_LIST_OP:
            return offset + (16 if self.version >= (8,) else 0)
        return self.dictionary(offset + 16, depth)  # past the layer offset: the custom data

    def dictionary(self, at: int, depth: int) -> int:
        """Check a dictionary's values; returns where the bytes after it start."""
        count, offset = self.u64(at), at + 8
        for _ in range(count):  # usd-core reads entry by entry: a lie ends at the file's end
            offset = self.value(offset + 4, depth)
        return offset

    def value(self, at: int, depth: int) -> int:
        """A value stored as a jump to its rep; returns where the bytes after the rep start."""
        rep_at = at + self.signed(at)
        self.check(self.u64(rep_at), depth + 1)
        return rep_at + 8



def crate_tokens(data: bytes) -> bytes | None:
    """The token table of crate bytes (NUL-separated), or ``None`` when it cannot be read here.
    Call after :func:`crate_problem` has passed the file."""
    try:
        (toc,) = struct.unpack_from("<q", data, 16)
        (count,) = struct.unpack_from("<Q", data, toc)
        for index in range(count):
            name, start, _ = struct.unpack_from("<16sqq", data, toc + 8 + 32 * index)
            if name.rstrip(bytes(1)) != b"TOKENS":
                continue
            if data[9] < 4:  # before crate 0.4.0 the token text is stored as is
                (_, stored) = struct.unpack_from("<QQ", data, start)
                return data[start + 16: start + 16 + stored]
            _, expanded, stored = struct.unpack_from("<QQQ", data, start)
            block = data[start + 24: start + 24 + stored]
            # TfFastCompression: a 0 byte, then one LZ4 block (several chunks only above 2 GB)
            return _lz4_block(block[1:], expanded) if block[:1] == b"\0" else None
    except (struct.error, ValueError, IndexError):
        return None
    return None


def _lz4_block(source: bytes, limit: int) -> bytes:
    """Decompress one LZ4 block (lz4's block format: literal runs and back-references)."""
    out, position = bytearray(), 0
    while position < len(source):
        token = source[position]
        length, position = _lz4_length(source, position + 1, token >> 4)
        out += source[position:position + length]
        position += length
        if position >= len(source):
            break
        offset = source[position] | source[position + 1] << 8
        length, position = _lz4_length(source, position + 2, token & 15)
        length += 4
        start = len(out) - offset
        if offset == 0 or start < 0 or len(out) + length > limit:
            raise ValueError("corrupt LZ4 block")
        out += out[start:start + length] if offset >= length else (out[start:] * (length // offset + 1))[:length]
    return bytes(out)


def _lz4_length(source: bytes, position: int, length: int) -> tuple[int, int]:
    """A run length: 15 in the token means more bytes follow, each adding up to 255."""
    if length == 15:
        while True:
            length += source[position]
            position += 1
            if source[position - 1] != 255:
                break
    return length, position


def _crate_section_problem(name: str, section: bytes, compressed: bool, budget: int) -> str | None:
    offset = 0

    def number() -> int:
        nonlocal offset
        if offset + 8 > len(section):
            raise ValueError("it ends inside a count")
        (value,) = struct.unpack_from("<Q", section, offset)
        offset += 8
        return value

    def block(expanded: int, what: str) -> None:
        """A compressed block of ``expanded`` bytes once decompressed."""
        nonlocal offset
        stored = number()
        if stored > len(section) - offset:
            raise ValueError(f"{what} declares {stored} bytes, more than the section holds")
        if expanded > 255 * stored + 64 or expanded > budget:
            raise ValueError(f"{what} declares {expanded} bytes from {stored} compressed ones")
        offset += stored

    def integers(count: int, what: str) -> None:
        """usd-core's compressed integers: 2 bits of code per integer plus the values, then LZ4. usd-core reads
        them into a buffer of TfFastCompression::GetCompressedBufferSize of the encoded size (LZ4's bound, plus
        one byte), so more stored bytes would overrun it; no integers still store a compressed empty block
        (2 bytes: usd-core writes them for an empty layer's fields)."""
        nonlocal offset
        stored = number()
        encoded = 4 + (2 * count + 7) // 8 + 4 * count if count else 0  # integerCoding's _GetEncodedBufferSize
        if stored > len(section) - offset or stored > encoded + encoded // 255 + 16 + 1:
            raise ValueError(f"{count} {what} cannot take {stored} compressed bytes")
        if count > 1020 * stored + 64 or 8 * count > budget:
            raise ValueError(f"{count} {what} cannot come from {stored} compressed bytes")
        offset += stored

    def vector(size: int, what: str) -> None:
        items = number()
        if items * size > len(section) - offset:
            raise ValueError(f"{items} {what} do not fit in the section")

    try:
        if name == "TOKENS":
            tokens = number()
            if compressed:
                expanded = number()
                block(expanded, "the token text")
            else:
                expanded = number()
                if expanded > len(section) - offset:
                    raise ValueError(f"the token text declares {expanded} bytes, more than the section holds")
            if tokens > expanded + 1:
                raise ValueError(f"{tokens} tokens cannot fit in {expanded} bytes")
        elif name == "STRINGS":
            vector(4, "strings")
        elif name == "FIELDS":
            if not compressed:
                return _vector_problem(vector, 16, "fields")
            fields = number()
            integers(fields, "field names")
            block(8 * fields, "the field values")
        elif name == "FIELDSETS":
            if not compressed:
                return _vector_problem(vector, 4, "field set entries")
            integers(number(), "field set entries")
        elif name == "PATHS":
            paths = number()
            if 8 * paths > budget or (not compressed and paths > len(section)):
                raise ValueError(f"{paths} paths cannot fit")
            if compressed:
                encoded = number()
                if encoded > paths:
                    raise ValueError(f"{encoded} encoded paths for {paths} paths")
                for what in ("path indexes", "path element tokens", "path jumps"):
                    integers(encoded, what)
        elif name == "SPECS":
            if not compressed:
                return _vector_problem(vector, 12, "specs")
            specs = number()
            for what in ("spec paths", "spec field sets", "spec types"):
                integers(specs, what)
    except ValueError as error:
        return str(error)
    return None


def _vector_problem(vector, size: int, what: str) -> str | None:
    try:
        vector(size, what)
    except ValueError as error:
        return str(error)
    return None
