// Jensen (2011)'s RiverLand 2.0 on a raster (RiverLand.h).
#include "RiverLand.h"

#include "FractalNoise.h"
#include "PolygonIsland.h" // SplitMix64, UnitDouble

#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <deque>
#include <functional>
#include <limits>
#include <queue>
#include <thread>
#include <utility>

namespace terroir
{
namespace generation
{

namespace
{
const double Pi = 3.14159265358979323846;
const double Sqrt2 = 1.41421356237309504880;
const int DI[8] = { 1, -1, 0, 0, 1, -1, 1, -1 };
const int DJ[8] = { 0, 0, 1, -1, 1, 1, -1, -1 };
const double DW[8] = { 1, 1, 1, 1, Sqrt2, Sqrt2, Sqrt2, Sqrt2 };
const double Inf = std::numeric_limits<double>::infinity();

/// Runs fn(row0, row1) on `threads` contiguous row blocks (fn must write only its rows).
void ParallelRows(int rows, int threads, const std::function<void(int, int)>& fn)
{
  threads = std::max(1, std::min(threads, rows));
  if (threads == 1)
  {
    fn(0, rows);
    return;
  }
  std::vector<std::thread> pool;
  for (int t = 0; t < threads; ++t)
  {
    const int r0 = static_cast<int>(static_cast<long long>(rows) * t / threads);
    const int r1 = static_cast<int>(static_cast<long long>(rows) * (t + 1) / threads);
    pool.emplace_back(fn, r0, r1);
  }
  for (auto& th : pool)
  {
    th.join();
  }
}

/// Is d(b) = d(a) + w (b reached through a on a shortest path)? Tolerant to the summation
/// order of the 1 and sqrt 2 steps.
inline bool Through(double da, double db, double w)
{
  return std::abs(db - (da + w)) <= 1e-9 * (1.0 + db);
}

/// The standard normal density.
inline double Phi(double x)
{
  return std::exp(-0.5 * x * x) / std::sqrt(2.0 * Pi);
}

struct Bend
{
  int cell;
  double side, tx, ty; // the concave side's sign and the river's direction there
};

/// Grows rivers on a land map (RiverLand.h step 2).
class RiverGrower
{
public:
  RiverGrower(const RiverLandParameters& p, std::vector<std::uint8_t>& cls, std::uint64_t& rng)
    : P(p)
    , W(p.width)
    , H(p.height)
    , Cls(cls)
    , Rng(rng)
    , Owner(static_cast<std::size_t>(p.width) * p.height, -1)
    , Index(static_cast<std::size_t>(p.width) * p.height, -1)
  {
  }

  /// Grows one river from the cell `start` (a coast mouth, or a junction's neighbour side)
  /// in direction (dx, dy). Returns false if not a single segment could be laid.
  bool Grow(int start, bool mouth, double dx, double dy, int level, int parent, int junction)
  {
    const double shrink = std::pow(P.tributaryShrink, level);
    const int segments = std::max(1, static_cast<int>(std::lround(P.segments * shrink)));
    const double length = std::max(2.0, P.segmentLength * shrink);
    const double turn = P.maxTurn * shrink * Pi / 180.0;
    const int id = static_cast<int>(Rivers.size());
    RiverLandRiverPath path;
    path.parent = parent;
    path.level = level;
    std::vector<Bend> bends;
    double px = start % W + 0.5, py = start / W + 0.5;
    int last = start;
    if (mouth)
    {
      path.cells.push_back(start);
    }
    else
    {
      px = junction % W + 0.5;
      py = junction / W + 0.5;
      last = junction;
    }
    const int allow = 2 * P.riverSpacing + 2;
    for (int k = 0; k < segments; ++k)
    {
      const double sideSign = (k % 2 == 0) ? 1.0 : -1.0;
      bool laid = false;
      for (int attempt = 0; attempt < 8 && !laid; ++attempt)
      {
        const double a = (k == 0 && attempt == 0) ? 0.0 : (2.0 * UnitDouble(Rng) - 1.0) * turn;
        const double amp = P.meander * length * UnitDouble(Rng) * sideSign;
        const double ndx = dx * std::cos(a) - dy * std::sin(a);
        const double ndy = dx * std::sin(a) + dy * std::cos(a);
        const double qx = px + length * ndx, qy = py + length * ndy;
        const double nx = -ndy, ny = ndx; // left normal
        std::vector<int> cand;
        int apex = -1;
        int ci = last % W, cj = last / W;
        const int samples = static_cast<int>(std::ceil(length * 4.0));
        bool ok = true;
        for (int s = 1; s <= samples && ok; ++s)
        {
          const double t = static_cast<double>(s) / samples;
          const double off = amp * std::sin(Pi * t);
          const int ti = static_cast<int>(std::floor(px + t * (qx - px) + off * nx));
          const int tj = static_cast<int>(std::floor(py + t * (qy - py) + off * ny));
          while ((ci != ti || cj != tj) && ok)
          {
            if (std::abs(ti - ci) >= std::abs(tj - cj))
            {
              ci += ti > ci ? 1 : -1;
            }
            else
            {
              cj += tj > cj ? 1 : -1;
            }
            const int c = cj * W + ci;
            ok = this->Free(ci, cj, id, path, cand, parent, allow);
            cand.push_back(c);
          }
          if (apex < 0 && 2 * s >= samples && !cand.empty())
          {
            apex = cand.back();
          }
        }
        if (!ok || cand.empty())
        {
          continue;
        }
        laid = true;
        for (int c : cand)
        {
          path.cells.push_back(c);
        }
        if (apex >= 0 && amp != 0.0)
        {
          // The concave (outer) bank of the bend is on the side the curve bulges to.
          bends.push_back({ apex, amp > 0 ? 1.0 : -1.0, ndx, ndy });
        }
        px = qx;
        py = qy;
        dx = ndx;
        dy = ndy;
        last = path.cells.back();
      }
      if (!laid)
      {
        break;
      }
      // Mark as we go so that the river keeps off itself.
      for (std::size_t q = 0; q < path.cells.size(); ++q)
      {
        Owner[path.cells[q]] = id;
        Index[path.cells[q]] = static_cast<int>(q);
      }
    }
    if (path.cells.size() < (mouth ? 2u : 1u))
    {
      for (int c : path.cells)
      {
        Owner[c] = -1;
        Index[c] = -1;
      }
      return false;
    }
    Junction.push_back(mouth ? -1 : junction);
    path.junction = mouth ? -1 : junction;
    Rivers.push_back(std::move(path));
    Bends.push_back(std::move(bends));
    return true;
  }

