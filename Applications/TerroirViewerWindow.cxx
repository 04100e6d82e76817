// The window of `terroir view` (Documentation/Viewer.md), built as the loadable module
// terroir-viewer.so: a thin layer over terroir::viewer::ViewerSession (the model, without any
// window). It draws the relief with vtkTerroirReliefSurface, the overlay legend with
// vtkTerroirOverlayLegend, the overlay list and the tool buttons (both clickable), the status
// line, the sliders, the compass (turned by dragging it) and the cluster table; it turns keys,
// clicks, drags and slider moves into session calls; a repeating interactor timer collects the
// worker thread's results (water-flow frames included); and it replays --script actions as
// real interactor events (SetEventInformation + InvokeEvent), so that scripts test the
// interaction code.
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
#include "vtkCellData.h"
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
#include "vtkUnsignedCharArray.h"
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
using terroir::viewer::ClusterTable;
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

/// The on-screen buttons, in ViewerButtonNames() order: their labels.
const char* const ButtonLabels[] = { "Navigate",
  "Lake",
  "Brush",
  "Fill",
  "Slope rule",
  "Water flow",
  "Undo",
  "Table" };
constexpr int ButtonCount = static_cast<int>(sizeof(ButtonLabels) / sizeof(ButtonLabels[0]));

/// Button k's rectangle in the button pane's normalised viewport coordinates (x0, y0, x1, y1):
/// a grid of two columns, row 0 at the top, with margins.
void ButtonCell(int k, double cell[4])
{
  const int columns = 2;
  const int rows = (ButtonCount + columns - 1) / columns;
  const double w = 0.92 / columns;
  const double h = 0.98 / rows;
  cell[0] = 0.04 + (k % columns) * w;
  cell[2] = cell[0] + w - 0.04;
  cell[3] = 0.98 - (k / columns) * h;
  cell[1] = cell[3] - 0.82 * h;
}

/// Display coordinates (pixels, origin bottom left) to the normalised viewport coordinates of
/// `renderer`; false when outside its viewport.
bool ToViewport(vtkRenderer* renderer, const int* windowSize, int x, int y, double& u, double& v)
{
  const double* vp = renderer->GetViewport();
  u = (x / static_cast<double>(windowSize[0]) - vp[0]) / (vp[2] - vp[0]);
  v = (y / static_cast<double>(windowSize[1]) - vp[1]) / (vp[3] - vp[1]);
  return u >= 0.0 && u < 1.0 && v >= 0.0 && v < 1.0;
}

