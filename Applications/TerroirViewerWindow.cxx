// The window of `terroir view` (Documentation/Viewer.md), built as the loadable module
// terroir-viewer.so: a thin layer over terroir::viewer::ViewerSession (the model, without any
// window). It draws the relief with vtkTerroirReliefSurface, the overlay legend with
// vtkTerroirOverlayLegend, the overlay list, the status line, the sliders and the compass;
// it turns keys, clicks and slider moves into session calls; a repeating interactor timer
// collects the worker thread's results; and it replays --script actions as real interactor
// events (SetEventInformationFlipY + InvokeEvent), so that scripts test the interaction code.
#include "TerroirViewerPlugin.h"

#include "TerroirCommandLine.h"
#include "TerroirSafeOutput.h"
#include "TerroirViewerScript.h"
#include "TerroirViewerSession.h"

#include "vtkActor.h"
#include "vtkActor2D.h"
#include "vtkCallbackCommand.h"
#include "vtkCamera.h"
#include "vtkCellArray.h"
#include "vtkCellPicker.h"
#include "vtkCommand.h"
#include "vtkCoordinate.h"
#include "vtkDataArray.h"
#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkLight.h"
#include "vtkLookupTable.h"
#include "vtkMath.h"
#include "vtkNew.h"
#include "vtkPNGWriter.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkPolyDataMapper2D.h"
#include "vtkProperty2D.h"
#include "vtkRenderWindow.h"
#include "vtkRenderWindowInteractor.h"
#include "vtkRenderer.h"
#include "vtkSliderRepresentation2D.h"
#include "vtkSliderWidget.h"
#include "vtkSmartPointer.h"
#include "vtkTerroirColorPresets.h"
#include "vtkTerroirInteractorStyleFirstPerson.h"
#include "vtkTerroirInteractorStyleTerrain.h"
#include "vtkTerroirOverlayLegend.h"
#include "vtkTerroirReliefSurface.h"
#include "vtkTerroirXDisplay.h"
#include "vtkTextActor.h"
#include "vtkTextProperty.h"
#include "vtkWindowToImageFilter.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

namespace
{
using terroir::viewer::OverlayResult;
using terroir::viewer::ViewerAction;
using terroir::viewer::ViewerOverlay;
using terroir::viewer::ViewerSession;

const char* const MonthNames[] = { "January",
  "February",
  "March",
  "April",
  "May",
  "June",
  "July",
  "August",
  "September",
  "October",
  "November",
  "December" };

/// The tool a click applies.
enum class Tool
{
  Navigate,
  Lake,
  Brush
};

const char* ToolName(Tool t)
{
  return t == Tool::Lake ? "lake" : t == Tool::Brush ? "brush" : "navigate";
}

/// Observer callback into a member function.
template<class T, void (T::*Method)(vtkObject*, unsigned long, void*)>
void Forward(vtkObject* caller, unsigned long event, void* clientData, void* callData)
{
  (static_cast<T*>(clientData)->*Method)(caller, event, callData);
}

class ViewerWindow
{
public:
  ViewerWindow(ViewerSession& session, const terroir::app::CommandLine& line)
    : Session(session)
    , Line(line)
  {
  }

  ~ViewerWindow()
  {
    for (auto& s : this->Sliders)
    {
      s->Off();
    }
    if (this->Window)
    {
      this->Window->Finalize();
    }
    this->Interactor = nullptr;
    this->Window = nullptr;
    terroir::rendering::CloseXDisplay(this->Display);
  }

  int Run(TerroirViewerRequest* request);

private:
  // ---- set-up ------------------------------------------------------------------------------
  bool Build(const std::string& title, std::string& error);
  vtkSmartPointer<vtkSliderWidget> AddSlider(const char* title,
    double lo,
    double hi,
    double value,
    double x0,
    double x1,
    const char* format);
  void BuildCompass();

  // ---- state to screen ---------------------------------------------------------------------
  void ApplyOverlay(const OverlayResult& result);
  void Recolour();
  void UpdateLight();
  void UpdateCompass();
  void UpdateTexts();
  void UpdateOverlayList();
  void ResetCamera(bool map);
  void CollectResults();

