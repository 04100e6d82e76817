/**
 * @file FractalNoise.h
 * @brief Seeded fractal gradient noise (Perlin 1985/2002) for synthetic DEMs, no VTK.
 *
 * One octave is 2-D gradient noise on the integer lattice: each lattice corner gets a unit
 * gradient chosen from 8 directions (the 4 axes and the 4 diagonals) by an integer hash of
 * (corner x, corner y, seed, octave); the noise is the quintic-faded (6t^5 - 15t^4 + 10t^3,
 * Perlin 2002) blend of the corners' dot products, scaled by sqrt(2) so that it lies in
 * [-1, 1]. The height of cell (i, j) is
 *
 *   h = BaseHeight + Amplitude * sum_{o=0}^{Octaves-1} Persistence^o * noise_o(
 *         (i + 0.5) / lambda_o + offx_o, (j + 0.5) / lambda_o + offy_o),
 *   lambda_o = FeatureSize / 2^o,
 *
 * with per-octave offsets from the hash (so lattice points of successive octaves do not
 * coincide). Hence |h - BaseHeight| <= Amplitude * sum_o Persistence^o (FractalNoiseBound).
 *
 * Determinism: only integer hashing (32-bit, wrap-around) and IEEE double +, -, *, /, floor;
 * no std:: random distributions and no transcendental functions, so the values are the same
 * on every platform and every thread count (TerroirIOCore is compiled with -ffp-contract=off,
 * so no fused multiply-add changes the last bit on FMA targets).
 *
 * References: K. Perlin, "An image synthesizer", SIGGRAPH 1985, doi:10.1145/325165.325247;
 * K. Perlin, "Improving noise", SIGGRAPH 2002, doi:10.1145/566570.566636.
 */
#ifndef terroir_io_FractalNoise_h
#define terroir_io_FractalNoise_h

#include <cstdint>

namespace terroir
{
namespace io
{

/// Parameters of the fractal (fBm) sum; defaults match vtkTerroirFractalTerrainSource.
struct FractalNoiseParameters
{
  std::uint32_t seed = 1;     ///< any value; different seeds give unrelated terrains
  int octaves = 8;            ///< number of summed octaves, >= 1
  double featureSize = 256.0; ///< largest wavelength, in cells, > 0
  double persistence = 0.5;   ///< amplitude ratio between successive octaves
  double amplitude = 500.0;   ///< metres, amplitude of the first octave
  double baseHeight = 1500.0; ///< metres, mean level
};

/// 32-bit integer hash of a lattice corner (lowbias32-style finaliser), platform independent.
std::uint32_t HashLattice(std::int32_t x, std::int32_t y, std::uint32_t seed);

/// One octave of 2-D gradient noise at (x, y) in lattice units; result in [-1, 1].
double GradientNoisePerlin2002(double x, double y, std::uint32_t seed);

/// Height (metres) of cell (i, j) (cell centre at i + 0.5, j + 0.5 in cell units).
double FractalNoisePerlin2002(const FractalNoiseParameters& p, int i, int j);

/// Bound on |height - baseHeight|: |amplitude| * sum_o |persistence|^o.
double FractalNoiseBound(const FractalNoiseParameters& p);

/**
 * @brief Fills rows [row0, row1) of an nx-wide grid (row j = 0 south).
 * @param[out] out the whole grid (nx * ny floats); only the given rows are written
 * @post each value depends only on (p, i, j): row ranges can be filled in any order or in
 *   parallel with bit-identical results.
 */
void FractalNoisePerlin2002Rows(const FractalNoiseParameters& p,
  int nx,
  int row0,
  int row1,
  float* out);

} // namespace io
} // namespace terroir

#endif