/// Code points of a UTF-8 string (for column widths).
std::size_t Utf8Length(const std::string& text)
{
  return static_cast<std::size_t>(std::count_if(text.begin(),
    text.end(),
    [](char c) { return (static_cast<unsigned char>(c) & 0xC0) != 0x80; }));
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
  void BuildButtons(int font);

  /// Quads in normalised viewport coordinates of their renderer, one RGB colour each.
  static vtkSmartPointer<vtkActor2D> MakeQuads(vtkPolyData* quads);
  static void SetQuad(vtkPolyData* quads, vtkIdType k, const double cell[4], const double rgb[3]);

  // ---- state to screen ---------------------------------------------------------------------
  void ApplyOverlay(const OverlayResult& result);
  void Recolour();
  void UpdateLight();
  void UpdateCompass();
  void UpdateTexts();
  void UpdateOverlayList();
  void UpdateButtons();
  void UpdateTable();
  void ResetCamera(bool map);
  void CollectResults();
  double EffectiveOrientation() const;

  // ---- commands ----------------------------------------------------------------------------
  void SetOverlay(ViewerOverlay overlay);
  void ParametersChanged(bool affectsOverlay);
  void SetStyle(bool firstPerson);
  void Undo();
  bool PickCell(int x, int y, int& i, int& j);
  void Click(int x, int y);
  void PressButton(int k);
  void InfiltrationChanged();
  void ShowTable(bool show);
  bool Screenshot(const std::string& path, std::string& error);
  std::string NextScreenshotName();

  // ---- observers ---------------------------------------------------------------------------
  void OnKey(vtkObject* caller, unsigned long event, void* callData);
  void OnWheel(vtkObject* caller, unsigned long event, void* callData);
  void OnClick(vtkObject* caller, unsigned long event, void* callData);
  void OnTimer(vtkObject* caller, unsigned long event, void* callData);
  void OnSlider(vtkObject* caller, unsigned long event, void* callData);
  void OnCamera(vtkObject* caller, unsigned long event, void* callData);
  void OnMouse(vtkObject* caller, unsigned long event, void* callData);

  // ---- script ------------------------------------------------------------------------------
  bool RunAction(const ViewerAction& a, const std::string& where, bool& quit, std::string& error);
  void SendKey(const std::string& symbol, bool control, bool shift);
  void SendDrag(int x0, int y0, int x1, int y1, int steps, bool control, bool shift);
  void PrintState();

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
  vtkNew<vtkRenderer> ButtonPane;
  vtkNew<vtkRenderer> LegendPane;
  vtkNew<vtkRenderer> TablePane;
  vtkNew<vtkTerroirReliefSurface> Relief;
  vtkNew<vtkLight> Sun;
  vtkNew<vtkTerroirInteractorStyleTerrain> TerrainStyle;
  vtkNew<vtkTerroirInteractorStyleFirstPerson> FirstPersonStyle;
  bool FirstPerson = false;
  vtkNew<vtkTextActor> Status;
  vtkNew<vtkTextActor> Settings;
  vtkNew<vtkTextActor> Help;
  std::vector<vtkSmartPointer<vtkTextActor>> ListEntries;
  vtkNew<vtkPolyData> ButtonQuads;
  std::vector<vtkSmartPointer<vtkTextActor>> ButtonTexts;
  std::vector<vtkSmartPointer<vtkSliderWidget>> Sliders; // latitude, month, hour, brush rate
  vtkNew<vtkPolyData> CompassArrow;
  vtkNew<vtkActor2D> CompassActor;
  vtkNew<vtkTextActor> CompassLabel;
  vtkNew<vtkCellPicker> Picker;
  vtkNew<vtkCallbackCommand> KeyCommand;
  vtkNew<vtkCallbackCommand> WheelCommand;
  vtkNew<vtkCallbackCommand> MouseCommand;
  OverlayResult Shown; ///< the overlay on screen
  Tool CurrentTool = Tool::Navigate;
  std::string Message;
  bool Computing = false;
  unsigned long WaterShown = 0;   ///< water version on screen
  unsigned long DisplayShown = 0; ///< displayed-water version on screen (flow frames)
  bool QuitRequested = false;     ///< Q or Escape was pressed
  int FontSize = 12;
  // The compass on screen (display pixels) and its drag.
  double CompassCentre[2] = { 0.0, 0.0 };
  double CompassRadius = 1.0;
  bool TurningCompass = false;
  double TurnStartAngle = 0.0;       ///< pointer angle at the press, degrees
  double TurnStartOrientation = 0.0; ///< orientation at the press, degrees
  // A brush stroke under way: the last cell painted.
  bool Painting = false;
  int LastCell[2] = { 0, 0 };
  bool HaveLastCell = false;
  // The cluster table.
  bool TableWanted = true; ///< T / the Table button; shown when the overlay is clusters
  ClusterTable Table;
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

  // Layout: the terrain on the left, a control panel under it, the overlay list, the tool
  // buttons and the legend on the right; the cluster table floats over the terrain.
  const double right = 0.78;
  const double panel = 0.14;
  this->Scene->SetViewport(0.0, panel, right, 1.0);
  this->Scene->SetBackground(0.93, 0.95, 0.98);
  this->Scene->AutomaticLightCreationOff();
  this->Panel->SetViewport(0.0, 0.0, right, panel);
  this->Panel->SetBackground(0.86, 0.87, 0.89);
  this->ListPane->SetViewport(right, 0.64, 1.0, 1.0);
  this->ListPane->SetBackground(1.0, 1.0, 1.0);
  this->ButtonPane->SetViewport(right, 0.42, 1.0, 0.64);
  this->ButtonPane->SetBackground(0.95, 0.95, 0.96);
  this->LegendPane->SetViewport(right, 0.0, 1.0, 0.42);
  this->LegendPane->SetBackground(1.0, 1.0, 1.0);
  // The table is drawn in a layer above the terrain (its own white card: layers above 0 do
  // not clear their background).
  this->Window->SetNumberOfLayers(2);
  this->TablePane->SetLayer(1);
  this->TablePane->DrawOff();
  for (vtkRenderer* r : { this->Scene.Get(),
         this->Panel.Get(),
         this->ListPane.Get(),
         this->ButtonPane.Get(),
         this->LegendPane.Get(),
         this->TablePane.Get() })
  {
    this->Window->AddRenderer(r);
    if (r != this->Scene.Get())
    {
      r->InteractiveOff();
    }
  }

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
  this->FontSize = font;
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
                       "G flow  T table  [ ] compass  V/M view  P screenshot  Q quit");
  this->Scene->AddActor2D(this->Status);
  this->Scene->AddActor2D(this->Settings);
  this->Scene->AddActor2D(this->Help);

  // Overlay list: one line per overlay (a click picks it), the current one bold and blue.
  vtkNew<vtkTextActor> listTitle;
  text(listTitle, 0.06, 0.96, true);
  listTitle->SetInput("Overlays (keys, click)");
  listTitle->GetTextProperty()->BoldOn();
  this->ListPane->AddActor2D(listTitle);
  const int count = static_cast<int>(ViewerOverlay::Count);
  for (int k = 0; k < count; ++k)
  {
    auto entry = vtkSmartPointer<vtkTextActor>::New();
    text(entry, 0.08, 0.84 - k * (0.84 / count), true);
    entry->SetInput(
      (std::to_string(k) + "  " + terroir::viewer::OverlayTitle(static_cast<ViewerOverlay>(k)))
        .c_str());
    this->ListPane->AddActor2D(entry);
    this->ListEntries.push_back(entry);
  }

  this->BuildCompass();
  this->BuildButtons(font);

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
  // Clicks on the list and the buttons, compass turns and brush strokes: before the
  // navigation style and the sliders.
  this->MouseCommand->SetCallback(Forward<ViewerWindow, &ViewerWindow::OnMouse>);
  this->MouseCommand->SetClientData(this);
  for (unsigned long event : { vtkCommand::LeftButtonPressEvent,
         vtkCommand::MouseMoveEvent,
         vtkCommand::LeftButtonReleaseEvent })
  {
    this->Interactor->AddObserver(event, this->MouseCommand, 1.0f);
  }
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

