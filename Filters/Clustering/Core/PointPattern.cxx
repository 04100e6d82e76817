// Multi-type point patterns: pair correlation, radial-distribution model, Metropolis-Hastings
// synthesis (see PointPattern.h for the formulas and sources).
#include "PointPattern.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>

namespace terroir
{
namespace clustering
{
namespace
{

constexpr double Pi = 3.14159265358979323846;

// ---------------------------------------------------------------------------------------------
// Errors

template<typename T>
std::string Str(const T& value)
{
  std::ostringstream s;
  s.precision(10);
  s << value;
  return s.str();
}

void Require(bool condition, const std::string& message)
{
  if (!condition)
  {
    throw std::invalid_argument("point pattern: " + message);
  }
}

// ---------------------------------------------------------------------------------------------
// Random numbers: our own mapping of mt19937_64's output (std distributions differ by library).

/// Uniform in [0, 1): the 53 high bits.
double Uniform(std::mt19937_64& rng)
{
  return static_cast<double>(rng() >> 11) * 0x1.0p-53;
}

/// Uniform in (0, 1].
double UniformOpenZero(std::mt19937_64& rng)
{
  return static_cast<double>((rng() >> 11) + 1) * 0x1.0p-53;
}

/// Uniform integer in [0, n), n >= 1.
std::size_t UniformIndex(std::mt19937_64& rng, std::size_t n)
{
  const auto i = static_cast<std::size_t>(Uniform(rng) * static_cast<double>(n));
  return std::min(i, n - 1);
}

// ---------------------------------------------------------------------------------------------
// Distance bins shared by the estimate and the synthesis.

struct Binning
{
  double rMin = 0.0;
  double rMax = 0.0;
  double rMin2 = 0.0;
  double rMax2 = 0.0;
  double inverseWidth = 0.0;
  int bins = 0;

  Binning(double rmin, double rmax, int nbins)
    : rMin(rmin)
    , rMax(rmax)
    , rMin2(rmin * rmin)
    , rMax2(rmax * rmax)
    , inverseWidth(nbins / (rmax - rmin))
    , bins(nbins)
  {
  }

  bool InRange(double d2) const { return d2 >= this->rMin2 && d2 < this->rMax2; }

  /// Bin of a squared distance already known to be in range.
  int Bin(double d2) const
  {
    const int k = static_cast<int>((std::sqrt(d2) - this->rMin) * this->inverseWidth);
    return std::min(std::max(k, 0), this->bins - 1);
  }

  double Edge(int k) const { return this->rMin + k * (this->rMax - this->rMin) / this->bins; }
};

void CheckRanges(double rMin, double rMax, int bins)
{
  Require(std::isfinite(rMin) && rMin >= 0.0, "rMin = " + Str(rMin) + " must be >= 0");
  Require(std::isfinite(rMax) && rMax > rMin,
    "rMax = " + Str(rMax) + " must be greater than rMin = " + Str(rMin));
  Require(bins >= 1 && bins <= PatternMaxBins,
    "bins = " + Str(bins) + " must be in 1.." + Str(PatternMaxBins));
}

// ---------------------------------------------------------------------------------------------
// Uniform grid of buckets of side >= the search radius: the points within that radius of (x, y)
// are in the 3 x 3 buckets around the bucket of (x, y).

class Buckets
{
public:
  Buckets(const double* box, double radius, std::size_t maxBuckets)
  {
    const double w = box[2] - box[0];
    const double h = box[3] - box[1];
    this->X0 = box[0];
    this->Y0 = box[1];
    this->Side = std::max(radius, std::sqrt(w * h / static_cast<double>(maxBuckets)));
    this->Nx = std::max(1, static_cast<int>(std::ceil(w / this->Side)));
    this->Ny = std::max(1, static_cast<int>(std::ceil(h / this->Side)));
    this->Cells.resize(static_cast<std::size_t>(this->Nx) * this->Ny);
  }

  std::size_t Of(double x, double y) const
  {
    const int i = this->Column(x);
    const int j = this->Row(y);
    return static_cast<std::size_t>(j) * this->Nx + i;
  }

  void Insert(std::size_t bucket, std::uint32_t id) { this->Cells[bucket].push_back(id); }

  void Remove(std::size_t bucket, std::uint32_t id)
  {
    auto& cell = this->Cells[bucket];
    auto it = std::find(cell.begin(), cell.end(), id);
    *it = cell.back();
    cell.pop_back();
  }

  void Rename(std::size_t bucket, std::uint32_t from, std::uint32_t to)
  {
    auto& cell = this->Cells[bucket];
    *std::find(cell.begin(), cell.end(), from) = to;
  }

  /// Calls visit(id) for the points of the 3 x 3 buckets around (x, y) until it returns false.
  template<typename Visit>
  void ForEachNear(double x, double y, Visit&& visit) const
  {
    const int i = this->Column(x);
    const int j = this->Row(y);
    for (int jj = std::max(0, j - 1); jj <= std::min(this->Ny - 1, j + 1); ++jj)
    {
      for (int ii = std::max(0, i - 1); ii <= std::min(this->Nx - 1, i + 1); ++ii)
      {
        for (std::uint32_t id : this->Cells[static_cast<std::size_t>(jj) * this->Nx + ii])
        {
          if (!visit(id))
          {
            return;
          }
        }
      }
    }
  }

private:
  int Column(double x) const
  {
    const int i = static_cast<int>(std::floor((x - this->X0) / this->Side));
    return std::min(std::max(i, 0), this->Nx - 1);
  }
  int Row(double y) const
  {
    const int j = static_cast<int>(std::floor((y - this->Y0) / this->Side));
    return std::min(std::max(j, 0), this->Ny - 1);
  }

