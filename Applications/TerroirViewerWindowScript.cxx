// The window of `terroir view` (TerroirViewerWindowPrivate.h): the --script actions, replayed
// as real interactor events (SetEventInformation + InvokeEvent) or session calls, and the
// `state` and `camera` lines they print.
#include "TerroirViewerWindowPrivate.h"

#include "vtkCamera.h"
#include "vtkCommand.h"
#include "vtkFloatArray.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

namespace terroir
{
namespace viewer
{

//------------------------------------------------------------------------------
void ViewerWindow::SendKey(const std::string& symbol, bool control, bool shift)
{
  vtkRenderWindowInteractor* rwi = this->Interactor;
  const int* last = rwi->GetEventPosition();
  const char code = symbol.size() == 1 ? symbol[0] : (symbol == "space" ? ' ' : 0);
  rwi->SetEventInformation(last[0], last[1], control, shift, code, 1, symbol.c_str());
  rwi->InvokeEvent(vtkCommand::KeyPressEvent, nullptr);
  rwi->InvokeEvent(vtkCommand::CharEvent, nullptr);
  rwi->InvokeEvent(vtkCommand::KeyReleaseEvent, nullptr);
}

void ViewerWindow::SendDrag(int x0, int y0, int x1, int y1, int steps, bool control, bool shift)
{
  // Display coordinates (origin bottom left): press at (x0, y0), `steps` moves to (x1, y1),
  // release there (a click: the same point and no steps).
  vtkRenderWindowInteractor* rwi = this->Interactor;
  rwi->SetEventInformation(x0, y0, control, shift);
  rwi->InvokeEvent(vtkCommand::MouseMoveEvent, nullptr);
  rwi->SetEventInformation(x0, y0, control, shift);
  rwi->InvokeEvent(vtkCommand::LeftButtonPressEvent, nullptr);
  for (int k = 1; k <= steps; ++k)
  {
    rwi->SetEventInformation(
      x0 + (x1 - x0) * k / steps, y0 + (y1 - y0) * k / steps, control, shift);
    rwi->InvokeEvent(vtkCommand::MouseMoveEvent, nullptr);
  }
  rwi->SetEventInformation(x1, y1, control, shift);
  rwi->InvokeEvent(vtkCommand::LeftButtonReleaseEvent, nullptr);
}

void ViewerWindow::PrintState()
{
  // One line for scripts and tests: the parameters, the tool, the undo depth, the sums of the
  // water (m) and infiltration (mm/h) arrays over the cells, and whether the table is shown.
  const auto& p = this->Session.Parameters();
  auto list = [](const std::array<double, 12>& values)
  {
    std::string s;
    for (double v : values)
    {
      char number[32];
      std::snprintf(number, sizeof(number), "%s%.6g", s.empty() ? "" : ",", v);
      s += number;
    }
    return s;
  };
  auto sum = [](vtkFloatArray* a)
  {
    double total = 0.0;
    for (vtkIdType k = 0; k < a->GetNumberOfValues(); ++k)
    {
      const float v = a->GetValue(k);
      total += std::isfinite(v) ? v : 0.0f;
    }
    return total;
  };
  std::printf("state overlay %s tool %s latitude %.6g month %d hour %.6g orientation %.6g "
              "lake-depth %.6g brush-size %.6g brush-rate %.6g slope-threshold %.6g undo %zu "
              "water-sum %.9g infiltration-sum %.9g table %s clusters %d weight-slope %.6g "
              "weight-temperature %.6g weight-sun %.6g weight-humidity %.6g flow-mode %s "
              "flow-iterations %d flow-water %.6g flow-rain-rate %.6g flow-stop %.6g "
              "flow-balance %.6g flow-last-iterations %lld flow-last-stop %s coldest %.6g "
              "warmest %.6g lapse-rate %.6g temperatures %s precipitation-jul %.6g "
              "intensity-jul %.6g orientation-edit %s card %s card-field %d card-month %d "
              "sensitivity %.6g move-speed %.6g sea-level %.9g precipitation-months %s "
              "intensity-months %s style %s detail %s erosion %s erosion-steps %lld "
              "erosion-brush %s erosion-amount %.6g erosion-water-sum %.9g erosion-bed-sum %.9g "
              "erosion-rate %.4g texture %s\n",
    terroir::viewer::OverlayName(this->Session.GetCurrentOverlay()),
    ToolName(this->CurrentTool),
    p.Latitude,
    p.Month,
    p.Hour,
    this->EffectiveOrientation(),
    p.LakeDepth,
    p.BrushRadius,
    p.BrushRate,
    p.SlopeThreshold,
    this->Session.GetUndoDepth(),
    sum(this->Session.GetWater()),
    sum(this->Session.GetInfiltration()),
    this->TablePane->GetDraw() ? "shown" : "hidden",
    p.Clusters,
    p.ClusterWeights[0],
    p.ClusterWeights[1],
    p.ClusterWeights[2],
    p.ClusterWeights[3],
    p.FlowRivers ? "rivers" : "pulse",
    p.FlowIterations,
    p.FlowWater,
    p.FlowRainRate,
    p.FlowStopRatio,
    p.FlowBalance,
    this->Session.GetLastFlowIterations(),
    this->Session.GetLastFlowStopReason().empty() ? "none"
                                                  : this->Session.GetLastFlowStopReason().c_str(),
    p.Coldest,
    p.Warmest,
    p.LapseRate,
    p.UseMonthlyTemperatures ? "monthly" : "extremes",
    p.Precipitation[6],
    p.PrecipitationIntensity[6],
    this->OrientationEdit ? "on" : "off",
    this->OpenCard == Card::Climate      ? "climate"
      : this->OpenCard == Card::Settings ? "settings"
                                         : "none",
    this->CardField,
    this->CardMonth + 1,
    this->TerrainStyle->GetMouseSensitivity(),
    this->FirstPersonStyle->GetMoveSensitivity(),
    this->SeaLevel,
    list(p.Precipitation).c_str(),
    list(p.PrecipitationIntensity).c_str(),
    this->FirstPerson ? "first-person" : "terrain",
    !this->HaveCoarse       ? "full-only"
      : this->LastDrawnFull ? "full"
                            : "coarse",
    this->Session.IsEroding()                    ? "running"
      : this->Session.GetErosionBed() != nullptr ? "stopped"
                                                 : "none",
    this->Session.GetErosionSteps(),
    p.ErosionBrush == 0     ? "soil"
      : p.ErosionBrush == 1 ? "water"
                            : "vegetation",
    p.ErosionAmount,
    this->Session.GetErosionWater() ? sum(this->Session.GetErosionWater()) : 0.0,
    this->Session.GetErosionBed() ? sum(this->Session.GetErosionBed()) : 0.0,
    this->Session.GetErosionStepsPerSecond(),
    this->Texturing ? "on" : "off");
  std::fflush(stdout);
}

void ViewerWindow::SetParameter(const ViewerAction& a)
{
  auto& p = this->Session.Parameters();
  const auto& n = a.Numbers;
  if (a.Verb == "latitude" || a.Verb == "longitude" || a.Verb == "month" || a.Verb == "hour" ||
    a.Verb == "orientation" || a.Verb == "clusters")
  {
    if (a.Verb == "month" || a.Verb == "clusters")
    {
      (a.Verb == "month" ? p.Month : p.Clusters) = static_cast<int>(n[0]);
    }
    else
    {
      (a.Verb == "latitude"       ? p.Latitude
          : a.Verb == "longitude" ? p.Longitude
          : a.Verb == "hour"      ? p.Hour
                                  : p.Orientation) = n[0];
    }
    this->ParametersChanged(true);
  }
  else if (a.Verb == "lake-depth" || a.Verb == "brush-size" || a.Verb == "brush-rate" ||
    a.Verb == "slope-threshold")
  {
    (a.Verb == "lake-depth"      ? p.LakeDepth
        : a.Verb == "brush-size" ? p.BrushRadius
        : a.Verb == "brush-rate" ? p.BrushRate
                                 : p.SlopeThreshold) = n[0];
    this->ParametersChanged(false);
  }
}

void ViewerWindow::SetFlowParameter(const ViewerAction& a)
{
  auto& p = this->Session.Parameters();
  if (a.Verb == "flow-mode")
  {
    p.FlowRivers = a.Text == "rivers";
  }
  else if (a.Verb == "flow-iterations")
  {
    p.FlowIterations = static_cast<int>(a.Numbers[0]);
  }
  else
  {
    (a.Verb == "flow-water"          ? p.FlowWater
        : a.Verb == "flow-rain-rate" ? p.FlowRainRate
        : a.Verb == "flow-stop"      ? p.FlowStopRatio
                                     : p.FlowBalance) = a.Numbers[0];
  }
  this->DescribeFlow();
}

bool ViewerWindow::SetClimate(const ViewerAction& a, std::string& error)
{
  auto& p = this->Session.Parameters();
  const auto& n = a.Numbers;
  if (a.Verb == "climate-save")
  {
    if (!this->Session.SaveClimate(a.Text, error))
    {
      return false;
    }
    this->Message = "Saved the climate to " + a.Text;
    return true;
  }
  if (a.Verb == "climate-load")
  {
    if (!this->Session.LoadClimate(a.Text, error))
    {
      return false;
    }
    this->Message = "Climate from " + a.Text;
  }
  else if (a.Verb == "precipitation" || a.Verb == "intensity")
  {
    (a.Verb == "precipitation" ? p.Precipitation
                               : p.PrecipitationIntensity)[static_cast<std::size_t>(n[0]) - 1] =
      n[1];
  }
  else if (a.Verb == "lapse-rate")
  {
    p.LapseRate = n[0];
  }
  else
  {
    (a.Verb == "coldest" ? p.Coldest : p.Warmest) = n[0];
    p.UseMonthlyTemperatures = false; // the extremes make the year again
  }
  this->ParametersChanged(true);
  return true;
}

bool ViewerWindow::SendButton(const ViewerAction& a, const std::string& where, std::string& error)
{
  // A real click at the middle of the button.
  const auto& names = terroir::viewer::ViewerButtonNames();
  const int k = static_cast<int>(std::find(names.begin(), names.end(), a.Text) - names.begin());
  if (k >= ButtonCount)
  {
    error = where + ": 'button': no button '" + a.Text + "' in this window";
    return false;
  }
  double cell[4];
  ButtonCell(k, cell);
  const int* size = this->Window->GetSize();
  const double* vp = this->ButtonPane->GetViewport();
  const double u = 0.5 * (cell[0] + cell[2]), v = 0.5 * (cell[1] + cell[3]);
  const int x = static_cast<int>((vp[0] + u * (vp[2] - vp[0])) * size[0]);
  const int y = static_cast<int>((vp[1] + v * (vp[3] - vp[1])) * size[1]);
  this->SendDrag(x, y, x, y, 0, false, false);
  return true;
}

void ViewerWindow::SendWheel(int notches)
{
  // At the centre of the terrain view.
  vtkRenderWindowInteractor* rwi = this->Interactor;
  const int* size = this->Window->GetSize();
  const double* vp = this->Scene->GetViewport();
  const int x = static_cast<int>(0.5 * (vp[0] + vp[2]) * size[0]);
  const int y = static_cast<int>(0.5 * (vp[1] + vp[3]) * size[1]);
  for (int k = 0; k < std::abs(notches); ++k)
  {
    rwi->SetEventInformation(x, y, 0, 0);
    rwi->InvokeEvent(
      notches > 0 ? vtkCommand::MouseWheelForwardEvent : vtkCommand::MouseWheelBackwardEvent,
      nullptr);
  }
}

void ViewerWindow::PrintCamera()
{
  vtkCamera* c = this->Scene->GetActiveCamera();
  double pos[3], focal[3];
  c->GetPosition(pos);
  c->GetFocalPoint(focal);
  std::printf("camera position %.3f %.3f %.3f focal %.3f %.3f %.3f\n",
    pos[0],
    pos[1],
    pos[2],
    focal[0],
    focal[1],
    focal[2]);
  std::fflush(stdout);
}

bool ViewerWindow::RunAction(const ViewerAction& a,
  const std::string& where,
  bool& quit,
  std::string& error)
{
  vtkRenderWindowInteractor* rwi = this->Interactor;
  const auto& n = a.Numbers;
  // What finished meanwhile reaches the screen, as the timer would do it.
  this->CollectResults();
  if (a.Verb == "overlay")
  {
    ViewerOverlay overlay = ViewerOverlay::None;
    terroir::viewer::OverlayFromName(a.Text, overlay);
    this->SetOverlay(overlay);
  }
  else if (a.Verb == "latitude" || a.Verb == "longitude" || a.Verb == "month" || a.Verb == "hour" ||
    a.Verb == "orientation" || a.Verb == "clusters" || a.Verb == "lake-depth" ||
    a.Verb == "brush-size" || a.Verb == "brush-rate" || a.Verb == "slope-threshold")
  {
    this->SetParameter(a);
  }
  else if (a.Verb == "cluster-weight")
  {
    auto& w = this->Session.Parameters().ClusterWeights;
    w[static_cast<std::size_t>(terroir::viewer::ClusterFeatureIndex(a.Text))] = n[0];
    this->ParametersChanged(true);
  }
  else if (a.Verb == "coldest" || a.Verb == "warmest" || a.Verb == "lapse-rate" ||
    a.Verb == "precipitation" || a.Verb == "intensity" || a.Verb == "climate-load" ||
    a.Verb == "climate-save")
  {
    if (!this->SetClimate(a, error))
    {
      error = where + ": " + error;
      return false;
    }
  }
  else if (a.Verb == "sea")
  {
    this->FloodSea(n[0]);
  }
  else if (a.Verb == "erosion")
  {
    this->ErosionCommand(a.Text);
  }
  else if (a.Verb == "texture")
  {
    this->SetTexturing(a.Text == "on");
  }
  else if (a.Verb == "erosion-brush" || a.Verb == "erosion-amount" || a.Verb == "erosion-rain")
  {
    auto& p = this->Session.Parameters();
    if (a.Verb == "erosion-brush")
    {
      p.ErosionBrush = a.Text == "soil" ? 0 : a.Text == "water" ? 1 : 2;
    }
    else
    {
      (a.Verb == "erosion-amount" ? p.ErosionAmount : p.ErosionRain) = n[0];
    }
    this->DescribeErosion();
  }
  else if (a.Verb == "wait-erosion")
  {
    if (!this->Session.WaitErosionSteps(static_cast<long long>(n[0]), 600.0))
    {
      error = where + ": the erosion did not reach " +
        std::to_string(static_cast<long long>(n[0])) + " steps (none running, or it stopped)";
      return false;
    }
    this->CollectResults();
    this->ShowErosionFrame(true);
    this->DescribeErosion();
  }
  else if (a.Verb.compare(0, 5, "flow-") == 0)
  {
    this->SetFlowParameter(a);
  }
  else if (a.Verb == "table-csv")
  {
    if (!this->ExportTable(a.Text, error))
    {
      error = where + ": " + error;
      return false;
    }
  }
  else if (a.Verb == "button")
  {
    if (!this->SendButton(a, where, error))
    {
      return false;
    }
  }
  else if (a.Verb == "state")
  {
    this->PrintState();
  }
  else if (a.Verb == "sensitivity" || a.Verb == "move-speed")
  {
    const bool mouse = a.Verb == "sensitivity";
    this->SetNavigation(mouse ? n[0] : this->TerrainStyle->GetMouseSensitivity(),
      mouse ? this->FirstPersonStyle->GetMoveSensitivity() : n[0]);
    this->UpdateTexts();
  }
  else if (a.Verb == "card")
  {
    this->ShowCard(a.Text == "climate" ? Card::Climate
        : a.Text == "settings"         ? Card::Settings
                                       : Card::None);
  }
  else if (a.Verb == "style")
  {
    this->SetStyle(a.Text == "first-person");
    this->UpdateTexts();
  }
  else if (a.Verb == "tool")
  {
    this->CurrentTool = a.Text == "lake" ? Tool::Lake
      : a.Text == "brush"                ? Tool::Brush
      : a.Text == "sea"                  ? Tool::Sea
                                         : Tool::Navigate;
    this->UpdateTexts();
  }
  else if (a.Verb == "view")
  {
    this->ResetCamera(a.Text == "map");
    this->UpdateCompass();
  }
  else if (a.Verb == "click" || a.Verb == "drag")
  {
    // Script coordinates have their origin at the top left (as SetEventInformationFlipY).
    const int top = rwi->GetSize()[1] - 1;
    const int x0 = static_cast<int>(n[0]), y0 = top - static_cast<int>(n[1]);
    const bool drag = a.Verb == "drag";
    const int x1 = drag ? static_cast<int>(n[2]) : x0;
    const int y1 = drag ? top - static_cast<int>(n[3]) : y0;
    this->SendDrag(x0, y0, x1, y1, drag ? 10 : 0, a.Control, a.Shift);
  }
  else if (a.Verb == "wheel")
  {
    this->SendWheel(static_cast<int>(n[0]));
  }
  else if (a.Verb == "key")
  {
    this->SendKey(a.Text, a.Control, a.Shift);
  }
  else if (a.Verb == "undo")
  {
    this->Undo();
  }
  else if (a.Verb == "flow")
  {
    this->PressButton(5);
  }
  else if (a.Verb == "wait")
  {
    this->Session.Wait();
    this->CollectResults();
  }
  else if (a.Verb == "camera")
  {
    this->PrintCamera();
  }
  else if (a.Verb == "screenshot")
  {
    this->UpdateTexts();
    if (!this->Screenshot(a.Text, error))
    {
      error = where + ": " + error;
      return false;
    }
  }
  else if (a.Verb == "quit")
  {
    quit = true;
  }
  this->UpdateTexts();
  this->Window->Render();
  return true;
}

} // namespace viewer
} // namespace terroir