  /// May a river step onto (i, j)? Land, not coast, no other river within riverSpacing.
  bool Free(int i,
    int j,
    int id,
    const RiverLandRiverPath& path,
    const std::vector<int>& cand,
    int parent,
    int allow) const
  {
    if (i < 1 || j < 1 || i >= W - 1 || j >= H - 1)
    {
      return false;
    }
    const int c = j * W + i;
    if (Cls[c] != RiverLandLand || Owner[c] >= 0)
    {
      return false;
    }
    if (std::find(cand.begin(), cand.end(), c) != cand.end())
    {
      return false;
    }
    const int own = static_cast<int>(path.cells.size() + cand.size());
    const int r = P.riverSpacing;
    for (int b = std::max(0, j - r); b <= std::min(H - 1, j + r); ++b)
    {
      for (int a = std::max(0, i - r); a <= std::min(W - 1, i + r); ++a)
      {
        const int o = Owner[b * W + a];
        if (o < 0)
        {
          if (Cls[b * W + a] == RiverLandCoast && own > allow && P.riverSpacing > 0 &&
            std::max(std::abs(a - i), std::abs(b - j)) <= 1)
          {
            return false; // keep one cell off the coast away from the mouth
          }
          continue;
        }
        if (o == id && Index[b * W + a] >= own - allow)
        {
          continue; // the river's own recent cells
        }
        if (o == parent && own <= allow)
        {
          continue; // near its junction
        }
        return false;
      }
    }
    return true;
  }

