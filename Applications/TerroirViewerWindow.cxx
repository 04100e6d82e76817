// The window of `terroir view` (Documentation/Viewer.md), built as the loadable module
// terroir-viewer.so: a thin layer over terroir::viewer::ViewerSession (the model, without any
// window). It draws the relief with vtkTerroirReliefSurface, the overlay legend with
// vtkTerroirOverlayLegend, the overlay list and the tool buttons (both clickable), the status
// line, the sliders, the compass (turned by dragging it) and the cluster table; it turns keys,
// clicks, drags and slider moves into session calls; a repeating interactor timer collects the
// worker thread's results (water-flow frames included); and it replays --script actions as
// real interactor events (SetEventInformation + InvokeEvent), so that scripts test the
// interaction code.
//
// This file builds the window and its widgets and holds the module's entry point; the class
// and the other files are listed in TerroirViewerWindowPrivate.h.
#include "TerroirViewerWindowPrivate.h"

#include "TerroirCommandLine.h"

#include "vtkActor.h"
#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkCommand.h"
#include "vtkCoordinate.h"
#include "vtkImageData.h"
#include "vtkMapper.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkPolyDataMapper.h"
#include "vtkPolyDataMapper2D.h"
#include "vtkProperty.h"
#include "vtkProperty2D.h"
#include "vtkSliderRepresentation2D.h"
#include "vtkTerroirFeatureCurveTerrain.h"
#include "vtkTextProperty.h"
#include "vtkUnsignedCharArray.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

namespace terroir
{
namespace viewer
{
namespace
{
/// Observer callback into a member function.
template<class T, void (T::*Method)(vtkObject*, unsigned long, void*)>
void Forward(vtkObject* caller, unsigned long event, void* clientData, void* callData)
{
  (static_cast<T*>(clientData)->*Method)(caller, event, callData);
}
} // namespace

const char* ToolName(Tool t)
{
  return t == Tool::Lake ? "lake"
    : t == Tool::Brush   ? "brush"
    : t == Tool::Sea     ? "sea"
                         : "navigate";
}

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
  this->BuildLayout(right);

  this->Relief->SetInputData(this->Session.GetTerrain());
  if (!this->Relief->BuildGeometry(error))
  {
    return false;
  }
  this->Relief->GetBaseColor(this->ReliefBaseColor);
  this->Scene->AddActor(this->Relief->GetSurfaceActor());
  this->Scene->AddActor(this->Relief->GetHoleActor());
  if (!this->BuildLevelOfDetail(v.LodPoints, error))
  {
    return false;
  }
  this->Scene->AddLight(this->Sun);
  this->Picker->PickFromListOn();
  this->Picker->AddPickList(this->Relief->GetSurfaceActor());
  this->Picker->SetTolerance(0.0);
  // A cell locator on the surface: a pick (every brush move) then costs a tree walk instead of
  // a test of every triangle.
  if (auto* surface = vtkDataSet::SafeDownCast(
        this->Relief->GetSurfaceActor()->GetMapper()->GetInputDataObject(0, 0)))
  {
    this->SurfaceLocator->SetDataSet(surface);
    this->SurfaceLocator->BuildLocator();
    this->Picker->AddLocator(this->SurfaceLocator);
  }

  const int font = std::max(10, this->Height / 52);
  this->FontSize = font;
  this->BuildTexts(font);

  this->BuildCompass();
  this->BuildButtons(font);
  this->BuildCard();
  this->BuildInteraction();
  this->BuildSliders(right);

