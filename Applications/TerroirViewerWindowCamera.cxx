// The window of `terroir view` (TerroirViewerWindowPrivate.h): the camera (relief and map
// views), the sun's light, the compass and grid north, the navigation styles, and the sliders
// that change the parameters.
#include "TerroirViewerWindowPrivate.h"

#include "vtkCamera.h"
#include "vtkMath.h"
#include "vtkPoints.h"
#include "vtkSliderRepresentation2D.h"

#include <algorithm>
#include <cmath>

namespace terroir
{
namespace viewer
{

double ViewerWindow::EffectiveOrientation() const
{
  const auto& p = this->Session.Parameters();
  if (std::isfinite(p.Orientation))
  {
    return p.Orientation;
  }
  // The session resolves NaN (convergence or 0); recover it from the sun's two frames.
  terroir::viewer::ViewerParameters q = p;
  q.Orientation = 0.0;
  double azTrue = 0.0, az = 0.0, el = 0.0;
  this->Session.SunDirection(q, azTrue, el);
  this->Session.SunDirection(p, az, el);
  return azTrue - az;
}

//------------------------------------------------------------------------------
void ViewerWindow::UpdateCompass()
{
  // True north on the screen: the grid direction of true north (grid azimuth -orientation)
  // projected from the focal point.
  const double gridNorth = this->EffectiveOrientation();
  vtkCamera* camera = this->Scene->GetActiveCamera();
  double focal[3];
  camera->GetFocalPoint(focal);
  double bounds[6];
  this->Relief->GetBounds(bounds);
  const double reach = 0.05 * std::hypot(bounds[1] - bounds[0], bounds[3] - bounds[2]);
  const double a = vtkMath::RadiansFromDegrees(-gridNorth);
  double p0[3], p1[3];
  this->Scene->SetWorldPoint(focal[0], focal[1], focal[2], 1.0);
  this->Scene->WorldToDisplay();
  this->Scene->GetDisplayPoint(p0);
  this->Scene->SetWorldPoint(
    focal[0] + reach * std::sin(a), focal[1] + reach * std::cos(a), focal[2], 1.0);
  this->Scene->WorldToDisplay();
  this->Scene->GetDisplayPoint(p1);
  double angle = std::atan2(p1[0] - p0[0], p1[1] - p0[1]); // clockwise from screen up
  if (!std::isfinite(angle) || (p1[0] == p0[0] && p1[1] == p0[1]))
  {
    angle = 0.0;
  }
  const int* size = this->Window->GetSize();
  const double* vp = this->Scene->GetViewport();
  const double cx = (vp[0] + 0.93 * (vp[2] - vp[0])) * size[0];
  const double cy = (vp[1] + 0.86 * (vp[3] - vp[1])) * size[1];
  const double r = 0.035 * size[1];
  this->CompassCentre[0] = cx;
  this->CompassCentre[1] = cy;
  this->CompassRadius = r;
  const double c = std::cos(angle), s = std::sin(angle);
  // Arrow in its own frame (y = north): tip, right barb, tail notch, left barb.
  const double shape[4][2] = { { 0.0, 1.0 }, { 0.55, -0.8 }, { 0.0, -0.45 }, { -0.55, -0.8 } };
  for (int k = 0; k < 4; ++k)
  {
    const double x = shape[k][0] * r, y = shape[k][1] * r;
    this->CompassArrow->GetPoints()->SetPoint(k, cx + x * c + y * s, cy - x * s + y * c, 0.0);
  }
  this->CompassArrow->GetPoints()->Modified();
  this->CompassLabel->GetPositionCoordinate()->SetCoordinateSystemToDisplay();
  this->CompassLabel->SetPosition(cx + 1.6 * r * s, cy + 1.6 * r * c);
}

void ViewerWindow::UpdateLight()
{
  double azimuth = 0.0, elevation = 0.0;
  this->Session.SunDirection(this->Session.Parameters(), azimuth, elevation);
  double bounds[6];
  this->Relief->GetBounds(bounds);
  // Below the horizon the relief keeps a grazing, dim light (ambient term only would be flat).
  vtkTerroirReliefSurface::ConfigureLight(this->Sun, azimuth, std::max(2.0, elevation), bounds);
  this->Sun->SetIntensity(elevation > 0.0 ? 1.0 : 0.3);
}

void ViewerWindow::ResetCamera(bool map)
{
  double bounds[6];
  this->Relief->GetBounds(bounds);
  const int* size = this->Window->GetSize();
  const double* vp = this->Scene->GetViewport();
  const double aspect = ((vp[2] - vp[0]) * size[0]) / std::max(1.0, (vp[3] - vp[1]) * size[1]);
  vtkCamera* camera = this->Scene->GetActiveCamera();
  if (map)
  {
    vtkTerroirReliefSurface::FitMapCamera(camera, bounds, aspect);
  }
  else
  {
    vtkTerroirReliefSurface::FitReliefCamera(camera, bounds, aspect);
  }
  this->Scene->ResetCameraClippingRange(bounds);
}

void ViewerWindow::ParametersChanged(bool affectsOverlay)
{
  this->UpdateLight();
  const ViewerOverlay o = this->Session.GetCurrentOverlay();
  if (affectsOverlay && o != ViewerOverlay::None && o != ViewerOverlay::Slope &&
    o != ViewerOverlay::Water)
  {
    this->Session.RequestOverlay();
  }
  // Slider values follow the parameters (the script and keys set them too).
  const auto& p = this->Session.Parameters();
  const double values[6] = { p.Latitude,
    static_cast<double>(p.Month),
    p.Hour,
    p.BrushRate,
    p.SlopeThreshold,
    std::isnan(this->SeaLevel) ? this->ElevationRange[0] : this->SeaLevel };
  for (std::size_t k = 0; k < this->Sliders.size(); ++k)
  {
    auto* rep = vtkSliderRepresentation2D::SafeDownCast(this->Sliders[k]->GetRepresentation());
    if (rep && rep->GetValue() != values[k])
    {
      rep->SetValue(values[k]);
    }
  }
  if (this->OpenCard == Card::Climate)
  {
    this->UpdateCard(); // script verbs and files change the climate too
  }
  this->UpdateTexts();
}

void ViewerWindow::SetStyle(bool firstPerson)
{
  this->FirstPerson = firstPerson;
  if (firstPerson)
  {
    this->Interactor->SetInteractorStyle(this->FirstPersonStyle);
  }
  else
  {
    this->Interactor->SetInteractorStyle(this->TerrainStyle);
  }
  if (this->OpenCard == Card::Settings)
  {
    this->UpdateCard();
  }
}

void ViewerWindow::OnSlider(vtkObject* caller, unsigned long, void*)
{
  auto* widget = vtkSliderWidget::SafeDownCast(caller);
  auto* rep = vtkSliderRepresentation2D::SafeDownCast(widget->GetRepresentation());
  auto& p = this->Session.Parameters();
  const double v = rep->GetValue();
  if (widget == this->Sliders[0])
  {
    p.Latitude = v;
  }
  else if (widget == this->Sliders[1])
  {
    const int month = static_cast<int>(std::lround(v));
    rep->SetValue(month);
    if (month == p.Month)
    {
      return;
    }
    p.Month = month;
  }
  else if (widget == this->Sliders[2])
  {
    p.Hour = v;
  }
  else if (widget == this->Sliders[3])
  {
    p.BrushRate = v;
    this->UpdateTexts();
    return;
  }
  else if (widget == this->Sliders[SlopeSlider])
  {
    p.SlopeThreshold = std::round(v);
    rep->SetValue(p.SlopeThreshold);
    char line[160];
    std::snprintf(line,
      sizeof(line),
      "Slope rule threshold %.0f deg: the Slope rule button sets 0 mm/h on steeper cells",
      p.SlopeThreshold);
    this->Message = line;
    this->UpdateTexts();
    return;
  }
  else
  {
    char line[160];
    std::snprintf(line, sizeof(line), "Sea level %.2f m: let go to flood from the edge", v);
    this->Message = line;
    this->UpdateTexts();
    return;
  }
  this->ParametersChanged(true);
}

void ViewerWindow::OnSeaSliderReleased(vtkObject*, unsigned long, void*)
{
  auto* rep =
    vtkSliderRepresentation2D::SafeDownCast(this->Sliders[SeaSlider]->GetRepresentation());
  const double level = rep->GetValue();
  // A second release right after the first moves that sea rather than adding to it.
  if (this->SliderSeaDepth > 0 && this->Session.GetUndoDepth() == this->SliderSeaDepth &&
    this->Session.GetWaterVersion() == this->SliderSeaWater)
  {
    this->Session.Undo();
  }
  this->SliderSeaDepth = 0;
  this->FloodSea(level);
  if (this->Session.GetUndoDepth() > 0 && this->SeaLevel == level)
  {
    this->SliderSeaDepth = this->Session.GetUndoDepth();
    this->SliderSeaWater = this->Session.GetWaterVersion();
  }
}

void ViewerWindow::OnCamera(vtkObject*, unsigned long, void*)
{
  this->UpdateCompass();
}

} // namespace viewer
} // namespace terroir
