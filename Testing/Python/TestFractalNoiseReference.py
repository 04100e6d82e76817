#!/usr/bin/python3
"""The fractal noise of the synthetic DEMs, transcribed into plain Python and checked bit for bit.

The definition lives in IO/Core/FractalNoise.h (header comment) and IO/Core/FractalNoise.cxx:
a lowbias32-style 32-bit hash chained over seed, x and y picks one of 8 unit gradients (4 axes,
4 diagonals) per lattice corner; one octave is the quintic-faded (6t^5 - 15t^4 + 10t^3) blend
of the corners' dot products times sqrt(2), clamped to [-1, 1]; the height sums Octaves octaves
of wavelength lambda_o = FeatureSize / 2^o, weight Persistence^o and per-octave offsets taken
from the hash. This script is the "independent Python transcription" that the values pinned in
Testing/Unit/TestFractalNoise.cxx (TerroirFractal.HashIsFixed, .MatchesIndependentTranscription)
cite, and it reproduces them: integers masked to 32 bits, Python floats are IEEE doubles, and
every operation is in the C++ order (TerroirIOCore is built with -ffp-contract=off, so no
FMA), hence == checks.

It checks that:
- the transcription reproduces the constants TestFractalNoise.cxx pins, exactly;
- terroir.vtkTerroirFractalTerrainSource (a float32 `Elevation` array) equals the transcription
  rounded to float32 (numpy.float32, round to nearest as static_cast<float>) in every cell of a
  37 x 23 grid, with the default parameters and with non-default ones (a seed above 2^31).
  The source only gives float32, so the grid catches changes above ~1/2 float ulp; a change of
  the last double bit is caught only by the three pinned heights.

Run by CTest with Debian's /usr/bin/python3 (PYTHONPATH = the built terroir package). Exits
non-zero on failure.
"""
import math
import sys

import numpy as np
from vtkmodules.util.numpy_support import vtk_to_numpy

import terroir

M32 = 0xFFFFFFFF
INV_SQRT2 = 0.70710678118654752440  # the C++ literals, rounded to the same doubles
NORMALISE = 1.41421356237309504880
GRAD_X = (1.0, -1.0, 0.0, 0.0, INV_SQRT2, -INV_SQRT2, INV_SQRT2, -INV_SQRT2)
GRAD_Y = (0.0, 0.0, 1.0, -1.0, INV_SQRT2, INV_SQRT2, -INV_SQRT2, -INV_SQRT2)
DEFAULTS = dict(seed=1, octaves=8, feature_size=256.0, persistence=0.5, amplitude=500.0,
                base_height=1500.0)


def mix(h):
    """lowbias32 finaliser on a uint32."""
    h ^= h >> 16
    h = (h * 0x7FEB352D) & M32
    h ^= h >> 15
    h = (h * 0x846CA68B) & M32
    return h ^ (h >> 16)


def seed_hash(seed):
    return mix((seed + 0x68E31DA4) & M32)


def hash_with_seed_hash(x, y, sh):
    h = mix(sh ^ (((x & M32) * 0x27D4EB2D) & M32))
    return mix(h ^ (((y & M32) * 0x165667B1) & M32))


def hash_lattice(x, y, seed):
    return hash_with_seed_hash(x, y, seed_hash(seed))


def fade(t):
    return t * t * t * (t * (t * 6.0 - 15.0) + 10.0)


def corner(ix, iy, sh, fx, fy):
    g = hash_with_seed_hash(ix, iy, sh) & 7
    return GRAD_X[g] * fx + GRAD_Y[g] * fy


def noise(x, y, sh):
    x0 = math.floor(x)  # an int; the C++'s int64 -> int32 cast is the & M32 in the hash
    y0 = math.floor(y)
    fx = x - x0  # x0 is exact as a double, so this is the C++'s double subtraction
    fy = y - y0
    n00 = corner(x0, y0, sh, fx, fy)
    n10 = corner(x0 + 1, y0, sh, fx - 1.0, fy)
    n01 = corner(x0, y0 + 1, sh, fx, fy - 1.0)
    n11 = corner(x0 + 1, y0 + 1, sh, fx - 1.0, fy - 1.0)
    u = fade(fx)
    v = fade(fy)
    nx0 = n00 + u * (n10 - n00)
    nx1 = n01 + u * (n11 - n01)
    n = NORMALISE * (nx0 + v * (nx1 - nx0))
    return 1.0 if n > 1.0 else (-1.0 if n < -1.0 else n)