  this->ResetCamera(false);
  this->UpdateLight();
  this->Recolour();
  this->UpdateTexts();
  return true;
}

void ViewerWindow::BuildLayout(double right)
{
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
}

void ViewerWindow::BuildTexts(int font)
{
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
  this->Help->SetInput(
    "0-8 overlay  Tab navigation  L lake  B brush  N navigate  Ctrl+Z undo  "
    "G flow  T table  F3 climate  F4 settings  [ ] compass  V/M view  P screenshot  Q quit");
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
}

void ViewerWindow::BuildInteraction()
{
  const terroir::app::ViewSettings& v = this->Line.View;
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
}

void ViewerWindow::BuildSliders(double right)
{
  const auto& p = this->Session.Parameters();
  const double w = right; // sliders share the panel's width: six of 0.145 each
  const double step = 0.163;
  auto span = [w, step](int k, double& x0, double& x1)
  {
    x0 = (0.015 + k * step) * w;
    x1 = x0 + 0.145 * w;
  };
  double x0, x1;
  span(0, x0, x1);
  this->Sliders.push_back(this->AddSlider("Latitude", -90.0, 90.0, p.Latitude, x0, x1, "%.1f"));
  span(1, x0, x1);
  this->Sliders.push_back(this->AddSlider("Month", 1.0, 12.0, p.Month, x0, x1, "%.0f"));
  span(2, x0, x1);
  this->Sliders.push_back(this->AddSlider("Hour", 0.0, 24.0, p.Hour, x0, x1, "%.2f"));
  span(3, x0, x1);
  this->Sliders.push_back(this->AddSlider("Brush mm/h", 0.0, 100.0, p.BrushRate, x0, x1, "%.0f"));
  span(4, x0, x1);
  this->Sliders.push_back(
    this->AddSlider("Slope rule deg", 0.0, 90.0, p.SlopeThreshold, x0, x1, "%.0f"));
  // The sea level runs over the terrain's valid heights; it floods when the drag ends.
  span(5, x0, x1);
  this->ElevationRange[0] = 0.0;
  this->ElevationRange[1] = 1.0;
  vtkImageData* terrain = this->Session.GetTerrain();
  if (!this->Relief->ComputeDataRange(
        terrain->GetPointData()->GetArray("Elevation"), 0, nullptr, this->ElevationRange) ||
    !(this->ElevationRange[1] > this->ElevationRange[0]))
  {
    this->ElevationRange[1] = this->ElevationRange[0] + 1.0;
  }
  this->Sliders.push_back(this->AddSlider("Sea level m",
    this->ElevationRange[0],
    this->ElevationRange[1],
    this->ElevationRange[0],
    x0,
    x1,
    "%.1f"));
  vtkNew<vtkCallbackCommand> released;
  released->SetCallback(Forward<ViewerWindow, &ViewerWindow::OnSeaSliderReleased>);
  released->SetClientData(this);
  this->Sliders[SeaSlider]->AddObserver(vtkCommand::EndInteractionEvent, released);
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
  // A 2 x 5 grid of buttons under the overlay list; a click inside a cell presses it.
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

bool ViewerWindow::BuildLevelOfDetail(long long points, std::string& error)
{
  vtkImageData* terrain = this->Session.GetTerrain();
  const double n = static_cast<double>(terrain->GetNumberOfPoints());
  if (points <= 0 || n <= static_cast<double>(points))
  {
    return true;
  }
  const int stride = static_cast<int>(std::ceil(std::sqrt(n / static_cast<double>(points))));
  this->Coarse->SetInputData(terrain);
  this->Coarse->SetStride(std::max(2, stride));
  if (!this->Coarse->BuildGeometry(error))
  {
    return false;
  }
  this->Scene->AddActor(this->Coarse->GetSurfaceActor());
  this->Scene->AddActor(this->Coarse->GetHoleActor());
  this->HaveCoarse = true;
  this->RenderStartCommand->SetCallback(Forward<ViewerWindow, &ViewerWindow::OnRenderStart>);
  this->RenderStartCommand->SetClientData(this);
  this->Window->AddObserver(vtkCommand::StartEvent, this->RenderStartCommand);
  return true;
}

void ViewerWindow::OnRenderStart(vtkObject*, unsigned long, void*)
{
  const bool full = this->StillRender;
  this->Relief->GetSurfaceActor()->SetVisibility(full);
  this->Relief->GetHoleActor()->SetVisibility(full);
  this->Coarse->GetSurfaceActor()->SetVisibility(!full);
  this->Coarse->GetHoleActor()->SetVisibility(!full);
  this->LastDrawnFull = full;
  if (!full)
  {
    this->StillPending = true;
    this->LastCoarse = std::chrono::steady_clock::now();
  }
}

void ViewerWindow::RenderStill()
{
  if (this->FullColoursStale)
  {
    this->ColouringFull = true;
    this->Recolour();
    this->ColouringFull = false;
    this->FullColoursStale = false;
  }
  this->StillRender = true;
  this->Window->Render();
  this->StillRender = false;
  this->StillPending = false;
}

//------------------------------------------------------------------------------
namespace
{
/// `--curves`: the feature curves' splines (vtkTerroirFeatureCurveTerrain::SampleCurves) draped
/// on the terrain, a little above it (1/200 of the relief), z as the relief surface's
/// (elevation x exaggeration); off the grid, at the curve's own elevation.
vtkSmartPointer<vtkActor> CurveActor(vtkPolyData* curves,
  vtkImageData* terrain,
  double exaggeration)
{
  double spacing[3];
  terrain->GetSpacing(spacing);
  vtkNew<vtkPolyData> lines;
  vtkTerroirFeatureCurveTerrain::SampleCurves(
    curves, 0.25 * std::min(std::abs(spacing[0]), std::abs(spacing[1])), lines);
  vtkDataArray* e = terrain->GetPointData()->GetArray("Elevation");
  double range[2] = { 0.0, 0.0 };
  if (e)
  {
    e->GetRange(range, 0);
  }
  const double lift = 0.005 * (range[1] - range[0]) + 0.5;
  vtkPoints* points = lines->GetPoints();
  for (vtkIdType k = 0; e && k < points->GetNumberOfPoints(); ++k)
  {
    double p[3], pc[3];
    int ijk[3];
    points->GetPoint(k, p);
    double z = p[2];
    const double at[3] = { p[0], p[1], terrain->GetOrigin()[2] };
    if (terrain->ComputeStructuredCoordinates(at, ijk, pc))
    {
      const int* ext = terrain->GetExtent();
      const int i1 = std::min(ijk[0] + 1, ext[1]), j1 = std::min(ijk[1] + 1, ext[3]);
      auto h = [&](int i, int j)
      {
        int q[3] = { i, j, ext[4] };
        return e->GetComponent(terrain->ComputePointId(q), 0);
      };
      const double v = (1 - pc[0]) * (1 - pc[1]) * h(ijk[0], ijk[1]) +
        pc[0] * (1 - pc[1]) * h(i1, ijk[1]) + (1 - pc[0]) * pc[1] * h(ijk[0], j1) +
        pc[0] * pc[1] * h(i1, j1);
      if (std::isfinite(v))
      {
        z = v;
      }
    }
    points->SetPoint(k, p[0], p[1], (z + lift) * exaggeration);
  }
  vtkNew<vtkPolyDataMapper> mapper;
  mapper->SetInputData(lines);
  auto actor = vtkSmartPointer<vtkActor>::New();
  actor->SetMapper(mapper);
  actor->GetProperty()->SetColor(0.85, 0.1, 0.1);
  actor->GetProperty()->SetLineWidth(3.0);
  actor->GetProperty()->LightingOff();
  actor->PickableOff();
  return actor;
}
} // namespace

int ViewerWindow::Run(TerroirViewerRequest* request)
{
  if (!this->Build(request->TerrainName, request->Error))
  {
    return 1;
  }
  if (request->Curves)
  {
    this->Scene->AddActor(CurveActor(
      request->Curves, this->Session.GetTerrain(), this->Relief->GetVerticalExaggeration()));
  }
  ViewerOverlay first = ViewerOverlay::None;
  terroir::viewer::OverlayFromName(this->Line.View.Overlay, first);
  this->SetOverlay(first);
  this->Window->Render();
  bool quit = false;
  if (request->Actions)
  {
    const std::string script = this->Line.View.Script;
    // TERROIR_VIEW_TIMINGS=1: one line per action, the milliseconds it held the window's
    // thread (its handling and the redraw; `wait` also waits for the worker), for
    // Testing/Benchmarks/viewer_session.py.
    const char* timings = std::getenv("TERROIR_VIEW_TIMINGS");
    const bool timed = timings && std::string(timings) == "1";
    for (const ViewerAction& a : *request->Actions)
    {
      const auto start = std::chrono::steady_clock::now();
      if (!this->RunAction(a, script + ":" + std::to_string(a.Line), quit, request->Error))
      {
        return 1;
      }
      if (timed)
      {
        const std::chrono::duration<double, std::milli> ms =
          std::chrono::steady_clock::now() - start;
        std::printf("timing %d %s %.3f\n", a.Line, a.Verb.c_str(), ms.count());
        std::fflush(stdout);
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

} // namespace viewer
} // namespace terroir

extern "C" TERROIR_VIEWER_PLUGIN_EXPORT int terroir_run_viewer(TerroirViewerRequest* request)
{
  terroir::viewer::ViewerSession session;
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
  if (!line.View.ClimateFile.empty())
  {
    if (!session.LoadClimate(line.View.ClimateFile, error))
    {
      request->Error = error;
      return 1;
    }
  }
  else
  {
    // The default climate is an illustrative temperate year, not the site's (on Sagehen Creek
    // it gives July about 6 °C where the station at 1930 m records about 16 °C): say so.
    std::fprintf(stderr,
      "terroir view: the climate is a placeholder (sea-level %.3g °C in the coldest month, %.3g "
      "°C in the warmest, %.3g °C/km, the filters' defaults), not this site's: give --climate "
      "FILE, or edit it in the climate card (F3) or with the script's climate verbs\n",
      p.Coldest,
      p.Warmest,
      p.LapseRate);
  }
  terroir::viewer::ViewerWindow window(session, line);
  return window.Run(request);
}