vtkSmartPointer<vtkActor2D> ViewerWindow::MakeQuads(vtkPolyData* quads)
{
  vtkNew<vtkPoints> points;
  quads->SetPoints(points);
  vtkNew<vtkCellArray> cells;
  quads->SetPolys(cells);
  vtkNew<vtkUnsignedCharArray> colours;
  colours->SetNumberOfComponents(3);
  quads->GetCellData()->SetScalars(colours);
  vtkNew<vtkPolyDataMapper2D> mapper;
  mapper->SetInputData(quads);
  mapper->SetScalarModeToUseCellData();
  mapper->SetColorModeToDirectScalars();
  vtkNew<vtkCoordinate> normalised;
  normalised->SetCoordinateSystemToNormalizedViewport();
  mapper->SetTransformCoordinate(normalised);
  auto actor = vtkSmartPointer<vtkActor2D>::New();
  actor->SetMapper(mapper);
  return actor;
}

void ViewerWindow::SetQuad(vtkPolyData* quads,
  vtkIdType k,
  const double cell[4],
  const double rgb[3])
{
  vtkPoints* points = quads->GetPoints();
  auto* colours = vtkUnsignedCharArray::SafeDownCast(quads->GetCellData()->GetScalars());
  // New quads are appended (InsertNext keeps the earlier ones).
  while (quads->GetPolys()->GetNumberOfCells() <= k)
  {
    const vtkIdType q = quads->GetPolys()->GetNumberOfCells();
    const vtkIdType ids[4] = { 4 * q, 4 * q + 1, 4 * q + 2, 4 * q + 3 };
    for (int c = 0; c < 4; ++c)
    {
      points->InsertNextPoint(0.0, 0.0, 0.0);
    }
    colours->InsertNextTuple3(0.0, 0.0, 0.0);
    quads->GetPolys()->InsertNextCell(4, ids);
  }
  points->SetPoint(4 * k, cell[0], cell[1], 0.0);
  points->SetPoint(4 * k + 1, cell[2], cell[1], 0.0);
  points->SetPoint(4 * k + 2, cell[2], cell[3], 0.0);
  points->SetPoint(4 * k + 3, cell[0], cell[3], 0.0);
  for (int c = 0; c < 3; ++c)
  {
    colours->SetComponent(k, c, std::max(0.0, std::min(255.0, std::round(255.0 * rgb[c]))));
  }
  points->Modified();
  colours->Modified();
  quads->Modified();
}

