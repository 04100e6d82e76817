/**
 * @file TerroirViewerWindowPrivate.h
 * @brief The window of `terroir view` (terroir-viewer.so), shared by its source files:
 * TerroirViewerWindow.cxx (construction, widgets, the module's entry point),
 * TerroirViewerWindowOverlay.cxx (overlay, legend, cluster table, texts),
 * TerroirViewerWindowCamera.cxx (camera, sun, compass, navigation styles, sliders),
 * TerroirViewerWindowTools.cxx (picking, tools, keys and mouse) and
 * TerroirViewerWindowScript.cxx (the --script actions replayed as interactor events).
 */
#ifndef TerroirViewerWindowPrivate_h
#define TerroirViewerWindowPrivate_h

#include "TerroirViewerPlugin.h"
#include "TerroirViewerScript.h"
#include "TerroirViewerSession.h"

#include "vtkActor2D.h"
#include "vtkCallbackCommand.h"
#include "vtkCellPicker.h"
#include "vtkLight.h"
#include "vtkNew.h"
#include "vtkPolyData.h"
#include "vtkRenderWindow.h"
#include "vtkRenderWindowInteractor.h"
#include "vtkRenderer.h"
#include "vtkSliderWidget.h"
#include "vtkSmartPointer.h"
#include "vtkStaticCellLocator.h"
#include "vtkTerroirInteractorStyleFirstPerson.h"
#include "vtkTerroirInteractorStyleTerrain.h"
#include "vtkTerroirReliefSurface.h"
#include "vtkTerroirTerrainTexture.h"
#include "vtkTerroirXDisplay.h"
#include "vtkTextActor.h"

#include <chrono>
#include <functional>
#include <limits>
#include <string>
#include <vector>

