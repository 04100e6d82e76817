#include "FractalNoise.h"

#include <cmath>
#include <cstddef>
#include <vector>

namespace terroir
{
namespace io
{
namespace
{
// Unit gradients: 4 axes and 4 diagonals.
constexpr double kInvSqrt2 = 0.70710678118654752440;
constexpr double kGradX[8] = { 1.0, -1.0, 0.0, 0.0, kInvSqrt2, -kInvSqrt2, kInvSqrt2, -kInvSqrt2 };
constexpr double kGradY[8] = { 0.0, 0.0, 1.0, -1.0, kInvSqrt2, kInvSqrt2, -kInvSqrt2, -kInvSqrt2 };
// The blend of unit-gradient dot products is at most sqrt(2)/2 in magnitude in 2-D.
constexpr double kNormalise = 1.41421356237309504880;

std::uint32_t Mix(std::uint32_t h)
{
  h ^= h >> 16;
  h *= 0x7feb352dU;
  h ^= h >> 15;
  h *= 0x846ca68bU;
  h ^= h >> 16;
  return h;
}

double Fade(double t)
{
  return t * t * t * (t * (t * 6.0 - 15.0) + 10.0);
}

// Long (2016)'s part of HashLattice, hoisted out of the per-corner work.
std::uint32_t SeedHash(std::uint32_t seed)
{
  return Mix(seed + 0x68e31da4U);
}

std::uint32_t HashWithSeedHash(std::int32_t x, std::int32_t y, std::uint32_t seedHash)
{
  std::uint32_t h = Mix(seedHash ^ (static_cast<std::uint32_t>(x) * 0x27d4eb2dU));
  return Mix(h ^ (static_cast<std::uint32_t>(y) * 0x165667b1U));
}

double Corner(std::int32_t ix, std::int32_t iy, std::uint32_t seedHash, double fx, double fy)
{
  const std::uint32_t g = HashWithSeedHash(ix, iy, seedHash) & 7U;
  return kGradX[g] * fx + kGradY[g] * fy;
}

double Noise(double x, double y, std::uint32_t seedHash)
{
  const double x0 = std::floor(x);
  const double y0 = std::floor(y);
  const double fx = x - x0;
  const double fy = y - y0;
  const auto ix = static_cast<std::int32_t>(static_cast<std::int64_t>(x0));
  const auto iy = static_cast<std::int32_t>(static_cast<std::int64_t>(y0));
  const double n00 = Corner(ix, iy, seedHash, fx, fy);
  const double n10 = Corner(ix + 1, iy, seedHash, fx - 1.0, fy);
  const double n01 = Corner(ix, iy + 1, seedHash, fx, fy - 1.0);
  const double n11 = Corner(ix + 1, iy + 1, seedHash, fx - 1.0, fy - 1.0);
  const double u = Fade(fx);
  const double v = Fade(fy);
  const double nx0 = n00 + u * (n10 - n00);
  const double nx1 = n01 + u * (n11 - n01);
  const double n = kNormalise * (nx0 + v * (nx1 - nx0));
  return n > 1.0 ? 1.0 : (n < -1.0 ? -1.0 : n);
}

std::uint32_t OctaveSeed(std::uint32_t seed, int octave)
{
  return Mix(seed ^ Mix(0x9e3779b9U * static_cast<std::uint32_t>(octave + 1)));
}
} // namespace

std::uint32_t HashLattice(std::int32_t x, std::int32_t y, std::uint32_t seed)
{
  return HashWithSeedHash(x, y, SeedHash(seed));
}

double GradientNoisePerlin2002(double x, double y, std::uint32_t seed)
{
  return Noise(x, y, SeedHash(seed));
}

namespace
{
struct Octave
{
  std::uint32_t seed;
  std::uint32_t seedHash;
  double offx, offy, weight, wavelength;
};

// Per-octave constants; the same table serves single cells and row ranges, so both give
// bit-identical values.
std::vector<Octave> MakeOctaves(const FractalNoiseParameters& p)
{
  std::vector<Octave> octaves;
  double weight = 1.0;
  double wavelength = p.featureSize;
  for (int o = 0; o < p.octaves; ++o)
  {
    Octave oct;
    oct.seed = OctaveSeed(p.seed, o);
    oct.seedHash = SeedHash(oct.seed);
    // Offsets in [0, 1) lattice units, from the hash (exact binary fractions).
    oct.offx = (Mix(oct.seed ^ 0xa5a5a5a5U) >> 8) * (1.0 / 16777216.0);
    oct.offy = (Mix(oct.seed ^ 0x5a5a5a5aU) >> 8) * (1.0 / 16777216.0);
    oct.weight = weight;
    oct.wavelength = wavelength;
    octaves.push_back(oct);
    weight *= p.persistence;
    wavelength *= 0.5;
  }
  return octaves;
}

double Height(const FractalNoiseParameters& p, const std::vector<Octave>& octaves, int i, int j)
{
  double sum = 0.0;
  const double cx = i + 0.5;
  const double cy = j + 0.5;
  for (const Octave& o : octaves)
  {
    sum += o.weight * Noise(cx / o.wavelength + o.offx, cy / o.wavelength + o.offy, o.seedHash);
  }
  return p.baseHeight + p.amplitude * sum;
}
} // namespace

double FractalNoisePerlin2002(const FractalNoiseParameters& p, int i, int j)
{
  return Height(p, MakeOctaves(p), i, j);
}

double FractalNoiseBound(const FractalNoiseParameters& p)
{
  double bound = 0.0;
  double weight = 1.0;
  for (int o = 0; o < p.octaves; ++o)
  {
    bound += weight;
    weight *= std::fabs(p.persistence);
  }
  return std::fabs(p.amplitude) * bound;
}

void FractalNoisePerlin2002Rows(const FractalNoiseParameters& p,
  int nx,
  int row0,
  int row1,
  float* out)
{
  const std::vector<Octave> octaves = MakeOctaves(p);
  for (int j = row0; j < row1; ++j)
  {
    float* row = out + static_cast<std::size_t>(j) * static_cast<std::size_t>(nx);
    for (int i = 0; i < nx; ++i)
    {
      row[i] = static_cast<float>(Height(p, octaves, i, j));
    }
  }
}

} // namespace io
} // namespace terroir
