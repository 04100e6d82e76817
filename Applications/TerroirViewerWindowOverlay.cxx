// The window of `terroir view` (TerroirViewerWindowPrivate.h): the overlay on the terrain and
// its legend, the water layer, the cluster table, the status and settings texts, the overlay
// list and the buttons' state, and the worker's results collected onto the screen.
#include "TerroirViewerWindowPrivate.h"

#include "vtkDataArray.h"
#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkLookupTable.h"
#include "vtkTerroirColorPresets.h"
#include "vtkTerroirOverlayLegend.h"
#include "vtkTextProperty.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <string>
#include <vector>

namespace terroir
{
namespace viewer
{
namespace
{
/// Code points of a UTF-8 string (for column widths).
std::size_t Utf8Length(const std::string& text)
{
  return static_cast<std::size_t>(std::count_if(text.begin(),
    text.end(),
    [](char c) { return (static_cast<unsigned char>(c) & 0xC0) != 0x80; }));
}
} // namespace

void ViewerWindow::UpdateButtons()
{
  // The current tool's button is blue, as the current overlay; Table is blue while shown.
  const bool tableShown = this->TablePane->GetDraw() != 0;
  for (int k = 0; k < ButtonCount; ++k)
  {
    const bool on = (k == 0 && this->CurrentTool == Tool::Navigate) ||
      (k == 1 && this->CurrentTool == Tool::Lake) || (k == 2 && this->CurrentTool == Tool::Brush) ||
      (k == 7 && tableShown) || (k == 8 && this->OpenCard == Card::Climate) ||
      (k == 9 && this->OpenCard == Card::Settings);
    double cell[4];
    ButtonCell(k, cell);
    const double grey[3] = { 0.8, 0.8, 0.82 };
    const double blue[3] = { 0.62, 0.74, 0.95 };
    SetQuad(this->ButtonQuads, k, cell, on ? blue : grey);
    this->ButtonTexts[k]->GetTextProperty()->SetBold(on);
  }
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
    this->Shown.Table && this->Shown.Error.empty() && this->OpenCard == Card::None;
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
  // With the terrain texture (F8) the texture replaces the overlay's colours.
  if (values && !this->Texturing && this->Shown.Overlay != ViewerOverlay::Water &&
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
    for (vtkTerroirReliefSurface* s : this->Surfaces())
    {
      s->SetColors(values, this->Shown.Component, lut, nullptr);
    }
    vtkTerroirOverlayLegend::AddLegend(this->LegendPane, lut, preset, title, font, 0.0, white);
    legend = true;
  }
  else
  {
    for (vtkTerroirReliefSurface* s : this->Surfaces())
    {
      s->SetUniformColor();
    }
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
    for (vtkTerroirReliefSurface* s : this->Surfaces())
    {
      s->SetColors(water, 0, lut, nullptr, true);
    }
    if (!legend)
    {
      vtkTerroirOverlayLegend::AddLegend(this->LegendPane, lut, "Water", "", font, 0.0, white);
    }
  }
}

void ViewerWindow::CollectResults()
{
  this->Session.Pump();
  OverlayResult result;
  if (this->Session.TakeOverlay(result))
  {
    this->ApplyOverlay(result);
  }
  if (this->Session.GetErosionFrameVersion() != this->ErosionShown)
  {
    // A live erosion's frame: the relief follows the bed (the water below).
    this->ErosionShown = this->Session.GetErosionFrameVersion();
    this->ShowErosionFrame(!this->Session.IsEroding());
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

bool ViewerWindow::ExportTable(const std::string& path, std::string& error)
{
  if (this->Shown.Overlay != ViewerOverlay::Clusters || !this->Shown.Table ||
    !this->Shown.Error.empty())
  {
    error = path + ": no cluster table on screen (show the clusters overlay, key 7)";
    return false;
  }
  const ClusterTable table = ClusterTable::FromKMeans(this->Shown.Table, 0);
  std::string ignored;
  return WriteThroughTemporary(
    path, [&](const std::string& temp) { return table.WriteCsv(temp, ignored); }, error);
}

} // namespace viewer
} // namespace terroir