def gradient_noise(x, y, seed):
    """GradientNoisePerlin2002."""
    return noise(x, y, seed_hash(seed))


def octaves(p):
    """MakeOctaves: (seedHash, offx, offy, weight, wavelength) per octave."""
    table, weight, wavelength = [], 1.0, p["feature_size"]
    for o in range(p["octaves"]):
        s = mix(p["seed"] ^ mix((0x9E3779B9 * (o + 1)) & M32))
        offx = (mix(s ^ 0xA5A5A5A5) >> 8) * (1.0 / 16777216.0)
        offy = (mix(s ^ 0x5A5A5A5A) >> 8) * (1.0 / 16777216.0)
        table.append((seed_hash(s), offx, offy, weight, wavelength))
        weight *= p["persistence"]
        wavelength *= 0.5
    return table


def height(p, table, i, j):
    total, cx, cy = 0.0, i + 0.5, j + 0.5
    for sh, offx, offy, weight, wavelength in table:
        total += weight * noise(cx / wavelength + offx, cy / wavelength + offy, sh)
    return p["base_height"] + p["amplitude"] * total


def fractal_noise(p, i, j):
    """FractalNoisePerlin2002."""
    return height(p, octaves(p), i, j)


failures = []


def check(condition, message):
    if not condition:
        failures.append(message)
        print("FAIL:", message)


# The constants Testing/Unit/TestFractalNoise.cxx pins (TerroirFractal.HashIsFixed and
# TerroirFractal.MatchesIndependentTranscription), as literals.
for args, want in (((0, 0, 1), 0xC0620424), ((1, 0, 1), 0xD5C1C17F), ((0, 1, 1), 0xB3E263B3),
                   ((-5, 17, 3), 0x8725E3D0)):
    got = hash_lattice(*args)
    check(got == want, "HashLattice%s = 0x%08x, pinned 0x%08x" % (args, got, want))
Q = dict(seed=1234567, octaves=5, feature_size=40.0, persistence=0.6, amplitude=120.0,
         base_height=-20.0)
for p, i, j, want in ((DEFAULTS, 0, 0, 1569.3068439396245), (DEFAULTS, 300, 17, 1713.957618485559),
                      (Q, -7, 99999, -50.39229532640476)):
    got = fractal_noise(p, i, j)
    check(got == want, "FractalNoisePerlin2002(%d, %d) = %r, pinned %r" % (i, j, got, want))
check(all(gradient_noise(x, y, 99) == 0.0 for x in range(-3, 4) for y in range(-3, 4)),
      "gradient noise is not 0 on the lattice")

# The built source, every cell, against the transcription rounded to float32.
NX, NY = 37, 23
for name, p in (("defaults", DEFAULTS),
                ("non-default", dict(seed=3000000001, octaves=5, feature_size=40.0,
                                     persistence=0.6, amplitude=120.0, base_height=-20.0))):
    source = terroir.vtkTerroirFractalTerrainSource()
    source.SetDimensions(NX, NY)
    source.SetSeed(p["seed"])
    source.SetOctaves(p["octaves"])
    source.SetFeatureSize(p["feature_size"])
    source.SetPersistence(p["persistence"])
    source.SetAmplitude(p["amplitude"])
    source.SetBaseHeight(p["base_height"])
    source.Update()
    array = source.GetOutput().GetPointData().GetArray("Elevation")
    check(array is not None and array.GetDataTypeAsString() == "float", "%s: Elevation %s"
          % (name, None if array is None else array.GetDataTypeAsString()))
    if array is None:
        continue
    vtk = vtk_to_numpy(array).reshape(NY, NX)  # row j = 0 south, i along a row
    table = octaves(p)
    ref = np.array([[np.float32(height(p, table, i, j)) for i in range(NX)] for j in range(NY)],
                   dtype=np.float32)
    diff = vtk != ref
    check(not diff.any(), "%s: %d of %d cells differ from the transcription, first (j, i) = %s"
          % (name, int(diff.sum()), diff.size, tuple(np.argwhere(diff)[0]) if diff.any() else ""))

if failures:
    print("%d failure(s)" % len(failures))
    sys.exit(1)
print("ok: 4 hashes and 3 heights as pinned; 2 x %d x %d cells of the source bit-identical"
      % (NX, NY))
