"""A small OpenEXR reader (standard library only), independent of OpenImageIO: the farm checks
part files with it before it keeps or merges them, and the tests read caustic's EXR files with it.
It reads
single-part scanline files with NO, ZIPS or ZIP compression and HALF or FLOAT channels, which
is what caustic writes. Returns the header's attributes and each channel as a flat list of floats
(row 0 at the top). Format: the OpenEXR file layout document (openexr.com, "OpenEXR File
Layout"): magic, version, header attributes (name, type, size, value) up to an empty name, the
chunk offset table, then chunks of (y, size, data); ZIP data is zlib with the bytes split into
two halves and delta-coded ("predictor")."""

import struct
import zlib

MAGIC = 20000630
COMPRESSION = {0: "none", 2: "zips", 3: "zip"}
LINES = {"none": 1, "zips": 1, "zip": 16}


def _cstr(data, pos):
    end = data.index(b"\0", pos)
    return data[pos:end].decode("latin-1"), end + 1


def _undo_zip(raw):
    # The predictor: each byte is the difference to the previous one, plus 128.
    t = bytearray(raw)
    for i in range(1, len(t)):
        t[i] = (t[i - 1] + t[i] - 128) & 0xFF
    # The two halves interleaved again: the first holds the even bytes, the second the odd ones.
    half = (len(t) + 1) // 2
    out = bytearray(len(t))
    out[0::2] = t[:half]
    out[1::2] = t[half:]
    return bytes(out)


def _header(data, path):
    """Parses the header: (attributes, channels [(name, type)], position of the offset table)."""
    magic, version = struct.unpack_from("<ii", data, 0)
    if magic != MAGIC:
        raise ValueError("%s: not an OpenEXR file" % path)
    if version & 0x1200:  # tiled (0x200) or multi-part (0x1000)
        raise ValueError("%s: tiled or multi-part EXR is not supported here" % path)
    pos = 8
    attrs, channels = {}, []
    while True:
        name, pos = _cstr(data, pos)
        if not name:
            break
        atype, pos = _cstr(data, pos)
        (size,) = struct.unpack_from("<i", data, pos)
        pos += 4
        value = data[pos:pos + size]
        pos += size
        if atype == "chlist":
            p = 0
            while value[p] != 0:
                cname, p = _cstr(value, p)
                ptype, = struct.unpack_from("<i", value, p)
                channels.append((cname, ptype))
                p += 16
        elif atype == "box2i":
            attrs[name] = struct.unpack("<iiii", value)
        elif atype == "compression":
            attrs[name] = COMPRESSION.get(value[0], value[0])
        elif atype == "string":
            attrs[name] = value.decode("utf-8", "replace")
        else:
            attrs[name] = value
    return attrs, channels, pos


def check_complete(path):
    """The header, and whether every chunk the offset table names lies wholly inside the file (a
    truncated or cut file fails): (attributes, width, height, channel names, problem or "")."""
    with open(path, "rb") as f:
        data = f.read()
    try:
        attrs, channels, pos = _header(data, path)
        x0, y0, x1, y1 = attrs["dataWindow"]
        w, h = x1 - x0 + 1, y1 - y0 + 1
        per_chunk = LINES[attrs["compression"]]
        chunks = (h + per_chunk - 1) // per_chunk
        offsets = struct.unpack_from("<%dQ" % chunks, data, pos)
        for off in offsets:
            y, size = struct.unpack_from("<ii", data, off)
            if off + 8 + size > len(data):
                return attrs, w, h, [c for c, _ in channels], "%s: cut short (chunk at line %d ends past the file's end)" % (path, y)
    except (ValueError, KeyError, IndexError, struct.error) as e:
        return {}, 0, 0, [], "%s: not a complete OpenEXR file (%s)" % (path, e)
    return attrs, w, h, [c for c, _ in channels], ""


def read_exr(path):
    """Returns (attributes dict, width, height, {channel name: [floats]})."""
    with open(path, "rb") as f:
        data = f.read()
    attrs, channels, pos = _header(data, path)
    x0, y0, x1, y1 = attrs["dataWindow"]
    w, h = x1 - x0 + 1, y1 - y0 + 1
    comp = attrs["compression"]
    if comp not in LINES:
        raise ValueError("%s: compression %r not supported here" % (path, comp))
    per_chunk = LINES[comp]
    chunks = (h + per_chunk - 1) // per_chunk
    offsets = struct.unpack_from("<%dQ" % chunks, data, pos)
    sizes = {2: 4, 1: 2, 0: 4}  # FLOAT, HALF, UINT
    out = {c: [0.0] * (w * h) for c, _ in channels}
    for off in offsets:
        y, size = struct.unpack_from("<ii", data, off)
        block = data[off + 8:off + 8 + size]
        lines = min(per_chunk, y1 + 1 - y)
        expected = lines * w * sum(sizes[t] for _, t in channels)
        if comp != "none" and size < expected:
            block = _undo_zip(zlib.decompress(block))
        if len(block) != expected:
            raise ValueError("%s: chunk at line %d holds %d bytes, expected %d" % (path, y, len(block), expected))
        p = 0
        for line in range(lines):
            row = (y - y0 + line) * w
            for cname, ctype in channels:
                fmt = {2: "<%df", 1: "<%de", 0: "<%dI"}[ctype] % w
                vals = struct.unpack_from(fmt, block, p)
                p += w * sizes[ctype]
                out[cname][row:row + w] = vals
    return attrs, w, h, out