  double X0 = 0.0;
  double Y0 = 0.0;
  double Side = 1.0;
  int Nx = 1;
  int Ny = 1;
  std::vector<std::vector<std::uint32_t>> Cells;
};

/// Checks a pattern against a domain and returns its number of categories.
int CheckPoints(const std::vector<PatternPoint>& points,
  const PatternDomain& domain,
  int categories)
{
  Require(categories >= 0 && categories <= PatternMaxCategories,
    "categories = " + Str(categories) + " must be in 0.." + Str(PatternMaxCategories));
  Require(points.size() < std::numeric_limits<std::uint32_t>::max(),
    "too many points (" + Str(points.size()) + ")");
  int largest = -1;
  for (std::size_t i = 0; i < points.size(); ++i)
  {
    const PatternPoint& p = points[i];
    Require(p.category >= 0 && p.category < PatternMaxCategories &&
        (categories == 0 || p.category < categories),
      "point " + Str(i) + " has category " + Str(p.category));
    Require(std::isfinite(p.x) && std::isfinite(p.y) && domain.Contains(p.x, p.y),
      "point " + Str(i) + " (" + Str(p.x) + ", " + Str(p.y) + ") is outside the domain");
    largest = std::max(largest, p.category);
  }
  return categories > 0 ? categories : largest + 1;
}

Buckets MakeBuckets(const std::vector<PatternPoint>& points, const PatternDomain& domain, double r)
{
  Buckets buckets(domain.Bounds(), r, std::max<std::size_t>(1024, 2 * points.size()));
  for (std::size_t i = 0; i < points.size(); ++i)
  {
    buckets.Insert(buckets.Of(points[i].x, points[i].y), static_cast<std::uint32_t>(i));
  }
  return buckets;
}

// Gauss-Legendre nodes and weights on [-1, 1], 4 points.
constexpr double GaussNodes[4] = { -0.8611363115940526,
  -0.3399810435848563,
  0.3399810435848563,
  0.8611363115940526 };
constexpr double GaussWeights[4] = { 0.3478548451374538,
  0.6521451548625461,
  0.6521451548625461,
  0.3478548451374538 };

} // namespace

// =============================================================================================
// PatternDomain

PatternDomain PatternDomain::Rectangle(double xMin, double yMin, double xMax, double yMax)
{
  Require(std::isfinite(xMin) && std::isfinite(xMax) && xMin < xMax,
    "window x range [" + Str(xMin) + ", " + Str(xMax) + ") is empty");
  Require(std::isfinite(yMin) && std::isfinite(yMax) && yMin < yMax,
    "window y range [" + Str(yMin) + ", " + Str(yMax) + ") is empty");
  PatternDomain d;
  d.Box[0] = xMin;
  d.Box[1] = yMin;
  d.Box[2] = xMax;
  d.Box[3] = yMax;
  d.AreaValue = (xMax - xMin) * (yMax - yMin);
  return d;
}

PatternDomain PatternDomain::Cells(int nx,
  int ny,
  double dx,
  double dy,
  double x0,
  double y0,
  std::vector<std::uint8_t> allowed)
{
  Require(nx >= 1 && ny >= 1, "mask size " + Str(nx) + " x " + Str(ny) + " is empty");
  Require(std::isfinite(dx) && dx > 0.0, "mask spacing dx = " + Str(dx) + " must be > 0");
  Require(std::isfinite(dy) && dy > 0.0, "mask spacing dy = " + Str(dy) + " must be > 0");
  Require(std::isfinite(x0) && std::isfinite(y0), "mask origin is not finite");
  Require(allowed.size() == static_cast<std::size_t>(nx) * ny,
    "mask has " + Str(allowed.size()) +
      " cells, expected nx * ny = " + Str(static_cast<std::size_t>(nx) * ny));
  PatternDomain d;
  d.Nx = nx;
  d.Ny = ny;
  d.Dx = dx;
  d.Dy = dy;
  d.Box[0] = x0;
  d.Box[1] = y0;
  d.Box[2] = x0 + nx * dx;
  d.Box[3] = y0 + ny * dy;
  for (std::size_t c = 0; c < allowed.size(); ++c)
  {
    if (allowed[c])
    {
      d.CellList.push_back(static_cast<std::uint32_t>(c));
    }
  }
  Require(!d.CellList.empty(), "mask has no allowed cell (empty domain)");
  d.AreaValue = static_cast<double>(d.CellList.size()) * dx * dy;
  d.Allowed = std::move(allowed);
  return d;
}

PatternDomain PatternDomain::CellsWithLabel(int nx,
  int ny,
  double dx,
  double dy,
  double x0,
  double y0,
  const int* labels,
  int label)
{
  Require(nx >= 1 && ny >= 1, "mask size " + Str(nx) + " x " + Str(ny) + " is empty");
  Require(labels != nullptr, "labels are null");
  std::vector<std::uint8_t> allowed(static_cast<std::size_t>(nx) * ny);
  for (std::size_t c = 0; c < allowed.size(); ++c)
  {
    allowed[c] = labels[c] == label ? 1 : 0;
  }
  return Cells(nx, ny, dx, dy, x0, y0, std::move(allowed));
}

bool PatternDomain::Contains(double x, double y) const
{
  if (!(x >= this->Box[0] && x < this->Box[2] && y >= this->Box[1] && y < this->Box[3]))
  {
    return false;
  }
  if (this->Allowed.empty())
  {
    return true;
  }
  const int i = std::min(static_cast<int>((x - this->Box[0]) / this->Dx), this->Nx - 1);
  const int j = std::min(static_cast<int>((y - this->Box[1]) / this->Dy), this->Ny - 1);
  return this->Allowed[static_cast<std::size_t>(j) * this->Nx + i] != 0;
}

// =============================================================================================
// PatternSetCovariance

PatternSetCovariance::PatternSetCovariance(const PatternDomain& domain, double maxLag)
  : Domain(domain)
  , MaxLag(maxLag)
{
  Require(std::isfinite(maxLag) && maxLag >= 0.0, "maxLag = " + Str(maxLag) + " must be >= 0");
  if (domain.IsRectangle())
  {
    return;
  }
  const int nx = domain.GridNx();
  const int ny = domain.GridNy();
  this->Px = std::min(nx, static_cast<int>(std::ceil(maxLag / domain.GridDx())) + 1);
  this->Py = std::min(ny, static_cast<int>(std::ceil(maxLag / domain.GridDy())) + 1);
  const int w = 2 * this->Px + 1;
  this->Table.assign(static_cast<std::size_t>(w) * (2 * this->Py + 1), 0.0);
  const auto& allowed = domain.AllowedCells();
  for (std::uint32_t cell : domain.AllowedCellList())
  {
    const int i = static_cast<int>(cell % nx);
    const int j = static_cast<int>(cell / nx);
    for (int q = std::max(-this->Py, -j); q <= std::min(this->Py, ny - 1 - j); ++q)
    {
      const std::uint8_t* row = allowed.data() + static_cast<std::size_t>(j + q) * nx;
      double* out = this->Table.data() + static_cast<std::size_t>(q + this->Py) * w + this->Px;
      for (int p = std::max(-this->Px, -i); p <= std::min(this->Px, nx - 1 - i); ++p)
      {
        out[p] += row[i + p] ? 1.0 : 0.0;
      }
    }
  }
}

double PatternSetCovariance::operator()(double hx, double hy) const
{
  const double* b = this->Domain.Bounds();
  if (this->Domain.IsRectangle())
  {
    const double ox = (b[2] - b[0]) - std::abs(hx);
    const double oy = (b[3] - b[1]) - std::abs(hy);
    return ox > 0.0 && oy > 0.0 ? ox * oy : 0.0;
  }
  const double u = hx / this->Domain.GridDx();
  const double v = hy / this->Domain.GridDy();
  const double fu = std::floor(u);
  const double fv = std::floor(v);
  const int p = static_cast<int>(fu);
  const int q = static_cast<int>(fv);
  if (p < -this->Px || p + 1 > this->Px || q < -this->Py || q + 1 > this->Py)
  {
    return 0.0;
  }
  const int w = 2 * this->Px + 1;
  const double* c = this->Table.data() + static_cast<std::size_t>(q + this->Py) * w + p + this->Px;
  const double tu = u - fu;
  const double tv = v - fv;
  const double lower = c[0] * (1.0 - tu) + c[1] * tu;
  const double upper = c[w] * (1.0 - tu) + c[w + 1] * tu;
  return (lower * (1.0 - tv) + upper * tv) * this->Domain.GridDx() * this->Domain.GridDy();
}

double PatternSetCovariance::PairMeasure(double r1, double r2) const
{
  Require(r1 >= 0.0 && r2 >= r1 && r2 <= this->MaxLag * (1.0 + 1e-12),
    "pair measure range [" + Str(r1) + ", " + Str(r2) +
      ") outside [0, maxLag = " + Str(this->MaxLag) + "]");
  if (r2 == r1)
  {
    return 0.0;
  }
  const double* b = this->Domain.Bounds();
  const double cell = this->Domain.IsRectangle()
    ? std::min(b[2] - b[0], b[3] - b[1])
    : std::min(this->Domain.GridDx(), this->Domain.GridDy());
  const int pieces = std::max(1, static_cast<int>(std::ceil((r2 - r1) / (0.25 * cell))));
  // gamma(h) = gamma(-h): half a turn, doubled.
  const int angles = std::min(65536, std::max(4096, 64 * static_cast<int>(std::ceil(r2 / cell))));
  const double dTheta = Pi / angles;
  std::vector<double> cosines(angles);
  std::vector<double> sines(angles);
  for (int m = 0; m < angles; ++m)
  {
    cosines[m] = std::cos((m + 0.5) * dTheta);
    sines[m] = std::sin((m + 0.5) * dTheta);
  }
  const double h = (r2 - r1) / pieces;
  double total = 0.0;
  for (int s = 0; s < pieces; ++s)
  {
    const double centre = r1 + (s + 0.5) * h;
    for (int g = 0; g < 4; ++g)
    {
      const double r = centre + 0.5 * h * GaussNodes[g];
      double ring = 0.0;
      for (int m = 0; m < angles; ++m)
      {
        ring += (*this)(r * cosines[m], r * sines[m]);
      }
      total += h * GaussWeights[g] * r * ring * dTheta;
    }
  }
  return total;
}

// =============================================================================================
// Pair correlation

namespace
{

/// A hard core is learned only when independent uniform points would have had at least this
/// many pairs closer than it (the chance of none is then e^-3, 5 %).
constexpr double HardCoreEvidence = 3.0;

/// The smallest a-b distances (capped at rMax) of a pattern, index a * C + b.
std::vector<double> SmallestDistances(const std::vector<PatternPoint>& points,
  const Buckets& buckets,
  int categories,
  double rMax)
{
  std::vector<double> smallest2(static_cast<std::size_t>(categories) * categories, rMax * rMax);
  for (std::size_t i = 0; i < points.size(); ++i)
  {
    const PatternPoint& p = points[i];
    buckets.ForEachNear(p.x,
      p.y,
      [&](std::uint32_t j)
      {
        if (j != i)
        {
          const double dx = points[j].x - p.x;
          const double dy = points[j].y - p.y;
          double& s =
            smallest2[static_cast<std::size_t>(p.category) * categories + points[j].category];
          s = std::min(s, dx * dx + dy * dy);
        }
        return true;
      });
  }
  std::vector<double> smallest(smallest2.size());
  for (std::size_t k = 0; k < smallest.size(); ++k)
  {
    smallest[k] = std::sqrt(smallest2[k]);
  }
  return smallest;
}

} // namespace

PairCorrelation EstimatePairCorrelation(const std::vector<PatternPoint>& points,
  const PatternDomain& domain,
  const PairCorrelationParameters& parameters)
{
  CheckRanges(parameters.rMin, parameters.rMax, parameters.bins);
  const int categories = CheckPoints(points, domain, parameters.categories);
  PairCorrelation out;
  out.categories = categories;
  out.bins = parameters.bins;
  out.rMin = parameters.rMin;
  out.rMax = parameters.rMax;
  out.area = domain.Area();
  out.counts.assign(static_cast<std::size_t>(categories), 0);
  for (const PatternPoint& p : points)
  {
    ++out.counts[p.category];
  }
  const std::size_t size = static_cast<std::size_t>(categories) * categories * parameters.bins;
  out.pairs.assign(size, 0);
  std::vector<double> weighted(size, 0.0);
  const Binning binning(parameters.rMin, parameters.rMax, parameters.bins);
  const PatternSetCovariance covariance(domain, parameters.rMax);
  const Buckets buckets = MakeBuckets(points, domain, parameters.rMax);
  for (std::size_t i = 0; i < points.size(); ++i)
  {
    const PatternPoint& a = points[i];
    buckets.ForEachNear(a.x,
      a.y,
      [&](std::uint32_t j)
      {
        const double hx = points[j].x - a.x;
        const double hy = points[j].y - a.y;
        const double d2 = hx * hx + hy * hy;
        if (j != i && binning.InRange(d2))
        {
          const double gamma = covariance(hx, hy);
          const std::size_t slot = out.Index(a.category, points[j].category, binning.Bin(d2));
          ++out.pairs[slot];
          weighted[slot] += gamma > 0.0 ? 1.0 / gamma : 0.0;
        }
        return true;
      });
  }
  // g_AB and g_BA sum the same pairs in two orders: make them equal to the last bit.
  for (int a = 0; a < categories; ++a)
  {
    for (int b = a + 1; b < categories; ++b)
    {
      for (int k = 0; k < parameters.bins; ++k)
      {
        const double mean = 0.5 * (weighted[out.Index(a, b, k)] + weighted[out.Index(b, a, k)]);
        weighted[out.Index(a, b, k)] = weighted[out.Index(b, a, k)] = mean;
      }
    }
  }
  out.g.assign(size, 1.0);
  const double area = domain.Area();
  for (int a = 0; a < categories; ++a)
  {
    for (int b = 0; b < categories; ++b)
    {
      const double na = static_cast<double>(out.counts[a]);
      const double nb = static_cast<double>(out.counts[b]) - (a == b ? 1.0 : 0.0);
      if (na <= 0.0 || nb <= 0.0)
      {
        continue;
      }
      const double lambda2 = na * nb / (area * area);
      for (int k = 0; k < parameters.bins; ++k)
      {
        const double r0 = binning.Edge(k);
        const double r1 = binning.Edge(k + 1);
        const double annulus = Pi * (r1 * r1 - r0 * r0);
        out.g[out.Index(a, b, k)] = weighted[out.Index(a, b, k)] / (lambda2 * annulus);
      }
    }
  }
  return out;
}

RadialDistributionModel LearnRadialDistribution(const std::vector<PatternPoint>& exemplar,
  const PatternDomain& domain,
  const PairCorrelationParameters& parameters,
  bool learnHardCore)
{
  const PairCorrelation pcf = EstimatePairCorrelation(exemplar, domain, parameters);
  RadialDistributionModel model;
  model.categories = pcf.categories;
  model.bins = pcf.bins;
  model.rMin = pcf.rMin;
  model.rMax = pcf.rMax;
  model.g = pcf.g;
  for (std::int64_t n : pcf.counts)
  {
    model.density.push_back(static_cast<double>(n) / domain.Area());
  }
  model.hardCore.assign(static_cast<std::size_t>(pcf.categories) * pcf.categories, 0.0);
  if (learnHardCore)
  {
    const Buckets buckets = MakeBuckets(exemplar, domain, parameters.rMax);
    const std::vector<double> smallest =
      SmallestDistances(exemplar, buckets, pcf.categories, parameters.rMax);
    const PatternSetCovariance covariance(domain, parameters.rMax);
    const double area2 = domain.Area() * domain.Area();
    for (int a = 0; a < pcf.categories; ++a)
    {
      for (int b = a; b < pcf.categories; ++b)
      {
        const double h = smallest[static_cast<std::size_t>(a) * pcf.categories + b];
        const double na = static_cast<double>(pcf.counts[a]);
        const double nb = static_cast<double>(pcf.counts[b]);
        const double pairs = a == b ? 0.5 * na * (na - 1.0) : na * nb;
        const double expected = pairs * covariance.PairMeasure(0.0, h) / area2;
        const double kept = expected >= HardCoreEvidence ? h : 0.0;
        model.hardCore[static_cast<std::size_t>(a) * pcf.categories + b] = kept;
        model.hardCore[static_cast<std::size_t>(b) * pcf.categories + a] = kept;
      }
    }
  }
  return model;
}

// =============================================================================================
// Synthesis

namespace
{

/// Equal to 1e-9 relative (symmetry of a model written by hand).
bool Close(double a, double b)
{
  return std::abs(a - b) <= 1e-9 * std::max(std::abs(a), std::abs(b));
}

void CheckModel(const RadialDistributionModel& m)
{
  Require(m.categories >= 1 && m.categories <= PatternMaxCategories,
    "model categories = " + Str(m.categories) + " must be in 1.." + Str(PatternMaxCategories));
  CheckRanges(m.rMin, m.rMax, m.bins);
  const std::size_t c = static_cast<std::size_t>(m.categories);
  Require(m.density.size() == c,
    "model has " + Str(m.density.size()) + " densities for " + Str(c) + " categories");
  Require(m.g.size() == c * c * m.bins,
    "model has " + Str(m.g.size()) + " g values, expected " + Str(c * c * m.bins));
  Require(m.hardCore.size() == c * c,
    "model has " + Str(m.hardCore.size()) + " hard cores, expected " + Str(c * c));
  for (std::size_t a = 0; a < c; ++a)
  {
    Require(std::isfinite(m.density[a]) && m.density[a] >= 0.0,
      "density of category " + Str(a) + " = " + Str(m.density[a]) + " must be >= 0");
  }
  for (int a = 0; a < m.categories; ++a)
  {
    for (int b = 0; b < m.categories; ++b)
    {
      const double h = m.HardCore(a, b);
      Require(std::isfinite(h) && h >= 0.0 && Close(h, m.HardCore(b, a)),
        "hard core " + Str(a) + "-" + Str(b) + " = " + Str(h) + " must be >= 0 and symmetric");
      for (int k = 0; k < m.bins; ++k)
      {
        const double g = m.G(a, b, k);
        Require(std::isfinite(g) && g >= 0.0 && Close(g, m.G(b, a, k)),
          "g " + Str(a) + "-" + Str(b) + " bin " + Str(k) + " = " + Str(g) +
            " must be >= 0 and symmetric");
      }
    }
  }
}

void CheckSynthesisParameters(const SynthesisParameters& p)
{
  Require(p.iterations >= 0, "iterations = " + Str(p.iterations) + " must be >= 0");
  Require(p.moveProbability >= 0.0 && p.moveProbability < 1.0,
    "moveProbability = " + Str(p.moveProbability) + " must be in [0, 1)");
  Require(std::isfinite(p.moveRadius) && p.moveRadius >= 0.0,
    "moveRadius = " + Str(p.moveRadius) + " must be >= 0");
  Require(std::isfinite(p.pairWeight) && p.pairWeight >= 0.0,
    "pairWeight = " + Str(p.pairWeight) + " must be >= 0");
  Require(std::isfinite(p.densityWeight) && p.densityWeight >= 0.0,
    "densityWeight = " + Str(p.densityWeight) + " must be >= 0");
}

/// The state of a Metropolis-Hastings run: points, buckets, pair counts and the energy terms.
class Synthesizer
{
public:
  Synthesizer(const RadialDistributionModel& model,
    const PatternDomain& domain,
    const SynthesisParameters& parameters)
    : Model(model)
    , Domain(domain)
    , Parameters(parameters)
    , Bins(model.rMin, model.rMax, model.bins)
    , C(model.categories)
    , K(model.bins)
    , Grid(domain.Bounds(), model.rMax, BucketLimit(model, domain))
    , Rng(parameters.seed)
  {
    this->SetUpCategories();
    this->SetUpTargets();
  }

