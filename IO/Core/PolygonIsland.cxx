// Weiss (2015)'s polygon-map island on a raster (PolygonIsland.h).
#include "PolygonIsland.h"

#include "FractalNoise.h"

#include <algorithm>
#include <cmath>
#include <deque>
#include <limits>
#include <numeric>

namespace terroir
{
namespace generation
{

namespace
{
struct BiomeRow
{
  const char* Name;
  double Amplitude;
  double Roughness;
};
// Weiss (2015), Table I, in the order of Biome.
const BiomeRow BiomeTable[] = {
  { "Snow", 0.5, 0.7 },
  { "Tundra", 0.5, 0.5 },
  { "Bare", 0.4, 0.4 },
  { "Scorched", 0.7, 0.3 },
  { "Taiga", 0.4, 0.3 },
  { "Shrubland", 0.5, 0.2 },
  { "Temperate desert", 0.1, 0.1 },
  { "Temperate rain forest", 0.3, 0.2 },
  { "Deciduous forest", 0.3, 0.4 },
  { "Grassland", 0.4, 0.5 },
  { "Tropical rain forest", 0.3, 0.2 },
  { "Tropical seasonal forest", 0.3, 0.2 },
  { "Subtropical desert", 0.3, 0.6 },
  { "Beach", 0.3, 0.5 },
  { "Lake", 0.2, 0.2 },
  { "Ocean", 0.2, 0.1 },
};
static_assert(sizeof(BiomeTable) / sizeof(BiomeTable[0]) == static_cast<int>(Biome::Count),
  "one Table I row per biome");

/// Cell (i, j)'s map coordinates.
inline void CellXY(int i, int j, int width, int height, double& x, double& y)
{
  const double s = 2.0 / width;
  x = (i + 0.5) * s - 1.0;
  y = (j + 0.5 - 0.5 * height) * s;
}

/// Ranks of `values` (ties share their mean rank), scaled to [0, 1].
std::vector<double> RankFractions(const std::vector<double>& values)
{
  const std::size_t n = values.size();
  std::vector<std::size_t> order(n);
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(),
    order.end(),
    [&](std::size_t a, std::size_t b) { return values[a] < values[b]; });
  std::vector<double> q(n, 0.0);
  std::size_t k = 0;
  while (k < n)
  {
    std::size_t e = k;
    while (e + 1 < n && values[order[e + 1]] == values[order[k]])
    {
      ++e;
    }
    const double mean = 0.5 * static_cast<double>(k + e);
    for (std::size_t t = k; t <= e; ++t)
    {
      q[order[t]] = n > 1 ? mean / static_cast<double>(n - 1) : 0.0;
    }
    k = e + 1;
  }
  return q;
}
} // namespace

const char* BiomeName(Biome b)
{
  return BiomeTable[static_cast<int>(b)].Name;
}
double BiomeAmplitude(Biome b)
{
  return BiomeTable[static_cast<int>(b)].Amplitude;
}
double BiomeRoughness(Biome b)
{
  return BiomeTable[static_cast<int>(b)].Roughness;
}

Biome LandBiome(double t, double m)
{
  // Patel (2010): elevation zones above 0.8, 0.6, 0.3; temperature = 1 - elevation.
  if (t < 0.2)
  {
    return m > 0.5 ? Biome::Snow
      : m > 0.33   ? Biome::Tundra
      : m > 0.16   ? Biome::Bare
                   : Biome::Scorched;
  }
  if (t < 0.4)
  {
    return m > 0.66 ? Biome::Taiga : m > 0.33 ? Biome::Shrubland : Biome::TemperateDesert;
  }
  if (t < 0.7)
  {
    return m > 0.83 ? Biome::TemperateRainForest
      : m > 0.5     ? Biome::DeciduousForest
      : m > 0.16    ? Biome::Grassland
                    : Biome::TemperateDesert;
  }
  return m > 0.66 ? Biome::TropicalRainForest
    : m > 0.33    ? Biome::TropicalSeasonalForest
    : m > 0.16    ? Biome::Grassland
                  : Biome::SubtropicalDesert;
}

std::uint64_t SplitMix64(std::uint64_t& state)
{
  std::uint64_t z = (state += 0x9e3779b97f4a7c15ULL);
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

double UnitDouble(std::uint64_t& state)
{
  return static_cast<double>(SplitMix64(state) >> 11) * (1.0 / 9007199254740992.0);
}

std::vector<int> VoronoiLabels(const std::vector<double>& x,
  const std::vector<double>& y,
  int width,
  int height)
{
  // Buckets of about one point each over the map's box; for each cell the rings of buckets
  // around it are searched until the next ring cannot hold a nearer point.
  const int n = static_cast<int>(x.size());
  std::vector<int> labels(static_cast<std::size_t>(width) * height, -1);
  if (n == 0)
  {
    return labels;
  }
  const double x0 = -1.0, y0 = -static_cast<double>(height) / width;
  const double w = 2.0, h = 2.0 * height / width;
  const int bx = std::max(1, static_cast<int>(std::ceil(std::sqrt(n * w / h))));
  const int by = std::max(1, static_cast<int>(std::ceil(static_cast<double>(n) / bx)));
  const double sx = w / bx, sy = h / by;
  std::vector<std::vector<int>> buckets(static_cast<std::size_t>(bx) * by);
  auto bucketOf = [&](double px, double py, int& a, int& b)
  {
    a = std::min(bx - 1, std::max(0, static_cast<int>(std::floor((px - x0) / sx))));
    b = std::min(by - 1, std::max(0, static_cast<int>(std::floor((py - y0) / sy))));
  };
  for (int k = 0; k < n; ++k)
  {
    int a, b;
    bucketOf(x[k], y[k], a, b);
    buckets[static_cast<std::size_t>(b) * bx + a].push_back(k);
  }
  for (int j = 0; j < height; ++j)
  {
    for (int i = 0; i < width; ++i)
    {
      double px, py;
      CellXY(i, j, width, height, px, py);
      int a, b;
      bucketOf(px, py, a, b);
      int best = -1;
      double bestD = std::numeric_limits<double>::infinity();
      for (int r = 0;; ++r)
      {
        // A point in ring r is at least (r - 1) bucket sizes away.
        const double reach = (r - 1) * std::min(sx, sy);
        if (best >= 0 && r > 0 && reach > 0.0 && reach * reach > bestD)
        {
          break;
        }
        if (r > bx + by)
        {
          break;
        }
        for (int v = b - r; v <= b + r; ++v)
        {
          if (v < 0 || v >= by)
          {
            continue;
          }
          for (int u = a - r; u <= a + r; ++u)
          {
            if (u < 0 || u >= bx || (std::abs(u - a) != r && std::abs(v - b) != r))
            {
              continue;
            }
            for (int k : buckets[static_cast<std::size_t>(v) * bx + u])
            {
              const double d = (x[k] - px) * (x[k] - px) + (y[k] - py) * (y[k] - py);
              if (d < bestD || (d == bestD && k < best))
              {
                bestD = d;
                best = k;
              }
            }
          }
        }
      }
      labels[static_cast<std::size_t>(j) * width + i] = best;
    }
  }
  return labels;
}

bool GeneratePolygonIsland(const PolygonIslandParameters& p, PolygonIsland& o, std::string& error)
{
  if (p.width < 8 || p.height < 8 || p.width > 65536 || p.height > 65536)
  {
    error = "the raster must be 8 to 65536 cells on each side";
    return false;
  }
  if (p.regions < 16 ||
    static_cast<long long>(p.regions) > static_cast<long long>(p.width) * p.height / 4)
  {
    error = "regions must be at least 16 and at most a quarter of the cells";
    return false;
  }
  if (p.relaxations < 0 || p.relaxations > 100 || p.shapeOctaves < 1 || p.shapeOctaves > 16 ||
    p.noiseOctaves < 1 || p.noiseOctaves > 16 || p.rivers < 0 ||
    !(p.moistureDecay > 0.0 && p.moistureDecay < 1.0) ||
    !(p.waterShare > 0.0 && p.waterShare <= 1.0) || !(p.noiseRatio > 1.0) ||
    !(p.heightExponent > 0.0) || !(p.maximumHeight > 0.0) || !(p.maximumDepth >= 0.0) ||
    !(p.perturbation >= 0.0) || !(p.noiseScale >= 0.0))
  {
    error = "a parameter is out of its range (see PolygonIsland.h)";
    return false;
  }
  const int W = p.width, H = p.height, N = p.regions;
  const std::size_t cells = static_cast<std::size_t>(W) * H;
  std::uint64_t rng = p.seed;
  const std::uint32_t noiseSeed = static_cast<std::uint32_t>(SplitMix64(rng));
  const double yHalf = static_cast<double>(H) / W;

  // 1. Random points, then Lloyd relaxation to the centroids of their discrete regions.
  o.siteX.assign(N, 0.0);
  o.siteY.assign(N, 0.0);
  for (int k = 0; k < N; ++k)
  {
    o.siteX[k] = -1.0 + 2.0 * UnitDouble(rng);
    o.siteY[k] = -yHalf + 2.0 * yHalf * UnitDouble(rng);
  }
  o.region = VoronoiLabels(o.siteX, o.siteY, W, H);
  for (int step = 0; step < p.relaxations; ++step)
  {
    std::vector<double> sx(N, 0.0), sy(N, 0.0), count(N, 0.0);
    for (int j = 0; j < H; ++j)
    {
      for (int i = 0; i < W; ++i)
      {
        double x, y;
        CellXY(i, j, W, H, x, y);
        const int r = o.region[static_cast<std::size_t>(j) * W + i];
        sx[r] += x;
        sy[r] += y;
        count[r] += 1.0;
      }
    }
    for (int k = 0; k < N; ++k)
    {
      if (count[k] > 0.0) // a point whose region is empty stays where it is
      {
        o.siteX[k] = sx[k] / count[k];
        o.siteY[k] = sy[k] / count[k];
      }
    }
    o.region = VoronoiLabels(o.siteX, o.siteY, W, H);
  }

  // 2. Adjacency, border regions, and each region's boundary cells (its "corners").
  o.neighbors.assign(N, {});
  o.border.assign(N, 0);
  std::vector<double> boundary(N, 0.0), boundaryWater(N, 0.0);
  auto shapeWater = [&](double x, double y)
  {
    // Weiss eq. 1 and 2, with each octave's noise in [0, 1] ((Perlin + 1) / 2): with noise in
    // [-1, 1] his parameters leave an islet of about 4 % of the map, unlike his figures.
    double noise = 0.0;
    for (int i = 0; i <= p.shapeOctaves; ++i)
    {
      const double f = p.baseOctave * std::pow(p.octaveScale, i);
      noise += 0.5 * (terroir::io::GradientNoisePerlin2002(x * f, y * f, noiseSeed) + 1.0) *
        p.baseAmplitude * std::pow(p.amplitudeScale, -i);
    }
    return noise < p.shapeOffset + p.shapeScale * (x * x + y * y);
  };
  for (int j = 0; j < H; ++j)
  {
    for (int i = 0; i < W; ++i)
    {
      const int r = o.region[static_cast<std::size_t>(j) * W + i];
      bool edge = i == 0 || j == 0 || i == W - 1 || j == H - 1;
      if (edge)
      {
        o.border[r] = 1;
      }
      const int di[4] = { 1, -1, 0, 0 }, dj[4] = { 0, 0, 1, -1 };
      for (int d = 0; d < 4; ++d)
      {
        const int a = i + di[d], b = j + dj[d];
        if (a < 0 || b < 0 || a >= W || b >= H)
        {
          continue;
        }
        const int s = o.region[static_cast<std::size_t>(b) * W + a];
        if (s != r)
        {
          edge = true;
          o.neighbors[r].push_back(s);
        }
      }
      if (edge)
      {
        double x, y;
        CellXY(i, j, W, H, x, y);
        boundary[r] += 1.0;
        boundaryWater[r] += shapeWater(x, y) ? 1.0 : 0.0;
      }
    }
  }
  for (auto& list : o.neighbors)
  {
    std::sort(list.begin(), list.end());
    list.erase(std::unique(list.begin(), list.end()), list.end());
  }

  // 3. Water (>= waterShare of the boundary), ocean by a flood from the border, coast.
  o.water.assign(N, 0);
  for (int k = 0; k < N; ++k)
  {
    o.water[k] =
      (boundary[k] == 0.0 || o.border[k] || boundaryWater[k] >= p.waterShare * boundary[k]) ? 1 : 0;
  }
  o.ocean.assign(N, 0);
  std::deque<int> queue;
  for (int k = 0; k < N; ++k)
  {
    if (o.border[k] && o.water[k])
    {
      o.ocean[k] = 1;
      queue.push_back(k);
    }
  }
  while (!queue.empty())
  {
    const int k = queue.front();
    queue.pop_front();
    for (int s : o.neighbors[k])
    {
      if (o.water[s] && !o.ocean[s])
      {
        o.ocean[s] = 1;
        queue.push_back(s);
      }
    }
  }
  o.coast.assign(N, 0);
  for (int k = 0; k < N; ++k)
  {
    if (!o.water[k])
    {
      for (int s : o.neighbors[k])
      {
        o.coast[k] = o.coast[k] || o.ocean[s];
      }
    }
  }

  // 4. Elevation: 0-1 breadth-first walk from the coast (land +1, into a lake +0, ocean -1).
  const int unset = std::numeric_limits<int>::max();
  std::vector<int> steps(N, unset);
  o.downslope.assign(N, -1);
  std::deque<int> walk;
  for (int k = 0; k < N; ++k)
  {
    if (o.coast[k])
    {
      steps[k] = 0;
      walk.push_back(k);
    }
  }
  while (!walk.empty())
  {
    const int k = walk.front();
    walk.pop_front();
    for (int s : o.neighbors[k])
    {
      if (o.ocean[s])
      {
        continue; // the sea is walked below
      }
      const int add = o.water[s] ? 0 : 1;
      if (steps[k] + add < steps[s])
      {
        steps[s] = steps[k] + add;
        o.downslope[s] = k;
        if (add == 0)
        {
          walk.push_front(s);
        }
        else
        {
          walk.push_back(s);
        }
      }
    }
  }
  std::vector<int> depth(N, unset);
  for (int k = 0; k < N; ++k)
  {
    if (o.ocean[k])
    {
      for (int s : o.neighbors[k])
      {
        if (o.coast[s])
        {
          depth[k] = 1;
          walk.push_back(k);
          break;
        }
      }
    }
  }
  while (!walk.empty())
  {
    const int k = walk.front();
    walk.pop_front();
    for (int s : o.neighbors[k])
    {
      if (o.ocean[s] && depth[s] == unset)
      {
        depth[s] = depth[k] + 1;
        walk.push_back(s);
      }
    }
  }
  o.elevation.assign(N, 0.0);
  std::vector<int> land;
  std::vector<double> landSteps;
  int deepest = 1;
  for (int k = 0; k < N; ++k)
  {
    if (o.ocean[k])
    {
      deepest = std::max(deepest, depth[k] == unset ? 1 : depth[k]);
    }
    else
    {
      land.push_back(k);
      // A land region the walk never reached (no coast: no ocean at all) is the lowest land.
      landSteps.push_back(steps[k] == unset ? 0.0 : static_cast<double>(steps[k]));
    }
  }
  const std::vector<double> q = RankFractions(landSteps);
  for (std::size_t t = 0; t < land.size(); ++t)
  {
    o.elevation[land[t]] = 1.0 - std::sqrt(1.0 - q[t]);
  }
  for (int k = 0; k < N; ++k)
  {
    if (o.ocean[k])
    {
      o.elevation[k] = -static_cast<double>(depth[k] == unset ? deepest : depth[k]) / deepest;
    }
  }
  o.temperature.assign(N, 0.0);
  for (int k = 0; k < N; ++k)
  {
    o.temperature[k] = 1.0 - std::max(0.0, o.elevation[k]);
  }

  // 5. Rivers from random springs (land, not coast, not lake, elevation >= 0.3, no river
  // next to them) down the walk's tree to the coast; the water a river carries grows by one
  // per step and adds up where rivers join.
  o.riverFlow.assign(N, 0.0);
  const int springs = p.rivers > 0 ? p.rivers : std::max(1, N / 20);
  int made = 0;
  for (int attempt = 0; attempt < 20 * springs && made < springs; ++attempt)
  {
    const int k = static_cast<int>(UnitDouble(rng) * N);
    if (o.water[k] || o.coast[k] || o.elevation[k] < 0.3 || o.riverFlow[k] > 0.0)
    {
      continue;
    }
    bool nearRiver = false;
    for (int s : o.neighbors[k])
    {
      nearRiver = nearRiver || o.riverFlow[s] > 0.0;
    }
    if (nearRiver)
    {
      continue;
    }
    double carried = 0.0;
    for (int c = k; c >= 0; c = o.downslope[c])
    {
      carried += 1.0;
      o.riverFlow[c] += carried;
    }
    ++made;
  }

  // 6. Moisture: rivers (their water) and lakes (the largest river's, at least 1) spread with
  // a factor per step, the largest arrival kept; land then ranked to [0, 1].
  double largest = 1.0;
  for (double f : o.riverFlow)
  {
    largest = std::max(largest, f);
  }
  std::vector<double> wet(N, 0.0);
  for (int k = 0; k < N; ++k)
  {
    if (o.water[k] && !o.ocean[k])
    {
      wet[k] = largest;
    }
    else if (o.riverFlow[k] > 0.0)
    {
      wet[k] = o.riverFlow[k];
    }
  }
  // Relaxation to the fixed point of wet[s] = max(wet[s], decay * wet[k]) over land.
  std::deque<int> spread;
  for (int k = 0; k < N; ++k)
  {
    if (wet[k] > 0.0)
    {
      spread.push_back(k);
    }
  }
  while (!spread.empty())
  {
    const int k = spread.front();
    spread.pop_front();
    for (int s : o.neighbors[k])
    {
      const double m = wet[k] * p.moistureDecay;
      if (!o.ocean[s] && m > wet[s] * (1.0 + 1e-12))
      {
        wet[s] = m;
        spread.push_back(s);
      }
    }
  }
  o.moisture.assign(N, 1.0);
  {
    std::vector<int> dry;
    std::vector<double> values;
    for (int k = 0; k < N; ++k)
    {
      if (!o.water[k])
      {
        dry.push_back(k);
        values.push_back(wet[k]);
      }
    }
    const std::vector<double> mq = RankFractions(values);
    for (std::size_t t = 0; t < dry.size(); ++t)
    {
      o.moisture[dry[t]] = mq[t];
    }
  }

  // 7. Biomes.
  o.biome.assign(N, Biome::Ocean);
  for (int k = 0; k < N; ++k)
  {
    o.biome[k] = o.ocean[k] ? Biome::Ocean
      : o.water[k]          ? Biome::Lake
      : o.coast[k]          ? Biome::Beach
                            : LandBiome(o.temperature[k], o.moisture[k]);
  }

  // 8. The height map. Base: inverse squared distance over the cell's region and its
  // neighbours' points, sampled at the cell moved by noise (perturbation); amplitude A and
  // roughness R of eq. 4 interpolated the same way.
  auto interpolate = [&](double x, double y, int r, double& z, double& a, double& rough)
  {
    double sw = 0.0, sz = 0.0, sa = 0.0, sr = 0.0;
    auto add = [&](int k)
    {
      const double d2 = (o.siteX[k] - x) * (o.siteX[k] - x) + (o.siteY[k] - y) * (o.siteY[k] - y);
      const double w = 1.0 / (d2 + 1e-12);
      sw += w;
      sz += w * o.elevation[k];
      sa += w * BiomeAmplitude(o.biome[k]);
      sr += w * BiomeRoughness(o.biome[k]);
    };
    add(r);
    for (int s : o.neighbors[r])
    {
      add(s);
    }
    z = sz / sw;
    a = sa / sw;
    rough = sr / sw;
  };
  std::vector<double> hmap(cells, 0.0);
  const std::uint32_t warpSeedX = noiseSeed ^ 0x68bc21ebU, warpSeedY = noiseSeed ^ 0x02e5be93U;
  const std::uint32_t detailSeed = noiseSeed ^ 0x967a889bU;
  for (int j = 0; j < H; ++j)
  {
    for (int i = 0; i < W; ++i)
    {
      double x, y;
      CellXY(i, j, W, H, x, y);
      const double wx =
        x + p.perturbation * terroir::io::GradientNoisePerlin2002(x * 8.0, y * 8.0, warpSeedX);
      const double wy =
        y + p.perturbation * terroir::io::GradientNoisePerlin2002(x * 8.0, y * 8.0, warpSeedY);
      const int wi =
        std::min(W - 1, std::max(0, static_cast<int>(std::floor((wx + 1.0) * W / 2.0))));
      const int wj =
        std::min(H - 1, std::max(0, static_cast<int>(std::floor(wy * W / 2.0 + 0.5 * H))));
      double z, a, rough;
      interpolate(wx, wy, o.region[static_cast<std::size_t>(wj) * W + wi], z, a, rough);
      double h = (z < 0.0 ? -1.0 : 1.0) * std::pow(std::fabs(z), p.heightExponent); // eq. 3
      // Eq. 4: N = A sum_k noise(r^k x, r^k y) / r^(k (1 - R)).
      double n = 0.0;
      for (int k = 0; k <= p.noiseOctaves; ++k)
      {
        const double f = p.noiseFrequency * std::pow(p.noiseRatio, k);
        n += terroir::io::GradientNoisePerlin2002(x * f, y * f, detailSeed + k) /
          std::pow(p.noiseRatio, k * (1.0 - rough));
      }
      hmap[static_cast<std::size_t>(j) * W + i] = h + p.noiseScale * a * n;
    }
  }
  // Normalise: 0 stays sea level, the highest cell 1, the deepest -1.
  double top = 0.0, bottom = 0.0;
  for (double h : hmap)
  {
    top = std::max(top, h);
    bottom = std::min(bottom, h);
  }
  o.heightMeters.assign(cells, 0.0f);
  o.biomeMap.assign(cells, 0);
  o.moistureMap.assign(cells, 0.0f);
  o.waterMap.assign(cells, 0);
  for (std::size_t c = 0; c < cells; ++c)
  {
    const double h = hmap[c];
    o.heightMeters[c] =
      static_cast<float>(h >= 0.0 ? (top > 0.0 ? h / top * p.maximumHeight : 0.0)
                                  : (bottom < 0.0 ? h / -bottom * p.maximumDepth : 0.0));
    const int r = o.region[c];
    o.biomeMap[c] = static_cast<std::uint8_t>(o.biome[r]);
    o.moistureMap[c] = static_cast<float>(o.moisture[r]);
    o.waterMap[c] = o.ocean[r] ? 2 : o.water[r] ? 1 : 0;
  }
  // Rivers: the segments between the points of successive river regions, drawn cell by cell.
  o.riverMap.assign(cells, 0);
  for (int k = 0; k < N; ++k)
  {
    const int next = o.downslope[k];
    if (o.riverFlow[k] <= 0.0 || next < 0)
    {
      continue;
    }
    const double fx0 = (o.siteX[k] + 1.0) * W / 2.0, fy0 = o.siteY[k] * W / 2.0 + 0.5 * H;
    const double fx1 = (o.siteX[next] + 1.0) * W / 2.0, fy1 = o.siteY[next] * W / 2.0 + 0.5 * H;
    const int samples =
      2 + static_cast<int>(2.0 * std::max(std::fabs(fx1 - fx0), std::fabs(fy1 - fy0)));
    for (int s = 0; s <= samples; ++s)
    {
      const double t = static_cast<double>(s) / samples;
      const int i = static_cast<int>(std::floor(fx0 + t * (fx1 - fx0)));
      const int j = static_cast<int>(std::floor(fy0 + t * (fy1 - fy0)));
      if (i >= 0 && j >= 0 && i < W && j < H)
      {
        o.riverMap[static_cast<std::size_t>(j) * W + i] = 1;
      }
    }
  }
  return true;
}

} // namespace generation
} // namespace terroir
