#!/usr/bin/env python3
"""Writes the small BMP textures shipped in worlds/ (24-bit, 2^n x 2^n). Run from the repo root:
    python3 tools/make_textures.py
Pure Python, no dependencies; the output is committed, so building never needs this."""
import math
import struct
from pathlib import Path


def write_bmp(path, size, pixel):
    row_bytes = size * 3  # 24-bit rows of a power-of-two width need no padding
    pixels = bytearray()
    for y in range(size - 1, -1, -1):  # BMP rows run bottom-up
        for x in range(size):
            r, g, b = pixel(x, y)
            pixels += bytes((b, g, r))
    header = struct.pack("<2sIHHI", b"BM", 54 + len(pixels), 0, 0, 54)
    info = struct.pack("<IiiHHIIiiII", 40, size, size, 1, 24, 0, len(pixels), 2835, 2835, 0, 0)
    path.write_bytes(header + info + pixels)


def wood(x, y):
    grain = 0.5 + 0.5 * math.sin(x * 0.35 + 3 * math.sin(y * 0.08))
    return (int(120 + 60 * grain), int(75 + 40 * grain), int(35 + 20 * grain))


def brick(x, y):
    row = y // 16
    offset = 16 if row % 2 else 0
    mortar = y % 16 < 2 or (x + offset) % 32 < 2
    return (200, 200, 190) if mortar else (150 + (x * 7 + y * 3) % 20, 60, 45)


def checker(x, y):
    return (230, 230, 230) if (x // 8 + y // 8) % 2 == 0 else (40, 40, 40)


def stripes(x, y):
    return (220, 40, 40) if (x // 4) % 2 == 0 else (240, 240, 240)


if __name__ == "__main__":
    out = Path("worlds/DemoEnvironment_v1/textures")
    out.mkdir(parents=True, exist_ok=True)
    write_bmp(out / "wood.bmp", 64, wood)
    write_bmp(out / "brick.bmp", 128, brick)
    write_bmp(out / "checker.bmp", 64, checker)
    write_bmp(out / "stripes.bmp", 32, stripes)