  PatternSynthesis Run()
  {
    std::int64_t iterations = this->Parameters.iterations;
    if (iterations == 0)
    {
      iterations = std::max<std::int64_t>(1000, static_cast<std::int64_t>(200.0 * this->Expected));
    }
    const double pm = this->Parameters.moveProbability;
    for (std::int64_t it = 0; it<iterations&& this->TotalDensity> 0.0; ++it)
    {
      const double u = Uniform(this->Rng);
      if (u < pm)
      {
        this->ProposeMove();
      }
      else if (u < pm + 0.5 * (1.0 - pm))
      {
        this->ProposeBirth();
      }
      else
      {
        this->ProposeDeath();
      }
    }
    PatternSynthesis out;
    out.statistics = this->Stats;
    out.statistics.iterations = iterations;
    out.statistics.energy = this->Energy();
    out.points.resize(this->Xs.size());
    for (std::size_t i = 0; i < this->Xs.size(); ++i)
    {
      out.points[i] = PatternPoint{ this->Xs[i], this->Ys[i], this->Cat[i] };
    }
    return out;
  }

private:
  static std::size_t BucketLimit(const RadialDistributionModel& model, const PatternDomain& domain)
  {
    double total = 0.0;
    for (double d : model.density)
    {
      total += d;
    }
    return std::max<std::size_t>(1024, static_cast<std::size_t>(2.0 * total * domain.Area()));
  }

