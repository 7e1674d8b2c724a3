"""The grey levels of a PNG screenshot (Chromium's: 8-bit RGB or RGBA, not interlaced), for
tests that check what a page drew. Standard library only (zlib): no imaging package is needed."""
import struct
import zlib


def _unfilter(rows, width, bpp):
    """PNG's five row filters undone (the PNG specification, section 9)."""
    out = []
    prev = bytearray(width * bpp)
    for row in rows:
        kind, line = row[0], bytearray(row[1:])
        for i in range(len(line)):
            a = line[i - bpp] if i >= bpp else 0
            b = prev[i]
            c = prev[i - bpp] if i >= bpp else 0
            if kind == 1:
                line[i] = (line[i] + a) & 0xFF
            elif kind == 2:
                line[i] = (line[i] + b) & 0xFF
            elif kind == 3:
                line[i] = (line[i] + (a + b) // 2) & 0xFF
            elif kind == 4:
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                line[i] = (line[i] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 0xFF
        out.append(line)
        prev = line
    return out


def grey(png):
    """(width, height, rows of grey levels 0-255: the mean of R, G and B)."""
    if png[:8] != b"\x89PNG\r\n\x1a\n":
        raise ValueError("not a PNG")
    pos, data, width, height, bpp = 8, b"", 0, 0, 0
    while pos < len(png):
        size, kind = struct.unpack(">I4s", png[pos:pos + 8])
        body = png[pos + 8:pos + 8 + size]
        pos += 12 + size
        if kind == b"IHDR":
            width, height, depth, colour, _, _, interlace = struct.unpack(">IIBBBBB", body)
            if depth != 8 or colour not in (2, 6) or interlace:
                raise ValueError("PNG: 8-bit RGB or RGBA, not interlaced, expected (depth %d, colour %d)" % (depth, colour))
            bpp = 3 if colour == 2 else 4
        elif kind == b"IDAT":
            data += body
    raw = zlib.decompress(data)
    stride = 1 + width * bpp
    rows = _unfilter([raw[y * stride:(y + 1) * stride] for y in range(height)], width, bpp)
    return width, height, [[sum(r[x * bpp:x * bpp + 3]) // 3 for x in range(width)] for r in rows]
