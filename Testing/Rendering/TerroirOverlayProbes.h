// Numeric probes of a Map-mode overlay (Testing/Rendering only, header only): the pixel under a
// known cell shows that cell's colour-table colour, lit as the view lights it.
//
// ExpectMapPixelsShowTheirCells(view, image) picks up to eight probe cells on a lattice over the
// terrain where the colour is locally uniform (the 5 x 5 cells around have the colour of the
// centre within 2 levels, so the pixel, which covers about two cells, cannot blend in another
// colour) and the ground locally plane. For each, the expected pixel is worked out by hand from
// the view's documented model: the cell's colour c from the colour table the view used (the
// preset over LastRange, blended over the base colour by its opacity; the base colour where a
// preset's mask is 0), the normal of the cell by central differences (times the vertical
// exaggeration), and Blinn-Phong seen from straight above,
//   pixel = 255 min(1, c (ka + kd max(0, N.L)) + ks max(0, N.H)^p)
// (TestOverlayView's FlatTerrainShadingMatchesTheFormula checks that formula on flat ground).
// The cell's pixel comes from the map camera: the terrain's bounding box centred in the
// viewport (legend and title strips taken off), scaled to fit (vtkTerroirReliefSurface's
// FitMapCamera). A wrong cell-to-pixel mapping, a wrong colour table or range, a mirrored image
// or wrong lighting fails the probe.
#ifndef TerroirOverlayProbes_h
#define TerroirOverlayProbes_h

#include "vtkDataArray.h"
#include "vtkImageData.h"
#include "vtkLookupTable.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkTerroirColorPresets.h"
#include "vtkTerroirOverlayView.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

namespace terroir
{
namespace testing
{

inline void ExpectMapPixelsShowTheirCells(vtkTerroirOverlayView* view, vtkImageData* image)
{
  constexpr double kPi = 3.14159265358979323846;
  vtkImageData* terrain = view->GetInputData();
  ASSERT_NE(terrain, nullptr);
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

  // The light and the half vector, seen from straight above.
  const double az = view->GetLightAzimuth() * kPi / 180.0;
  const double el = view->GetLightElevation() * kPi / 180.0;
  const double l[3] = { std::sin(az) * std::cos(el), std::cos(az) * std::cos(el), std::sin(el) };
  const double hn = std::sqrt(l[0] * l[0] + l[1] * l[1] + (l[2] + 1.0) * (l[2] + 1.0));
  const double h[3] = { l[0] / hn, l[1] / hn, (l[2] + 1.0) / hn };
  const double e = view->GetVerticalExaggeration();

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
  for (int j = 3; j < ny - 3 && probes < 8; j += step)
  {
    for (int i = 3 + (j / step) % 2 * step / 2; i < nx - 3 && probes < 8; i += step)
    {
      double c0[3], n0[3];
      if (!colour(i, j, c0))
      {
        continue;
      }
      normal(i, j, n0);
      bool uniform = true;
      for (int dj = -2; dj <= 2 && uniform; ++dj)
      {
        for (int di = -2; di <= 2 && uniform; ++di)
        {
          double c[3], n[3];
          uniform = colour(i + di, j + dj, c) && std::isfinite(at(z, i + di, j + dj, 0));
          normal(i + di, j + dj, n);
          for (int k = 0; k < 3 && uniform; ++k)
          {
            uniform = std::fabs(c[k] - c0[k]) * 255.0 <= 2.0 && std::fabs(n[k] - n0[k]) <= 0.01;
          }
        }
      }
      if (!uniform)
      {
        continue;
      }
      const double ndl = n0[0] * l[0] + n0[1] * l[1] + n0[2] * l[2];
      const double ndh = n0[0] * h[0] + n0[1] * h[1] + n0[2] * h[2];
      const double diffuse = std::max(0.0, ndl);
      const double spec =
        diffuse > 0 ? std::pow(std::max(0.0, ndh), view->GetSpecularPower()) : 0.0;
      const double px = 0.5 * vw + ((i - 0.5 * (nx - 1)) * std::fabs(spacing[0])) * pixelsPerMetre;
      const double py = 0.5 * vh + ((j - 0.5 * (ny - 1)) * std::fabs(spacing[1])) * pixelsPerMetre;
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