  void SetUpCategories()
  {
    const std::size_t cc = static_cast<std::size_t>(this->C) * this->C;
    this->PairSlot.resize(cc);
    this->HardCore2.resize(cc);
    int slot = 0;
    for (int a = 0; a < this->C; ++a)
    {
      for (int b = a; b < this->C; ++b, ++slot)
      {
        this->PairSlot[a * this->C + b] = this->PairSlot[b * this->C + a] = slot;
      }
      for (int b = 0; b < this->C; ++b)
      {
        const double h = this->Parameters.useHardCore ? this->Model.HardCore(a, b) : 0.0;
        this->HardCore2[a * this->C + b] = h * h;
      }
    }
    this->Mean.resize(this->C);
    this->Counts.assign(this->C, 0);
    for (int c = 0; c < this->C; ++c)
    {
      this->TotalDensity += this->Model.density[c];
      this->Mean[c] = this->Model.density[c] * this->Domain.Area();
    }
    this->Expected = this->TotalDensity * this->Domain.Area();
    this->MoveRadius =
      this->Parameters.moveRadius > 0.0 ? this->Parameters.moveRadius : 0.5 * this->Model.rMax;
  }

  void SetUpTargets()
  {
    const PatternSetCovariance covariance(this->Domain, this->Model.rMax);
    std::vector<double> gamma(this->K);
    for (int k = 0; k < this->K; ++k)
    {
      gamma[k] = covariance.PairMeasure(this->Bins.Edge(k), this->Bins.Edge(k + 1));
    }
    const std::size_t slots = static_cast<std::size_t>(this->C) * (this->C + 1) / 2 * this->K;
    this->Target.assign(slots, 0.0);
    this->InverseTwoVariance.assign(slots, 0.0);
    this->Pairs.assign(slots, 0);
    this->Delta.assign(slots, 0);
    this->Marked.assign(slots, 0);
    for (int a = 0; a < this->C; ++a)
    {
      for (int b = a; b < this->C; ++b)
      {
        const double la = this->Model.density[a];
        const double lb = this->Model.density[b];
        for (int k = 0; k < this->K; ++k)
        {
          const std::size_t s = this->Slot(a, b, k);
          this->Target[s] = la * lb * this->Model.G(a, b, k) * gamma[k] * (a == b ? 0.5 : 1.0);
          this->InverseTwoVariance[s] = 0.5 / std::max(this->Target[s], 1.0);
        }
      }
    }
  }

