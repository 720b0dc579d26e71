#!/usr/bin/env python3
"""Random reflector profiles of the kind `lucerna design`'s benchmark uses:
a smooth 5-point Catmull-Rom mirror between the revolved reflector's
neck (6, 0) mm and aperture (40, -60) mm, its three interior points on
the chord between them, each moved along the chord by a little and
across it by a smooth random bulge (outward or inward), kept only where
r grows and z falls from end to end (a reflector opening downwards).

    deploy/design-profiles.py SEED COUNT

prints one profile a line, as the TOML array the scene file takes. The
held-out set's seed is written in deploy/bench-design.sh and BENCHMARKS.md
and is never used while developing; the development set uses others.
"""
import math
import random
import sys

NECK = (6.0, 0.0)
RIM = (40.0, -60.0)


def profile(rng):
    dx, dz = RIM[0] - NECK[0], RIM[1] - NECK[1]
    length = math.hypot(dx, dz)
    tx, tz = dx / length, dz / length
    nx, nz = -tz, tx  # outward (away from the axis, up)
    a = rng.uniform(-6.0, 9.0)  # the bulge's size across the chord (mm)
    b = rng.uniform(-3.0, 3.0)  # its asymmetry
    points = [NECK]
    for k in (1, 2, 3):
        s = k / 4 + rng.uniform(-0.05, 0.05)
        off = a * math.sin(math.pi * s) + b * math.sin(2 * math.pi * s) + rng.uniform(-1.0, 1.0)
        points.append((NECK[0] + s * dx + off * nx, NECK[1] + s * dz + off * nz))
    points.append(RIM)
    return points


def ok(points):
    return all(b[0] > a[0] + 1.0 and b[1] < a[1] - 1.0 for a, b in zip(points, points[1:]))


def main():
    seed, count = int(sys.argv[1]), int(sys.argv[2])
    rng = random.Random(seed)
    made = 0
    while made < count:
        p = profile(rng)
        if not ok(p):
            continue
        made += 1
        print("[" + ", ".join(f"[{x / 1000:.4f}, {z / 1000:.4f}]" for x, z in p) + "]")


if __name__ == "__main__":
    main()