namespace terroir
{
namespace app
{
struct CommandLine;
}
namespace viewer
{

/// Month names, January first (the settings line, the table title, the climate card).
inline const char* const MonthNames[12] = { "January",
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

/// Display coordinates (pixels, origin bottom left) to the normalised viewport coordinates of
/// `renderer`; false when outside its viewport.
inline bool ToViewport(vtkRenderer* renderer,
  const int* windowSize,
  int x,
  int y,
  double& u,
  double& v)
{
  const double* vp = renderer->GetViewport();
  u = (x / static_cast<double>(windowSize[0]) - vp[0]) / (vp[2] - vp[0]);
  v = (y / static_cast<double>(windowSize[1]) - vp[1]) / (vp[3] - vp[1]);
  return u >= 0.0 && u < 1.0 && v >= 0.0 && v < 1.0;
}

/// The cards drawn over the terrain (TerroirViewerWindowCards.cxx).
enum class Card
{
  None,
  Climate, ///< Long (2016)'s climate dialog: monthly precipitation, temperatures, lapse rate
  Settings ///< the navigation settings: control type, mouse sensitivity, move speed
};

/// The tool a click applies.
enum class Tool
{
  Navigate,
  Lake,
  Brush,
  Sea
};

/// The on-screen buttons, in ViewerButtonNames() order: their labels.
const char* const ButtonLabels[] = { "Navigate",
  "Lake",
  "Brush",
  "Fill",
  "Slope rule",
  "Water flow",
  "Undo",
  "Table",
  "Climate",
  "Settings" };
constexpr int ButtonCount = static_cast<int>(sizeof(ButtonLabels) / sizeof(ButtonLabels[0]));

/// Name of a tool as the texts and the state line spell it.
const char* ToolName(Tool t);

/// Button k's rectangle in the button pane's normalised viewport coordinates (x0, y0, x1, y1):
/// a grid of two columns, row 0 at the top, with margins.
void ButtonCell(int k, double cell[4]);

/// The window over a ViewerSession: its renderers and widgets, and the observers that turn
/// keys, clicks, drags, wheel notches and slider moves into session calls.
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
  void BuildLayout(double right); ///< the renderers' viewports (panes right of `right`)
  void BuildTexts(int font);      ///< status, settings, help and the overlay list
  void BuildInteraction();        ///< the interactor, the styles and the observers
  /// Latitude, month, hour, brush rate, slope-rule threshold and sea level under the terrain.
  void BuildSliders(double right);
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
  /// Level of detail: a DEM of more than `points` grid points (--lod-points; 0 never) also gets
  /// a coarse surface (every s-th point, s = ceil(sqrt(points in the DEM / `points`))). Every
  /// render draws the coarse one, except RenderStill's, which the timer makes once the window
  /// has had nothing to draw for StillDelay, and screenshots make: so dragging, zooming,
  /// sliders and keys redraw quickly, and the full detail follows when the user stops.
  bool BuildLevelOfDetail(long long points, std::string& error);
  /// The surface Recolour colours: the full one, or, when there is a coarse one, that one
  /// (the full one is coloured by RenderStill, when it is drawn).
  std::vector<vtkTerroirReliefSurface*> Surfaces()
  {
    if (!this->HaveCoarse || this->ColouringFull)
    {
      return { this->Relief.Get() };
    }
    this->FullColoursStale = true;
    return { this->Coarse.Get() };
  }
  void RenderStill();
  void OnRenderStart(vtkObject* caller, unsigned long event, void* callData);
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
  /// The sea at `level` m (ViewerSession::FloodSea), its outcome in Message.
  void FloodSea(double level);
  void ShowTable(bool show);
  bool Screenshot(const std::string& path, std::string& error);
  /// Runs `write` on a temporary name beside `path`, then renames it into place; false with
  /// "PATH: problem" (and no file left) when either fails.
  static bool WriteThroughTemporary(const std::string& path,
    const std::function<bool(const std::string&)>& write,
    std::string& error);
  /// The first free "terroir-view-NNN.<extension>" in the screenshot folder.
  std::string NextScreenshotName(const char* extension = "png");
  /// K, J, X: K up (Shift: down), the next feature weight under edit, its weight doubled
  /// (Shift: halved); false for another key.
  bool ClusterKey(const std::string& symbol, bool shift);
  /// F2 toggles the orientation edit mode; Left / Right turn the compass while it is on;
  /// false for another key or Left / Right outside the mode.
  bool OrientationKey(const std::string& symbol, bool shift);
  /// Describes K and the weights in Message (the one under edit marked).
  void DescribeClusters();
  /// O, I, Y: the water-flow mode (pulse / rivers), its iterations doubled (Shift: halved),
  /// its water (pulse, mm) or rain rate (rivers, mm/h) doubled (Shift: halved; from the
  /// month's standing water: 10 mm, 1 mm/h); false for another key.
  bool FlowKey(const std::string& symbol, bool shift);
  /// Describes the water-flow settings (and the last run) in Message.
  void DescribeFlow();
  ///@{
  /// Live erosion (TerroirViewerWindowErosion.cxx). ErosionKey: F5 starts or stops it, F6
  /// cycles the erosion brush, F7 keeps the eroded terrain (false for another key).
  /// ErosionCommand: "start", "stop" or "keep", the outcome in Message. ShowErosionFrame: the
  /// relief rebuilt on the newest bed (at most twice a second unless `force`).
  /// PaintErosionAlong: dabs every half radius from cell (i0, j0) to (i1, j1).
  bool ErosionKey(const std::string& symbol);
  void ErosionCommand(const std::string& what);
  void DescribeErosion();
  void ShowErosionFrame(bool force);
  void PaintErosionAlong(double i0, double j0, double i1, double j1);
  std::chrono::steady_clock::time_point LastBedShown;
  unsigned long ErosionShown = 0; ///< erosion frame version on screen
  ///@}
  ///@{
  /// Jensen's terrain texture (F8, `texture on|off`; vtkTerroirTerrainTexture) on the relief
  /// surfaces instead of the overlay's colours; SetTexturing puts it on or takes it off and
  /// redraws, ApplyTexturing puts it back after the geometry was rebuilt.
  void SetTexturing(bool on);
  void ApplyTexturing();
  vtkNew<vtkTerroirTerrainTexture> Texturer;
  bool Texturing = false;
  double ReliefBaseColor[3] = { 0.0, 0.0, 0.0 }; ///< the surfaces' colour without the texture
  ///@}
  /// flow-mode, flow-iterations, flow-water, flow-rain-rate, flow-stop, flow-balance.
  void SetFlowParameter(const ViewerAction& a);
  /// coldest, warmest, lapse-rate, precipitation, intensity, climate-load, climate-save: sets
  /// the climate and recomputes the overlay; false with the error of a file verb.
  bool SetClimate(const ViewerAction& a, std::string& error);
  ///@{
  /// The cards (TerroirViewerWindowCards.cxx). ShowCard opens one (Card::None closes it; the
  /// cluster table gives way while one is open); UpdateCard draws it again; CardKey takes Up,
  /// Down, Left, Right, +, - while one is open; CardMouse a press, drag or release on it
  /// (false when the event is not the card's). StepCardField steps a field by one step
  /// (direction -1 or 1); ClimateEdited recomputes the overlay after a climate change.
  void BuildCard();
  void ShowCard(Card card);
  void UpdateCard();
  void RescaleCharts();
  int CardFieldCount() const;
  bool CardKey(const std::string& symbol);
  bool CardMouse(unsigned long event, int x, int y);
  void StepCardField(int field, int direction);
  void ClimateEdited();
  ///@}
  /// Mouse sensitivity (both navigation styles) and first-person move speed, clamped to
  /// [0.01, 100].
  void SetNavigation(double mouse, double move);
  /// The cluster table on screen with every month's columns as CSV; false with the error.
  bool ExportTable(const std::string& path, std::string& error);

  // ---- observers ---------------------------------------------------------------------------
  void OnKey(vtkObject* caller, unsigned long event, void* callData);
  void OnWheel(vtkObject* caller, unsigned long event, void* callData);
  void OnClick(vtkObject* caller, unsigned long event, void* callData);
  void OnTimer(vtkObject* caller, unsigned long event, void* callData);
  void OnSlider(vtkObject* caller, unsigned long event, void* callData);
  /// The sea-level slider let go: the sea at its value, replacing the sea the slider made
  /// just before when nothing changed the water since (one undo step per release).
  void OnSeaSliderReleased(vtkObject* caller, unsigned long event, void* callData);
  void OnCamera(vtkObject* caller, unsigned long event, void* callData);
  void OnMouse(vtkObject* caller, unsigned long event, void* callData);

  // ---- script ------------------------------------------------------------------------------
  bool RunAction(const ViewerAction& a, const std::string& where, bool& quit, std::string& error);
  /// latitude ... slope-threshold: sets the parameter and redraws (the overlay if it depends).
  void SetParameter(const ViewerAction& a);
  /// A click at the middle of the named button; false when this window has no such button.
  bool SendButton(const ViewerAction& a, const std::string& where, std::string& error);
  void SendWheel(int notches); ///< notches (< 0: backward) at the centre of the terrain view
  void PrintCamera();          ///< the `camera` line: position and focal point
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
  vtkNew<vtkRenderer> CardPane; ///< layer 1, over the terrain: the open card
  Card OpenCard = Card::None;
  /// The card's field under edit: climate 0 precipitation, 1 intensity, 2 coldest, 3 warmest,
  /// 4 lapse rate; settings 0 control type, 1 mouse sensitivity, 2 move speed.
  int CardField = 0;
  int CardMonth = 0;                   ///< the month (0..11) under edit in the climate charts
  int DraggingChart = -1;              ///< the chart a drag is setting, -1 none
  double ChartTops[2] = { 50.0, 5.0 }; ///< the charts' scales, fixed while the card is open
  vtkNew<vtkTerroirReliefSurface> Relief;
  vtkNew<vtkTerroirReliefSurface> Coarse; ///< the level of detail drawn while interacting
  bool HaveCoarse = false;
  bool StillRender = false;      ///< the render under way is RenderStill's (full detail)
  bool StillPending = false;     ///< the screen shows the coarse surface
  bool LastDrawnFull = true;     ///< what the last render drew (`state` prints it)
  bool ColouringFull = false;    ///< Recolour colours the full surface (RenderStill)
  bool FullColoursStale = false; ///< the full surface's colours are older than the coarse's
  std::chrono::steady_clock::time_point LastCoarse; ///< when the coarse surface was last drawn
  static constexpr double StillDelay = 0.3;         ///< seconds without a render, then full
  vtkNew<vtkCallbackCommand> RenderStartCommand;
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
  /// Latitude, month, hour, brush rate, slope-rule threshold, sea level (SeaSlider).
  std::vector<vtkSmartPointer<vtkSliderWidget>> Sliders;
  static constexpr std::size_t SlopeSlider = 4;
  static constexpr std::size_t SeaSlider = 5;
  double ElevationRange[2] = { 0.0, 1.0 }; ///< the sea slider's range: valid heights, m
  /// The last sea level set (slider, click or script), NaN before any; the slider shows it.
  double SeaLevel = std::numeric_limits<double>::quiet_NaN();
  /// Water version and undo depth right after the slider's last sea: when both still hold,
  /// the next release replaces that sea instead of adding to it.
  unsigned long SliderSeaWater = 0;
  std::size_t SliderSeaDepth = 0;
  vtkNew<vtkPolyData> CompassArrow;
  vtkNew<vtkActor2D> CompassActor;
  vtkNew<vtkTextActor> CompassLabel;
  vtkNew<vtkCellPicker> Picker;
  vtkNew<vtkStaticCellLocator> SurfaceLocator; ///< the full surface's cells, for the picker
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
  /// Long (2016)'s orientation edit mode (F2): the compass turns green and Left / Right turn
  /// grid north 1° (Shift: 10°) anticlockwise / clockwise from true north.
  bool OrientationEdit = false;
  double TurnStartAngle = 0.0;       ///< pointer angle at the press, degrees
  double TurnStartOrientation = 0.0; ///< orientation at the press, degrees
  // A brush stroke under way: the last cell painted.
  bool Painting = false;
  int LastCell[2] = { 0, 0 };
  bool HaveLastCell = false;
  // The cluster table.
  bool TableWanted = true; ///< T / the Table button; shown when the overlay is clusters
  ClusterTable Table;
  int WeightUnderEdit = 3; ///< J cycles kViewerClusterFeatures; X doubles, Shift+X halves
};

} // namespace viewer
} // namespace terroir

#endif
