"""A small OpenEXR reader for the tools in this folder (numpy only, no OpenEXR bindings).

Reads single-part scanline or tiled (one level) files with no, RLE, ZIPS or ZIP compression and
half or float channels — what `ophis render` writes — into a dict of float32 arrays by channel
name, plus the header's string attributes. Written from the OpenEXR file-layout documentation
("The OpenEXR File Layout", openexr.com); anything else is refused with a message.
"""

import struct
import zlib

import numpy as np

MAGIC = b"\x76\x2f\x31\x01"
COMPRESSION = {0: "none", 1: "rle", 2: "zips", 3: "zip"}


def _cstr(b, at):
    end = b.index(b"\0", at)
    return b[at:end].decode("latin-1"), end + 1


def _header(b):
    if b[:4] != MAGIC:
        raise ValueError("not an OpenEXR file")
    flags = struct.unpack_from("<I", b, 4)[0]
    if flags & 0x1000 or flags & 0x800:
        raise ValueError("multi-part and deep files are not supported")
    at, attrs = 8, {}
    while b[at] != 0:
        name, at = _cstr(b, at)
        kind, at = _cstr(b, at)
        size = struct.unpack_from("<i", b, at)[0]
        at += 4
        attrs[name] = (kind, b[at : at + size])
        at += size
    return flags, attrs, at + 1


def _channels(raw):
    out, at = [], 0
    while raw[at] != 0:
        name, at = _cstr(raw, at)
        ptype, _plin, xs, ys = struct.unpack_from("<iB3xii", raw, at)
        at += 16
        if (xs, ys) != (1, 1):
            raise ValueError(f"sub-sampled channel {name}")
        out.append((name, ptype))
    return out


def _decode(data, raw_size, compression):
    if len(data) == raw_size:
        return data  # stored uncompressed (compression did not pay)
    if compression == "rle":
        out = bytearray()
        i = 0
        while i < len(data):
            n = struct.unpack_from("<b", data, i)[0]
            i += 1
            if n < 0:
                out += data[i : i - n]
                i -= n
            else:
                out += bytes([data[i]]) * (n + 1)
                i += 1
    elif compression in ("zip", "zips"):
        out = bytearray(zlib.decompress(data))
    else:
        raise ValueError(f"compression {compression} is not supported")
    # Undo the predictor, then the interleaving of the two halves.
    t = _predictor(np.frombuffer(bytes(out), dtype=np.uint8))
    half = (len(t) + 1) // 2
    res = np.empty(len(t), dtype=np.uint8)
    res[0::2] = t[:half]
    res[1::2] = t[half:]
    return res.tobytes()


def _predictor(a):
    # t[i] = t[i-1] + a[i] - 128 (mod 256), t[0] = a[0].
    d = a.astype(np.int64)
    d[1:] -= 128
    return (np.cumsum(d) % 256).astype(np.uint8)


def read_exr(path):
    """Returns ({channel: 2-D float32 array}, {attribute: string}) for an ophis EXR."""
    b = open(path, "rb").read()
    flags, attrs, at = _header(b)
    chans = _channels(attrs["channels"][1])
    compression = COMPRESSION.get(attrs["compression"][1][0])
    if compression is None:
        raise ValueError(f"compression {attrs['compression'][1][0]} is not supported")
    x0, y0, x1, y1 = struct.unpack("<4i", attrs["dataWindow"][1])
    w, h = x1 - x0 + 1, y1 - y0 + 1
    width = {0: 4, 1: 2, 2: 4}
    dtype = {0: "<u4", 1: "<f2", 2: "<f4"}
    planes = {n: np.zeros((h, w), dtype=np.float32) for n, _ in chans}
    tiled = bool(flags & 0x200)

    def fill(data, bx, by, bw, bh):
        raw = bw * bh * sum(width[t] for _, t in chans)
        buf = _decode(data, raw, compression)
        at = 0
        for row in range(bh):
            for name, t in chans:
                n = bw * width[t]
                vals = np.frombuffer(buf[at : at + n], dtype=dtype[t]).astype(np.float32)
                planes[name][by + row, bx : bx + bw] = vals
                at += n

    if tiled:
        tx, ty, mode = struct.unpack("<IIB", attrs["tiles"][1])
        if mode & 0xF != 0:
            raise ValueError("only one-level tiled files are supported")
        nx, ny = -(-w // tx), -(-h // ty)
        offsets = struct.unpack_from(f"<{nx * ny}Q", b, at)
        for off in offsets:
            cx, cy, _lx, _ly, size = struct.unpack_from("<5i", b, off)
            bw, bh = min(tx, w - cx * tx), min(ty, h - cy * ty)
            fill(b[off + 20 : off + 20 + size], cx * tx, cy * ty, bw, bh)
    else:
        lines = {"none": 1, "rle": 1, "zips": 1, "zip": 16}[compression]
        n = -(-h // lines)
        offsets = struct.unpack_from(f"<{n}Q", b, at)
        for off in offsets:
            y, size = struct.unpack_from("<2i", b, off)
            bh = min(lines, y1 - y + 1)
            fill(b[off + 8 : off + 8 + size], 0, y - y0, w, bh)
    text = {
        k: v[1].decode("latin-1") for k, v in attrs.items() if v[0] == "string"
    }
    return planes, text
