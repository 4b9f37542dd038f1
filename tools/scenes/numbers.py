"""How numbers reach the files: float32 for the .bin, six decimals for the JSON (readable, and
the same bytes on every run)."""

import struct


def f32(x):
    """The float32 value nearest x, as a Python float (what ends up in the .bin)."""
    return struct.unpack("<f", struct.pack("<f", x))[0]


def r6(x):
    """Rounded for JSON so the files stay readable and deterministic."""
    v = round(float(x), 6)
    return 0.0 if v == 0.0 else v


def r6v(v):
    return [r6(c) for c in v]
