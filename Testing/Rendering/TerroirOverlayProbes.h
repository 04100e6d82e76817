// Numeric probes of an overlay (Testing/Rendering only, header only): the pixel under a known
// cell shows that cell's colour-table colour, lit as the view lights it. CompareWithBaseline
// runs them on every overlay test, map and relief.
//
// ExpectPixelsShowTheirCells(view, image) picks up to eight probe cells on a lattice over the
// terrain where the colour is locally uniform (the 5 x 5 cells around, 9 x 9 in relief where a
// pixel covers more cells along the line of sight, have the colour of the centre within 2
// levels, so the pixel cannot blend in another colour) and the ground locally plane (5 x 5
// normals within 0.01). For each, the expected pixel is worked out from the view's documented
// model: the cell's colour c from the colour table the view used (the preset over LastRange,
// over the base colour by its opacity; the base colour where a preset's mask is 0), the normal N
// by central differences (times the vertical exaggeration), and Blinn-Phong
//   pixel = 255 min(1, c (ka + kd max(0, N.L)) + ks max(0, N.H)^p),  H = norm(L + V)
// with V towards the eye (TestOverlayView checks that formula on flat ground and a ridge).
// Where the cell is drawn: a map centres the terrain's box in the viewport (legend and title
// strips taken off) at the scale that fits it; a relief view projects the cell with the
// perspective camera vtkTerroirReliefSurface::FitReliefCamera places, and skips cells hidden
// behind higher ground on the line of sight. A wrong cell-to-pixel mapping, a mirrored image, a
// wrong colour table or range, or wrong lighting fails a probe (Documentation/Testing.md).
#ifndef TerroirOverlayProbes_h
#define TerroirOverlayProbes_h

#include "vtkCamera.h"
#include "vtkDataArray.h"
#include "vtkImageData.h"
#include "vtkLookupTable.h"
#include "vtkMatrix4x4.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkTerroirColorPresets.h"
#include "vtkTerroirOverlayView.h"
#include "vtkTerroirReliefSurface.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

