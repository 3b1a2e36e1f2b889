#!/usr/bin/env python3
"""Writes the small test textures of scenes/textured.toml (Python standard library only).

checker.png     64x64 sRGB albedo: a two-tone checker with a red and a blue quadrant mark
                (shows orientation: red at the top-left of the image, blue at the bottom-right).
roughmetal.png  64x64 linear data, glTF packing: G = roughness (left 0.15 -> right 0.9),
                B = metallic (bands: 0 in the top half, 1 in the bottom half).
bumps.png       64x64 linear tangent-space normal map (+Y up): a grid of hemispherical bumps.
glow.png        32x32 sRGB emission: a bright ring on black.
"""
import math
import struct
import zlib
from pathlib import Path


def write_png(path, w, h, rows):
    raw = b"".join(b"\x00" + bytes(r) for r in rows)

    def chunk(kind, data):
        c = struct.pack(">I", len(data)) + kind + data
        return c + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)

    png = b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 6, 0, 0, 0))
    png += chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b"")
    Path(path).write_bytes(png)


def checker():
    rows = []
    for y in range(64):
        row = []
        for x in range(64):
            c = (230, 220, 200) if (x // 8 + y // 8) % 2 == 0 else (60, 70, 90)
            if x < 16 and y < 16:
                c = (200, 30, 30)
            if x >= 48 and y >= 48:
                c = (30, 60, 200)
            row += [*c, 255]
        rows.append(row)
    return rows


def roughmetal():
    rows = []
    for y in range(64):
        row = []
        for x in range(64):
            rough = 0.15 + 0.75 * x / 63
            metal = 0 if y < 32 else 255
            row += [255, round(rough * 255), metal, 255]
        rows.append(row)
    return rows


def bumps():
    rows = []
    for y in range(64):
        row = []
        for x in range(64):
            # Cell centre, offsets in [-1, 1]; +Y up the image.
            dx = ((x % 16) + 0.5) / 8 - 1
            dy = -(((y % 16) + 0.5) / 8 - 1)
            r2 = dx * dx + dy * dy
            n = (0.0, 0.0, 1.0)
            if r2 < 0.8:
                nz = math.sqrt(1 - r2)
                n = (dx, dy, nz)
            row += [round((c * 0.5 + 0.5) * 255) for c in n] + [255]
        rows.append(row)
    return rows


def glow():
    rows = []
    for y in range(32):
        row = []
        for x in range(32):
            r = math.hypot(x + 0.5 - 16, y + 0.5 - 16)
            v = 255 if 9 < r < 13 else 0
            row += [v, round(v * 0.8), round(v * 0.5), 255]
        rows.append(row)
    return rows


if __name__ == "__main__":
    here = Path(__file__).parent
    write_png(here / "checker.png", 64, 64, checker())
    write_png(here / "roughmetal.png", 64, 64, roughmetal())
    write_png(here / "bumps.png", 64, 64, bumps())
    write_png(here / "glow.png", 32, 32, glow())
