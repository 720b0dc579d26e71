"""Writes synthetic_led.tm25ray: a made-up LED for examples and tests, not
a measurement. A 1 x 1 mm die at z = 0 emitting along +z (the LED's own
frame, as makers' files have it), Lambertian, 100 lm in 20 000 rays of
equal luminous flux, from a fixed low-discrepancy sequence (reproducible).
Layout: IES TM-25-13, as lucerna_photometry::tm25 reads it.

    python3 assets/rayfiles/make_synthetic_led.py
"""
import math
import os
import struct

N = 20_000
FLUX_LM = 100.0
out = bytearray()
out += b"TM25" + struct.pack("<ii", 2013, 0)            # type, version, simulation
out += struct.pack("<ff", FLUX_LM, float("nan"))        # luminous, radiant (unknown)
out += struct.pack("<Q", N)
out += b"2026-12-04T00:00:00+00:00".ljust(28, b"\0")
out += struct.pack("<iifffiii", 0, 0, float("nan"), float("nan"), float("nan"), 0, 0, 0)
out += bytes(256 - len(out))
out += struct.pack("<8i", 1, 1, 0, 0, 1, 0, 0, 0)       # position, direction, luminous flux
texts = [
    "Synthetic 1 mm Lambertian LED",
    "Lucerna examples",
    "Lucerna",
    "assets/rayfiles/make_synthetic_led.py",
    "none (synthetic)",
    "none",
    "not a measurement",
    "A made-up source for examples and tests",
    "Lucerna repository",
]
for t in texts:
    b = t.encode("utf-32-le")
    out += b + bytes(4000 - len(b))
a1, a2, a3, a4 = 0.8566748838545029, 0.7338918566271260, 0.6287067210378086, 0.5385972572236101
for i in range(N):
    u = (0.5 + a1 * i) % 1.0
    v = (0.5 + a2 * i) % 1.0
    x = (0.5 + a3 * i) % 1.0 - 0.5
    y = (0.5 + a4 * i) % 1.0 - 0.5
    r, phi = math.sqrt(u), 2.0 * math.pi * v
    kz = math.sqrt(max(0.0, 1.0 - r * r))
    out += struct.pack("<7f", x, y, 0.0, r * math.cos(phi), r * math.sin(phi), kz, FLUX_LM / N)
path = os.path.join(os.path.dirname(os.path.abspath(__file__)), "synthetic_led.tm25ray")
with open(path, "wb") as f:
    f.write(out)
print(path, len(out), "bytes")
