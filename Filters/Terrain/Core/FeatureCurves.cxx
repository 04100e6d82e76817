#include "FeatureCurves.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace terroir
{
namespace terrain
{
namespace
{
constexpr double kPi = 3.14159265358979323846;

void Position(const FeatureControlPoint& c, double p[3])
{
  p[0] = c.x;
  p[1] = c.y;
  p[2] = c.elevation;
}

double Lerp(double a, double b, double t)
{
  return a + (b - a) * t;
}

/// Linear interpolation of the non-positional values (x, y, elevation are set by the caller).
FeatureControlPoint LerpPoint(const FeatureControlPoint& a, const FeatureControlPoint& b, double t)
{
  FeatureControlPoint c;
  c.constrainElevation = t < 0.5 ? a.constrainElevation : b.constrainElevation;
  c.plateauWidth = Lerp(a.plateauWidth, b.plateauWidth, t);
  c.slopeLeftWidth = Lerp(a.slopeLeftWidth, b.slopeLeftWidth, t);
  c.slopeRightWidth = Lerp(a.slopeRightWidth, b.slopeRightWidth, t);
  c.slopeLeftAngle = Lerp(a.slopeLeftAngle, b.slopeLeftAngle, t);
  c.slopeRightAngle = Lerp(a.slopeRightAngle, b.slopeRightAngle, t);
  // An unbounded envelope at either end stays unbounded.
  c.envelopeLeft =
    a.envelopeLeft < 0.0 || b.envelopeLeft < 0.0 ? -1.0 : Lerp(a.envelopeLeft, b.envelopeLeft, t);
  c.envelopeRight = a.envelopeRight < 0.0 || b.envelopeRight < 0.0
    ? -1.0
    : Lerp(a.envelopeRight, b.envelopeRight, t);
  return c;
}

/// Mirror index at the grid's edges (index -1 is 1, index n is n - 2; 0 when n is 1).
inline int Mirror(int i, int n)
{
  if (i < 0)
  {
    return n > 1 ? -i : 0;
  }
  if (i >= n)
  {
    return n > 1 ? 2 * n - 2 - i : 0;
  }
  return i;
}

void Serial(int rows, const std::function<void(int, int)>& body)
{
  body(0, rows);
}

bool BadPoint(const FeatureControlPoint& p)
{
  const double v[] = { p.x,
    p.y,
    p.elevation,
    p.plateauWidth,
    p.slopeLeftWidth,
    p.slopeRightWidth,
    p.slopeLeftAngle,
    p.slopeRightAngle,
    p.envelopeLeft,
    p.envelopeRight };
  for (double x : v)
  {
    if (!std::isfinite(x))
    {
      return true;
    }
  }
  return false;
}
} // namespace

//------------------------------------------------------------------------------
void FeatureCurveTangent(const FeatureCurve& curve, int k, double m[3])
{
  const int n = static_cast<int>(curve.size());
  double a[3], b[3];
  if (n < 2)
  {
    m[0] = m[1] = m[2] = 0.0;
    return;
  }
  if (n == 2)
  {
    Position(curve[0], a);
    Position(curve[1], b);
    for (int c = 0; c < 3; ++c)
    {
      m[c] = b[c] - a[c];
    }
    return;
  }
  if (k > 0 && k < n - 1)
  {
    // Catmull-Rom.
    Position(curve[k - 1], a);
    Position(curve[k + 1], b);
    for (int c = 0; c < 3; ++c)
    {
      m[c] = 0.5 * (b[c] - a[c]);
    }
    return;
  }
  // End points: the tangent that makes the end segment a parabola (quadratic Hermite).
  double inner[3];
  if (k == 0)
  {
    FeatureCurveTangent(curve, 1, inner);
    Position(curve[0], a);
    Position(curve[1], b);
  }
  else
  {
    FeatureCurveTangent(curve, n - 2, inner);
    Position(curve[n - 2], a);
    Position(curve[n - 1], b);
  }
  for (int c = 0; c < 3; ++c)
  {
    m[c] = 2.0 * (b[c] - a[c]) - inner[c];
  }
}

//------------------------------------------------------------------------------
void FeatureCurveHermite(const FeatureCurve& curve, int s, double t, double p[3], double dp[3])
{
  double p0[3], p1[3], m0[3], m1[3];
  Position(curve[s], p0);
  Position(curve[s + 1], p1);
  FeatureCurveTangent(curve, s, m0);
  FeatureCurveTangent(curve, s + 1, m1);
  const double t2 = t * t, t3 = t2 * t;
  const double h00 = 2.0 * t3 - 3.0 * t2 + 1.0, h10 = t3 - 2.0 * t2 + t;
  const double h01 = -2.0 * t3 + 3.0 * t2, h11 = t3 - t2;
  const double d00 = 6.0 * t2 - 6.0 * t, d10 = 3.0 * t2 - 4.0 * t + 1.0;
  const double d01 = -6.0 * t2 + 6.0 * t, d11 = 3.0 * t2 - 2.0 * t;
  for (int c = 0; c < 3; ++c)
  {
    p[c] = h00 * p0[c] + h10 * m0[c] + h01 * p1[c] + h11 * m1[c];
    dp[c] = d00 * p0[c] + d10 * m0[c] + d01 * p1[c] + d11 * m1[c];
  }
}

//------------------------------------------------------------------------------
std::vector<FeatureControlPoint> SampleFeatureCurve(const FeatureCurve& curve, double step)
{
  std::vector<FeatureControlPoint> out;
  const int n = static_cast<int>(curve.size());
  if (n < 2 || !(step > 0.0))
  {
    return out;
  }
  for (int s = 0; s + 1 < n; ++s)
  {
    // Length of the segment from 16 chords.
    double length = 0.0, prev[3], p[3], dp[3];
    FeatureCurveHermite(curve, s, 0.0, prev, dp);
    for (int q = 1; q <= 16; ++q)
    {
      FeatureCurveHermite(curve, s, q / 16.0, p, dp);
      length += std::hypot(p[0] - prev[0], p[1] - prev[1]);
      std::copy(p, p + 3, prev);
    }
    const int k = std::max(1, static_cast<int>(std::ceil(1.25 * length / step)));
    for (int q = s == 0 ? 0 : 1; q <= k; ++q)
    {
      const double t = static_cast<double>(q) / k;
      FeatureCurveHermite(curve, s, t, p, dp);
      FeatureControlPoint c = LerpPoint(curve[s], curve[s + 1], t);
      c.x = p[0];
      c.y = p[1];
      c.elevation = p[2];
      out.push_back(c);
    }
  }
  return out;
}

//------------------------------------------------------------------------------
std::vector<FeatureControlPoint> SampleFeatureCurveFlat(const FeatureCurve& curve,
  double flatness,
  double maxStep)
{
  std::vector<FeatureControlPoint> out;
  const int n = static_cast<int>(curve.size());
  if (n < 2 || !(flatness > 0.0) || !(maxStep > 0.0))
  {
    return out;
  }
  auto emit = [&](int s, double t)
  {
    double p[3], dp[3];
    FeatureCurveHermite(curve, s, t, p, dp);
    FeatureControlPoint c = LerpPoint(curve[s], curve[s + 1], t);
    c.x = p[0];
    c.y = p[1];
    c.elevation = p[2];
    out.push_back(c);
  };
  // Halves [t0, t1] until the spline's midpoint is within `flatness` of the chord's and the
  // chord is at most maxStep, at least three times (an S bend has its midpoint on the chord).
  std::function<void(int, double, double, int)> split = [&](int s, double t0, double t1, int depth)
  {
    double a[3], b[3], m[3], d[3];
    FeatureCurveHermite(curve, s, t0, a, d);
    FeatureCurveHermite(curve, s, t1, b, d);
    const double tm = 0.5 * (t0 + t1);
    FeatureCurveHermite(curve, s, tm, m, d);
    const double dev = std::hypot(m[0] - 0.5 * (a[0] + b[0]), m[1] - 0.5 * (a[1] + b[1]));
    const double chord = std::hypot(b[0] - a[0], b[1] - a[1]);
    if (depth < 24 && (depth < 3 || dev > flatness || chord > maxStep))
    {
      split(s, t0, tm, depth + 1);
      split(s, tm, t1, depth + 1);
      return;
    }
    emit(s, t1);
  };
  emit(0, 0.0);
  for (int s = 0; s + 1 < n; ++s)
  {
    split(s, 0.0, 1.0, 0);
  }
  return out;
}

//------------------------------------------------------------------------------
bool RasterizeFeatureCurves(const std::vector<FeatureCurve>& curves,
  const FeatureGrid& grid,
  const FeatureSolverParameters& params,
  FeatureConstraints& out,
  std::string& error)
{
  if (grid.nx < 1 || grid.ny < 1 || !(grid.dx > 0.0) || !(grid.dy > 0.0))
  {
    error = "the grid needs at least one point and positive spacings";
    return false;
  }
  if (!(params.plateauWeight > 0.0 && params.plateauWeight <= 1.0) ||
    !(params.slopeWeight >= 0.0 && params.slopeWeight <= 1.0))
  {
    error = "the plateau weight must be in (0, 1] and the slope weight in [0, 1]";
    return false;
  }
  for (std::size_t c = 0; c < curves.size(); ++c)
  {
    const std::string which = "curve " + std::to_string(c);
    if (curves[c].size() < 2)
    {
      error = which + " has fewer than two control points";
      return false;
    }
    for (std::size_t k = 0; k < curves[c].size(); ++k)
    {
      const FeatureControlPoint& p = curves[c][k];
      const std::string at = which + ", point " + std::to_string(k);
      if (BadPoint(p))
      {
        error = at + ": a value is not finite";
        return false;
      }
      if (p.plateauWidth < 0.0 || p.slopeLeftWidth < 0.0 || p.slopeRightWidth < 0.0)
      {
        error = at + ": widths must not be negative";
        return false;
      }
      if (!(std::abs(p.slopeLeftAngle) < 90.0) || !(std::abs(p.slopeRightAngle) < 90.0))
      {
        error = at + ": slope angles must be within (-90, 90) degrees";
        return false;
      }
    }
  }
  const std::size_t n = static_cast<std::size_t>(grid.nx) * grid.ny;
  out.alpha.assign(n, 0.0f);
  out.beta.assign(n, 0.0f);
  out.gamma.assign(n, 0.0f);
  out.elevation.assign(n, 0.0f);
  out.gradient.assign(n, 0.0f);
  out.dirX.assign(n, 0.0f);
  out.dirY.assign(n, 0.0f);
  out.kind.assign(n, 0);
  std::vector<double> best(n, std::numeric_limits<double>::infinity());
  bool unbounded = false;
  const double cell = std::min(grid.dx, grid.dy);
  const double eps = 1e-6 * cell;
  for (const FeatureCurve& curve : curves)
  {
    // A polyline within a twentieth of a cell of the spline, without zero-length pieces.
    std::vector<FeatureControlPoint> s;
    for (const FeatureControlPoint& p : SampleFeatureCurveFlat(curve, 0.05 * cell, 64.0 * cell))
    {
      if (s.empty() || p.x != s.back().x || p.y != s.back().y)
      {
        s.push_back(p);
      }
    }
    if (s.size() == 1)
    {
      s.push_back(s.back()); // every control point at one place: a disc
    }
    for (const FeatureControlPoint& p : s)
    {
      unbounded = unbounded || p.envelopeLeft < 0.0 || p.envelopeRight < 0.0;
    }
    for (std::size_t q = 0; q + 1 < s.size(); ++q)
    {
      const FeatureControlPoint& A = s[q];
      const FeatureControlPoint& B = s[q + 1];
      auto reach = [](const FeatureControlPoint& p)
      {
        return 0.5 * p.plateauWidth +
          std::max(p.slopeLeftWidth + std::max(p.envelopeLeft, 0.0),
            p.slopeRightWidth + std::max(p.envelopeRight, 0.0));
      };
      const double R = std::max(reach(A), reach(B)) + 1e-9;
      const double ex = B.x - A.x, ey = B.y - A.y, len2 = ex * ex + ey * ey;
      const double len = std::sqrt(len2);
      const double tx = len > 0.0 ? ex / len : 1.0, ty = len > 0.0 ? ey / len : 0.0;
      // The cells whose nearest point of the polyline can be on this piece: a strip R wide on
      // each side, extended past a joint by R tan(turn / 2) (the wedge on the outer side of
      // the bend) and past the curve's ends by R (the round caps); two cells of margin.
      auto extension = [&](std::size_t other, bool atStart)
      {
        if (atStart ? q == 0 : q + 2 == s.size())
        {
          return R;
        }
        const FeatureControlPoint& o = s[other];
        const double ox = atStart ? A.x - o.x : o.x - B.x, oy = atStart ? A.y - o.y : o.y - B.y;
        const double ol = std::hypot(ox, oy);
        const double c = ol > 0.0 ? std::max(-1.0, std::min(1.0, (ox * tx + oy * ty) / ol)) : 1.0;
        const double turn = std::min(std::acos(c), 2.0);
        return std::min(R, R * std::tan(0.5 * turn)) + 2.0 * std::max(grid.dx, grid.dy);
      };
      const double e0 = extension(q == 0 ? 0 : q - 1, true);
      const double e1 = extension(q + 2 < s.size() ? q + 2 : q + 1, false);
      const double m = 2.0 * std::max(grid.dx, grid.dy);
      double cx[4], cy[4]; // corners in grid units
      const double along[4] = { -e0, len + e1, len + e1, -e0 };
      const double across[4] = { -R - m, -R - m, R + m, R + m };
      for (int k = 0; k < 4; ++k)
      {
        cx[k] = (A.x + along[k] * tx - across[k] * ty - grid.x0) / grid.dx;
        cy[k] = (A.y + along[k] * ty + across[k] * tx - grid.y0) / grid.dy;
      }
      const double ylo = std::min(std::min(cy[0], cy[1]), std::min(cy[2], cy[3]));
      const double yhi = std::max(std::max(cy[0], cy[1]), std::max(cy[2], cy[3]));
      const int j0 = std::max(0, static_cast<int>(std::floor(ylo)));
      const int j1 = std::min(grid.ny - 1, static_cast<int>(std::ceil(yhi)));
      for (int j = j0; j <= j1; ++j)
      {
        // The quad's x range on this row (convex: the edges that cross it), one cell wider.
        double xlo = std::numeric_limits<double>::infinity(), xhi = -xlo;
        for (int k = 0; k < 4; ++k)
        {
          const int l = (k + 1) % 4;
          const double ya = cy[k], yb = cy[l];
          if ((ya - j) * (yb - j) > 0.0)
          {
            continue;
          }
          if (ya == yb)
          {
            xlo = std::min(xlo, std::min(cx[k], cx[l]));
            xhi = std::max(xhi, std::max(cx[k], cx[l]));
            continue;
          }
          const double x = cx[k] + (j - ya) * (cx[l] - cx[k]) / (yb - ya);
          xlo = std::min(xlo, x);
          xhi = std::max(xhi, x);
        }
        if (!(xlo <= xhi))
        {
          continue;
        }
        const int i0 = std::max(0, static_cast<int>(std::floor(xlo)) - 1);
        const int i1 = std::min(grid.nx - 1, static_cast<int>(std::ceil(xhi)) + 1);
        for (int i = i0; i <= i1; ++i)
        {
          const double px = grid.x0 + i * grid.dx, py = grid.y0 + j * grid.dy;
          double u = len2 > 0.0 ? ((px - A.x) * ex + (py - A.y) * ey) / len2 : 0.0;
          u = std::min(1.0, std::max(0.0, u));
          const double qx = A.x + u * ex, qy = A.y + u * ey;
          const double vx = px - qx, vy = py - qy;
          // Within a millionth of a cell of an edge counts as on it (the spline's rounding).
          const double d = std::max(0.0, std::hypot(vx, vy) - eps);
          const bool left = ex * (py - A.y) - ey * (px - A.x) > 0.0;
          const FeatureControlPoint c = LerpPoint(A, B, u);
          const double half = 0.5 * c.plateauWidth;
          const double slopeWidth = left ? c.slopeLeftWidth : c.slopeRightWidth;
          const double envelope = left ? c.envelopeLeft : c.envelopeRight;
          const std::size_t k = static_cast<std::size_t>(j) * grid.nx + i;
          if (envelope >= 0.0 && d <= half + slopeWidth + envelope)
          {
            out.gamma[k] = 1.0f;
          }
          if (!(d <= half + slopeWidth) || !(d < best[k]))
          {
            continue;
          }
          best[k] = d;
          out.dirX[k] = out.dirY[k] = out.gradient[k] = out.elevation[k] = 0.0f;
          out.alpha[k] = out.beta[k] = 0.0f;
          out.kind[k] = 0;
          if (d <= half)
          {
            if (c.constrainElevation)
            {
              out.kind[k] = 1;
              out.alpha[k] = static_cast<float>(params.plateauWeight);
              out.elevation[k] = static_cast<float>(Lerp(A.elevation, B.elevation, u));
            }
            continue;
          }
          const double len = std::hypot(vx, vy);
          const double nx = vx / len, ny = vy / len;
          const double angle = left ? c.slopeLeftAngle : c.slopeRightAngle;
          const double t = std::tan(angle * kPi / 180.0);
          out.kind[k] = 2;
          out.beta[k] = static_cast<float>(params.slopeWeight);
          out.dirX[k] = static_cast<float>(nx);
          out.dirY[k] = static_cast<float>(ny);
          out.gradient[k] = static_cast<float>(
            -t * (std::abs(nx * nx * nx) * grid.dx + std::abs(ny * ny * ny) * grid.dy));
        }
      }
    }
  }
  if (unbounded || curves.empty())
  {
    std::fill(out.gamma.begin(), out.gamma.end(), curves.empty() ? 0.0f : 1.0f);
  }
  return true;
}

//------------------------------------------------------------------------------
std::vector<DiffusionLevel> BuildDiffusionLevels(const FeatureConstraints& c,
  int nx,
  int ny,
  const float* base,
  const FeatureSolverParameters& params)
{
  // The fine terms: identity weight, four gradient weights and the Laplace weight.
  struct Terms
  {
    int nx, ny;
    std::vector<double> a, g[4], w; // g: W, E, S, N
  };
  std::vector<Terms> terms(1);
  const std::size_t n = static_cast<std::size_t>(nx) * ny;
  Terms& t0 = terms[0];
  t0.nx = nx;
  t0.ny = ny;
  t0.a.assign(n, 0.0);
  t0.w.assign(n, 0.0);
  for (auto& g : t0.g)
  {
    g.assign(n, 0.0);
  }
  std::vector<DiffusionLevel> levels(1);
  DiffusionLevel& fine = levels[0];
  fine.nx = nx;
  fine.ny = ny;
  fine.b.assign(n, 0.0);
  fine.h.assign(n, 0.0);
  fine.r.assign(n, 0.0);
  for (std::size_t k = 0; k < n; ++k)
  {
    const double alpha = c.alpha[k], beta = c.beta[k], gamma = c.gamma[k];
    const double rest = std::max(0.0, 1.0 - alpha - beta);
    const double B = base ? static_cast<double>(base[k]) : 0.0;
    t0.a[k] = alpha + (1.0 - gamma) * rest;
    t0.w[k] = gamma * rest;
    const double dx = c.dirX[k], dy = c.dirY[k];
    t0.g[dx > 0.0 ? 0 : 1][k] = beta * dx * dx;
    t0.g[dy > 0.0 ? 2 : 3][k] = beta * dy * dy;
    fine.b[k] = alpha * c.elevation[k] + beta * c.gradient[k] + (1.0 - gamma) * rest * B;
    fine.h[k] = c.kind[k] == 1 ? c.elevation[k] : B;
  }
  // Coarser terms by full weighting.
  while (std::max(terms.back().nx, terms.back().ny) > std::max(2, params.coarsestSize))
  {
    const Terms& f = terms.back();
    Terms t;
    t.nx = CoarseSize(f.nx);
    t.ny = CoarseSize(f.ny);
    const std::size_t m = static_cast<std::size_t>(t.nx) * t.ny;
    auto restrict = [&](const std::vector<double>& src, std::vector<double>& dst)
    {
      dst.assign(m, 0.0);
      for (int J = 0; J < t.ny; ++J)
      {
        for (int I = 0; I < t.nx; ++I)
        {
          double s = 0.0;
          for (int dj = -1; dj <= 1; ++dj)
          {
            for (int di = -1; di <= 1; ++di)
            {
              const double wgt = (di == 0 ? 0.5 : 0.25) * (dj == 0 ? 0.5 : 0.25);
              const int i = Mirror(2 * I + di, f.nx), j = Mirror(2 * J + dj, f.ny);
              s += wgt * src[static_cast<std::size_t>(j) * f.nx + i];
            }
          }
          dst[static_cast<std::size_t>(J) * t.nx + I] = s;
        }
      }
    };
    restrict(f.a, t.a);
    restrict(f.w, t.w);
    for (int q = 0; q < 4; ++q)
    {
      restrict(f.g[q], t.g[q]);
    }
    terms.push_back(std::move(t));
  }
  levels.resize(terms.size());
  for (std::size_t l = 0; l < terms.size(); ++l)
  {
    const Terms& t = terms[l];
    DiffusionLevel& L = levels[l];
    L.nx = t.nx;
    L.ny = t.ny;
    const std::size_t m = L.Size();
    if (l > 0)
    {
      L.h.assign(m, 0.0);
      L.b.assign(m, 0.0);
      L.r.assign(m, 0.0);
    }
    L.coef.assign(6 * m, 0.0f);
    const double f = std::ldexp(1.0, static_cast<int>(l)), f2 = f * f;
    for (std::size_t k = 0; k < m; ++k)
    {
      double cw[4];
      double gsum = 0.0;
      for (int q = 0; q < 4; ++q)
      {
        cw[q] = t.g[q][k] / f + t.w[k] / (4.0 * f2);
        gsum += t.g[q][k];
      }
      double d = t.a[k] + gsum / f + t.w[k] / f2;
      // A dimension of one point: the neighbours across it are the cell itself.
      if (t.nx == 1)
      {
        d -= cw[0] + cw[1];
        cw[0] = cw[1] = 0.0;
      }
      if (t.ny == 1)
      {
        d -= cw[2] + cw[3];
        cw[2] = cw[3] = 0.0;
      }
      if (!(d > 0.0))
      {
        d = 1.0; // a cell with no equation (cannot happen for weights in range)
      }
      L.coef[k] = static_cast<float>(d);
      L.coef[m + k] = static_cast<float>(1.0 / d);
      for (int q = 0; q < 4; ++q)
      {
        L.coef[(2 + q) * m + k] = static_cast<float>(cw[q]);
      }
    }
  }
  return levels;
}

//------------------------------------------------------------------------------
void DiffusionSmoothRows(DiffusionLevel& l, int colour, int row0, int row1)
{
  const int nx = l.nx, ny = l.ny;
  const std::size_t m = l.Size();
  const float* d1 = l.coef.data() + m;
  const float* cW = l.coef.data() + 2 * m;
  const float* cE = l.coef.data() + 3 * m;
  const float* cS = l.coef.data() + 4 * m;
  const float* cN = l.coef.data() + 5 * m;
  double* h = l.h.data();
  const double* b = l.b.data();
  for (int j = row0; j < row1; ++j)
  {
    const std::size_t rs = static_cast<std::size_t>(Mirror(j - 1, ny)) * nx;
    const std::size_t rn = static_cast<std::size_t>(Mirror(j + 1, ny)) * nx;
    const std::size_t rc = static_cast<std::size_t>(j) * nx;
    for (int i = (colour + j) & 1; i < nx; i += 2)
    {
      const std::size_t k = rc + i;
      double s = b[k];
      s = s + cW[k] * h[rc + Mirror(i - 1, nx)];
      s = s + cE[k] * h[rc + Mirror(i + 1, nx)];
      s = s + cS[k] * h[rs + i];
      s = s + cN[k] * h[rn + i];
      h[k] = s * d1[k];
    }
  }
}

//------------------------------------------------------------------------------
double DiffusionResidualRows(DiffusionLevel& l, int row0, int row1)
{
  const int nx = l.nx, ny = l.ny;
  const std::size_t m = l.Size();
  const float* d = l.coef.data();
  const float* cW = l.coef.data() + 2 * m;
  const float* cE = l.coef.data() + 3 * m;
  const float* cS = l.coef.data() + 4 * m;
  const float* cN = l.coef.data() + 5 * m;
  const double* h = l.h.data();
  const double* b = l.b.data();
  double* r = l.r.data();
  double largest = 0.0;
  for (int j = row0; j < row1; ++j)
  {
    const std::size_t rs = static_cast<std::size_t>(Mirror(j - 1, ny)) * nx;
    const std::size_t rn = static_cast<std::size_t>(Mirror(j + 1, ny)) * nx;
    const std::size_t rc = static_cast<std::size_t>(j) * nx;
    for (int i = 0; i < nx; ++i)
    {
      const std::size_t k = rc + i;
      double t = d[k] * h[k];
      t = t - cW[k] * h[rc + Mirror(i - 1, nx)];
      t = t - cE[k] * h[rc + Mirror(i + 1, nx)];
      t = t - cS[k] * h[rs + i];
      t = t - cN[k] * h[rn + i];
      const double v = b[k] - t;
      r[k] = v;
      largest = std::max(largest, std::abs(v));
    }
  }
  return largest;
}

//------------------------------------------------------------------------------
void DiffusionRestrictRows(const DiffusionLevel& fine, DiffusionLevel& coarse, int row0, int row1)
{
  const int fx = fine.nx, fy = fine.ny;
  const double* r = fine.r.data();
  for (int J = row0; J < row1; ++J)
  {
    const std::size_t js = static_cast<std::size_t>(Mirror(2 * J - 1, fy)) * fx;
    const std::size_t jc = static_cast<std::size_t>(Mirror(2 * J, fy)) * fx;
    const std::size_t jn = static_cast<std::size_t>(Mirror(2 * J + 1, fy)) * fx;
    for (int I = 0; I < coarse.nx; ++I)
    {
      const std::size_t iw = Mirror(2 * I - 1, fx), ic = Mirror(2 * I, fx),
                        ie = Mirror(2 * I + 1, fx);
      double s1 = r[jc + iw] + r[jc + ie];
      s1 = s1 + r[js + ic];
      s1 = s1 + r[jn + ic];
      double s2 = r[js + iw] + r[js + ie];
      s2 = s2 + r[jn + iw];
      s2 = s2 + r[jn + ie];
      double v = r[jc + ic] * 0.25;
      v = v + s1 * 0.125;
      v = v + s2 * 0.0625;
      const std::size_t K = static_cast<std::size_t>(J) * coarse.nx + I;
      coarse.b[K] = v;
      coarse.h[K] = 0.0;
    }
  }
}

//------------------------------------------------------------------------------
void DiffusionProlongRows(const DiffusionLevel& coarse, DiffusionLevel& fine, int row0, int row1)
{
  const int cx = coarse.nx, cy = coarse.ny;
  const double* e = coarse.h.data();
  for (int j = row0; j < row1; ++j)
  {
    const int J0 = j / 2, J1 = (j & 1) ? std::min(J0 + 1, cy - 1) : J0;
    const std::size_t r0 = static_cast<std::size_t>(J0) * cx,
                      r1 = static_cast<std::size_t>(J1) * cx;
    for (int i = 0; i < fine.nx; ++i)
    {
      const int I0 = i / 2, I1 = (i & 1) ? std::min(I0 + 1, cx - 1) : I0;
      double v;
      if (!(i & 1) && !(j & 1))
      {
        v = e[r0 + I0];
      }
      else if (!(j & 1))
      {
        v = (e[r0 + I0] + e[r0 + I1]) * 0.5;
      }
      else if (!(i & 1))
      {
        v = (e[r0 + I0] + e[r1 + I0]) * 0.5;
      }
      else
      {
        const double a = e[r0 + I0] + e[r0 + I1];
        const double b = e[r1 + I0] + e[r1 + I1];
        v = (a + b) * 0.25;
      }
      const std::size_t k = static_cast<std::size_t>(j) * fine.nx + i;
      fine.h[k] = fine.h[k] + v;
    }
  }
}

//------------------------------------------------------------------------------
namespace
{
double Residual(DiffusionLevel& l, const RowParallel& par)
{
  std::vector<double> rowMax(static_cast<std::size_t>(l.ny), 0.0);
  par(l.ny,
    [&](int j0, int j1)
    {
      for (int j = j0; j < j1; ++j)
      {
        rowMax[j] = DiffusionResidualRows(l, j, j + 1);
      }
    });
  return *std::max_element(rowMax.begin(), rowMax.end());
}

void Sweeps(DiffusionLevel& l, int count, const RowParallel& par)
{
  for (int s = 0; s < count; ++s)
  {
    for (int colour = 0; colour < 2; ++colour)
    {
      par(l.ny, [&](int j0, int j1) { DiffusionSmoothRows(l, colour, j0, j1); });
    }
  }
}

void VCycle(std::vector<DiffusionLevel>& levels,
  std::size_t l,
  const FeatureSolverParameters& p,
  const RowParallel& par)
{
  DiffusionLevel& L = levels[l];
  if (l + 1 == levels.size())
  {
    Sweeps(L, p.coarsestSweeps, par);
    return;
  }
  Sweeps(L, p.preSmooth, par);
  Residual(L, par);
  DiffusionLevel& C = levels[l + 1];
  par(C.ny, [&](int j0, int j1) { DiffusionRestrictRows(L, C, j0, j1); });
  VCycle(levels, l + 1, p, par);
  par(L.ny, [&](int j0, int j1) { DiffusionProlongRows(C, L, j0, j1); });
  Sweeps(L, p.postSmooth, par);
}
} // namespace

//------------------------------------------------------------------------------
DiffusionReport SolveDiffusionMultigrid(std::vector<DiffusionLevel>& levels,
  const FeatureSolverParameters& params,
  const RowParallel& parallel)
{
  const RowParallel par = parallel ? parallel : RowParallel(Serial);
  DiffusionReport report;
  report.levels = static_cast<int>(levels.size());
  DiffusionLevel& fine = levels[0];
  report.initialResidual = Residual(fine, par);
  std::vector<double> previous(fine.h);
  std::vector<double> rowMax(static_cast<std::size_t>(fine.ny), 0.0);
  while (report.cycles < params.maxCycles)
  {
    VCycle(levels, 0, params, par);
    ++report.cycles;
    par(fine.ny,
      [&](int j0, int j1)
      {
        for (int j = j0; j < j1; ++j)
        {
          rowMax[j] = DiffusionChangeRows(fine, previous.data(), j, j + 1);
        }
      });
    const double change = *std::max_element(rowMax.begin(), rowMax.end());
    report.history.push_back(change);
    if (change <= params.tolerance)
    {
      report.converged = true;
      break;
    }
  }
  report.residual = Residual(fine, par);
  return report;
}

//------------------------------------------------------------------------------
double DiffusionChangeRows(const DiffusionLevel& l, double* previous, int row0, int row1)
{
  double largest = 0.0;
  const std::size_t k0 = static_cast<std::size_t>(row0) * l.nx;
  const std::size_t k1 = static_cast<std::size_t>(row1) * l.nx;
  for (std::size_t k = k0; k < k1; ++k)
  {
    largest = std::max(largest, std::abs(l.h[k] - previous[k]));
    previous[k] = l.h[k];
  }
  return largest;
}

//------------------------------------------------------------------------------
int SolveDiffusionJacobi(DiffusionLevel& fine, double change, int maxIterations)
{
  // In double, from the float stencil: a reference with other arithmetic than the solver's.
  const int nx = fine.nx, ny = fine.ny;
  const std::size_t m = fine.Size();
  const float* c = fine.coef.data();
  std::vector<double> h(fine.h), next(m);
  int it = 0;
  while (it < maxIterations)
  {
    double largest = 0.0;
    for (int j = 0; j < ny; ++j)
    {
      const std::size_t rs = static_cast<std::size_t>(Mirror(j - 1, ny)) * nx;
      const std::size_t rn = static_cast<std::size_t>(Mirror(j + 1, ny)) * nx;
      const std::size_t rc = static_cast<std::size_t>(j) * nx;
      for (int i = 0; i < nx; ++i)
      {
        const std::size_t k = rc + i;
        // Division by d rather than the solver's product by 1 / d.
        const double s = fine.b[k] + c[2 * m + k] * h[rc + Mirror(i - 1, nx)] +
          c[3 * m + k] * h[rc + Mirror(i + 1, nx)] + c[4 * m + k] * h[rs + i] +
          c[5 * m + k] * h[rn + i];
        next[k] = s / c[k];
        largest = std::max(largest, std::abs(next[k] - h[k]));
      }
    }
    h.swap(next);
    ++it;
    if (largest <= change)
    {
      break;
    }
  }
  fine.h.swap(h);
  return it;
}

//------------------------------------------------------------------------------
bool FeatureCurveTerrain(const std::vector<FeatureCurve>& curves,
  const FeatureGrid& grid,
  const float* base,
  const FeatureSolverParameters& params,
  std::vector<float>& heights,
  DiffusionReport& report,
  std::string& error,
  const RowParallel& parallel)
{
  if (!(params.tolerance > 0.0) || params.maxCycles < 1 || params.preSmooth < 0 ||
    params.postSmooth < 0 || params.coarsestSweeps < 1)
  {
    error = "the tolerance must be positive and the cycle and sweep counts at least 1";
    return false;
  }
  FeatureConstraints c;
  if (!RasterizeFeatureCurves(curves, grid, params, c, error))
  {
    return false;
  }
  std::vector<DiffusionLevel> levels = BuildDiffusionLevels(c, grid.nx, grid.ny, base, params);
  report = SolveDiffusionMultigrid(levels, params, parallel);
  heights.assign(levels[0].h.begin(), levels[0].h.end());
  return true;
}

} // namespace terrain
} // namespace terroir
