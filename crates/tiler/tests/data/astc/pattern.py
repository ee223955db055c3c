#!/usr/bin/env python3
"""Writes pattern.png, the 60×60 RGBA image the ASTC test files are encoded from: gradients,
a checker of hard edges, a ring, smooth and noisy alpha, noisy grey rows — so that an
exhaustive encoder uses many block modes, one to four partitions and dual planes."""
import random
import struct
import zlib

random.seed(17)
W = H = 60
rows = []
for y in range(H):
    row = bytearray()
    for x in range(W):
        r, g = (x * 4) & 255, (y * 4) & 255
        b = 255 if ((x // 7) + (y // 5)) % 2 else 30
        d = ((x - 30) ** 2 + (y - 30) ** 2) ** 0.5
        if 12 < d < 18:
            r, g, b = 250, 240, 10
        a = 255 if x < 20 else (random.randrange(256) if x > 40 else (x * y) & 255)
        if y > 45:
            r = g = b = random.randrange(256)
        row += bytes((r, g, b, a))
    rows.append(b"\x00" + bytes(row))


def chunk(kind, data):
    body = kind + data
    return struct.pack(">I", len(data)) + body + struct.pack(">I", zlib.crc32(body) & 0xFFFFFFFF)


png = b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", W, H, 8, 6, 0, 0, 0))
png += chunk(b"IDAT", zlib.compress(b"".join(rows), 9)) + chunk(b"IEND", b"")
open("pattern.png", "wb").write(png)
