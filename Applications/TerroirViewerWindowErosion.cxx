// The window of `terroir view` (TerroirViewerWindowPrivate.h): live erosion and the terrain
// texture. F5 starts or stops the erosion, F6 picks what the Brush tool paints while it runs
// (soil, water, vegetation), F7 keeps the eroded terrain; the relief follows the bed and the
// water layer shows the erosion's water. F8 puts Jensen's terrain texture on the relief.
#include "TerroirViewerWindowPrivate.h"

#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkPointData.h"
#include "vtkTerroirGeoreference.h"

#include <cmath>
#include <cstdio>

namespace terroir
{
namespace viewer
{

namespace
{
const char* const BrushNames[] = { "soil", "water", "vegetation" };
}

bool ViewerWindow::ErosionKey(const std::string& sym)
{
  auto& p = this->Session.Parameters();
  if (sym == "F5")
  {
    this->ErosionCommand(this->Session.IsEroding() ? "stop" : "start");
  }
  else if (sym == "F6")
  {
    p.ErosionBrush = (std::max(0, std::min(2, p.ErosionBrush)) + 1) % 3;
    this->DescribeErosion();
  }
  else if (sym == "F7")
  {
    this->ErosionCommand("keep");
  }
  else if (sym == "F8")
  {
    this->SetTexturing(!this->Texturing);
  }
  else
  {
    return false;
  }
  this->UpdateTexts();
  return true;
}

void ViewerWindow::ErosionCommand(const std::string& what)
{
  std::string error;
  if (what == "start")
  {
    if (this->Session.StartErosion(error))
    {
      this->CurrentTool = Tool::Brush;
      this->LastBedShown = std::chrono::steady_clock::time_point();
      this->DescribeErosion();
    }
    else
    {
      this->Message = "error: " + error;
    }
  }
  else if (what == "stop")
  {
    this->Session.StopErosion();
    this->ShowErosionFrame(true);
    this->DescribeErosion();
  }
  else
  {
    if (this->Session.KeepErosion(error))
    {
      this->ShowErosionFrame(true); // the new terrain's relief
      this->Message = "Eroded terrain kept (the overlays are computed on it)";
      this->Session.RequestOverlay();
    }
    else
    {
      this->Message = "error: " + error;
    }
  }
  this->UpdateTexts();
}

void ViewerWindow::DescribeErosion()
{
  const auto& p = this->Session.Parameters();
  char line[200];
  std::snprintf(line,
    sizeof(line),
    "Erosion %s: %lld steps, %.1f steps/s | brush (F6) %s %.3g%s",
    this->Session.IsEroding() ? "running (F5 stops, F7 keeps)" : "stopped (F5 runs, F7 keeps)",
    this->Session.GetErosionSteps(),
    this->Session.GetErosionStepsPerSecond(),
    BrushNames[std::max(0, std::min(2, p.ErosionBrush))],
    p.ErosionAmount,
    p.ErosionBrush == 2 ? "" : " m");
  this->Message = line;
}

void ViewerWindow::ShowErosionFrame(bool force)
{
  using clock = std::chrono::steady_clock;
  vtkImageData* current = this->Session.GetTerrain();
  vtkFloatArray* bed = this->Session.GetErosionBed();
  const bool live = bed && bed->GetNumberOfValues() == current->GetNumberOfPoints();
  // Rebuilding the relief costs about a render: at most twice a second while the run goes on.
  if (!force && std::chrono::duration<double>(clock::now() - this->LastBedShown).count() < 0.5)
  {
    return;
  }
  this->LastBedShown = clock::now();
  vtkSmartPointer<vtkImageData> terrain = current;
  if (live)
  {
    // The bed on the cells with data (the others keep their elevation, NaN or masked).
    vtkDataArray* z = current->GetPointData()->GetArray(vtkTerroirGeoreference::ElevationName());
    vtkDataArray* mask = current->GetPointData()->GetArray(vtkTerroirGeoreference::ValidMaskName());
    vtkNew<vtkFloatArray> heights;
    heights->SetName(vtkTerroirGeoreference::ElevationName());
    heights->SetNumberOfValues(bed->GetNumberOfValues());
    for (vtkIdType k = 0; k < bed->GetNumberOfValues(); ++k)
    {
      const double e = z->GetComponent(k, 0);
      const bool data = std::isfinite(e) && !(mask && mask->GetComponent(k, 0) == 0.0);
      heights->SetValue(k, data ? bed->GetValue(k) : static_cast<float>(e));
    }
    terrain = vtkSmartPointer<vtkImageData>::New();
    terrain->ShallowCopy(current);
    terrain->GetPointData()->RemoveArray(vtkTerroirGeoreference::ElevationName());
    terrain->GetPointData()->AddArray(heights);
  }
  std::string error;
  for (vtkTerroirReliefSurface* s : { this->Relief.Get(), this->Coarse.Get() })
  {
    if (s == this->Coarse.Get() && !this->HaveCoarse)
    {
      continue;
    }
    s->SetInputData(terrain);
    if (!s->BuildGeometry(error))
    {
      this->Message = "error: " + error;
      return;
    }
  }
  this->SurfaceLocator->BuildLocator();
  this->ApplyTexturing();
  this->Recolour();
}

void ViewerWindow::SetTexturing(bool on)
{
  this->Texturing = on;
  this->ApplyTexturing();
  this->Recolour();
  if (this->Message.rfind("error:", 0) != 0)
  {
    this->Message = on ? "Terrain texture (Jensen 2011): F8 takes it off"
                       : "Terrain texture off: the overlay's colours";
  }
  this->UpdateTexts();
}

void ViewerWindow::ApplyTexturing()
{
  std::string error;
  for (vtkTerroirReliefSurface* s : { this->Relief.Get(), this->Coarse.Get() })
  {
    if (s == this->Coarse.Get() && !this->HaveCoarse)
    {
      continue;
    }
    if (!this->Texturing)
    {
      vtkTerroirTerrainTexture::Remove(s);
      s->SetBaseColor(this->ReliefBaseColor);
    }
    else if (!this->Texturer->ApplyTo(s, this->Session.GetTerrain(), error))
    {
      this->Texturing = false;
      this->Message = "error: " + error;
      this->ApplyTexturing();
      return;
    }
  }
}

void ViewerWindow::PaintErosionAlong(double i0, double j0, double i1, double j1)
{
  // Dabs every half radius along the drag, so that a fast stroke leaves no gaps.
  const double radius = std::max(0.5, this->Session.Parameters().BrushRadius);
  const double length = std::hypot(i1 - i0, j1 - j0);
  const int dabs = std::max(1, static_cast<int>(std::ceil(length / (0.5 * radius))));
  for (int d = 1; d <= dabs; ++d)
  {
    const double t = static_cast<double>(d) / dabs;
    this->Session.PaintErosion(i0 + t * (i1 - i0), j0 + t * (j1 - j0));
  }
}

} // namespace viewer
} // namespace terroir
