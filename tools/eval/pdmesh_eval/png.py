"""PNG files in pure Python: read 8-bit non-interlaced images, write them, and copy a picture at half
size (a 2x2 box average), so that reports stay small."""

import os
import shutil
import struct
import zlib

from .common import write_atomically


def png_read(path):
    with open(path, "rb") as f:
        data = f.read()
    if data[:8] != b"\x89PNG\r\n\x1a\n":
        raise ValueError(f"{path}: not a PNG file")
    pos, idat, header = 8, [], None
    while pos < len(data):
        length, ctype = struct.unpack(">I4s", data[pos:pos + 8])
        chunk = data[pos + 8:pos + 8 + length]
        if ctype == b"IHDR":
            header = struct.unpack(">IIBBBBB", chunk)
        elif ctype == b"IDAT":
            idat.append(chunk)
        pos += 12 + length
    width, height, depth, color, _, _, interlace = header
    channels = {2: 3, 6: 4, 0: 1, 4: 2}.get(color)
    if depth != 8 or channels is None or interlace:
        return None
    raw = zlib.decompress(b"".join(idat))
    stride = width * channels
    rows, prev = [], bytearray(stride)
    for y in range(height):
        ftype = raw[y * (stride + 1)]
        row = bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
        if ftype == 1:
            for i in range(channels, stride):
                row[i] = (row[i] + row[i - channels]) & 255
        elif ftype == 2:
            row = bytearray((a + b) & 255 for a, b in zip(row, prev))
        elif ftype == 3:
            for i in range(stride):
                left = row[i - channels] if i >= channels else 0
                row[i] = (row[i] + ((left + prev[i]) >> 1)) & 255
        elif ftype == 4:
            for i in range(stride):
                a = row[i - channels] if i >= channels else 0
                b = prev[i]
                c = prev[i - channels] if i >= channels else 0
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                row[i] = (row[i] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
        rows.append(row)
        prev = row
    return width, height, channels, rows


def png_write(path, width, height, channels, rows):
    def chunk(ctype, body):
        return struct.pack(">I", len(body)) + ctype + body + struct.pack(">I", zlib.crc32(ctype + body))
    color = {3: 2, 4: 6, 1: 0, 2: 4}[channels]
    raw = b"".join(b"\x00" + bytes(r) for r in rows)
    data = (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, color, 0, 0, 0))
            + chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b""))
    write_atomically(path, data)


def copy_picture(src, dst, scale_down):
    """Copies a PNG, halving it (2x2 box average) when scale_down is set."""
    image = png_read(src) if scale_down else None
    if image is None:
        shutil.copyfile(src, dst + ".tmp")
        os.replace(dst + ".tmp", dst)
        return
    width, height, ch, rows = image
    w2, h2 = width // 2, height // 2
    out = []
    for y in range(h2):
        r0, r1 = rows[2 * y], rows[2 * y + 1]
        row = bytearray(w2 * ch)
        for x in range(w2):
            i = 2 * x * ch
            for c in range(ch):
                row[x * ch + c] = (r0[i + c] + r0[i + ch + c] + r1[i + c] + r1[i + ch + c] + 2) >> 2
        out.append(row)
    png_write(dst, w2, h2, ch, out)