namespace terroir
{
namespace testing
{

inline void ExpectPixelsShowTheirCells(vtkTerroirOverlayView* view, vtkImageData* image)
{
  constexpr double kPi = 3.14159265358979323846;
  vtkImageData* terrain = view->GetInputData();
  ASSERT_NE(terrain, nullptr);
  if (view->GetPlantsData())
  {
    return; // plants stand in front of the cells (their image is checked against the baseline)
  }
  if (view->GetTexturing())
  {
    return; // the texture, not the table, colours the cells (TestTexturingImages.cxx probes it)
  }
  vtkDataArray* values = terrain->GetPointData()->GetArray(view->GetArrayName());
  vtkDataArray* z = terrain->GetPointData()->GetArray("Elevation");
  ASSERT_NE(values, nullptr) << view->GetArrayName();
  ASSERT_NE(z, nullptr);
  const char* preset = view->GetEffectivePreset();
  // A preset's mask (lakes, rivers) leaves its zero cells in the base colour.
  const char* maskName = vtkTerroirColorPresets::GetMaskArrayName(preset);
  vtkDataArray* mask = maskName ? terrain->GetPointData()->GetArray(maskName) : nullptr;
  double base[3];
  view->GetBaseColor(base);
  int dims[3];
  double spacing[3];
  terrain->GetDimensions(dims);
  terrain->GetSpacing(spacing);
  const int nx = dims[0], ny = dims[1];
  const int comp = view->GetArrayComponent();
  double range[2];
  view->GetLastRange(range);
  vtkNew<vtkLookupTable> lut;
  ASSERT_TRUE(vtkTerroirColorPresets::ConfigureLookupTable(lut, preset, range[0], range[1]));

  // The viewport and the map camera.
  int size[3];
  image->GetDimensions(size);
  const double W = size[0], H = size[1];
  const bool hasTitle = view->GetTitle() && *view->GetTitle();
  const double legendWidth = view->GetShowLegend() ? 0.25 : 0.0;
  const double titleHeight = hasTitle ? std::max(0.08, 24.0 / H) : 0.0;
  const double vw = (1.0 - legendWidth) * W, vh = (1.0 - titleHeight) * H;
  const double sizeX = (nx - 1) * std::fabs(spacing[0]), sizeY = (ny - 1) * std::fabs(spacing[1]);
  const double scale = std::max(0.5 * sizeY, 0.5 * sizeX / (vw / vh)); // half height, metres
  const double pixelsPerMetre = vh / (2.0 * scale);
  const double e = view->GetVerticalExaggeration();
  const bool map = view->GetMode() == vtkTerroirOverlayView::Map;
  double origin[3];
  terrain->GetOrigin(origin);

  // Relief: the perspective camera vtkTerroirReliefSurface fits to the surface's bounds.
  double bounds[6] = { origin[0], origin[0] + sizeX, origin[1], origin[1] + sizeY, 1e300, -1e300 };
  for (vtkIdType k = 0; k < z->GetNumberOfTuples(); ++k)
  {
    const double h = z->GetComponent(k, 0) * e;
    if (std::isfinite(h))
    {
      bounds[4] = std::min(bounds[4], h);
      bounds[5] = std::max(bounds[5], h);
    }
  }
  vtkNew<vtkCamera> camera;
  vtkTerroirReliefSurface::FitReliefCamera(camera,
    bounds,
    vw / vh,
    vtkTerroirOverlayView::GetReliefCameraAzimuth(),
    vtkTerroirOverlayView::GetReliefCameraElevation(),
    vtkTerroirOverlayView::GetReliefViewAngle());
  vtkMatrix4x4* projection = camera->GetCompositeProjectionTransformMatrix(vw / vh, -1.0, 1.0);
  double eye[3];
  camera->GetPosition(eye);

  // The light and the half vector, seen from straight above.
  const double az = view->GetLightAzimuth() * kPi / 180.0;
  const double el = view->GetLightElevation() * kPi / 180.0;
  const double l[3] = { std::sin(az) * std::cos(el), std::cos(az) * std::cos(el), std::sin(el) };
  const double hn = std::sqrt(l[0] * l[0] + l[1] * l[1] + (l[2] + 1.0) * (l[2] + 1.0));
  const double hMap[3] = { l[0] / hn, l[1] / hn, (l[2] + 1.0) / hn };

  auto at = [&](vtkDataArray* a, int i, int j, int c)
  { return a->GetComponent(static_cast<vtkIdType>(j) * nx + i, c); };
  auto colour = [&](int i, int j, double rgb[3])
  {
    const double v = at(values, i, j, comp);
    if (!std::isfinite(v))
    {
      return false;
    }
    // The table's colour over the base colour by the table's opacity; the base colour alone
    // where the mask is 0.
    double rgba[3];
    lut->GetColor(v, rgba);
    const double a = (mask && at(mask, i, j, 0) == 0.0) ? 0.0 : lut->GetOpacity(v);
    for (int k = 0; k < 3; ++k)
    {
      rgb[k] = a * rgba[k] + (1.0 - a) * base[k];
    }
    return true;
  };
  auto normal = [&](int i, int j, double n[3])
  {
    const double gx = (at(z, i + 1, j, 0) - at(z, i - 1, j, 0)) / (2.0 * spacing[0]);
    const double gy = (at(z, i, j + 1, 0) - at(z, i, j - 1, 0)) / (2.0 * spacing[1]);
    const double len = std::sqrt(e * e * (gx * gx + gy * gy) + 1.0);
    n[0] = -e * gx / len;
    n[1] = -e * gy / len;
    n[2] = 1.0 / len;
  };

  int probes = 0;
  const int step = std::max(3, std::min(nx, ny) / 24);
  // A pixel covers about two cells of a map; seen obliquely, a relief pixel covers more along
  // the line of sight: the neighbourhood that must be uniform is 5 x 5 or 9 x 9 cells.
  const int r = map ? 2 : 4;
  for (int j = r + 1; j < ny - r - 1 && probes < 8; j += step)
  {
    for (int i = r + 1 + (j / step) % 2 * step / 2; i < nx - r - 1 && probes < 8; i += step)
    {
      double c0[3], n0[3];
      if (!colour(i, j, c0))
      {
        continue;
      }
      normal(i, j, n0);
      bool uniform = true;
      for (int dj = -r; dj <= r && uniform; ++dj)
      {
        for (int di = -r; di <= r && uniform; ++di)
        {
          double c[3], n[3];
          uniform = colour(i + di, j + dj, c) && std::isfinite(at(z, i + di, j + dj, 0));
          normal(i + di, j + dj, n);
          for (int k = 0; k < 3 && uniform; ++k)
          {
            uniform = std::fabs(c[k] - c0[k]) * 255.0 <= 2.0 &&
              (std::abs(di) > 2 || std::abs(dj) > 2 || std::fabs(n[k] - n0[k]) <= 0.01);
          }
        }
      }
      if (!uniform)
      {
        continue;
      }
      // Where the cell is drawn, and the half vector towards the eye.
      const double p[3] = {
        origin[0] + i * spacing[0], origin[1] + j * spacing[1], at(z, i, j, 0) * e
      };
      double px, py, h[3] = { hMap[0], hMap[1], hMap[2] };
      if (map)
      {
        px = 0.5 * vw + ((i - 0.5 * (nx - 1)) * std::fabs(spacing[0])) * pixelsPerMetre;
        py = 0.5 * vh + ((j - 0.5 * (ny - 1)) * std::fabs(spacing[1])) * pixelsPerMetre;
      }
      else
      {
        const double in[4] = { p[0], p[1], p[2], 1.0 };
        double out[4];
        projection->MultiplyPoint(in, out);
        px = 0.5 * (out[0] / out[3] + 1.0) * vw;
        py = 0.5 * (out[1] / out[3] + 1.0) * vh;
        double v[3] = { eye[0] - p[0], eye[1] - p[1], eye[2] - p[2] };
        const double vn = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
        double hh[3] = { l[0] + v[0] / vn, l[1] + v[1] / vn, l[2] + v[2] / vn };
        const double hl = std::sqrt(hh[0] * hh[0] + hh[1] * hh[1] + hh[2] * hh[2]);
        for (int k = 0; k < 3; ++k)
        {
          h[k] = hh[k] / hl;
        }
        // Hidden behind a ridge: the terrain rises above the line of sight (nearest cell).
        bool hidden = false;
        const double stepLength = 0.5 * std::min(std::fabs(spacing[0]), std::fabs(spacing[1]));
        for (double t = 3.0 * stepLength; t < vn && !hidden; t += stepLength)
        {
          const double q[3] = { p[0] + v[0] / vn * t, p[1] + v[1] / vn * t, p[2] + v[2] / vn * t };
          const int qi = static_cast<int>(std::lround((q[0] - origin[0]) / spacing[0]));
          const int qj = static_cast<int>(std::lround((q[1] - origin[1]) / spacing[1]));
          if (qi < 0 || qj < 0 || qi >= nx || qj >= ny || q[2] > bounds[5])
          {
            break;
          }
          hidden = at(z, qi, qj, 0) * e > q[2];
        }
        if (hidden || px < 0 || py < 0 || px >= vw || py >= vh)
        {
          continue;
        }
      }
      const double ndl = n0[0] * l[0] + n0[1] * l[1] + n0[2] * l[2];
      const double ndh = n0[0] * h[0] + n0[1] * h[1] + n0[2] * h[2];
      const double diffuse = std::max(0.0, ndl);
      const double spec =
        diffuse > 0 ? std::pow(std::max(0.0, ndh), view->GetSpecularPower()) : 0.0;
      auto* pixel = static_cast<unsigned char*>(
        image->GetScalarPointer(static_cast<int>(px), static_cast<int>(py), 0));
      for (int k = 0; k < 3; ++k)
      {
        const double expected = 255.0 *
          std::min(1.0,
            c0[k] * (view->GetAmbient() + view->GetDiffuse() * diffuse) +
              view->GetSpecular() * spec);
        EXPECT_NEAR(pixel[k], expected, 6.0)
          << "cell (" << i << ", " << j << ") at pixel (" << static_cast<int>(px) << ", "
          << static_cast<int>(py) << "), channel " << k << ", value " << at(values, i, j, comp);
      }
      ++probes;
    }
  }
  EXPECT_GE(probes, 3) << "too few cells of uniform colour to probe in " << view->GetArrayName();
  std::cout << "[ probes ] " << probes << " cells of " << view->GetArrayName() << " probed"
            << std::endl;
}

} // namespace testing
} // namespace terroir

#endif
