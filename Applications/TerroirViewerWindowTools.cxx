// The window of `terroir view` (TerroirViewerWindowPrivate.h): picking cells, the tools (lake,
// brush, fill, slope rule, water flow, undo, table), screenshots, and the observers of keys,
// the wheel, clicks, the timer and the mouse (list, buttons, compass turns, brush strokes).
#include "TerroirViewerWindowPrivate.h"

#include "TerroirCommandLine.h"
#include "TerroirSafeOutput.h"

#include "vtkCommand.h"
#include "vtkImageData.h"
#include "vtkMath.h"
#include "vtkPNGWriter.h"
#include "vtkPointData.h"
#include "vtkProperty2D.h"
#include "vtkSliderRepresentation2D.h"
#include "vtkTextProperty.h"
#include "vtkWindowToImageFilter.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>

namespace terroir
{
namespace viewer
{
namespace
{
/// A one-letter key symbol in lower case, `shift` set when it came in capitals (X sends
/// capitals with Shift; scripts send the lower case and the flag); other symbols unchanged.
std::string LowerKey(const std::string& symbol, bool& shift)
{
  if (symbol.size() != 1)
  {
    return symbol;
  }
  const auto c = static_cast<unsigned char>(symbol[0]);
  shift = shift || std::isupper(c);
  return std::string(1, static_cast<char>(std::tolower(c)));
}
} // namespace

void ViewerWindow::Undo()
{
  const unsigned long soil = this->Session.GetInfiltrationVersion();
  if (this->Session.Undo())
  {
    this->Message = "Undone (" + std::to_string(this->Session.GetUndoDepth()) + " step(s) left)";
    this->Recolour();
    if (this->Session.GetInfiltrationVersion() != soil)
    {
      this->InfiltrationChanged();
    }
  }
  else
  {
    this->Message = "Nothing to undo";
  }
  this->UpdateTexts();
}

bool ViewerWindow::PickCell(int x, int y, int& i, int& j)
{
  // The full-detail surface is picked even while the coarse one is drawn (a picker skips
  // hidden actors).
  vtkActor* surface = this->Relief->GetSurfaceActor();
  const int visible = surface->GetVisibility();
  surface->VisibilityOn();
  const bool picked = this->Picker->Pick(x, y, 0.0, this->Scene) != 0;
  surface->SetVisibility(visible);
  if (!picked)
  {
    return false;
  }
  double world[3];
  this->Picker->GetPickPosition(world);
  vtkImageData* terrain = this->Session.GetTerrain();
  double origin[3], spacing[3];
  terrain->GetOrigin(origin);
  terrain->GetSpacing(spacing);
  i = static_cast<int>(std::lround((world[0] - origin[0]) / spacing[0]));
  j = static_cast<int>(std::lround((world[1] - origin[1]) / spacing[1]));
  return true;
}

void ViewerWindow::Click(int x, int y)
{
  if (this->CurrentTool != Tool::Lake && this->CurrentTool != Tool::Sea)
  {
    return; // the brush paints on press and drag (OnMouse)
  }
  int i = 0, j = 0;
  if (!this->PickCell(x, y, i, j))
  {
    this->Message = "No terrain under the pointer";
    this->UpdateTexts();
    return;
  }
  std::string error;
  if (this->CurrentTool == Tool::Sea)
  {
    // The clicked cell's height is the sea level: the shore passes through the click.
    int dims[3];
    vtkImageData* terrain = this->Session.GetTerrain();
    terrain->GetDimensions(dims);
    this->FloodSea(terrain->GetPointData()
                     ->GetArray("Elevation")
                     ->GetComponent(static_cast<vtkIdType>(j) * dims[0] + i, 0));
    return;
  }
  if (this->Session.FloodFillAt(i, j, error))
  {
    this->Message =
      "Lake at cell (" + std::to_string(i) + ", " + std::to_string(j) + ") (Ctrl+Z undoes it)";
    this->Recolour();
  }
  else
  {
    this->Message = error;
  }
  this->UpdateTexts();
}

void ViewerWindow::FloodSea(double level)
{
  std::string error;
  const long long cells = this->Session.FloodSea(level, error);
  if (cells >= 0)
  {
    char line[160];
    std::snprintf(
      line, sizeof(line), "Sea at %.2f m: %lld cells under water (Ctrl+Z undoes it)", level, cells);
    this->Message = line;
    this->SeaLevel = level;
    this->SliderSeaDepth = 0; // a sea by click or script is not the slider's to move
    auto* rep =
      vtkSliderRepresentation2D::SafeDownCast(this->Sliders[SeaSlider]->GetRepresentation());
    rep->SetValue(level);
    this->Recolour();
  }
  else
  {
    this->Message = error;
  }
  this->UpdateTexts();
}

void ViewerWindow::InfiltrationChanged()
{
  const ViewerOverlay o = this->Session.GetCurrentOverlay();
  if (o == ViewerOverlay::Humidity || o == ViewerOverlay::Clusters ||
    o == ViewerOverlay::WeightedHumidity)
  {
    this->Session.RequestOverlay();
  }
}

void ViewerWindow::PressButton(int k)
{
  const auto& p = this->Session.Parameters();
  char line[160];
  switch (k)
  {
    case 0:
    case 1:
    case 2:
      this->CurrentTool = k == 1 ? Tool::Lake : k == 2 ? Tool::Brush : Tool::Navigate;
      this->Message = std::string("Tool: ") + ToolName(this->CurrentTool);
      break;
    case 3:
    {
      const long long changed = this->Session.FillInfiltration();
      std::snprintf(line,
        sizeof(line),
        "Fill: %lld cells changed to %.0f mm/h (Ctrl+Z undoes it)",
        changed,
        p.BrushRate);
      this->Message = line;
      this->InfiltrationChanged();
      break;
    }
    case 4:
    {
      std::string error;
      const long long changed = this->Session.ApplySlopeRule(error);
      if (changed < 0)
      {
        this->Message = "error: " + error;
        break;
      }
      std::snprintf(line,
        sizeof(line),
        "Slope rule: %lld cells steeper than %.0f\xc2\xb0 set to 0 mm/h (Ctrl+Z undoes it)",
        changed,
        p.SlopeThreshold);
      this->Message = line;
      this->InfiltrationChanged();
      break;
    }
    case 5:
      this->Session.RequestWaterFlow();
      this->Message = "Water flow started";
      break;
    case 6:
      this->Undo();
      break;
    case 7:
      this->ShowTable(this->TablePane->GetDraw() == 0);
      if (this->TableWanted && this->Shown.Overlay != ViewerOverlay::Clusters)
      {
        this->Message = "The cluster table comes with the clusters overlay (key 7)";
      }
      break;
    case 8:
    case 9:
    {
      const Card card = k == 8 ? Card::Climate : Card::Settings;
      this->ShowCard(this->OpenCard == card ? Card::None : card);
      break;
    }
    default:
      break;
  }
  this->UpdateTexts();
}

std::string ViewerWindow::NextScreenshotName(const char* extension)
{
  const std::string dir =
    this->Line.View.ScreenshotDir.empty() ? "." : this->Line.View.ScreenshotDir;
  for (int k = 1;; ++k)
  {
    char name[64];
    std::snprintf(name, sizeof(name), "terroir-view-%03d.%s", k, extension);
    const std::string path = (std::filesystem::path(dir) / name).string();
    std::error_code ec;
    if (!std::filesystem::exists(path, ec))
    {
      return path;
    }
  }
}

bool ViewerWindow::Screenshot(const std::string& path, std::string& error)
{
  this->RenderStill(); // screenshots show the full detail
  vtkNew<vtkWindowToImageFilter> grab;
  grab->SetInput(this->Window);
  grab->SetInputBufferTypeToRGB();
  grab->ReadFrontBufferOff();
  grab->ShouldRerenderOff();
  grab->Update();
  return WriteThroughTemporary(
    path,
    [&](const std::string& temp)
    {
      vtkNew<vtkPNGWriter> writer;
      writer->SetFileName(temp.c_str());
      writer->SetInputConnection(grab->GetOutputPort());
      writer->Write();
      return writer->GetErrorCode() == 0;
    },
    error);
}

bool ViewerWindow::WriteThroughTemporary(const std::string& path,
  const std::function<bool(const std::string&)>& write,
  std::string& error)
{
  const std::string temp = terroir::TemporaryNameFor(path);
  if (!write(temp))
  {
    terroir::DiscardTemporary(temp);
    error = path + ": could not be written";
    return false;
  }
  if (!terroir::CommitTemporary(temp, path, error))
  {
    error = path + ": " + error;
    return false;
  }
  return true;
}

//------------------------------------------------------------------------------
void ViewerWindow::OnKey(vtkObject*, unsigned long, void*)
{
  vtkRenderWindowInteractor* rwi = this->Interactor;
  const std::string sym = rwi->GetKeySym() ? rwi->GetKeySym() : "";
  const bool control = rwi->GetControlKey() != 0;
  auto& p = this->Session.Parameters();
  bool handled = true;
  if (control && (sym == "z" || sym == "Z"))
  {
    this->Undo();
  }
  else if (control)
  {
    handled = false;
  }
  else if (sym.size() == 1 && sym[0] >= '0' &&
    sym[0] < '0' + static_cast<int>(ViewerOverlay::Count))
  {
    this->SetOverlay(static_cast<ViewerOverlay>(sym[0] - '0'));
  }
  else if (sym == "F3" || sym == "F4")
  {
    this->PressButton(sym == "F3" ? 8 : 9);
  }
  else if (this->CardKey(sym))
  {
    this->UpdateTexts();
  }
  else if (sym == "Tab")
  {
    this->SetStyle(!this->FirstPerson);
    this->Message = this->FirstPerson ? "First-person: W/A/S/D move, R/F up/down, drag to look"
                                      : "Terrain: drag pans, wheel zooms, Ctrl+drag rotates";
    this->UpdateTexts();
  }
  else if (sym == "l" || sym == "b" || sym == "n" || sym == "c")
  {
    this->CurrentTool = sym == "l" ? Tool::Lake
      : sym == "b"                 ? Tool::Brush
      : sym == "c"                 ? Tool::Sea
                                   : Tool::Navigate;
    this->Message = std::string("Tool: ") + ToolName(this->CurrentTool);
    this->UpdateTexts();
  }
  else if (sym == "g")
  {
    this->PressButton(5);
  }
  else if (sym == "t")
  {
    this->PressButton(7);
  }
  else if (this->ClusterKey(sym, rwi->GetShiftKey() != 0) ||
    this->FlowKey(sym, rwi->GetShiftKey() != 0) ||
    this->OrientationKey(sym, rwi->GetShiftKey() != 0))
  {
  }
  else if (sym == "e")
  {
    std::string error;
    const std::string path = this->NextScreenshotName("csv");
    this->Message = this->ExportTable(path, error) ? "Saved " + path : error;
    this->UpdateTexts();
  }
  else if (sym == "bracketleft" || sym == "bracketright")
  {
    const double current = this->EffectiveOrientation();
    p.Orientation = std::fmod(current + (sym == "bracketleft" ? -5.0 : 5.0) + 360.0, 360.0);
    this->ParametersChanged(true);
  }
  else if (sym == "v" || sym == "m")
  {
    this->ResetCamera(sym == "m");
    this->UpdateCompass();
  }
  else if (sym == "p" || sym == "F12")
  {
    std::string error;
    const std::string path = this->NextScreenshotName();
    this->Message = this->Screenshot(path, error) ? "Saved " + path : error;
    this->UpdateTexts();
  }
  else if (this->ErosionKey(sym))
  {
  }
  else if (sym == "q" || sym == "Escape")
  {
    this->QuitRequested = true; // a script's `key q` ends the session too
    rwi->TerminateApp();
  }
  else
  {
    handled = false; // W/A/S/D/R/F go on to the first-person style
  }
  if (handled)
  {
    // The navigation style does not see it.
    this->KeyCommand->SetAbortFlag(1);
    this->Window->Render();
  }
}

bool ViewerWindow::ClusterKey(const std::string& symbol, bool shift)
{
  const std::string sym = LowerKey(symbol, shift);
  auto& p = this->Session.Parameters();
  if (sym == "k")
  {
    p.Clusters = std::max(1, std::min(64, p.Clusters + (shift ? -1 : 1)));
  }
  else if (sym == "j")
  {
    this->WeightUnderEdit =
      (this->WeightUnderEdit + 1) % static_cast<int>(kViewerClusterFeatureCount);
  }
  else if (sym == "x")
  {
    double& w = p.ClusterWeights[this->WeightUnderEdit];
    w = shift ? (w / 2.0 < 0.01 ? 0.0 : w / 2.0) : (w > 0.0 ? std::min(1000.0, 2.0 * w) : 0.01);
  }
  else
  {
    return false;
  }
  this->ParametersChanged(sym != "j");
  this->DescribeClusters();
  this->UpdateTexts();
  return true;
}

void ViewerWindow::DescribeClusters()
{
  const auto& p = this->Session.Parameters();
  char line[200];
  std::snprintf(line, sizeof(line), "Clusters: K=%d, weights", p.Clusters);
  std::string text = line;
  for (std::size_t f = 0; f < kViewerClusterFeatureCount; ++f)
  {
    std::snprintf(line,
      sizeof(line),
      " %s%s %.3g",
      static_cast<int>(f) == this->WeightUnderEdit ? "*" : "",
      kViewerClusterFeatures[f].Name,
      p.ClusterWeights[f]);
    text += line;
  }
  this->Message = text + " (K/Shift+K, J next, X/Shift+X)";
}

bool ViewerWindow::OrientationKey(const std::string& symbol, bool shift)
{
  if (symbol == "F2")
  {
    this->OrientationEdit = !this->OrientationEdit;
    const double green[3] = { 0.1, 0.65, 0.15 }, red[3] = { 0.75, 0.1, 0.1 };
    const double* c = this->OrientationEdit ? green : red;
    this->CompassActor->GetProperty()->SetColor(c[0], c[1], c[2]);
    this->CompassLabel->GetTextProperty()->SetColor(c[0], c[1], c[2]);
    this->Message = this->OrientationEdit
      ? "Orientation edit: Left / Right turn the compass 1\xc2\xb0 (Shift: 10\xc2\xb0), F2 ends"
      : "Orientation edit ended";
    this->UpdateTexts();
    return true;
  }
  if (!this->OrientationEdit || (symbol != "Left" && symbol != "Right"))
  {
    return false;
  }
  auto& p = this->Session.Parameters();
  const double step = (shift ? 10.0 : 1.0) * (symbol == "Left" ? -1.0 : 1.0);
  p.Orientation = std::fmod(this->EffectiveOrientation() + step + 360.0, 360.0);
  this->ParametersChanged(true);
  this->UpdateCompass();
  return true;
}

bool ViewerWindow::FlowKey(const std::string& symbol, bool shift)
{
  const std::string sym = LowerKey(symbol, shift);
  auto& p = this->Session.Parameters();
  if (sym == "o")
  {
    p.FlowRivers = !p.FlowRivers;
  }
  else if (sym == "i")
  {
    p.FlowIterations =
      std::max(1, std::min(1000000, shift ? p.FlowIterations / 2 : p.FlowIterations * 2));
  }
  else if (sym == "y")
  {
    double& v = p.FlowRivers ? p.FlowRainRate : p.FlowWater;
    const double first = p.FlowRivers ? 1.0 : 10.0;
    v = !std::isfinite(v) ? first : shift ? v / 2.0 : v * 2.0;
    v = std::max(p.FlowRivers ? 0.001 : 0.0, std::min(p.FlowRivers ? 1000.0 : 100000.0, v));
  }
  else
  {
    return false;
  }
  this->DescribeFlow();
  this->UpdateTexts();
  return true;
}

void ViewerWindow::DescribeFlow()
{
  const auto& p = this->Session.Parameters();
  char line[240];
  const double amount = p.FlowRivers ? p.FlowRainRate : p.FlowWater;
  char what[64];
  if (std::isfinite(amount))
  {
    std::snprintf(what, sizeof(what), p.FlowRivers ? "rain %.3g mm/h" : "water %.3g mm", amount);
  }
  else
  {
    std::snprintf(what, sizeof(what), "the month's standing water");
  }
  std::snprintf(line,
    sizeof(line),
    "Water flow: %s, %s, stop %s %.3g, at most %d iterations (O mode, Y/Shift+Y water, "
    "I/Shift+I iterations, G run)",
    p.FlowRivers ? "rivers" : "pulse",
    what,
    p.FlowRivers ? "at balance within" : "below",
    p.FlowRivers ? p.FlowBalance : p.FlowStopRatio,
    p.FlowIterations);
  this->Message = line;
}

void ViewerWindow::OnWheel(vtkObject*, unsigned long event, void*)
{
  if (this->CurrentTool != Tool::Brush)
  {
    return; // zoom or move
  }
  auto& p = this->Session.Parameters();
  const double factor = event == vtkCommand::MouseWheelForwardEvent ? 1.25 : 0.8;
  p.BrushRadius = std::max(0.0, std::min(1000.0, std::round(p.BrushRadius * factor * 4) / 4));
  if (event == vtkCommand::MouseWheelForwardEvent && p.BrushRadius < 1.0)
  {
    p.BrushRadius = 1.0;
  }
  this->WheelCommand->SetAbortFlag(1);
  this->UpdateTexts();
  this->Window->Render();
}

void ViewerWindow::OnClick(vtkObject*, unsigned long, void* callData)
{
  const int* position = static_cast<const int*>(callData);
  this->Click(position[0], position[1]);
  this->Window->Render();
}

void ViewerWindow::OnTimer(vtkObject*, unsigned long, void*)
{
  const bool eroding = this->Session.IsEroding();
  const bool busy = !this->Session.IsIdle() || eroding;
  this->CollectResults();
  if (eroding)
  {
    this->DescribeErosion();
  }
  if (busy || this->Computing)
  {
    this->UpdateTexts();
    this->Window->Render();
  }
  this->Computing = !this->Session.IsIdle();
  // The full detail once the window has rested (the coarse surface meanwhile).
  if (this->StillPending &&
    std::chrono::duration<double>(std::chrono::steady_clock::now() - this->LastCoarse).count() >=
      StillDelay)
  {
    this->RenderStill();
  }
}

void ViewerWindow::OnMouse(vtkObject*, unsigned long event, void*)
{
  vtkRenderWindowInteractor* rwi = this->Interactor;
  const int* position = rwi->GetEventPosition();
  const int x = position[0], y = position[1];
  const int* size = this->Window->GetSize();
  // Pointer angle about the compass centre, degrees clockwise from screen up.
  auto pointerAngle = [this, x, y]()
  {
    return vtkMath::DegreesFromRadians(
      std::atan2(x - this->CompassCentre[0], y - this->CompassCentre[1]));
  };
  bool handled = false;
  if (this->CardMouse(event, x, y))
  {
    handled = true; // a press on the open card, or a drag of its bars
  }
  else if (event == vtkCommand::LeftButtonPressEvent)
  {
    double u = 0.0, v = 0.0;
    if (ToViewport(this->ListPane, size, x, y, u, v))
    {
      // The list's entries hang from 0.84 - k h, h = 0.84 / count apart (Build); the band of
      // entry k is [0.84 - (k + 1) h, 0.84 - k h].
      const int count = static_cast<int>(ViewerOverlay::Count);
      const double h = 0.84 / count;
      const int row = static_cast<int>(std::floor((0.84 - v) / h));
      if (row >= 0 && row < count)
      {
        this->SetOverlay(static_cast<ViewerOverlay>(row));
      }
      handled = true;
    }
    else if (ToViewport(this->ButtonPane, size, x, y, u, v))
    {
      for (int k = 0; k < ButtonCount; ++k)
      {
        double cell[4];
        ButtonCell(k, cell);
        if (u >= cell[0] && u <= cell[2] && v >= cell[1] && v <= cell[3])
        {
          this->PressButton(k);
        }
      }
      handled = true;
    }
    else if (this->TablePane->GetDraw() && ToViewport(this->TablePane, size, x, y, u, v))
    {
      handled = true; // the table is not the terrain
    }
    else if (ToViewport(this->Scene, size, x, y, u, v) &&
      std::hypot(x - this->CompassCentre[0], y - this->CompassCentre[1]) <=
        1.9 * this->CompassRadius)
    {
      this->TurningCompass = true;
      this->TurnStartAngle = pointerAngle();
      this->TurnStartOrientation = this->EffectiveOrientation();
      this->Message = "Turning the compass";
      handled = true;
    }
    else if (this->CurrentTool == Tool::Brush && !rwi->GetControlKey() &&
      ToViewport(this->Scene, size, x, y, u, v))
    {
      this->Painting = true;
      this->Session.BeginStroke();
      this->HaveLastCell = this->PickCell(x, y, this->LastCell[0], this->LastCell[1]);
      if (this->HaveLastCell && this->Session.IsEroding())
      {
        this->Session.PaintErosion(this->LastCell[0], this->LastCell[1]);
      }
      else if (this->HaveLastCell)
      {
        this->Session.PaintInfiltration(this->LastCell[0], this->LastCell[1]);
      }
      handled = true;
    }
  }
  else if (event == vtkCommand::MouseMoveEvent && (this->TurningCompass || this->Painting))
  {
    if (this->TurningCompass)
    {
      // The arrow follows the pointer about the compass centre: turning it clockwise on the
      // screen turns grid north anticlockwise from true north.
      const double turned = pointerAngle() - this->TurnStartAngle;
      auto& p = this->Session.Parameters();
      p.Orientation = std::fmod(this->TurnStartOrientation - turned + 720.0, 360.0);
      this->ParametersChanged(true);
    }
    else
    {
      int i = 0, j = 0;
      if (this->PickCell(x, y, i, j))
      {
        if (this->Session.IsEroding())
        {
          if (this->HaveLastCell)
          {
            this->PaintErosionAlong(this->LastCell[0], this->LastCell[1], i, j);
          }
          else
          {
            this->Session.PaintErosion(i, j);
          }
        }
        else if (this->HaveLastCell)
        {
          this->Session.PaintInfiltrationAlong(this->LastCell[0], this->LastCell[1], i, j);
        }
        else
        {
          this->Session.PaintInfiltration(i, j);
        }
        this->LastCell[0] = i;
        this->LastCell[1] = j;
        this->HaveLastCell = true;
      }
    }
    handled = true;
  }
  else if (event == vtkCommand::LeftButtonReleaseEvent && (this->TurningCompass || this->Painting))
  {
    if (this->TurningCompass)
    {
      this->TurningCompass = false;
      char line[96];
      std::snprintf(line,
        sizeof(line),
        "Grid north %.1f\xc2\xb0 from true north",
        this->Session.Parameters().Orientation);
      this->Message = line;
    }
    else
    {
      this->Painting = false;
      const long long changed = this->Session.EndStroke();
      if (this->Session.IsEroding())
      {
        this->DescribeErosion(); // the dabs reach the run between two steps
      }
      else
      {
        char line[128];
        std::snprintf(line,
          sizeof(line),
          "Painted %lld cells at %.0f mm/h (Ctrl+Z undoes the stroke)",
          changed,
          this->Session.Parameters().BrushRate);
        this->Message = line;
      }
      if (changed > 0)
      {
        this->InfiltrationChanged();
      }
    }
    handled = true;
  }
  if (handled)
  {
    this->MouseCommand->SetAbortFlag(1);
    this->UpdateTexts();
    this->Window->Render();
  }
}

} // namespace viewer
} // namespace terroir
