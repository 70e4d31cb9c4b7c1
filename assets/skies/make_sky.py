#!/usr/bin/env python3
"""Makes assets/skies/clear_day.png: an equirectangular (latitude-longitude) 1024x512 sky for
kurage's `render.environment` ("type": "image"), made here so it can be shipped freely (CC0).

Layout as kurage reads it (render/lights.cpp): the centre column looks along +x, longitude grows to
the right (towards +y), the top row is straight up (+z). Contents: a clear-day gradient (a deep
zenith blue to a pale horizon, Rayleigh-like), a warm glow around the sun's direction (the sun
itself is not drawn: kurage lights it as `render.light`, and drawing it would count it twice),
soft fair-weather clouds from fractal value noise above 8 degrees, and a muted ground below the
horizon. Deterministic (fixed seed): running it again gives the same bytes.

    python3 assets/skies/make_sky.py [OUT.png] [--sun AZIMUTH_DEG,ELEVATION_DEG]
"""
import math
import random
import struct
import sys
import zlib

W, H = 1024, 512


def smoothstep(a, b, x):
    t = min(1.0, max(0.0, (x - a) / (b - a)))
    return t * t * (3 - 2 * t)


class ValueNoise:
    """Tileable-in-longitude 2-D value noise on a lattice, smooth interpolation."""

    def __init__(self, seed, period):
        rng = random.Random(seed)
        self.period = period
        self.values = [[rng.random() for _ in range(period)] for _ in range(period)]

    def __call__(self, u, v):
        p = self.period
        x, y = u * p, v * p
        x0, y0 = int(math.floor(x)), int(math.floor(y))
        fx, fy = x - x0, y - y0
        fx, fy = fx * fx * (3 - 2 * fx), fy * fy * (3 - 2 * fy)
        a = self.values[y0 % p][x0 % p]
        b = self.values[y0 % p][(x0 + 1) % p]
        c = self.values[(y0 + 1) % p][x0 % p]
        d = self.values[(y0 + 1) % p][(x0 + 1) % p]
        return (a * (1 - fx) + b * fx) * (1 - fy) + (c * (1 - fx) + d * fx) * fy


def srgb(v):
    v = min(1.0, max(0.0, v))
    return int(round(255 * (12.92 * v if v <= 0.0031308 else 1.055 * v ** (1 / 2.4) - 0.055)))


def png(path, rows):
    raw = b"".join(b"\x00" + bytes(r) for r in rows)
    chunk = lambda tag, data: struct.pack(">I", len(data)) + tag + data + struct.pack(">I", zlib.crc32(tag + data))
    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", W, H, 8, 2, 0, 0, 0))
                + chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b""))


def main():
    out = "assets/skies/clear_day.png"
    # The default scenes' sun: their light travels along (-0.4, 0.6, -1), so it stands at
    # azimuth atan2(-0.6, 0.4) = -56.3 degrees, elevation atan(1 / |(0.4, -0.6)|) = 54.2 degrees.
    azimuth, elevation = -56.3, 54.2
    args = sys.argv[1:]
    if "--sun" in args:
        i = args.index("--sun")
        azimuth, elevation = (float(x) for x in args[i + 1].split(","))
        del args[i:i + 2]
    if args:
        out = args[0]
    sun = (math.cos(math.radians(elevation)) * math.cos(math.radians(azimuth)),
           math.cos(math.radians(elevation)) * math.sin(math.radians(azimuth)), math.sin(math.radians(elevation)))
    octaves = [ValueNoise(11 + k, 4 * 2 ** k) for k in range(4)]
    zenith, horizon = (0.10, 0.25, 0.62), (0.62, 0.74, 0.86)
    ground = (0.12, 0.11, 0.095)
    rows = []
    for j in range(H):
        theta = math.pi * (j + 0.5) / H  # 0 at the top (up)
        z = math.cos(theta)
        s = math.sin(theta)
        row = []
        for i in range(W):
            phi = 2 * math.pi * (i + 0.5) / W - math.pi  # centre column: +x, right of it: +y
            d = (s * math.cos(phi), s * math.sin(phi), z)
            if z < 0:
                fade = smoothstep(0.0, 0.08, -z)
                c = [h * (1 - fade) + g * fade for h, g in zip(horizon, ground)]
            else:
                t = z ** 0.45
                c = [h * (1 - t) + zz * t for h, zz in zip(horizon, zenith)]
                cos_sun = sum(a * b for a, b in zip(d, sun))
                glow = 0.35 * max(0.0, cos_sun) ** 24 + 0.08 * max(0.0, cos_sun) ** 3
                c = [c[0] + glow * 1.0, c[1] + glow * 0.85, c[2] + glow * 0.6]
                # Clouds on a sky dome: noise in the plane above, stretched towards the horizon.
                if z > 0.02:
                    u, v = d[0] / (z + 0.15), d[1] / (z + 0.15)
                    n = sum(o(0.5 + 0.3 * u, 0.5 + 0.3 * v) * 0.5 ** k for k, o in enumerate(octaves)) / 1.875
                    cover = 0.9 * smoothstep(0.56, 0.74, n) * smoothstep(0.1, 0.3, z)
                    lit = 0.85 + 0.15 * max(0.0, cos_sun)
                    c = [a * (1 - cover) + lit * cover for a in c]
            row.extend(srgb(x) for x in c)
        rows.append(row)
    png(out, rows)
    print(out)


if __name__ == "__main__":
    main()