  std::size_t Slot(int a, int b, int k) const
  {
    return static_cast<std::size_t>(this->PairSlot[a * this->C + b]) * this->K + k;
  }

  /// Adds sign to the scratch counts of the pairs (x, y, c)-neighbour, skipping point `skip`.
  /// Returns false when sign > 0 and a hard core is broken.
  bool Collect(double x, double y, int c, std::uint32_t skip, int sign)
  {
    bool ok = true;
    this->Grid.ForEachNear(x,
      y,
      [&](std::uint32_t j)
      {
        ++this->Stats.neighboursVisited;
        if (j == skip)
        {
          return true;
        }
        const double dx = this->Xs[j] - x;
        const double dy = this->Ys[j] - y;
        const double d2 = dx * dx + dy * dy;
        const int cj = this->Cat[j];
        if (sign > 0 && d2 < this->HardCore2[c * this->C + cj])
        {
          ok = false;
          return false;
        }
        if (this->Bins.InRange(d2))
        {
          const std::size_t s = this->Slot(c, cj, this->Bins.Bin(d2));
          if (!this->Marked[s])
          {
            this->Marked[s] = 1;
            this->Touched.push_back(s);
          }
          this->Delta[s] += sign;
        }
        return true;
      });
    return ok;
  }

  /// Energy change of the scratch counts (pair term).
  double PairEnergyChange() const
  {
    double de = 0.0;
    for (std::size_t s : this->Touched)
    {
      const double d = this->Delta[s];
      const double n = static_cast<double>(this->Pairs[s]);
      de += d * (2.0 * (n - this->Target[s]) + d) * this->InverseTwoVariance[s];
    }
    return this->Parameters.pairWeight * de;
  }