  // ---- commands ----------------------------------------------------------------------------
  void SetOverlay(ViewerOverlay overlay);
  void ParametersChanged(bool affectsOverlay);
  void SetStyle(bool firstPerson);
  void Undo();
  bool PickCell(int x, int y, int& i, int& j);
  void Click(int x, int y);
  bool Screenshot(const std::string& path, std::string& error);
  std::string NextScreenshotName();

  // ---- observers ---------------------------------------------------------------------------
  void OnKey(vtkObject* caller, unsigned long event, void* callData);
  void OnWheel(vtkObject* caller, unsigned long event, void* callData);
  void OnClick(vtkObject* caller, unsigned long event, void* callData);
  void OnTimer(vtkObject* caller, unsigned long event, void* callData);
  void OnSlider(vtkObject* caller, unsigned long event, void* callData);
  void OnCamera(vtkObject* caller, unsigned long event, void* callData);

  // ---- script ------------------------------------------------------------------------------
  bool RunAction(const ViewerAction& a, const std::string& where, bool& quit, std::string& error);
  void SendKey(const std::string& symbol, bool control, bool shift);

  ViewerSession& Session;
  const terroir::app::CommandLine& Line;
  void* Display = nullptr;
  int Width = 1024;
  int Height = 768;
  vtkSmartPointer<vtkRenderWindow> Window;
  vtkSmartPointer<vtkRenderWindowInteractor> Interactor;
  vtkNew<vtkRenderer> Scene;
  vtkNew<vtkRenderer> Panel;
  vtkNew<vtkRenderer> ListPane;
  vtkNew<vtkRenderer> LegendPane;
  vtkNew<vtkTerroirReliefSurface> Relief;
  vtkNew<vtkLight> Sun;
  vtkNew<vtkTerroirInteractorStyleTerrain> TerrainStyle;
  vtkNew<vtkTerroirInteractorStyleFirstPerson> FirstPersonStyle;
  bool FirstPerson = false;
  vtkNew<vtkTextActor> Status;
  vtkNew<vtkTextActor> Settings;
  vtkNew<vtkTextActor> Help;
  std::vector<vtkSmartPointer<vtkTextActor>> ListEntries;
  std::vector<vtkSmartPointer<vtkSliderWidget>> Sliders; // latitude, month, hour, brush rate
  vtkNew<vtkPolyData> CompassArrow;
  vtkNew<vtkActor2D> CompassActor;
  vtkNew<vtkTextActor> CompassLabel;
  vtkNew<vtkCellPicker> Picker;
  vtkNew<vtkCallbackCommand> KeyCommand;
  vtkNew<vtkCallbackCommand> WheelCommand;
  OverlayResult Shown; ///< the overlay on screen
  Tool CurrentTool = Tool::Navigate;
  std::string Message;
  bool Computing = false;
  unsigned long WaterShown = 0; ///< water version on screen
  bool QuitRequested = false;   ///< Q or Escape was pressed
};

//------------------------------------------------------------------------------
bool ViewerWindow::Build(const std::string& title, std::string& error)
{
  const terroir::app::ViewSettings& v = this->Line.View;
  this->Width = v.Width;
  this->Height = v.Height;
  this->Display = terroir::rendering::OpenXDisplay(error);
  if (!this->Display)
  {
    return false;
  }
  this->Window = vtkSmartPointer<vtkRenderWindow>::New();
  this->Window->SetDisplayId(this->Display);
  this->Window->SetSize(this->Width, this->Height);
  this->Window->SetMultiSamples(0);
  this->Window->SetWindowName(("terroir view: " + title).c_str());

  // Layout: the terrain on the left, a control panel under it, the overlay list and the
  // legend on the right.
  const double right = 0.78;
  const double panel = 0.14;
  this->Scene->SetViewport(0.0, panel, right, 1.0);
  this->Scene->SetBackground(0.93, 0.95, 0.98);
  this->Scene->AutomaticLightCreationOff();
  this->Panel->SetViewport(0.0, 0.0, right, panel);
  this->Panel->SetBackground(0.86, 0.87, 0.89);
  this->ListPane->SetViewport(right, 0.6, 1.0, 1.0);
  this->ListPane->SetBackground(1.0, 1.0, 1.0);
  this->LegendPane->SetViewport(right, 0.0, 1.0, 0.6);
  this->LegendPane->SetBackground(1.0, 1.0, 1.0);
  for (vtkRenderer* r :
    { this->Scene.Get(), this->Panel.Get(), this->ListPane.Get(), this->LegendPane.Get() })
  {
    this->Window->AddRenderer(r);
  }
  this->Panel->InteractiveOff();
  this->ListPane->InteractiveOff();
  this->LegendPane->InteractiveOff();

  this->Relief->SetInputData(this->Session.GetTerrain());
  if (!this->Relief->BuildGeometry(error))
  {
    return false;
  }
  this->Scene->AddActor(this->Relief->GetSurfaceActor());
  this->Scene->AddActor(this->Relief->GetHoleActor());
  this->Scene->AddLight(this->Sun);
  this->Picker->PickFromListOn();
  this->Picker->AddPickList(this->Relief->GetSurfaceActor());
  this->Picker->SetTolerance(0.0);

  const int font = std::max(10, this->Height / 52);
  auto text = [font](vtkTextActor* actor, double x, double y, bool top)
  {
    actor->GetTextProperty()->SetFontSize(font);
    actor->GetTextProperty()->SetColor(0.1, 0.1, 0.1);
    if (top)
    {
      actor->GetTextProperty()->SetVerticalJustificationToTop();
    }
    actor->GetPositionCoordinate()->SetCoordinateSystemToNormalizedViewport();
    actor->SetPosition(x, y);
  };
  text(this->Status, 0.01, 0.01, false);
  text(this->Settings, 0.01, 0.985, true);
  text(this->Help, 0.01, 0.94, true);
  this->Help->GetTextProperty()->SetColor(0.35, 0.35, 0.35);
  this->Help->SetInput("0-7 overlay  Tab navigation  L lake  B brush  N navigate  Ctrl+Z undo  "
                       "G flow  [ ] compass  V/M view  P screenshot  Q quit");
  this->Scene->AddActor2D(this->Status);
  this->Scene->AddActor2D(this->Settings);
  this->Scene->AddActor2D(this->Help);

  // Overlay list: one line per overlay, the current one bold and blue.
  vtkNew<vtkTextActor> listTitle;
  text(listTitle, 0.06, 0.96, true);
  listTitle->SetInput("Overlays (keys)");
  listTitle->GetTextProperty()->BoldOn();
  this->ListPane->AddActor2D(listTitle);
  const int count = static_cast<int>(ViewerOverlay::Count);
  for (int k = 0; k < count; ++k)
  {
    auto entry = vtkSmartPointer<vtkTextActor>::New();
    text(entry, 0.08, 0.84 - k * (0.8 / count), true);
    entry->SetInput(
      (std::to_string(k) + "  " + terroir::viewer::OverlayTitle(static_cast<ViewerOverlay>(k)))
        .c_str());
    this->ListPane->AddActor2D(entry);
    this->ListEntries.push_back(entry);
  }

  this->BuildCompass();

  this->Interactor = vtkSmartPointer<vtkRenderWindowInteractor>::New();
  this->Interactor->SetRenderWindow(this->Window);
  const double sensitivity = v.Sensitivity;
  this->TerrainStyle->SetMouseSensitivity(sensitivity);
  this->FirstPersonStyle->SetMouseSensitivity(sensitivity);
  this->FirstPersonStyle->SetMoveSensitivity(v.MoveSpeed);
  double bounds[6];
  this->Relief->GetBounds(bounds);
  const double diagonal = std::hypot(bounds[1] - bounds[0], bounds[3] - bounds[2]);
  this->FirstPersonStyle->SetMoveStep(std::max(1e-3, 0.01 * diagonal));
  for (vtkTerroirInteractorStyleTerrain* s :
    { static_cast<vtkTerroirInteractorStyleTerrain*>(this->TerrainStyle.Get()),
      static_cast<vtkTerroirInteractorStyleTerrain*>(this->FirstPersonStyle.Get()) })
  {
    s->SetDefaultRenderer(this->Scene);
    vtkNew<vtkCallbackCommand> click;
    click->SetCallback(Forward<ViewerWindow, &ViewerWindow::OnClick>);
    click->SetClientData(this);
    s->AddObserver(vtkTerroirInteractorStyleTerrain::ClickEvent, click);
    vtkNew<vtkCallbackCommand> moved;
    moved->SetCallback(Forward<ViewerWindow, &ViewerWindow::OnCamera>);
    moved->SetClientData(this);
    s->AddObserver(vtkCommand::InteractionEvent, moved);
  }
  this->SetStyle(v.Style == "first-person");
  this->Interactor->Initialize();

  // Keys and the brush's wheel go to the window before the navigation style.
  this->KeyCommand->SetCallback(Forward<ViewerWindow, &ViewerWindow::OnKey>);
  this->KeyCommand->SetClientData(this);
  this->Interactor->AddObserver(vtkCommand::KeyPressEvent, this->KeyCommand, 1.0f);
  this->WheelCommand->SetCallback(Forward<ViewerWindow, &ViewerWindow::OnWheel>);
  this->WheelCommand->SetClientData(this);
  this->Interactor->AddObserver(vtkCommand::MouseWheelForwardEvent, this->WheelCommand, 1.0f);
  this->Interactor->AddObserver(vtkCommand::MouseWheelBackwardEvent, this->WheelCommand, 1.0f);
  vtkNew<vtkCallbackCommand> timer;
  timer->SetCallback(Forward<ViewerWindow, &ViewerWindow::OnTimer>);
  timer->SetClientData(this);
  this->Interactor->AddObserver(vtkCommand::TimerEvent, timer);

  const auto& p = this->Session.Parameters();
  const double w = right; // sliders share the panel's width
  this->Sliders.push_back(
    this->AddSlider("Latitude", -90.0, 90.0, p.Latitude, 0.02 * w, 0.24 * w, "%.1f"));
  this->Sliders.push_back(this->AddSlider("Month", 1.0, 12.0, p.Month, 0.28 * w, 0.48 * w, "%.0f"));
  this->Sliders.push_back(this->AddSlider("Hour", 0.0, 24.0, p.Hour, 0.52 * w, 0.74 * w, "%.2f"));
  this->Sliders.push_back(
    this->AddSlider("Brush mm/h", 0.0, 100.0, p.BrushRate, 0.78 * w, 0.98 * w, "%.0f"));

  this->ResetCamera(false);
  this->UpdateLight();
  this->Recolour();
  this->UpdateTexts();
  return true;
}

vtkSmartPointer<vtkSliderWidget> ViewerWindow::AddSlider(const char* title,
  double lo,
  double hi,
  double value,
  double x0,
  double x1,
  const char* format)
{
  vtkNew<vtkSliderRepresentation2D> rep;
  rep->SetMinimumValue(lo);
  rep->SetMaximumValue(hi);
  rep->SetValue(value);
  rep->SetTitleText(title);
  rep->SetLabelFormat(format);
  rep->GetPoint1Coordinate()->SetCoordinateSystemToNormalizedDisplay();
  rep->GetPoint1Coordinate()->SetValue(x0, 0.045);
  rep->GetPoint2Coordinate()->SetCoordinateSystemToNormalizedDisplay();
  rep->GetPoint2Coordinate()->SetValue(x1, 0.045);
  // Sizes are fractions of the slider's length.
  rep->SetSliderLength(0.04);
  rep->SetSliderWidth(0.1);
  rep->SetEndCapLength(0.015);
  rep->SetEndCapWidth(0.1);
  rep->SetTubeWidth(0.025);
  rep->SetTitleHeight(0.09);
  rep->SetLabelHeight(0.08);
  for (vtkTextProperty* tp : { rep->GetTitleProperty(), rep->GetLabelProperty() })
  {
    tp->SetColor(0.1, 0.1, 0.1);
    tp->ShadowOff();
    tp->BoldOff();
  }
  rep->GetSliderProperty()->SetColor(0.15, 0.35, 0.75);
  rep->GetTubeProperty()->SetColor(0.45, 0.45, 0.45);
  rep->GetCapProperty()->SetColor(0.45, 0.45, 0.45);
  auto widget = vtkSmartPointer<vtkSliderWidget>::New();
  widget->SetInteractor(this->Interactor);
  widget->SetRepresentation(rep);
  widget->SetDefaultRenderer(this->Panel);
  widget->SetCurrentRenderer(this->Panel);
  widget->SetAnimationModeToJump();
  vtkNew<vtkCallbackCommand> moved;
  moved->SetCallback(Forward<ViewerWindow, &ViewerWindow::OnSlider>);
  moved->SetClientData(this);
  widget->AddObserver(vtkCommand::InteractionEvent, moved);
  widget->EnabledOn();
  return widget;
}

void ViewerWindow::BuildCompass()
{
  // A north arrow (unit size, pointing +y) drawn in display coordinates around its centre;
  // UpdateCompass turns it.
  vtkNew<vtkPoints> points;
  points->SetNumberOfPoints(4);
  vtkNew<vtkCellArray> cells;
  const vtkIdType tri[3] = { 0, 1, 2 };
  const vtkIdType tri2[3] = { 0, 2, 3 };
  cells->InsertNextCell(3, tri);
  cells->InsertNextCell(3, tri2);
  this->CompassArrow->SetPoints(points);
  this->CompassArrow->SetPolys(cells);
  vtkNew<vtkPolyDataMapper2D> mapper;
  mapper->SetInputData(this->CompassArrow);
  vtkNew<vtkCoordinate> display; // the arrow's points are window pixels
  display->SetCoordinateSystemToDisplay();
  mapper->SetTransformCoordinate(display);
  this->CompassActor->SetMapper(mapper);
  this->CompassActor->GetProperty()->SetColor(0.75, 0.1, 0.1);
  this->Scene->AddActor2D(this->CompassActor);
  this->CompassLabel->SetInput("N");
  this->CompassLabel->GetTextProperty()->SetFontSize(std::max(10, this->Height / 40));
  this->CompassLabel->GetTextProperty()->BoldOn();
  this->CompassLabel->GetTextProperty()->SetColor(0.75, 0.1, 0.1);
  this->CompassLabel->GetTextProperty()->SetJustificationToCentered();
  this->CompassLabel->GetTextProperty()->SetVerticalJustificationToCentered();
  this->Scene->AddActor2D(this->CompassLabel);
}

//------------------------------------------------------------------------------
void ViewerWindow::UpdateCompass()
{
  // True north on the screen: the grid direction of true north (grid azimuth -orientation)
  // projected from the focal point.
  const auto& p = this->Session.Parameters();
  double gridNorth = p.Orientation;
  double az = 0.0, el = 0.0;
  if (!std::isfinite(gridNorth))
  {
    // The session resolves NaN (convergence or 0); recover it from the sun's two frames.
    terroir::viewer::ViewerParameters q = p;
    q.Orientation = 0.0;
    double azTrue = 0.0;
    this->Session.SunDirection(q, azTrue, el);
    this->Session.SunDirection(p, az, el);
    gridNorth = azTrue - az;
  }
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

void ViewerWindow::UpdateOverlayList()
{
  const int current = static_cast<int>(this->Session.GetCurrentOverlay());
  for (int k = 0; k < static_cast<int>(this->ListEntries.size()); ++k)
  {
    vtkTextProperty* tp = this->ListEntries[k]->GetTextProperty();
    tp->SetBold(k == current);
    if (k == current)
    {
      tp->SetColor(0.1, 0.3, 0.8);
    }
    else
    {
      tp->SetColor(0.1, 0.1, 0.1);
    }
  }
}

void ViewerWindow::UpdateTexts()
{
  const auto& p = this->Session.Parameters();
  char settings[256];
  const int minutes = static_cast<int>(std::lround(p.Hour * 60.0));
  std::snprintf(settings,
    sizeof(settings),
    "%.2f%s %s, %s 15, %02d:%02d solar time | %s | tool: %s | lake +%.1f m | brush r=%.0f, %.0f "
    "mm/h | undo: %zu",
    std::fabs(p.Latitude),
    "\xc2\xb0",
    p.Latitude < 0.0 ? "S" : "N",
    MonthNames[std::max(1, std::min(12, p.Month)) - 1],
    minutes / 60,
    minutes % 60,
    this->FirstPerson ? "first-person" : "terrain navigation",
    ToolName(this->CurrentTool),
    p.LakeDepth,
    p.BrushRadius,
    p.BrushRate,
    this->Session.GetUndoDepth());
  this->Settings->SetInput(settings);
  std::string status;
  if (!this->Session.IsIdle())
  {
    char line[160];
    std::snprintf(line,
      sizeof(line),
      "%s\xe2\x80\xa6 %.0f %%",
      this->Session.GetProgressLabel().c_str(),
      100.0 * this->Session.GetProgress());
    status = line;
  }
  else
  {
    status = this->Message;
  }
  this->Status->SetInput(status.c_str());
  this->UpdateOverlayList();
  this->UpdateCompass();
}

//------------------------------------------------------------------------------
void ViewerWindow::ApplyOverlay(const OverlayResult& result)
{
  if (!result.Error.empty())
  {
    this->Message = std::string("error: ") + result.Error;
    std::cerr << "terroir: warning: " << result.Error << "\n";
    return;
  }
  this->Shown = result;
  this->Recolour();
}

void ViewerWindow::Recolour()
{
  this->LegendPane->RemoveAllViewProps();
  vtkImageData* terrain = this->Session.GetTerrain();
  const double white[3] = { 1.0, 1.0, 1.0 };
  const int font = std::max(9, this->Height / 56);
  vtkDataArray* values = this->Shown.GetValues();
  const char* preset = this->Shown.Preset.c_str();
  bool legend = false;
  if (values && this->Shown.Overlay != ViewerOverlay::Water &&
    vtkTerroirColorPresets::HasPreset(preset))
  {
    double range[2] = { 0.0, 1.0 };
    if (!vtkTerroirColorPresets::GetDefaultRange(preset, range) &&
      !this->Relief->ComputeDataRange(values, this->Shown.Component, nullptr, range))
    {
      range[0] = 0.0;
      range[1] = 1.0;
    }
    vtkNew<vtkLookupTable> lut;
    vtkTerroirColorPresets::ConfigureLookupTable(lut, preset, range[0], range[1]);
    const std::string title =
      vtkTerroirOverlayLegend::ApplyClusterShares(lut, preset, this->Shown.Output);
    this->Relief->SetColors(values, this->Shown.Component, lut, nullptr);
    vtkTerroirOverlayLegend::AddLegend(this->LegendPane, lut, preset, title, font, 0.0, white);
    legend = true;
  }
  else
  {
    this->Relief->SetUniformColor();
  }
  // The water state is a layer over every overlay: transparent where dry.
  this->WaterShown = this->Session.GetWaterVersion();
  vtkFloatArray* water = this->Session.GetWater();
  double wet[2] = { 0.0, 0.0 };
  water->GetRange(wet, 0);
  if (terrain && wet[1] > 0.0)
  {
    vtkNew<vtkLookupTable> lut;
    vtkTerroirColorPresets::ConfigureLookupTable(lut, "Water", 0.0, std::max(1.0, wet[1]));
    this->Relief->SetColors(water, 0, lut, nullptr, true);
    if (!legend)
    {
      vtkTerroirOverlayLegend::AddLegend(this->LegendPane, lut, "Water", "", font, 0.0, white);
    }
  }
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

void ViewerWindow::CollectResults()
{
  this->Session.Pump();
  OverlayResult result;
  if (this->Session.TakeOverlay(result))
  {
    this->ApplyOverlay(result);
  }
  if (this->Session.GetWaterVersion() != this->WaterShown)
  {
    // A water-flow run replaced the water state (fills and undos redraw at once).
    this->Message = "Water flow done (Ctrl+Z undoes it)";
    this->Recolour();
    if (this->Session.GetCurrentOverlay() == ViewerOverlay::Humidity)
    {
      this->Session.RequestOverlay();
    }
  }
  const std::string error = this->Session.TakeError();
  if (!error.empty())
  {
    this->Message = "error: " + error;
    std::cerr << "terroir: warning: " << error << "\n";
  }
}

//------------------------------------------------------------------------------
void ViewerWindow::SetOverlay(ViewerOverlay overlay)
{
  this->Session.SetCurrentOverlay(overlay);
  this->Session.RequestOverlay();
  OverlayResult result;
  if (this->Session.TakeOverlay(result)) // None and Water answer at once
  {
    this->ApplyOverlay(result);
  }
  this->Message = std::string("Overlay: ") + terroir::viewer::OverlayTitle(overlay);
  this->UpdateTexts();
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
  const double values[4] = { p.Latitude, static_cast<double>(p.Month), p.Hour, p.BrushRate };
  for (std::size_t k = 0; k < this->Sliders.size(); ++k)
  {
    auto* rep = vtkSliderRepresentation2D::SafeDownCast(this->Sliders[k]->GetRepresentation());
    if (rep && rep->GetValue() != values[k])
    {
      rep->SetValue(values[k]);
    }
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
}

void ViewerWindow::Undo()
{
  if (this->Session.Undo())
  {
    this->Message = "Undone (" + std::to_string(this->Session.GetUndoDepth()) + " step(s) left)";
    this->Recolour();
  }
  else
  {
    this->Message = "Nothing to undo";
  }
  this->UpdateTexts();
}

bool ViewerWindow::PickCell(int x, int y, int& i, int& j)
{
  if (!this->Picker->Pick(x, y, 0.0, this->Scene))
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
  if (this->CurrentTool == Tool::Navigate)
  {
    return;
  }
  int i = 0, j = 0;
  if (!this->PickCell(x, y, i, j))
  {
    this->Message = "No terrain under the pointer";
    this->UpdateTexts();
    return;
  }
  if (this->CurrentTool == Tool::Lake)
  {
    std::string error;
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
  }
  else
  {
    const int painted = this->Session.PaintInfiltration(i, j);
    this->Message = "Painted " + std::to_string(painted) + " cells";
    if (this->Session.GetCurrentOverlay() == ViewerOverlay::Humidity)
    {
      this->Session.RequestOverlay();
    }
  }
  this->UpdateTexts();
}

std::string ViewerWindow::NextScreenshotName()
{
  const std::string dir =
    this->Line.View.ScreenshotDir.empty() ? "." : this->Line.View.ScreenshotDir;
  for (int k = 1;; ++k)
  {
    char name[64];
    std::snprintf(name, sizeof(name), "terroir-view-%03d.png", k);
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
  this->Window->Render();
  vtkNew<vtkWindowToImageFilter> grab;
  grab->SetInput(this->Window);
  grab->SetInputBufferTypeToRGB();
  grab->ReadFrontBufferOff();
  grab->ShouldRerenderOff();
  grab->Update();
  const std::string temp = terroir::TemporaryNameFor(path);
  vtkNew<vtkPNGWriter> writer;
  writer->SetFileName(temp.c_str());
  writer->SetInputConnection(grab->GetOutputPort());
  writer->Write();
  if (writer->GetErrorCode() != 0)
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
  else if (sym.size() == 1 && sym[0] >= '0' && sym[0] <= '7')
  {
    this->SetOverlay(static_cast<ViewerOverlay>(sym[0] - '0'));
  }
  else if (sym == "Tab")
  {
    this->SetStyle(!this->FirstPerson);
    this->Message = this->FirstPerson ? "First-person: W/A/S/D move, R/F up/down, drag to look"
                                      : "Terrain: drag pans, wheel zooms, Ctrl+drag rotates";
    this->UpdateTexts();
  }
  else if (sym == "l" || sym == "b" || sym == "n")
  {
    this->CurrentTool = sym == "l" ? Tool::Lake : sym == "b" ? Tool::Brush : Tool::Navigate;
    this->Message = std::string("Tool: ") + ToolName(this->CurrentTool);
    this->UpdateTexts();
  }
  else if (sym == "g")
  {
    this->Session.RequestWaterFlow();
    this->UpdateTexts();
  }
  else if (sym == "bracketleft" || sym == "bracketright")
  {
    double current = p.Orientation;
    if (!std::isfinite(current))
    {
      current = 0.0;
    }
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
  const bool busy = !this->Session.IsIdle();
  this->CollectResults();
  if (busy || this->Computing)
  {
    this->UpdateTexts();
    this->Window->Render();
  }
  this->Computing = !this->Session.IsIdle();
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
  else
  {
    p.BrushRate = v;
    this->UpdateTexts();
    return;
  }
  this->ParametersChanged(true);
}

void ViewerWindow::OnCamera(vtkObject*, unsigned long, void*)
{
  this->UpdateCompass();
}

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

bool ViewerWindow::RunAction(const ViewerAction& a,
  const std::string& where,
  bool& quit,
  std::string& error)
{
  vtkRenderWindowInteractor* rwi = this->Interactor;
  auto& p = this->Session.Parameters();
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
  else if (a.Verb == "lake-depth" || a.Verb == "brush-size" || a.Verb == "brush-rate")
  {
    (a.Verb == "lake-depth"      ? p.LakeDepth
        : a.Verb == "brush-size" ? p.BrushRadius
                                 : p.BrushRate) = n[0];
    this->ParametersChanged(false);
  }
  else if (a.Verb == "sensitivity")
  {
    this->TerrainStyle->SetMouseSensitivity(n[0]);
    this->FirstPersonStyle->SetMouseSensitivity(n[0]);
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
    const int x0 = static_cast<int>(n[0]), y0 = static_cast<int>(n[1]);
    const int x1 = a.Verb == "drag" ? static_cast<int>(n[2]) : x0;
    const int y1 = a.Verb == "drag" ? static_cast<int>(n[3]) : y0;
    rwi->SetEventInformationFlipY(x0, y0, a.Control, a.Shift);
    rwi->InvokeEvent(vtkCommand::MouseMoveEvent, nullptr);
    rwi->SetEventInformationFlipY(x0, y0, a.Control, a.Shift);
    rwi->InvokeEvent(vtkCommand::LeftButtonPressEvent, nullptr);
    const int steps = a.Verb == "drag" ? 10 : 0;
    for (int k = 1; k <= steps; ++k)
    {
      const int x = x0 + (x1 - x0) * k / steps;
      const int y = y0 + (y1 - y0) * k / steps;
      rwi->SetEventInformationFlipY(x, y, a.Control, a.Shift);
      rwi->InvokeEvent(vtkCommand::MouseMoveEvent, nullptr);
    }
    rwi->SetEventInformationFlipY(x1, y1, a.Control, a.Shift);
    rwi->InvokeEvent(vtkCommand::LeftButtonReleaseEvent, nullptr);
  }
  else if (a.Verb == "wheel")
  {
    // At the centre of the terrain view.
    const int* size = this->Window->GetSize();
    const double* vp = this->Scene->GetViewport();
    const int x = static_cast<int>(0.5 * (vp[0] + vp[2]) * size[0]);
    const int y = static_cast<int>(0.5 * (vp[1] + vp[3]) * size[1]);
    const int notches = static_cast<int>(n[0]);
    for (int k = 0; k < std::abs(notches); ++k)
    {
      rwi->SetEventInformation(x, y, 0, 0);
      rwi->InvokeEvent(
        notches > 0 ? vtkCommand::MouseWheelForwardEvent : vtkCommand::MouseWheelBackwardEvent,
        nullptr);
    }
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
    this->Session.RequestWaterFlow();
  }
  else if (a.Verb == "wait")
  {
    this->Session.Wait();
    this->CollectResults();
  }
  else if (a.Verb == "camera")
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

//------------------------------------------------------------------------------
int ViewerWindow::Run(TerroirViewerRequest* request)
{
  if (!this->Build(request->TerrainName, request->Error))
  {
    return 1;
  }
  ViewerOverlay first = ViewerOverlay::None;
  terroir::viewer::OverlayFromName(this->Line.View.Overlay, first);
  this->SetOverlay(first);
  this->Window->Render();
  bool quit = false;
  if (request->Actions)
  {
    const std::string script = this->Line.View.Script;
    for (const ViewerAction& a : *request->Actions)
    {
      if (!this->RunAction(a, script + ":" + std::to_string(a.Line), quit, request->Error))
      {
        return 1;
      }
      if (quit || this->QuitRequested)
      {
        break;
      }
    }
  }
  if (!quit && !this->QuitRequested)
  {
    this->Interactor->CreateRepeatingTimer(100);
    this->Interactor->Start();
  }
  this->Session.Wait();
  return 0;
}
} // namespace

extern "C" TERROIR_VIEWER_PLUGIN_EXPORT int terroir_run_viewer(TerroirViewerRequest* request)
{
  ViewerSession session;
  std::string error;
  if (!session.SetTerrain(request->Terrain, error))
  {
    request->Error = request->TerrainName + ": " + error;
    return 1;
  }
  const terroir::app::CommandLine& line = *request->Line;
  auto& p = session.Parameters();
  if (std::isfinite(line.Illumination.Latitude))
  {
    p.Latitude = line.Illumination.Latitude;
  }
  if (std::isfinite(line.Illumination.Longitude))
  {
    p.Longitude = line.Illumination.Longitude;
  }
  p.Month = line.View.Month;
  p.Hour = line.View.Hour;
  p.Orientation = line.View.Orientation;
  p.Clusters = line.View.Clusters;
  p.LakeDepth = line.View.LakeDepth;
  ViewerWindow window(session, line);
  return window.Run(request);
}