  const RiverLandParameters& P;
  int W, H;
  std::vector<std::uint8_t>& Cls;
  std::uint64_t& Rng;
  std::vector<int> Owner, Index;
  std::vector<RiverLandRiverPath> Rivers;
  std::vector<std::vector<Bend>> Bends;
  std::vector<int> Junction;
};

/// Land of the island mode (largest 4-connected mass, lakes filled) or of the border mode.
std::vector<std::uint8_t> LandMask(const RiverLandParameters& p)
{
  const int W = p.width, H = p.height;
  const std::size_t n = static_cast<std::size_t>(W) * H;
  std::vector<std::uint8_t> land(n, 0);
  for (int j = 1; j < H - 1; ++j)
  {
    for (int i = 1; i < W - 1; ++i)
    {
      if (!p.island)
      {
        land[static_cast<std::size_t>(j) * W + i] = 1;
        continue;
      }
      const double x = (i + 0.5) / W * 2.0 - 1.0, y = (j + 0.5) / H * 2.0 - 1.0;
      double noise = 0.0, amp = 1.0, freq = 3.0, norm = 0.0;
      for (int o = 0; o < 4; ++o)
      {
        noise += amp *
          terroir::io::GradientNoisePerlin2002(
            x * freq + 17.0, y * freq + 31.0, static_cast<std::uint32_t>(p.seed * 2654435761u + o));
        norm += amp;
        amp *= 0.5;
        freq *= 2.0;
      }
      const double v = 1.0 - (x * x + y * y) + p.islandNoise * noise / norm;
      land[static_cast<std::size_t>(j) * W + i] = v > 0.5 + p.landLevel ? 1 : 0;
    }
  }
  if (!p.island)
  {
    return land;
  }
  // Largest 4-connected land mass.
  std::vector<int> label(n, -1);
  int best = -1;
  std::size_t bestSize = 0;
  std::vector<int> stack;
  for (std::size_t s = 0; s < n; ++s)
  {
    if (!land[s] || label[s] >= 0)
    {
      continue;
    }
    const int id = static_cast<int>(s);
    std::size_t size = 0;
    stack.assign(1, id);
    label[s] = id;
    while (!stack.empty())
    {
      const int c = stack.back();
      stack.pop_back();
      ++size;
      const int i = c % W, j = c / W;
      for (int k = 0; k < 4; ++k)
      {
        const int a = i + DI[k], b = j + DJ[k];
        if (a < 0 || b < 0 || a >= W || b >= H)
          continue;
        const int nb = b * W + a;
        if (land[nb] && label[nb] < 0)
        {
          label[nb] = id;
          stack.push_back(nb);
        }
      }
    }
    if (size > bestSize)
    {
      bestSize = size;
      best = id;
    }
  }
  // Sea: flood from the border over everything not in that mass; the rest is land.
  std::vector<std::uint8_t> sea(n, 0);
  stack.clear();
  for (int i = 0; i < W; ++i)
  {
    for (int j : { 0, H - 1 })
    {
      stack.push_back(j * W + i);
    }
  }
  for (int j = 0; j < H; ++j)
  {
    for (int i : { 0, W - 1 })
    {
      stack.push_back(j * W + i);
    }
  }
  for (int c : stack)
  {
    sea[c] = 1;
  }
  while (!stack.empty())
  {
    const int c = stack.back();
    stack.pop_back();
    const int i = c % W, j = c / W;
    for (int k = 0; k < 4; ++k)
    {
      const int a = i + DI[k], b = j + DJ[k];
      if (a < 0 || b < 0 || a >= W || b >= H)
        continue;
      const int nb = b * W + a;
      if (!sea[nb] && label[nb] != best)
      {
        sea[nb] = 1;
        stack.push_back(nb);
      }
    }
  }
  for (std::size_t s = 0; s < n; ++s)
  {
    land[s] = (best >= 0 && !sea[s]) ? 1 : 0;
  }
  return land;
}

/// Is the distance along the river network between river cells a and b under `limit`
/// cells? The path runs through their lowest common cell; each side climbs downstream
/// (towards the mouth) from the deeper of the two, at most `limit` steps in all.
bool NearAlongRivers(int a,
  int b,
  const std::vector<int>& down,
  const std::vector<int>& depth,
  double limit)
{
  int steps = 0;
  while (a != b)
  {
    if (!(steps + 1 < limit))
      return false;
    if (depth[a] >= depth[b])
      a = down[a];
    else
      b = down[b];
    ++steps;
    if (a < 0 || b < 0)
      return false; // different networks
  }
  return steps < limit;
}
} // namespace

//------------------------------------------------------------------------------
double SlopeProfileValue(SlopeProfile profile,
  double t,
  const std::vector<double>& curveX,
  const std::vector<double>& curveY)
{
  t = std::min(1.0, std::max(0.0, t));
  switch (profile)
  {
    case SlopeProfile::Linear:
      return t;
    case SlopeProfile::Cos:
      return 1.0 - std::cos(0.5 * Pi * t);
    case SlopeProfile::Cos2:
    {
      const double c = std::cos(0.5 * Pi * t);
      return 1.0 - c * c;
    }
    case SlopeProfile::Gauss:
      return (Phi(3.1 * (1.0 - t)) - Phi(3.1)) / (Phi(0.0) - Phi(3.1));
    case SlopeProfile::Custom:
    {
      const std::size_t m = std::min(curveX.size(), curveY.size());
      if (m == 0)
        return t;
      if (t <= curveX[0])
        return curveY[0];
      for (std::size_t k = 1; k < m; ++k)
      {
        if (t <= curveX[k])
        {
          const double u = (t - curveX[k - 1]) / (curveX[k] - curveX[k - 1]);
          return curveY[k - 1] + u * (curveY[k] - curveY[k - 1]);
        }
      }
      return curveY[m - 1];
    }
  }
  return t;
}

//------------------------------------------------------------------------------
double BlendSlopeHeights(double linearHeight,
  const std::vector<double>& slopeHeights,
  const std::vector<double>& influenceFractions)
{
  const std::size_t m = slopeHeights.size();
  if (m == 0)
  {
    return linearHeight;
  }
  if (m == 1)
  {
    // Jensen 2.4.2.
    const double w = influenceFractions[0];
    return w * slopeHeights[0] + (1.0 - w) * linearHeight;
  }
  // Jensen 2.4.3: the linear slope's fraction is always 1.
  double total = 1.0;
  for (double w : influenceFractions)
    total += w;
  double h = linearHeight / total;
  for (std::size_t k = 0; k < m; ++k)
    h += influenceFractions[k] / total * slopeHeights[k];
  return h;
}

//------------------------------------------------------------------------------
bool ParseSlopeProfile(const std::string& name, SlopeProfile& out)
{
  static const char* names[] = { "linear", "cos", "cos2", "gauss", "custom" };
  for (int k = 0; k < 5; ++k)
  {
    if (name == names[k])
    {
      out = static_cast<SlopeProfile>(k);
      return true;
    }
  }
  return false;
}

const char* SlopeProfileName(SlopeProfile profile)
{
  static const char* names[] = { "linear", "cos", "cos2", "gauss", "custom" };
  return names[static_cast<int>(profile)];
}

//------------------------------------------------------------------------------
bool ValidateRiverLandParameters(const RiverLandParameters& p, std::string& error)
{
  auto fail = [&](const std::string& e)
  {
    error = e;
    return false;
  };
  if (p.width < 8 || p.height < 8 || p.width > 65536 || p.height > 65536)
    return fail("width and height must be 8 to 65536");
  if (!(p.spacing > 0.0) || !std::isfinite(p.spacing))
    return fail("spacing must be positive");
  if (p.rivers < 0 || p.rivers > 100000)
    return fail("rivers must be 0 to 100000");
  if (p.segments < 1 || p.segments > 10000 || !(p.segmentLength >= 2.0) ||
    !(p.segmentLength <= 10000.0))
    return fail("segments must be 1 to 10000 and segment_length 2 to 10000 cells");
  if (!(p.maxTurn >= 0.0 && p.maxTurn <= 180.0))
    return fail("max_turn must be 0 to 180 degrees");
  if (!(p.meander >= 0.0 && p.meander <= 2.0))
    return fail("meander must be 0 to 2");
  if (!(p.tributaryChance >= 0.0 && p.tributaryChance <= 1.0) || p.tributaryLevels < 0 ||
    p.tributaryLevels > 8 || !(p.tributaryShrink > 0.0 && p.tributaryShrink <= 1.0))
    return fail("tributary_chance must be 0 to 1, tributary_levels 0 to 8, tributary_shrink "
                "(0, 1]");
  if (p.riverSpacing < 0 || p.riverSpacing > 64 || p.mouthSpacing < 1)
    return fail("river_spacing must be 0 to 64 and mouth_spacing at least 1");
  if (!(p.averageSlope >= 0.0 && p.averageSlope <= 10.0) || !(p.steepening >= 0.0) ||
    !(p.steepening <= 1000.0) || !(p.roughness >= 0.0 && p.roughness < 1.0))
    return fail("average_slope must be 0 to 10, steepening 0 to 1000, roughness [0, 1)");
  if (!(p.hillSlope >= 0.0 && p.hillSlope <= 100.0))
    return fail("hill_slope must be 0 to 100");
  if (!(p.pruneThreshold >= 0.0 && p.pruneThreshold <= 1e6))
    return fail("prune_threshold must be 0 to 1e6");
  if (!(p.noiseAmplitude >= 0.0 && p.noiseAmplitude <= 1e5) || !(p.noiseFeature > 0.0) ||
    !(p.noiseFeature <= 1e6) || !(p.seaDepth >= 0.0 && p.seaDepth <= 1e5))
    return fail("noise_amplitude must be 0 to 1e5, noise_feature positive, sea_depth 0 to 1e5");
  if (!(std::abs(p.landLevel) <= 10.0) || !(p.islandNoise >= 0.0 && p.islandNoise <= 10.0))
    return fail("land_level must be -10 to 10 and island_noise 0 to 10");
  if (p.threads < 1 || p.threads > 1024)
    return fail("threads must be 1 to 1024");
  for (std::size_t k = 0; k < p.slopes.size(); ++k)
  {
    const RiverLandSlope& s = p.slopes[k];
    const std::string name = "slope " + std::to_string(k);
    if (!(s.x >= 0.0 && s.x <= 1.0 && s.y >= 0.0 && s.y <= 1.0))
      return fail(name + ": x and y must be fractions of the map, 0 to 1");
    if (!(s.influence > 0.0 && s.influence <= 1e6))
      return fail(name + ": influence must be positive");
    if (s.profile == SlopeProfile::Custom)
    {
      if (s.curveX.size() != s.curveY.size() || s.curveX.size() < 2 || s.curveX.size() > 64)
        return fail(name + ": a custom curve has 2 to 64 points");
      for (std::size_t q = 0; q < s.curveX.size(); ++q)
      {
        if (!(s.curveX[q] >= 0.0 && s.curveX[q] <= 1.0 && s.curveY[q] >= 0.0 &&
              s.curveY[q] <= 1.0) ||
          (q > 0 && !(s.curveX[q] > s.curveX[q - 1])))
          return fail(name + ": curve points must lie in [0, 1] with x increasing");
      }
    }
  }
  return true;
}

//------------------------------------------------------------------------------
bool RiverLandParametersFromJson(const std::string& text,
  RiverLandParameters& p,
  std::string& error)
{
  nlohmann::json j;
  try
  {
    j = nlohmann::json::parse(text);
  }
  catch (const std::exception& e)
  {
    error = std::string("not JSON (") + e.what() + ")";
    return false;
  }
  if (!j.is_object())
  {
    error = "expected a JSON object of parameters";
    return false;
  }
  try
  {
    for (auto it = j.begin(); it != j.end(); ++it)
    {
      const std::string& k = it.key();
      const nlohmann::json& v = *it;
      auto num = [&]()
      {
        if (!v.is_number())
          throw std::invalid_argument("'" + k + "' is not a number");
        return v.get<double>();
      };
      auto whole = [&](double lo, double hi)
      {
        const double x = num();
        if (x != std::floor(x) || x < lo || x > hi)
          throw std::invalid_argument("'" + k + "' must be a whole number in [" +
            std::to_string(static_cast<long long>(lo)) + ", " +
            std::to_string(static_cast<long long>(hi)) + "]");
        return static_cast<long long>(x);
      };
      auto flag = [&]()
      {
        if (!v.is_boolean())
          throw std::invalid_argument("'" + k + "' is not true or false");
        return v.get<bool>();
      };
      if (k == "comment" || k == "figure")
      {
        if (!v.is_string())
          throw std::invalid_argument("'" + k + "' is not a string");
      }
      else if (k == "seed")
        p.seed = static_cast<std::uint64_t>(whole(-9.0e15, 9.0e15));
      else if (k == "width")
        p.width = static_cast<int>(whole(8, 65536));
      else if (k == "height")
        p.height = static_cast<int>(whole(8, 65536));
      else if (k == "spacing")
        p.spacing = num();
      else if (k == "island")
        p.island = flag();
      else if (k == "land_level")
        p.landLevel = num();
      else if (k == "island_noise")
        p.islandNoise = num();
      else if (k == "rivers")
        p.rivers = static_cast<int>(whole(0, 100000));
      else if (k == "mouth_spacing")
        p.mouthSpacing = static_cast<int>(whole(1, 65536));
      else if (k == "segments")
        p.segments = static_cast<int>(whole(1, 10000));
      else if (k == "segment_length")
        p.segmentLength = num();
      else if (k == "max_turn")
        p.maxTurn = num();
      else if (k == "meander")
        p.meander = num();
      else if (k == "tributary_chance")
        p.tributaryChance = num();
      else if (k == "tributary_levels")
        p.tributaryLevels = static_cast<int>(whole(0, 8));
      else if (k == "tributary_shrink")
        p.tributaryShrink = num();
      else if (k == "river_spacing")
        p.riverSpacing = static_cast<int>(whole(0, 64));
      else if (k == "average_slope")
        p.averageSlope = num();
      else if (k == "steepening")
        p.steepening = num();
      else if (k == "roughness")
        p.roughness = num();
      else if (k == "hill_slope")
        p.hillSlope = num();
      else if (k == "prune")
        p.prune = flag();
      else if (k == "prune_threshold")
        p.pruneThreshold = num();
      else if (k == "prune_coast")
        p.pruneCoast = flag();
      else if (k == "noise_amplitude")
        p.noiseAmplitude = num();
      else if (k == "noise_feature")
        p.noiseFeature = num();
      else if (k == "sea_depth")
        p.seaDepth = num();
      else if (k == "threads")
        p.threads = static_cast<int>(whole(1, 1024));
      else if (k == "slopes")
      {
        if (!v.is_array())
          throw std::invalid_argument("'slopes' is not an array");
        p.slopes.clear();
        for (std::size_t q = 0; q < v.size(); ++q)
        {
          const nlohmann::json& o = v[q];
          const std::string name = "slopes[" + std::to_string(q) + "]";
          if (!o.is_object())
            throw std::invalid_argument(name + " is not an object");
          RiverLandSlope s;
          for (auto f = o.begin(); f != o.end(); ++f)
          {
            const std::string& fk = f.key();
            if (fk == "x" || fk == "y" || fk == "influence")
            {
              if (!f->is_number())
                throw std::invalid_argument(name + "." + fk + " is not a number");
              (fk == "x" ? s.x : fk == "y" ? s.y : s.influence) = f->get<double>();
            }
            else if (fk == "profile")
            {
              if (!f->is_string() || !ParseSlopeProfile(f->get<std::string>(), s.profile))
                throw std::invalid_argument(
                  name + ".profile must be linear, cos, cos2, gauss or custom");
            }
            else if (fk == "curve")
            {
              if (!f->is_array())
                throw std::invalid_argument(name + ".curve is not an array of [x, y]");
              for (const auto& pt : *f)
              {
                if (!pt.is_array() || pt.size() != 2 || !pt[0].is_number() || !pt[1].is_number())
                  throw std::invalid_argument(name + ".curve is not an array of [x, y]");
                s.curveX.push_back(pt[0].get<double>());
                s.curveY.push_back(pt[1].get<double>());
              }
            }
            else
            {
              throw std::invalid_argument("unknown parameter '" + name + "." + fk + "'");
            }
          }
          p.slopes.push_back(s);
        }
      }
      else
        throw std::invalid_argument("unknown parameter '" + k + "'");
    }
  }
  catch (const std::exception& e)
  {
    error = e.what();
    return false;
  }
  return ValidateRiverLandParameters(p, error);
}

//------------------------------------------------------------------------------
bool ShapeRiverLand(const RiverLandParameters& p,
  const std::vector<std::uint8_t>& cls,
  const std::vector<double>& riverHeight,
  const std::vector<int>& riverDown,
  const std::vector<int>& riverDepth,
  RiverLand& out,
  std::string& error)
{
  const int W = p.width, H = p.height;
  const std::size_t n = static_cast<std::size_t>(W) * H;
  if (cls.size() != n || riverHeight.size() != n || riverDown.size() != n || riverDepth.size() != n)
  {
    error = "ShapeRiverLand: the maps must have width x height cells";
    return false;
  }
  out.cls = cls;
  out.riverHeight = riverHeight;
  auto isSource = [&](std::size_t c)
  { return cls[c] == RiverLandRiver || cls[c] == RiverLandCoast; };

  // Step 4: distance propagation (Dijkstra, 8 neighbours, steps 1 and sqrt 2).
  std::vector<double>& d = out.distance;
  std::vector<int>& parent = out.parent;
  std::vector<int>& source = out.source;
  d.assign(n, Inf);
  parent.assign(n, -1);
  source.assign(n, -1);
  std::vector<int> order;
  order.reserve(n);
  {
    using Item = std::pair<double, int>;
    std::priority_queue<Item, std::vector<Item>, std::greater<Item>> heap;
    for (std::size_t c = 0; c < n; ++c)
    {
      if (isSource(c))
      {
        d[c] = 0.0;
        source[c] = static_cast<int>(c);
        heap.push({ 0.0, static_cast<int>(c) });
      }
    }
    std::vector<std::uint8_t> done(n, 0);
    while (!heap.empty())
    {
      const Item top = heap.top();
      heap.pop();
      const int c = top.second;
      if (done[c])
        continue;
      done[c] = 1;
      order.push_back(c);
      const int i = c % W, j = c / W;
      for (int k = 0; k < 8; ++k)
      {
        const int a = i + DI[k], b = j + DJ[k];
        if (a < 0 || b < 0 || a >= W || b >= H)
          continue;
        const int nb = b * W + a;
        if (cls[nb] != RiverLandLand)
          continue;
        const double nd = top.first + DW[k];
        if (nd < d[nb])
        {
          d[nb] = nd;
          parent[nb] = c;
          source[nb] = source[c];
          heap.push({ nd, nb });
        }
      }
    }
  }

  // Medial cells (no neighbour reached through them) and each land cell's up pointer.
  std::vector<std::uint8_t>& medial = out.medial;
  medial.assign(n, 0);
  std::vector<int> up(n, -1);
  ParallelRows(H,
    p.threads,
    [&](int r0, int r1)
    {
      for (int j = r0; j < r1; ++j)
      {
        for (int i = 0; i < W; ++i)
        {
          const int c = j * W + i;
          if (cls[c] != RiverLandLand || !std::isfinite(d[c]))
            continue;
          const int pc = parent[c];
          const double px = i - pc % W, py = j - pc / W;
          double best = -Inf;
          int bestK = -1;
          for (int k = 0; k < 8; ++k)
          {
            const int a = i + DI[k], b = j + DJ[k];
            if (a < 0 || b < 0 || a >= W || b >= H)
              continue;
            const int nb = b * W + a;
            if (cls[nb] != RiverLandLand || !Through(d[c], d[nb], DW[k]))
              continue;
            const double dot = (DI[k] * px + DJ[k] * py) / DW[k];
            if (dot > best + 1e-12)
            {
              best = dot;
              bestK = k;
            }
          }
          if (bestK < 0)
            medial[c] = 1;
          else
            up[c] = (j + DJ[bestK]) * W + (i + DI[bestK]);
        }
      }
    });
  out.medialBefore = 0;
  for (std::size_t c = 0; c < n; ++c)
    out.medialBefore += medial[c] == 1 ? 1 : 0;

  // Step 5: pruning, medial cells in ascending (d, cell) = the settling order.
  std::vector<int> next(n, -1);
  const auto t0 = std::chrono::steady_clock::now();
  if (p.prune)
  {
    const double T = p.pruneThreshold;
    auto near = [&](int a, int b)
    {
      if (a == b)
        return true;
      if (cls[a] == RiverLandRiver && cls[b] == RiverLandRiver)
        return NearAlongRivers(a, b, riverDown, riverDepth, T);
      if (p.pruneCoast && cls[a] == RiverLandCoast && cls[b] == RiverLandCoast)
        return std::max(std::abs(a % W - b % W), std::abs(a / W - b / W)) < T;
      return false;
    };
    for (int m : order)
    {
      if (medial[m] != 1)
        continue;
      const int i = m % W, j = m / W;
      bool prunable = true;
      int bestMedial = -1, bestHigher = -1;
      for (int k = 0; k < 8 && prunable; ++k)
      {
        const int a = i + DI[k], b = j + DJ[k];
        if (a < 0 || b < 0 || a >= W || b >= H)
          continue;
        const int nb = b * W + a;
        if (cls[nb] == RiverLandSea || source[nb] < 0)
          continue;
        prunable = near(source[m], source[nb]);
        if (cls[nb] != RiverLandLand)
          continue;
        if (medial[nb] == 1 &&
          (bestMedial < 0 || d[nb] > d[bestMedial] || (d[nb] == d[bestMedial] && nb < bestMedial)))
          bestMedial = nb;
        if (medial[nb] == 0 && d[nb] > d[m] &&
          (bestHigher < 0 || d[nb] > d[bestHigher] || (d[nb] == d[bestHigher] && nb < bestHigher)))
          bestHigher = nb;
      }
      if (!prunable)
        continue;
      const int to = bestMedial >= 0 ? bestMedial : bestHigher;
      if (to < 0)
        continue;
      medial[m] = 2;
      next[m] = to;
    }
  }
  out.pruneSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  out.medialAfter = 0;
  for (std::size_t c = 0; c < n; ++c)
    out.medialAfter += medial[c] == 1 ? 1 : 0;

  // Targets: every land cell's medial cell, in descending settling order (3.3's pointer fix).
  std::vector<int>& target = out.target;
  target.assign(n, -1);
  for (auto it = order.rbegin(); it != order.rend(); ++it)
  {
    const int c = *it;
    if (cls[c] != RiverLandLand)
      continue;
    if (medial[c] == 1)
      target[c] = c;
    else if (medial[c] == 2)
      target[c] = medial[next[c]] == 1 ? next[c] : target[next[c]];
    else if (up[c] >= 0)
      target[c] = medial[up[c]] == 1 ? up[c] : target[up[c]];
  }

  // Heights of the sources and of the medial cells (the higher river that meets there).
  auto sourceHeight = [&](int s) { return cls[s] == RiverLandRiver ? riverHeight[s] : 0.0; };
  std::vector<double> medialHeight(n, 0.0);
  for (std::size_t c = 0; c < n; ++c)
  {
    if (medial[c] != 1)
      continue;
    const int i = static_cast<int>(c) % W, j = static_cast<int>(c) / W;
    double base = sourceHeight(source[c]);
    for (int k = 0; k < 8; ++k)
    {
      const int a = i + DI[k], b = j + DJ[k];
      if (a < 0 || b < 0 || a >= W || b >= H)
        continue;
      const int nb = b * W + a;
      if (source[nb] >= 0)
        base = std::max(base, sourceHeight(source[nb]));
    }
    medialHeight[c] = base + p.hillSlope * d[c] * p.spacing;
  }

  // Step 7: the user slopes' paths and influence floods (4 neighbours).
  struct Applied
  {
    const RiverLandSlope* slope;
    std::vector<float> influence;
  };
  std::vector<Applied> applied;
  for (const RiverLandSlope& s : p.slopes)
  {
    const int i = std::min(W - 1, static_cast<int>(s.x * W));
    const int j = std::min(H - 1, static_cast<int>(s.y * H));
    // The chosen cell, or the nearest plain land cell within 8 cells (ties: lowest index).
    int c0 = -1;
    double best = Inf;
    for (int b = std::max(0, j - 8); b <= std::min(H - 1, j + 8); ++b)
    {
      for (int a = std::max(0, i - 8); a <= std::min(W - 1, i + 8); ++a)
      {
        const int c = b * W + a;
        const double r = std::hypot(a - i, b - j);
        if (cls[c] == RiverLandLand && target[c] >= 0 && r <= 8.0 && r < best)
        {
          best = r;
          c0 = c;
        }
      }
    }
    if (c0 < 0)
      continue;
    Applied a{ &s, std::vector<float>(n, 0.0f) };
    std::deque<int> queue;
    auto seed = [&](int c)
    {
      if (a.influence[c] == 0.0f)
      {
        a.influence[c] = static_cast<float>(s.influence);
        if (medial[c] != 1)
          queue.push_back(c);
      }
    };
    for (int c = c0; c >= 0 && cls[c] == RiverLandLand; c = parent[c])
      seed(c);
    int c = c0;
    for (std::size_t guard = 0; guard < n && c >= 0 && medial[c] != 1; ++guard)
    {
      c = medial[c] == 2 ? next[c] : up[c];
      if (c >= 0)
        seed(c);
    }
    while (!queue.empty())
    {
      const int q = queue.front();
      queue.pop_front();
      const float v = a.influence[q] - 1.0f;
      if (v <= 0.0f)
        continue;
      const int qi = q % W, qj = q / W;
      for (int k = 0; k < 4; ++k)
      {
        const int na = qi + DI[k], nb = qj + DJ[k];
        if (na < 0 || nb < 0 || na >= W || nb >= H)
          continue;
        const int r = nb * W + na;
        if (cls[r] != RiverLandLand || medial[r] == 1 || a.influence[r] >= v)
          continue;
        a.influence[r] = v;
        queue.push_back(r);
      }
    }
    applied.push_back(std::move(a));
  }
  out.slopesApplied = static_cast<int>(applied.size());

  // Step 6-8: heights, per cell.
  out.heightMeters.assign(n, 0.0f);
  out.slopeWeight.assign(n, 0.0f);
  terroir::io::FractalNoiseParameters noise;
  noise.seed = static_cast<std::uint32_t>(p.seed ^ (p.seed >> 32) ^ 0x9e3779b9u);
  noise.octaves = 6;
  noise.featureSize = p.noiseFeature;
  noise.persistence = 0.5;
  noise.amplitude = p.noiseAmplitude;
  noise.baseHeight = 0.0;
  ParallelRows(H,
    p.threads,
    [&](int r0, int r1)
    {
      std::vector<double> hs, ws;
      for (int j = r0; j < r1; ++j)
      {
        for (int i = 0; i < W; ++i)
        {
          const std::size_t c = static_cast<std::size_t>(j) * W + i;
          double h = 0.0;
          if (cls[c] == RiverLandSea)
            h = -p.seaDepth;
          else if (cls[c] == RiverLandRiver)
            h = riverHeight[c];
          else if (cls[c] == RiverLandCoast)
            h = 0.0;
          else if (target[c] >= 0)
          {
            const int m = target[c];
            const double hr = sourceHeight(source[c]);
            const double hm = medialHeight[m];
            const double t = d[m] > 0.0 ? std::min(1.0, d[c] / d[m]) : 1.0;
            const double linear = hr + t * (hm - hr);
            hs.clear();
            ws.clear();
            double sum = 0.0;
            for (const Applied& a : applied)
            {
              if (a.influence[c] > 0.0f)
              {
                const RiverLandSlope& s = *a.slope;
                hs.push_back(hr + SlopeProfileValue(s.profile, t, s.curveX, s.curveY) * (hm - hr));
                ws.push_back(a.influence[c] / s.influence);
                sum += ws.back();
              }
            }
            h = BlendSlopeHeights(linear, hs, ws);
            out.slopeWeight[c] = static_cast<float>(sum);
            if (p.noiseAmplitude > 0.0)
              h += t * terroir::io::FractalNoisePerlin2002(noise, i, j);
          }
          out.heightMeters[c] = static_cast<float>(h);
        }
      }
    });
  return true;
}

//------------------------------------------------------------------------------
bool GenerateRiverLand(const RiverLandParameters& p, RiverLand& out, std::string& error)
{
  if (!ValidateRiverLandParameters(p, error))
  {
    return false;
  }
  const int W = p.width, H = p.height;
  const std::size_t n = static_cast<std::size_t>(W) * H;
  std::uint64_t rng = p.seed;

  // Step 1: land, sea and coast.
  std::vector<std::uint8_t> land = LandMask(p);
  std::vector<std::uint8_t> cls(n, RiverLandSea);
  std::vector<int> coast;
  for (int j = 0; j < H; ++j)
  {
    for (int i = 0; i < W; ++i)
    {
      const int c = j * W + i;
      if (!land[c])
        continue;
      cls[c] = RiverLandLand;
      for (int k = 0; k < 4; ++k)
      {
        const int a = i + DI[k], b = j + DJ[k];
        if (a < 0 || b < 0 || a >= W || b >= H || !land[b * W + a])
        {
          cls[c] = RiverLandCoast;
          coast.push_back(c);
          break;
        }
      }
    }
  }

  // Step 2: mouths (shuffled coast cells, spaced) and rivers.
  for (std::size_t k = coast.size(); k > 1; --k)
  {
    const std::size_t r = static_cast<std::size_t>(UnitDouble(rng) * static_cast<double>(k));
    std::swap(coast[k - 1], coast[std::min(r, k - 1)]);
  }
  RiverGrower grower(p, cls, rng);
  std::vector<int> mouths;
  for (int c : coast)
  {
    if (static_cast<int>(grower.Rivers.size()) >= p.rivers)
      break;
    const int i = c % W, j = c / W;
    bool spaced = true;
    for (int m : mouths)
    {
      if (std::max(std::abs(m % W - i), std::abs(m / W - j)) < p.mouthSpacing)
      {
        spaced = false;
        break;
      }
    }
    if (!spaced)
      continue;
    // Inland: away from the sea cells within 4 cells.
    double dx = 0.0, dy = 0.0;
    for (int b = std::max(0, j - 4); b <= std::min(H - 1, j + 4); ++b)
    {
      for (int a = std::max(0, i - 4); a <= std::min(W - 1, i + 4); ++a)
      {
        if (cls[b * W + a] == RiverLandSea)
        {
          dx += i - a;
          dy += j - b;
        }
      }
    }
    const double len = std::hypot(dx, dy);
    if (len == 0.0)
      continue;
    mouths.push_back(c);
    if (grower.Grow(c, true, dx / len, dy / len, 0, -1, -1))
    {
      for (int rc : grower.Rivers.back().cells)
        cls[rc] = RiverLandRiver;
    }
  }
  // Tributaries from the concave banks, breadth first.
  for (std::size_t r = 0; r < grower.Rivers.size(); ++r)
  {
    const int level = grower.Rivers[r].level;
    if (level >= p.tributaryLevels)
      continue;
    const std::vector<Bend> bends = grower.Bends[r];
    for (const Bend& b : bends)
    {
      if (!(UnitDouble(rng) < p.tributaryChance))
        continue;
      // Left normal of the river's direction, on the concave side, leaning upstream.
      double dx = -b.ty * b.side + 0.5 * b.tx, dy = b.tx * b.side + 0.5 * b.ty;
      const double len = std::hypot(dx, dy);
      if (grower.Grow(-1, false, dx / len, dy / len, level + 1, static_cast<int>(r), b.cell))
      {
        for (int rc : grower.Rivers.back().cells)
          cls[rc] = RiverLandRiver;
      }
    }
  }

  // Step 3: river heights, parents first (tributaries come after their parent).
  std::vector<double> riverHeight(n, 0.0);
  std::vector<int> riverDown(n, -1), riverDepth(n, 0);
  out.riverId.assign(n, -1);
  const double L = std::max(W, H);
  for (std::size_t r = 0; r < grower.Rivers.size(); ++r)
  {
    const RiverLandRiverPath& path = grower.Rivers[r];
    int prev = grower.Junction[r];
    double h = prev >= 0 ? riverHeight[prev] : 0.0;
    int depth = prev >= 0 ? riverDepth[prev] : -1;
    for (int c : path.cells)
    {
      out.riverId[c] = static_cast<int>(r);
      if (prev >= 0)
      {
        const double s = depth + 1;
        const double slope = p.averageSlope * (1.0 + p.steepening * s / L) *
          (1.0 + p.roughness * (2.0 * UnitDouble(rng) - 1.0));
        h += slope * p.spacing;
      }
      riverHeight[c] = h;
      riverDown[c] = prev;
      riverDepth[c] = ++depth;
      prev = c;
    }
  }
  out.rivers = std::move(grower.Rivers);

  // Steps 4-8.
  if (!ShapeRiverLand(p, cls, riverHeight, riverDown, riverDepth, out, error))
    return false;
  return true;
}

} // namespace generation
} // namespace terroir