  /// Energy change of one more (sign = 1) or one fewer (sign = -1) point of category c.
  double DensityEnergyChange(int c, int sign) const
  {
    const double d = static_cast<double>(this->Counts[c]) - this->Mean[c];
    return this->Parameters.densityWeight * (2.0 * sign * d + 1.0) / (2.0 * this->Mean[c]);
  }

  /// Applies (accept) or drops the scratch counts.
  void Finish(bool accept)
  {
    for (std::size_t s : this->Touched)
    {
      if (accept)
      {
        this->Pairs[s] += this->Delta[s];
      }
      this->Delta[s] = 0;
      this->Marked[s] = 0;
    }
    this->Touched.clear();
  }

  bool Accept(double logRatio) { return std::log(UniformOpenZero(this->Rng)) <= logRatio; }

  int DrawCategory()
  {
    const double u = Uniform(this->Rng) * this->TotalDensity;
    double sum = 0.0;
    int last = 0;
    for (int c = 0; c < this->C; ++c)
    {
      if (this->Model.density[c] > 0.0)
      {
        last = c;
        sum += this->Model.density[c];
        if (u < sum)
        {
          return c;
        }
      }
    }
    return last;
  }

  void DrawLocation(double& x, double& y)
  {
    const double* b = this->Domain.Bounds();
    if (this->Domain.IsRectangle())
    {
      x = b[0] + Uniform(this->Rng) * (b[2] - b[0]);
      y = b[1] + Uniform(this->Rng) * (b[3] - b[1]);
      return;
    }
    const auto& cells = this->Domain.AllowedCellList();
    const std::uint32_t cell = cells[UniformIndex(this->Rng, cells.size())];
    const int nx = this->Domain.GridNx();
    x = b[0] + (static_cast<int>(cell % nx) + Uniform(this->Rng)) * this->Domain.GridDx();
    y = b[1] + (static_cast<int>(cell / nx) + Uniform(this->Rng)) * this->Domain.GridDy();
  }

