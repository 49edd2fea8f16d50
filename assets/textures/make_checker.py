"""Writes checker.png: an 8x8 checkerboard, 256x256, whose light squares shade from red (u = 0) to
green (u = 1) and whose dark squares from blue (v = 0) to yellow (v = 1), so a student can read which
way u and v run on a surface. Run: python3 make_checker.py (standard library only)."""
import struct
import zlib

SIZE, SQUARES = 256, 8
rows = []
for row in range(SIZE):
    v = 1 - (row + 0.5) / SIZE
    line = bytearray([0])
    for column in range(SIZE):
        u = (column + 0.5) / SIZE
        light = (column * SQUARES // SIZE + row * SQUARES // SIZE) % 2 == 0
        if light:
            rgb = (0.95 - 0.6 * u, 0.35 + 0.6 * u, 0.3)
        else:
            rgb = (0.15 + 0.7 * v, 0.15 + 0.6 * v, 0.6 - 0.5 * v)
        line += bytes(round(c * 255) for c in rgb)
    rows.append(bytes(line))


def chunk(kind, data):
    return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data))


png = b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", SIZE, SIZE, 8, 2, 0, 0, 0))
png += chunk(b"IDAT", zlib.compress(b"".join(rows), 9)) + chunk(b"IEND", b"")
open("checker.png", "wb").write(png)