void ViewerWindow::BuildButtons(int font)
{
  // A 2 x 4 grid of buttons under the overlay list; a click inside a cell presses it.
  // UpdateButtons (from UpdateTexts) draws the rectangles, the current tool's in blue.
  this->ButtonPane->AddActor2D(MakeQuads(this->ButtonQuads));
  for (int k = 0; k < ButtonCount; ++k)
  {
    double cell[4];
    ButtonCell(k, cell);
    auto label = vtkSmartPointer<vtkTextActor>::New();
    label->SetInput(ButtonLabels[k]);
    vtkTextProperty* tp = label->GetTextProperty();
    tp->SetFontSize(std::max(9, font - 2));
    tp->SetColor(0.1, 0.1, 0.1);
    tp->SetJustificationToCentered();
    tp->SetVerticalJustificationToCentered();
    label->GetPositionCoordinate()->SetCoordinateSystemToNormalizedViewport();
    label->SetPosition(0.5 * (cell[0] + cell[2]), 0.5 * (cell[1] + cell[3]));
    this->ButtonPane->AddActor2D(label);
    this->ButtonTexts.push_back(label);
  }
}

void ViewerWindow::UpdateButtons()
{
  // The current tool's button is blue, as the current overlay; Table is blue while shown.
  const bool tableShown = this->TablePane->GetDraw() != 0;
  for (int k = 0; k < ButtonCount; ++k)
  {
    const bool on = (k == 0 && this->CurrentTool == Tool::Navigate) ||
      (k == 1 && this->CurrentTool == Tool::Lake) || (k == 2 && this->CurrentTool == Tool::Brush) ||
      (k == 7 && tableShown);
    double cell[4];
    ButtonCell(k, cell);
    const double grey[3] = { 0.8, 0.8, 0.82 };
    const double blue[3] = { 0.62, 0.74, 0.95 };
    SetQuad(this->ButtonQuads, k, cell, on ? blue : grey);
    this->ButtonTexts[k]->GetTextProperty()->SetBold(on);
  }
}

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

void ViewerWindow::ShowTable(bool show)
{
  this->TableWanted = show;
  this->UpdateTable();
  this->UpdateButtons();
}