  void ProposeBirth()
  {
    ++this->Stats.birthsProposed;
    const int c = this->DrawCategory();
    double x = 0.0;
    double y = 0.0;
    this->DrawLocation(x, y);
    const auto none = static_cast<std::uint32_t>(this->Xs.size());
    const bool inside = this->Domain.Contains(x, y);
    const bool allowed = inside && this->Collect(x, y, c, none, +1);
    const double q = this->Model.density[c] / this->TotalDensity;
    const double logRatio = allowed
      ? std::log(this->Mean[c] / (q * static_cast<double>(this->Xs.size() + 1))) -
        this->PairEnergyChange() - this->DensityEnergyChange(c, +1)
      : 0.0;
    const bool accept = this->Accept(logRatio) && allowed;
    this->Finish(accept);
    if (accept)
    {
      ++this->Stats.birthsAccepted;
      this->Xs.push_back(x);
      this->Ys.push_back(y);
      this->Cat.push_back(c);
      this->Bucket.push_back(this->Grid.Of(x, y));
      this->Grid.Insert(this->Bucket.back(), none);
      ++this->Counts[c];
    }
  }

  void ProposeDeath()
  {
    ++this->Stats.deathsProposed;
    if (this->Xs.empty())
    {
      return;
    }
    const auto i = static_cast<std::uint32_t>(UniformIndex(this->Rng, this->Xs.size()));
    const int c = this->Cat[i];
    this->Collect(this->Xs[i], this->Ys[i], c, i, -1);
    const double q = this->Model.density[c] / this->TotalDensity;
    const double logRatio = std::log(q * static_cast<double>(this->Xs.size()) / this->Mean[c]) -
      this->PairEnergyChange() - this->DensityEnergyChange(c, -1);
    const bool accept = this->Accept(logRatio);
    this->Finish(accept);
    if (accept)
    {
      ++this->Stats.deathsAccepted;
      --this->Counts[c];
      this->RemovePoint(i);
    }
  }

  void ProposeMove()
  {
    ++this->Stats.movesProposed;
    if (this->Xs.empty())
    {
      return;
    }
    const auto i = static_cast<std::uint32_t>(UniformIndex(this->Rng, this->Xs.size()));
    const double s = this->MoveRadius;
    const double x = this->Xs[i] + (2.0 * Uniform(this->Rng) - 1.0) * s;
    const double y = this->Ys[i] + (2.0 * Uniform(this->Rng) - 1.0) * s;
    const int c = this->Cat[i];
    bool allowed = this->Domain.Contains(x, y);
    if (allowed)
    {
      this->Collect(this->Xs[i], this->Ys[i], c, i, -1);
      allowed = this->Collect(x, y, c, i, +1);
    }
    const double logRatio = allowed ? -this->PairEnergyChange() : 0.0;
    const bool accept = this->Accept(logRatio) && allowed;
    this->Finish(accept);
    if (accept)
    {
      ++this->Stats.movesAccepted;
      const std::size_t bucket = this->Grid.Of(x, y);
      if (bucket != this->Bucket[i])
      {
        this->Grid.Remove(this->Bucket[i], i);
        this->Grid.Insert(bucket, i);
        this->Bucket[i] = bucket;
      }
      this->Xs[i] = x;
      this->Ys[i] = y;
    }
  }

