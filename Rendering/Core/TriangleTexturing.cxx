#include "TriangleTexturing.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace terroir
{
namespace rendering
{
namespace
{
/// Throws "<where>: <name> = <value> is not <range>".
[[noreturn]] void BadParameter(const char* where, const char* name, double value, const char* range)
{
  throw std::invalid_argument(
    std::string(where) + ": " + name + " = " + std::to_string(value) + " is not " + range);
}

/// splitmix64 (Steele, Lea & Flood 2014): the next value of the stream `state`.
std::uint64_t SplitMix64(std::uint64_t& state)
{
  std::uint64_t z = (state += 0x9E3779B97F4A7C15ull);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

/// A hash of (seed, stream, ix, iy) mapped to [-1, 1].
double LatticeValue(std::uint64_t seed, std::uint64_t stream, std::int64_t ix, std::int64_t iy)
{
  std::uint64_t state = seed ^ (stream * 0xD1B54A32D192ED03ull);
  state ^= SplitMix64(state) + static_cast<std::uint64_t>(ix) * 0xABC98388FB8FAC03ull;
  state ^= SplitMix64(state) + static_cast<std::uint64_t>(iy) * 0x8CB92BA72F3D8DD7ull;
  const std::uint64_t h = SplitMix64(state);
  return static_cast<double>(h >> 11) * (2.0 / 9007199254740992.0) - 1.0;
}

double Fade(double t)
{
  return t * t * t * (t * (t * 6.0 - 15.0) + 10.0);
}

/// Value noise with quintic fade at (x, y) (lattice units), in [-1, 1].
double ValueNoise(std::uint64_t seed, std::uint64_t stream, double x, double y)
{
  const double fx = std::floor(x), fy = std::floor(y);
  const auto ix = static_cast<std::int64_t>(fx);
  const auto iy = static_cast<std::int64_t>(fy);
  const double u = Fade(x - fx), v = Fade(y - fy);
  const double v00 = LatticeValue(seed, stream, ix, iy);
  const double v10 = LatticeValue(seed, stream, ix + 1, iy);
  const double v01 = LatticeValue(seed, stream, ix, iy + 1);
  const double v11 = LatticeValue(seed, stream, ix + 1, iy + 1);
  return (1 - v) * ((1 - u) * v00 + u * v10) + v * ((1 - u) * v01 + u * v11);
}

/// Three octaves of value noise (gain 1/2, lacunarity 2), normalised to [-1, 1]. Each octave's
/// lattice is turned by its own angle (0.6 + 1.3 o radians), so that no axis shows: the bands
/// along the diagonals then look like those along the legs.
double Fbm(std::uint64_t seed, std::uint64_t stream, double x, double y)
{
  double sum = 0.0, amplitude = 1.0, norm = 0.0, frequency = 1.0;
  for (int o = 0; o < 3; ++o)
  {
    const double angle = 0.6 + 1.3 * o;
    const double c = std::cos(angle), s = std::sin(angle);
    const double u = frequency * (c * x - s * y), v = frequency * (s * x + c * y);
    sum += amplitude * ValueNoise(seed, stream * 8 + o, u, v);
    norm += amplitude;
    amplitude *= 0.5;
    frequency *= 2.0;
  }
  return sum / norm;
}

double Smoothstep(double e0, double e1, double x)
{
  const double t = std::min(1.0, std::max(0.0, (x - e0) / (e1 - e0)));
  return t * t * (3.0 - 2.0 * t);
}

void CheckTexelsPerSide(const char* where, int t)
{
  if (t < 2 || t > 256)
  {
    BadParameter(where, "texelsPerTile", t, "in [2, 256]");
  }
}

/// The tile synthesis of one material (file comment of TriangleTexturing.h).
struct TileSynth
{
  std::uint64_t Seed;
  int T;
  double Period; ///< noise lattice period in texels
  double R;      ///< band width in texels
  double Rv;     ///< radius around the corners where the bands fade to the base colour
  std::uint64_t BandStream[3] = { 1, 2, 3 }; ///< noise stream of each band (ChooseBandStreams)

  /// Band s (0: A, 1: B, 2: C) at integer (t, d) along/into the side; `scale` converts them to
  /// texels (1/sqrt 2 on the diagonal), `length` is the side's length in the same integers.
  double Band(int s, int t, int d, int length, double scale) const
  {
    const double tt = t * scale, dd = d * scale, ll = length * scale;
    const double taper = Smoothstep(0.0, this->Rv, tt) * Smoothstep(0.0, this->Rv, ll - tt);
    if (taper == 0.0)
    {
      return 0.0;
    }
    return taper * Fbm(this->Seed, this->BandStream[s], tt / this->Period, dd / this->Period);
  }

  /// Side s of tile `tile` read at integer (t, d): edge s or s' (bit s of the tile index).
  double Edge(int tile, int s, int t, int d, int length, double scale) const
  {
    return ((tile >> s) & 1) ? this->Band(s, length - t, -d, length, scale)
                             : this->Band(s, t, d, length, scale);
  }

  /// Mean and standard deviation of a stream's noise over a side's band (t in [0, length],
  /// d in [-R, R], texel steps).
  void BandStatistics(std::uint64_t stream,
    int length,
    double scale,
    double& mean,
    double& sd) const
  {
    double sum = 0.0, sum2 = 0.0;
    long n = 0;
    const int r = static_cast<int>(std::ceil(this->R / scale));
    for (int t = 0; t <= length; ++t)
    {
      for (int d = -r; d <= r; ++d)
      {
        const double v =
          Fbm(this->Seed, stream, t * scale / this->Period, d * scale / this->Period);
        sum += v;
        sum2 += v * v;
        ++n;
      }
    }
    mean = sum / n;
    sd = std::sqrt(std::max(0.0, sum2 / n - mean * mean));
  }

  /// Every side of a kind carries the same band (or its turn) all over the terrain, so a band
  /// darker, lighter or flatter than the rest would draw the grid. Each band's stream is the
  /// one of 32 candidates whose mean is nearest 0 and whose spread is nearest the interiors'.
  void ChooseBandStreams()
  {
    double target = 0.0;
    for (int tile = 0; tile < 8; ++tile)
    {
      double mean, sd;
      this->BandStatistics(4 + tile, this->T, 1.0, mean, sd);
      target += sd / 8.0;
    }
    const int length[3] = { this->T, this->T, 2 * this->T };
    const double scale[3] = { 1.0, 1.0, 1.0 / std::sqrt(2.0) };
    for (int s = 0; s < 3; ++s)
    {
      double best = std::numeric_limits<double>::infinity();
      for (std::uint64_t c = 0; c < 32; ++c)
      {
        const std::uint64_t stream = 100 + 32 * s + c;
        double mean, sd;
        this->BandStatistics(stream, length[s], scale[s], mean, sd);
        const double cost = std::abs(mean) + std::abs(sd - target);
        if (cost < best)
        {
          best = cost;
          this->BandStream[s] = stream;
        }
      }
    }
  }

  /// Noise value of texel (a, b), b <= a, of tile `tile`.
  double Value(int tile, int a, int b) const
  {
    const int T = this->T;
    const double kDiag = 1.0 / std::sqrt(2.0);
    // Integer (t, d) and lengths of the sides: bottom (A), right (B), diagonal (C).
    const int t[3] = { a, b, a + b };
    const int d[3] = { b, T - a, a - b };
    const int len[3] = { T, T, 2 * T };
    const double scale[3] = { 1.0, 1.0, kDiag };
    for (int s = 0; s < 3; ++s)
    {
      if (d[s] == 0)
      {
        return this->Edge(tile, s, t[s], 0, len[s], scale[s]);
      }
    }
    double dist[3], edge[3];
    for (int s = 0; s < 3; ++s)
    {
      dist[s] = d[s] * scale[s];
      edge[s] = this->Edge(tile, s, t[s], d[s], len[s], scale[s]);
    }
    // Blends of independent noises are divided by the root of the summed squared weights, so
    // that they keep the noise's contrast (a plain average would fade it between the sides).
    double num = 0.0, den = 0.0;
    for (int s = 0; s < 3; ++s)
    {
      const double h = dist[(s + 1) % 3] * dist[(s + 2) % 3];
      num += h * edge[s];
      den += h * h;
    }
    const double g = Smoothstep(0.0, this->R, std::min({ dist[0], dist[1], dist[2] }));
    const double interior = Fbm(this->Seed, 4 + tile, a / this->Period, b / this->Period);
    return ((1.0 - g) * (num / std::sqrt(den)) + g * interior) /
      std::sqrt((1.0 - g) * (1.0 - g) + g * g);
  }
};

} // namespace

std::uint64_t MaterialTileSeed(std::uint64_t seed, std::size_t m)
{
  std::uint64_t state = seed + 0x632BE59BD9B4E019ull * (m + 1);
  return SplitMix64(state);
}

//------------------------------------------------------------------------------
TileAssignment AssignTilesJensen2011(int cellsX, int cellsY, std::uint64_t seed)
{
  if (cellsX < 1)
  {
    BadParameter("AssignTilesJensen2011", "cellsX", cellsX, ">= 1");
  }
  if (cellsY < 1)
  {
    BadParameter("AssignTilesJensen2011", "cellsY", cellsY, ">= 1");
  }
  const std::size_t nx = cellsX, ny = cellsY;
  TileAssignment out;
  out.CellsX = cellsX;
  out.CellsY = cellsY;
  const std::uint8_t unset = 255;
  out.Horizontal.assign(nx * (ny + 1), unset);
  out.Vertical.assign((nx + 1) * ny, unset);
  out.Diagonal.assign(nx * ny, unset);
  out.Tiles.assign(2 * nx * ny, 0);
  std::uint64_t state = seed;
  // The edge a triangle reads on a side: L reads the stored label, U (turned) the other one; an
  // unset side gets a random edge (1/2 each) for the triangle that reaches it first.
  auto edge = [&](std::uint8_t& side, bool upper) -> int
  {
    if (side == unset)
    {
      const int mine = static_cast<int>(SplitMix64(state) >> 63);
      side = static_cast<std::uint8_t>(upper ? 1 - mine : mine);
      return mine;
    }
    return upper ? 1 - side : side;
  };
  for (std::size_t j = 0; j < ny; ++j)
  {
    for (std::size_t i = 0; i < nx; ++i)
    {
      const std::size_t c = j * nx + i;
      // L: bottom (A), right (B), diagonal (C). U: top (A), left (B), diagonal (C).
      const int la = edge(out.Horizontal[j * nx + i], false);
      const int lb = edge(out.Vertical[j * (nx + 1) + i + 1], false);
      const int lc = edge(out.Diagonal[c], false);
      out.Tiles[2 * c] = static_cast<std::uint8_t>(la | (lb << 1) | (lc << 2));
      const int ua = edge(out.Horizontal[(j + 1) * nx + i], true);
      const int ub = edge(out.Vertical[j * (nx + 1) + i], true);
      const int uc = edge(out.Diagonal[c], true);
      out.Tiles[2 * c + 1] = static_cast<std::uint8_t>(ua | (ub << 1) | (uc << 2));
    }
  }
  return out;
}

//------------------------------------------------------------------------------
std::vector<Material> DefaultMaterials()
{
  auto make = [](const char* name, float r, float g, float b, float amp, float feature)
  {
    Material m;
    m.Name = name;
    m.Color[0] = r;
    m.Color[1] = g;
    m.Color[2] = b;
    m.Amplitude = amp;
    m.FeatureSize = feature;
    return m;
  };
  return { make("grass", 0.36f, 0.52f, 0.22f, 0.25f, 0.25f),
    make("forest", 0.20f, 0.30f, 0.14f, 0.35f, 0.2f),
    make("dry soil", 0.62f, 0.50f, 0.33f, 0.2f, 0.3f),
    make("rock", 0.50f, 0.48f, 0.45f, 0.35f, 0.15f),
    make("sand", 0.86f, 0.79f, 0.58f, 0.1f, 0.4f),
    make("snow", 0.95f, 0.96f, 0.98f, 0.04f, 0.5f) };
}

//------------------------------------------------------------------------------
TileSet SynthesizeTiles(const Material& material, int texelsPerSide, std::uint64_t seed)
{
  CheckTexelsPerSide("SynthesizeTiles", texelsPerSide);
  if (!(material.Amplitude >= 0.0f && material.Amplitude <= 1.0f))
  {
    BadParameter("SynthesizeTiles", "Amplitude", material.Amplitude, "in [0, 1]");
  }
  if (!(material.FeatureSize > 0.0f && material.FeatureSize <= 4.0f))
  {
    BadParameter("SynthesizeTiles", "FeatureSize", material.FeatureSize, "in (0, 4]");
  }
  const int T = texelsPerSide;
  TileSynth synth{ seed,
    T,
    std::max(1.0, double(material.FeatureSize) * T),
    std::max(1.0, T / 8.0),
    std::max(1.5, T / 16.0) };
  synth.ChooseBandStreams();
  TileSet set;
  set.TexelsPerSide = T;
  const std::size_t n = std::size_t(T) + 1;
  set.Texels.assign(8 * n * n * 3, 0.0f);
  for (int tile = 0; tile < 8; ++tile)
  {
    for (int b = 0; b <= T; ++b)
    {
      for (int a = b; a <= T; ++a)
      {
        const double v = synth.Value(tile, a, b);
        float* rgb = &set.Texels[((std::size_t(tile) * n + b) * n + a) * 3];
        for (int c = 0; c < 3; ++c)
        {
          const double x = material.Color[c] * (1.0 + material.Amplitude * v);
          rgb[c] = static_cast<float>(std::min(1.0, std::max(0.0, x)));
        }
      }
    }
  }
  return set;
}

//------------------------------------------------------------------------------
void MaterialWeightsAt(double slopeDeg,
  double height,
  int zone,
  const MaterialRules& rules,
  float weights[MaterialCount])
{
  if (!(rules.RockSlopeFull > rules.RockSlopeStart))
  {
    BadParameter("MaterialWeightsAt", "RockSlopeFull", rules.RockSlopeFull, "> RockSlopeStart");
  }
  if (!(rules.SandHeight > 0.0))
  {
    BadParameter("MaterialWeightsAt", "SandHeight", rules.SandHeight, "> 0");
  }
  if (!(rules.SnowBand > 0.0))
  {
    BadParameter("MaterialWeightsAt", "SnowBand", rules.SnowBand, "> 0");
  }
  std::fill(weights, weights + MaterialCount, 0.0f);
  const int ground =
    zone < 0 ? Grass : (zone % 3 == 0 ? Grass : (zone % 3 == 1 ? Forest : DrySoil));
  if (!std::isfinite(slopeDeg) || !std::isfinite(height))
  {
    weights[ground] = 1.0f;
    return;
  }
  const double r = Smoothstep(rules.RockSlopeStart, rules.RockSlopeFull, slopeDeg);
  const double s = Smoothstep(
    rules.SnowLine - 0.5 * rules.SnowBand, rules.SnowLine + 0.5 * rules.SnowBand, height);
  const double q = 1.0 - Smoothstep(rules.SeaLevel, rules.SeaLevel + rules.SandHeight, height);
  weights[Rock] = static_cast<float>(r);
  weights[Snow] = static_cast<float>((1 - r) * s);
  weights[Sand] = static_cast<float>((1 - r) * (1 - s) * q);
  weights[ground] = static_cast<float>((1 - r) * (1 - s) * (1 - q));
}

//------------------------------------------------------------------------------
namespace
{
void CheckGrid(const char* where, int pointsX, int pointsY, std::size_t values)
{
  if (pointsX < 2)
  {
    BadParameter(where, "pointsX", pointsX, ">= 2");
  }
  if (pointsY < 2)
  {
    BadParameter(where, "pointsY", pointsY, ">= 2");
  }
  if (values != std::size_t(pointsX) * pointsY)
  {
    BadParameter(where, "heights.size()", static_cast<double>(values), "pointsX * pointsY");
  }
}

/// dz/dx along one axis at k: central where both neighbours are finite, else one-sided.
double Derivative(const std::vector<float>& z,
  std::size_t k,
  bool hasMinus,
  std::size_t km,
  bool hasPlus,
  std::size_t kp,
  double h)
{
  hasMinus = hasMinus && std::isfinite(z[km]);
  hasPlus = hasPlus && std::isfinite(z[kp]);
  if (hasMinus && hasPlus)
  {
    return (z[kp] - z[km]) / (2.0 * h);
  }
  if (hasPlus)
  {
    return (z[kp] - z[k]) / h;
  }
  if (hasMinus)
  {
    return (z[k] - z[km]) / h;
  }
  return 0.0;
}
} // namespace

std::vector<float> SlopeDegrees(int pointsX,
  int pointsY,
  double dx,
  double dy,
  const std::vector<float>& heights)
{
  CheckGrid("SlopeDegrees", pointsX, pointsY, heights.size());
  if (!(dx > 0.0) || !std::isfinite(dx))
  {
    BadParameter("SlopeDegrees", "dx", dx, "> 0");
  }
  if (!(dy > 0.0) || !std::isfinite(dy))
  {
    BadParameter("SlopeDegrees", "dy", dy, "> 0");
  }
  const std::size_t nx = pointsX;
  std::vector<float> slope(heights.size(), 0.0f);
  for (int j = 0; j < pointsY; ++j)
  {
    for (int i = 0; i < pointsX; ++i)
    {
      const std::size_t k = j * nx + i;
      if (!std::isfinite(heights[k]))
      {
        continue;
      }
      const double gx = Derivative(heights, k, i > 0, k - 1, i + 1 < pointsX, k + 1, dx);
      const double gy = Derivative(heights, k, j > 0, k - nx, j + 1 < pointsY, k + nx, dy);
      slope[k] = static_cast<float>(std::atan(std::hypot(gx, gy)) * 180.0 / M_PI);
    }
  }
  return slope;
}

std::vector<float> MaterialWeights(int pointsX,
  int pointsY,
  double dx,
  double dy,
  const std::vector<float>& heights,
  const std::vector<int>& zones,
  const MaterialRules& rules)
{
  const std::vector<float> slope = SlopeDegrees(pointsX, pointsY, dx, dy, heights);
  if (!zones.empty() && zones.size() != heights.size())
  {
    BadParameter("MaterialWeights",
      "zones.size()",
      static_cast<double>(zones.size()),
      "0 or pointsX * pointsY");
  }
  std::vector<float> weights(heights.size() * MaterialCount);
  for (std::size_t k = 0; k < heights.size(); ++k)
  {
    MaterialWeightsAt(
      slope[k], heights[k], zones.empty() ? -1 : zones[k], rules, &weights[k * MaterialCount]);
  }
  return weights;
}

//------------------------------------------------------------------------------
TextureLayout PlanTexture(int cellsX, int cellsY, int texelsPerTile, int maxSize)
{
  if (cellsX < 1)
  {
    BadParameter("PlanTexture", "cellsX", cellsX, ">= 1");
  }
  if (cellsY < 1)
  {
    BadParameter("PlanTexture", "cellsY", cellsY, ">= 1");
  }
  CheckTexelsPerSide("PlanTexture", texelsPerTile);
  if (maxSize < texelsPerTile + 1)
  {
    BadParameter("PlanTexture", "maxSize", maxSize, ">= texelsPerTile + 1");
  }
  TextureLayout layout;
  layout.CellsX = cellsX;
  layout.CellsY = cellsY;
  layout.TexelsPerTile = texelsPerTile;
  const long long tilesFit = (static_cast<long long>(maxSize) - 1) / texelsPerTile;
  const int largest = std::max(cellsX, cellsY);
  int k = static_cast<int>((largest + tilesFit - 1) / tilesFit); // ceil(largest / tilesFit)
  k = std::max(1, k);
  layout.CellsPerTile = k;
  layout.TilesX = (cellsX + k - 1) / k;
  layout.TilesY = (cellsY + k - 1) / k;
  layout.Width = layout.TilesX * texelsPerTile + 1;
  layout.Height = layout.TilesY * texelsPerTile + 1;
  return layout;
}

//------------------------------------------------------------------------------
const float* TileTexel(const TileSet& tiles, int lowerTile, int upperTile, int a, int b)
{
  const int T = tiles.TexelsPerSide;
  return b <= a ? tiles.At(lowerTile, a, b) : tiles.At(upperTile, T - a, T - b);
}

namespace
{
void CheckWeights(int pointsX, int pointsY, const std::vector<float>& weights, std::size_t nm)
{
  if (nm == 0)
  {
    BadParameter("BuildTerrainTexture", "materials.size()", 0, ">= 1");
  }
  if (pointsX < 2 || pointsY < 2)
  {
    BadParameter("BuildTerrainTexture",
      pointsX < 2 ? "pointsX" : "pointsY",
      pointsX < 2 ? pointsX : pointsY,
      ">= 2");
  }
  const std::size_t n = std::size_t(pointsX) * pointsY;
  if (weights.size() != n * nm)
  {
    BadParameter("BuildTerrainTexture",
      "weights.size()",
      static_cast<double>(weights.size()),
      "pointsX * pointsY * materials.size()");
  }
  for (std::size_t k = 0; k < n; ++k)
  {
    double sum = 0.0;
    for (std::size_t m = 0; m < nm; ++m)
    {
      const float w = weights[k * nm + m];
      if (!(w >= 0.0f))
      {
        BadParameter("BuildTerrainTexture", "weight", w, ">= 0");
      }
      sum += w;
    }
    if (std::abs(sum - 1.0) > 1e-3)
    {
      BadParameter("BuildTerrainTexture", "sum of a point's weights", sum, "1");
    }
  }
}
} // namespace

TerrainTexture BuildTerrainTexture(int pointsX,
  int pointsY,
  const std::vector<float>& weights,
  const std::vector<Material>& materials,
  int texelsPerTile,
  std::uint64_t seed,
  int maxSize)
{
  const std::size_t nm = materials.size();
  CheckWeights(pointsX, pointsY, weights, nm);
  TerrainTexture out;
  out.Layout = PlanTexture(pointsX - 1, pointsY - 1, texelsPerTile, maxSize);
  const TextureLayout& L = out.Layout;
  out.Tiles = AssignTilesJensen2011(L.TilesX, L.TilesY, seed);
  std::vector<TileSet> sets;
  for (std::size_t m = 0; m < nm; ++m)
  {
    sets.push_back(SynthesizeTiles(materials[m], texelsPerTile, MaterialTileSeed(seed, m)));
  }
  const int T = L.TexelsPerTile;
  const double cellsPerTexel = static_cast<double>(L.CellsPerTile) / T;
  out.Rgb.assign(std::size_t(L.Width) * L.Height * 3, 0);
  std::vector<double> w(nm);
  for (int py = 0; py < L.Height; ++py)
  {
    const int tj = std::min(py / T, L.TilesY - 1);
    const int b = py - tj * T;
    // Bilinear weights at the texel's position (cells), clamped to the grid.
    const double y = std::min<double>(py * cellsPerTexel, pointsY - 1);
    const int j0 = std::min(static_cast<int>(y), pointsY - 2);
    const double fy = y - j0;
    for (int px = 0; px < L.Width; ++px)
    {
      const int ti = std::min(px / T, L.TilesX - 1);
      const int a = px - ti * T;
      const double x = std::min<double>(px * cellsPerTexel, pointsX - 1);
      const int i0 = std::min(static_cast<int>(x), pointsX - 2);
      const double fx = x - i0;
      const std::size_t k00 = std::size_t(j0) * pointsX + i0;
      const std::size_t k01 = k00 + pointsX;
      for (std::size_t m = 0; m < nm; ++m)
      {
        w[m] = (1 - fy) * ((1 - fx) * weights[k00 * nm + m] + fx * weights[(k00 + 1) * nm + m]) +
          fy * ((1 - fx) * weights[k01 * nm + m] + fx * weights[(k01 + 1) * nm + m]);
      }
      const int lower = out.Tiles.LowerTile(ti, tj);
      const int upper = out.Tiles.UpperTile(ti, tj);
      double rgb[3] = { 0.0, 0.0, 0.0 };
      for (std::size_t m = 0; m < nm; ++m)
      {
        if (w[m] > 0.0)
        {
          const float* c = TileTexel(sets[m], lower, upper, a, b);
          for (int q = 0; q < 3; ++q)
          {
            rgb[q] += w[m] * c[q];
          }
        }
      }
      std::uint8_t* o = &out.Rgb[(std::size_t(py) * L.Width + px) * 3];
      for (int q = 0; q < 3; ++q)
      {
        o[q] = static_cast<std::uint8_t>(std::lround(255.0 * std::min(1.0, std::max(0.0, rgb[q]))));
      }
    }
  }
  return out;
}

} // namespace rendering
} // namespace terroir