void ViewerWindow::UpdateTable()
{
  // The cluster table of the clusters overlay on screen: a swatch, the cluster, its share and
  // the month's means, one row per cluster (16 at most), in a fixed-width font.
  this->TablePane->RemoveAllViewProps();
  const bool show = this->TableWanted && this->Shown.Overlay == ViewerOverlay::Clusters &&
    this->Shown.Table && this->Shown.Error.empty();
  this->TablePane->SetDraw(show ? 1 : 0);
  if (!show)
  {
    return;
  }
  const int month = std::max(1, std::min(12, this->Session.Parameters().Month));
  this->Table = ClusterTable::FromKMeans(this->Shown.Table, month);
  const std::size_t maxRows = 16;
  const std::size_t shownRows = std::min(this->Table.Rows.size(), maxRows);
  std::vector<std::size_t> widths;
  std::string header = "Zone  Share";
  for (const std::string& title : this->Table.Columns)
  {
    widths.push_back(std::max<std::size_t>(7, Utf8Length(title)) + 2);
    header += std::string(widths.back() - Utf8Length(title), ' ') + title;
  }
  std::vector<std::string> lines;
  for (std::size_t r = 0; r < shownRows; ++r)
  {
    const auto& row = this->Table.Rows[r];
    char cell[64];
    std::snprintf(cell, sizeof(cell), "%4d %5.1f%%", row.Id, 100.0 * row.Share);
    std::string line = cell;
    for (std::size_t c = 0; c < row.Means.size() && c < widths.size(); ++c)
    {
      std::snprintf(cell, sizeof(cell), "%*.1f", static_cast<int>(widths[c]), row.Means[c]);
      line += cell;
    }
    lines.push_back(line);
  }
  if (this->Table.Rows.size() > shownRows)
  {
    lines.push_back("  ... and " + std::to_string(this->Table.Rows.size() - shownRows) + " more");
  }
  // Size in pixels: Courier is 0.6 em wide; lines 1.35 em apart.
  const int font = std::max(9, this->FontSize - 1);
  const double lineHeight = 1.35 * font;
  const double charWidth = 0.6 * font;
  const double swatch = 1.4 * font;
  std::size_t columns = Utf8Length(header);
  for (const std::string& line : lines)
  {
    columns = std::max(columns, Utf8Length(line));
  }
  const int* size = this->Window->GetSize();
  const double* scene = this->Scene->GetViewport();
  const double widthPx = std::min(
    (scene[2] - scene[0]) * size[0] * 0.96, swatch + charWidth * (columns + 2) + 0.8 * font);
  const double heightPx = lineHeight * (lines.size() + 2.6);
  const double x0 = scene[0] + 0.01;
  const double y0 = scene[1] + 0.06 * (scene[3] - scene[1]);
  this->TablePane->SetViewport(x0,
    y0,
    std::min(scene[2], x0 + widthPx / size[0]),
    std::min(scene[3], y0 + heightPx / size[1]));
  vtkNew<vtkPolyData> card; // a grey frame and the white card inside it
  this->TablePane->AddActor2D(MakeQuads(card));
  const double frame[4] = { 0.0, 0.0, 1.0, 1.0 };
  const double inner[4] = {
    1.5 / widthPx, 1.5 / heightPx, 1.0 - 1.5 / widthPx, 1.0 - 1.5 / heightPx
  };
  const double frameColour[3] = { 0.55, 0.55, 0.58 };
  const double white[3] = { 1.0, 1.0, 1.0 };
  SetQuad(card, 0, frame, frameColour);
  SetQuad(card, 1, inner, white);
  auto place = [&](const std::string& text, double row, double x, bool bold)
  {
    vtkNew<vtkTextActor> actor;
    actor->SetInput(text.c_str());
    vtkTextProperty* tp = actor->GetTextProperty();
    tp->SetFontFamilyToCourier();
    tp->SetFontSize(font);
    tp->SetColor(0.1, 0.1, 0.1);
    tp->SetBold(bold);
    tp->SetVerticalJustificationToCentered();
    actor->GetPositionCoordinate()->SetCoordinateSystemToNormalizedViewport();
    actor->SetPosition(x / widthPx, 1.0 - (row + 0.9) * lineHeight / heightPx);
    this->TablePane->AddActor2D(actor);
  };
  char title[96];
  std::snprintf(title, sizeof(title), "Cluster table, %s (T hides)", MonthNames[month - 1]);
  place(title, 0.0, 0.4 * font, true);
  place(header, 1.1, 0.4 * font + swatch, false);
  vtkNew<vtkPolyData> swatches;
  for (std::size_t r = 0; r < lines.size(); ++r)
  {
    place(lines[r], r + 2.1, 0.4 * font + swatch, false);
    if (r < shownRows)
    {
      double rgb[3] = { 0.5, 0.5, 0.5 };
      unsigned int hex = 0;
      if (std::sscanf(this->Table.Rows[r].Color.c_str(), "#%x", &hex) == 1)
      {
        rgb[0] = ((hex >> 16) & 0xFF) / 255.0;
        rgb[1] = ((hex >> 8) & 0xFF) / 255.0;
        rgb[2] = (hex & 0xFF) / 255.0;
      }
      const double yc = 1.0 - (r + 2.1 + 0.9) * lineHeight / heightPx;
      const double half = 0.4 * font / heightPx;
      const double box[4] = {
        0.4 * font / widthPx, yc - half, (0.4 * font + 0.8 * font) / widthPx, yc + half
      };
      if (r == 0)
      {
        this->TablePane->AddActor2D(MakeQuads(swatches));
      }
      SetQuad(swatches, static_cast<vtkIdType>(r), box, rgb);
    }
  }
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
    char line[200];
    const long long iteration = this->Session.GetFlowFrameIteration();
    std::snprintf(line,
      sizeof(line),
      iteration > 0 ? "%s\xe2\x80\xa6 %.0f %% (iteration %lld on screen)"
                    : "%s\xe2\x80\xa6 %.0f %%",
      this->Session.GetProgressLabel().c_str(),
      100.0 * this->Session.GetProgress(),
      iteration);
    status = line;
  }
  else
  {
    status = this->Message;
  }
  this->Status->SetInput(status.c_str());
  this->UpdateOverlayList();
  this->UpdateButtons();
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
  this->UpdateTable();
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
  // The water state (or the running flow's frame) is a layer over every overlay: transparent
  // where dry.
  this->WaterShown = this->Session.GetWaterVersion();
  this->DisplayShown = this->Session.GetDisplayedWaterVersion();
  vtkFloatArray* water = this->Session.GetDisplayedWater();
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
  else if (this->Session.GetDisplayedWaterVersion() != this->DisplayShown)
  {
    // A frame of the running water flow (or its end, when it changed nothing).
    this->Recolour();
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
  if (this->CurrentTool != Tool::Lake)
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

void ViewerWindow::InfiltrationChanged()
{
  if (this->Session.GetCurrentOverlay() == ViewerOverlay::Humidity)
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
    default:
      break;
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
    this->PressButton(5);
  }
  else if (sym == "t")
  {
    this->PressButton(7);
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
  if (event == vtkCommand::LeftButtonPressEvent)
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
      if (this->HaveLastCell)
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
        if (this->HaveLastCell)
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
      char line[128];
      std::snprintf(line,
        sizeof(line),
        "Painted %lld cells at %.0f mm/h (Ctrl+Z undoes the stroke)",
        changed,
        this->Session.Parameters().BrushRate);
      this->Message = line;
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
              "water-sum %.9g infiltration-sum %.9g table %s\n",
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
    this->TablePane->GetDraw() ? "shown" : "hidden");
  std::fflush(stdout);
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
  else if (a.Verb == "lake-depth" || a.Verb == "brush-size" || a.Verb == "brush-rate" ||
    a.Verb == "slope-threshold")
  {
    (a.Verb == "lake-depth"      ? p.LakeDepth
        : a.Verb == "brush-size" ? p.BrushRadius
        : a.Verb == "brush-rate" ? p.BrushRate
                                 : p.SlopeThreshold) = n[0];
    this->ParametersChanged(false);
  }
  else if (a.Verb == "button")
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
  }
  else if (a.Verb == "state")
  {
    this->PrintState();
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
    this->PressButton(5);
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