  /// Removes point i: the last point takes its index.
  void RemovePoint(std::uint32_t i)
  {
    this->Grid.Remove(this->Bucket[i], i);
    const auto last = static_cast<std::uint32_t>(this->Xs.size() - 1);
    if (i != last)
    {
      this->Grid.Rename(this->Bucket[last], last, i);
      this->Xs[i] = this->Xs[last];
      this->Ys[i] = this->Ys[last];
      this->Cat[i] = this->Cat[last];
      this->Bucket[i] = this->Bucket[last];
    }
    this->Xs.pop_back();
    this->Ys.pop_back();
    this->Cat.pop_back();
    this->Bucket.pop_back();
  }

  /// E(X) from the integer counts (see SynthesizePattern).
  double Energy() const
  {
    double pairs = 0.0;
    for (std::size_t s = 0; s < this->Pairs.size(); ++s)
    {
      const double d = static_cast<double>(this->Pairs[s]) - this->Target[s];
      pairs += d * d * this->InverseTwoVariance[s];
    }
    double counts = 0.0;
    for (int c = 0; c < this->C; ++c)
    {
      if (this->Mean[c] > 0.0)
      {
        const double d = static_cast<double>(this->Counts[c]) - this->Mean[c];
        counts += d * d / (2.0 * this->Mean[c]);
      }
    }
    return this->Parameters.pairWeight * pairs + this->Parameters.densityWeight * counts;
  }

  const RadialDistributionModel& Model;
  const PatternDomain& Domain;
  const SynthesisParameters& Parameters;
  const Binning Bins;
  const int C;
  const int K;
  Buckets Grid;
  std::mt19937_64 Rng;
  SynthesisStatistics Stats;

  std::vector<int> PairSlot;     ///< unordered category pair of (a, b), index a * C + b
  std::vector<double> HardCore2; ///< squared hard cores, index a * C + b
  std::vector<double> Mean;      ///< mu_c = lambda_c |D|
  std::vector<std::int64_t> Counts;
  double TotalDensity = 0.0;
  double Expected = 0.0;
  double MoveRadius = 0.0;

  std::vector<double> Target;             ///< T, per unordered pair slot and bin
  std::vector<double> InverseTwoVariance; ///< 1 / (2 max(T, 1))
  std::vector<std::int64_t> Pairs;        ///< N
  std::vector<std::int32_t> Delta;        ///< scratch change of N
  std::vector<std::uint8_t> Marked;
  std::vector<std::size_t> Touched;

  std::vector<double> Xs, Ys;
  std::vector<int> Cat;
  std::vector<std::size_t> Bucket;
};

} // namespace

PatternSynthesis SynthesizePattern(const RadialDistributionModel& model,
  const PatternDomain& domain,
  const SynthesisParameters& parameters)
{
  CheckModel(model);
  CheckSynthesisParameters(parameters);
  Synthesizer synthesizer(model, domain, parameters);
  return synthesizer.Run();
}

std::uint64_t PatternZoneSeed(std::uint64_t seed, int zone)
{
  std::uint64_t z =
    seed + static_cast<std::uint64_t>(static_cast<std::int64_t>(zone) + 1) * 0x9E3779B97F4A7C15ull;
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

ZonePatterns SynthesizeZones(int nx,
  int ny,
  double dx,
  double dy,
  double x0,
  double y0,
  const int* labels,
  const std::vector<ZoneModel>& models,
  const SynthesisParameters& parameters,
  const PatternParallelFor& parallelFor)
{
  Require(nx >= 1 && ny >= 1, "label grid size " + Str(nx) + " x " + Str(ny) + " is empty");
  Require(labels != nullptr, "labels are null");
  Require(std::isfinite(dx) && dx > 0.0, "grid spacing dx = " + Str(dx) + " must be > 0");
  Require(std::isfinite(dy) && dy > 0.0, "grid spacing dy = " + Str(dy) + " must be > 0");
  for (std::size_t m = 0; m < models.size(); ++m)
  {
    CheckModel(models[m].model);
    for (std::size_t other = 0; other < m; ++other)
    {
      Require(
        models[other].zone != models[m].zone, "zone " + Str(models[m].zone) + " has two models");
    }
  }
  CheckSynthesisParameters(parameters);
  const std::size_t cells = static_cast<std::size_t>(nx) * ny;
  std::vector<PatternSynthesis> runs(models.size());
  auto body = [&](std::size_t begin, std::size_t end)
  {
    for (std::size_t m = begin; m < end; ++m)
    {
      std::vector<std::uint8_t> allowed(cells);
      bool any = false;
      for (std::size_t c = 0; c < cells; ++c)
      {
        allowed[c] = labels[c] == models[m].zone ? 1 : 0;
        any = any || allowed[c];
      }
      if (!any)
      {
        continue;
      }
      const PatternDomain domain = PatternDomain::Cells(nx, ny, dx, dy, x0, y0, std::move(allowed));
      SynthesisParameters p = parameters;
      p.seed = PatternZoneSeed(parameters.seed, models[m].zone);
      runs[m] = SynthesizePattern(models[m].model, domain, p);
    }
  };
  if (parallelFor)
  {
    parallelFor(0, models.size(), body);
  }
  else
  {
    body(0, models.size());
  }
  ZonePatterns out;
  for (std::size_t m = 0; m < models.size(); ++m)
  {
    out.points.insert(out.points.end(), runs[m].points.begin(), runs[m].points.end());
    out.zones.insert(out.zones.end(), runs[m].points.size(), models[m].zone);
    out.statistics.push_back(runs[m].statistics);
  }
  return out;
}

} // namespace clustering
} // namespace terroir
