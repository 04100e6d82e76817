// The window of `terroir view` (TerroirViewerWindowPrivate.h): the cards drawn over the terrain
// (layer 1, as the cluster table): the climate card, Long (2016)'s climate dialog (§3.2.3,
// Fig. 3.11: twelve monthly precipitation quantities and intensities as bar charts, the
// coldest and warmest sea-level temperatures and the lapse rate), and the navigation settings
// card (his settings interface, §3.1.3 and Table 3.1: control type and sensitivities).
// Mouse: a press or drag in a chart sets the month under the pointer to the height of the
// pointer; [-] and [+] step a value. Keys while a card is open: Up / Down pick the field,
// Left / Right the month, + / - step the value. F3 and F4 (or the Climate and Settings buttons)
// open and close them.
#include "TerroirViewerWindowPrivate.h"

#include "vtkTextProperty.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace terroir
{
namespace viewer
{

namespace
{
const char* const MonthLetters[12] = { "J", "F", "M", "A", "M", "J", "J", "A", "S", "O", "N", "D" };

/// Where the parts of a card lie, in the card's normalised viewport coordinates.
struct CardLayout
{
  /// Chart c (0 precipitation, 1 intensity): its plot box x0, y0, x1, y1.
  static void Chart(int c, double box[4])
  {
    box[0] = 0.11;
    box[2] = 0.97;
    box[1] = c == 0 ? 0.63 : 0.285;
    box[3] = c == 0 ? 0.86 : 0.515;
  }
  /// The climate card's rows below the charts (fields 2, 3, 4) or the settings card's rows
  /// (fields 0, 1, 2): the middle height of row r.
  static double Row(Card card, int r)
  {
    return card == Card::Climate ? 0.205 - 0.07 * r : 0.70 - 0.2 * r;
  }
  /// The [-] (sign < 0) or [+] button of a row whose middle is at `y`.
  static void StepButton(Card card, double y, int sign, double box[4])
  {
    const double h = card == Card::Climate ? 0.026 : 0.07;
    box[0] = sign < 0 ? 0.74 : 0.86;
    box[2] = box[0] + 0.1;
    box[1] = y - h;
    box[3] = y + h;
  }
  /// The climate card's Save button (top right).
  static void SaveButton(double box[4])
  {
    box[0] = 0.80;
    box[2] = 0.97;
    box[1] = 0.925;
    box[3] = 0.985;
  }
  static bool Inside(const double box[4], double u, double v)
  {
    return u >= box[0] && u <= box[2] && v >= box[1] && v <= box[3];
  }
};

/// A chart's top value: a round number at least 1.25 times the largest month.
double ChartTop(const std::array<double, 12>& values, double unit, double least)
{
  const double largest = *std::max_element(values.begin(), values.end());
  return std::max(least, unit * std::ceil(1.25 * largest / unit));
}

} // namespace

int ViewerWindow::CardFieldCount() const
{
  return this->OpenCard == Card::Climate ? 5 : this->OpenCard == Card::Settings ? 3 : 0;
}

void ViewerWindow::ShowCard(Card card)
{
  this->OpenCard = card;
  this->CardField = 0;
  this->DraggingChart = -1;
  if (card == Card::Climate)
  {
    this->RescaleCharts();
    this->CardPane->SetViewport(0.01, 0.17, 0.55, 0.93);
    this->Message = "Climate: drag the bars, [-]/[+] or Up/Down, Left/Right, +/- (F3 closes)";
  }
  else if (card == Card::Settings)
  {
    this->CardPane->SetViewport(0.01, 0.60, 0.55, 0.93);
    this->Message = "Navigation settings: [-]/[+] or Up/Down, +/- (F4 closes)";
  }
  else
  {
    this->Message = "Card closed";
  }
  this->UpdateCard();
  this->UpdateTable(); // the cluster table gives way to a card
  this->UpdateTexts();
}

void ViewerWindow::RescaleCharts()
{
  const auto& p = this->Session.Parameters();
  this->ChartTops[0] = ChartTop(p.Precipitation, 50.0, 50.0);
  this->ChartTops[1] = ChartTop(p.PrecipitationIntensity, 5.0, 5.0);
}

void ViewerWindow::BuildCard()
{
  this->CardPane->SetLayer(1);
  this->CardPane->InteractiveOff();
  this->CardPane->DrawOff();
  this->Window->AddRenderer(this->CardPane);
}

void ViewerWindow::UpdateCard()
{
  this->CardPane->RemoveAllViewProps();
  this->CardPane->SetDraw(this->OpenCard == Card::None ? 0 : 1);
  if (this->OpenCard == Card::None)
  {
    return;
  }
  const auto& p = this->Session.Parameters();
  const int font = this->FontSize;
  // The quads (background, bars, buttons) first: the texts are drawn over them.
  vtkNew<vtkPolyData> quads;
  this->CardPane->AddActor2D(MakeQuads(quads));
  vtkIdType q = 0;
  const double white[3] = { 1.0, 1.0, 1.0 };
  const double frame[4] = { 0.0, 0.0, 1.0, 1.0 };
  SetQuad(quads, q++, frame, white);
  auto text = [this](const std::string& s, double x, double y, int size, bool bold, int align)
  {
    vtkNew<vtkTextActor> t;
    t->SetInput(s.c_str());
    vtkTextProperty* tp = t->GetTextProperty();
    tp->SetFontSize(size);
    tp->SetBold(bold);
    tp->SetColor(bold ? 0.1 : 0.15, bold ? 0.25 : 0.15, bold ? 0.6 : 0.15);
    tp->SetJustification(align < 0 ? VTK_TEXT_LEFT
        : align > 0                ? VTK_TEXT_RIGHT
                                   : VTK_TEXT_CENTERED);
    tp->SetVerticalJustificationToCentered();
    t->GetPositionCoordinate()->SetCoordinateSystemToNormalizedViewport();
    t->SetPosition(x, y);
    this->CardPane->AddActor2D(t);
  };
  const double grey[3] = { 0.8, 0.8, 0.82 };
  const double blue[3] = { 0.2, 0.42, 0.78 };
  const double orange[3] = { 0.93, 0.55, 0.15 };
  const double axis[3] = { 0.45, 0.45, 0.45 };
  auto stepButtons = [&](double y)
  {
    for (int sign : { -1, 1 })
    {
      double box[4];
      CardLayout::StepButton(this->OpenCard, y, sign, box);
      SetQuad(quads, q++, box, grey);
      text(sign < 0 ? "-" : "+", 0.5 * (box[0] + box[2]), y, font, false, 0);
    }
  };
  char line[160];
  if (this->OpenCard == Card::Climate)
  {
    text("Climate (Long 2016, eq. 3.4-3.5)   F3 closes", 0.03, 0.955, font, true, -1);
    double save[4];
    CardLayout::SaveButton(save);
    SetQuad(quads, q++, save, grey);
    text("Save CSV", 0.5 * (save[0] + save[2]), 0.5 * (save[1] + save[3]), font - 2, false, 0);
    for (int c = 0; c < 2; ++c)
    {
      const auto& values = c == 0 ? p.Precipitation : p.PrecipitationIntensity;
      double box[4];
      CardLayout::Chart(c, box);
      const bool chartSelected = this->CardField == c;
      std::snprintf(line,
        sizeof(line),
        c == 0 ? "Precipitation, mm per month (0-%.0f)" : "Intensity, mm/h (0-%.0f)",
        this->ChartTops[c]);
      text(line, 0.03, box[3] + 0.04, font - 1, chartSelected, -1);
      const double base[4] = { box[0], box[1] - 0.002, box[2], box[1] };
      SetQuad(quads, q++, base, axis);
      const double slot = (box[2] - box[0]) / 12.0;
      for (int m = 0; m < 12; ++m)
      {
        const double top = this->ChartTops[c];
        const double h = std::max(0.0, std::min(1.0, values[m] / top)) * (box[3] - box[1]);
        const double bar[4] = { box[0] + (m + 0.15) * slot,
          box[1],
          box[0] + (m + 0.85) * slot,
          box[1] + std::max(h, 0.002) };
        SetQuad(quads, q++, bar, chartSelected && m == this->CardMonth ? orange : blue);
        std::snprintf(line, sizeof(line), c == 0 ? "%.0f" : "%.1f", values[m]);
        text(line, box[0] + (m + 0.5) * slot, bar[3] + 0.018, font - 4, false, 0);
        text(MonthLetters[m], box[0] + (m + 0.5) * slot, box[1] - 0.022, font - 3, false, 0);
      }
    }
    const char* const labels[3] = { "Coldest month, sea level: %.1f \xc2\xb0"
                                    "C",
      "Warmest month, sea level: %.1f \xc2\xb0"
      "C",
      "Lapse rate: %.2f \xc2\xb0"
      "C per km" };
    const double values[3] = { p.Coldest, p.Warmest, p.LapseRate };
    for (int r = 0; r < 3; ++r)
    {
      const double y = CardLayout::Row(this->OpenCard, r);
      std::snprintf(line, sizeof(line), labels[r], values[r]);
      std::string s = line;
      if (r < 2 && p.UseMonthlyTemperatures)
      {
        s += " (12 months from a file in use)";
      }
      text(s, 0.03, y, font - 1, this->CardField == r + 2, -1);
      stepButtons(y);
    }
  }
  else
  {
    text("Navigation settings (Long 2016, Table 3.1)   F4 closes", 0.03, 0.9, font, true, -1);
    const double move = this->FirstPersonStyle->GetMoveSensitivity();
    const double mouse = this->TerrainStyle->GetMouseSensitivity();
    std::string rows[3] = { std::string("Control type: ") +
        (this->FirstPerson ? "first-person (W/A/S/D move, drag looks)"
                           : "click and drag (drag pans, wheel zooms)"),
      "",
      "" };
    std::snprintf(line, sizeof(line), "Mouse sensitivity: %.3g", mouse);
    rows[1] = line;
    std::snprintf(line, sizeof(line), "First-person move speed: %.3g", move);
    rows[2] = line;
    for (int r = 0; r < 3; ++r)
    {
      const double y = CardLayout::Row(this->OpenCard, r);
      text(rows[r], 0.03, y, font - 1, this->CardField == r, -1);
      stepButtons(y);
    }
  }
}

void ViewerWindow::StepCardField(int field, int direction)
{
  auto& p = this->Session.Parameters();
  if (this->OpenCard == Card::Climate)
  {
    if (field == 0 || field == 1)
    {
      auto& values = field == 0 ? p.Precipitation : p.PrecipitationIntensity;
      const double step = field == 0 ? 5.0 : 0.5;
      double& v = values[static_cast<std::size_t>(this->CardMonth)];
      v = std::max(0.0, std::min(field == 0 ? 10000.0 : 500.0, v + direction * step));
      if (v > this->ChartTops[field])
      {
        this->RescaleCharts();
      }
    }
    else if (field == 2 || field == 3)
    {
      double& v = field == 2 ? p.Coldest : p.Warmest;
      v = std::max(-90.0, std::min(60.0, v + direction));
      p.UseMonthlyTemperatures = false;
    }
    else
    {
      p.LapseRate = std::max(0.0, std::min(20.0, p.LapseRate + 0.5 * direction));
    }
    this->ClimateEdited();
  }
  else if (this->OpenCard == Card::Settings)
  {
    if (field == 0)
    {
      this->SetStyle(!this->FirstPerson);
    }
    else
    {
      const double factor = direction > 0 ? 1.25 : 0.8;
      if (field == 1)
      {
        this->SetNavigation(this->TerrainStyle->GetMouseSensitivity() * factor,
          this->FirstPersonStyle->GetMoveSensitivity());
      }
      else
      {
        this->SetNavigation(this->TerrainStyle->GetMouseSensitivity(),
          this->FirstPersonStyle->GetMoveSensitivity() * factor);
      }
    }
    this->UpdateCard();
    this->UpdateTexts();
  }
}

void ViewerWindow::SetNavigation(double mouse, double move)
{
  mouse = std::max(0.01, std::min(100.0, mouse));
  move = std::max(0.01, std::min(100.0, move));
  this->TerrainStyle->SetMouseSensitivity(mouse);
  this->FirstPersonStyle->SetMouseSensitivity(mouse);
  this->FirstPersonStyle->SetMoveSensitivity(move);
  char line[120];
  std::snprintf(line, sizeof(line), "Mouse sensitivity %.3g, move speed %.3g", mouse, move);
  this->Message = line;
  if (this->OpenCard == Card::Settings)
  {
    this->UpdateCard();
  }
}

void ViewerWindow::ClimateEdited()
{
  const auto& p = this->Session.Parameters();
  const int m = this->CardMonth;
  char line[200];
  std::snprintf(line,
    sizeof(line),
    "Climate: %s %.0f mm at %.1f mm/h; coldest %.1f, warmest %.1f \xc2\xb0"
    "C; lapse rate %.2f \xc2\xb0"
    "C/km",
    MonthNames[m],
    p.Precipitation[static_cast<std::size_t>(m)],
    p.PrecipitationIntensity[static_cast<std::size_t>(m)],
    p.Coldest,
    p.Warmest,
    p.LapseRate);
  this->Message = line;
  this->ParametersChanged(true); // draws the card again
}

bool ViewerWindow::CardKey(const std::string& symbol)
{
  if (this->OpenCard == Card::None)
  {
    return false;
  }
  const int fields = this->CardFieldCount();
  if (symbol == "Up" || symbol == "Down")
  {
    this->CardField = (this->CardField + (symbol == "Down" ? 1 : fields - 1)) % fields;
  }
  else if ((symbol == "Left" || symbol == "Right") && this->OpenCard == Card::Climate)
  {
    this->CardMonth = (this->CardMonth + (symbol == "Right" ? 1 : 11)) % 12;
  }
  else if (symbol == "plus" || symbol == "+" || symbol == "equal" || symbol == "=" ||
    symbol == "KP_Add" || symbol == "minus" || symbol == "-" || symbol == "KP_Subtract")
  {
    const bool down = symbol == "minus" || symbol == "-" || symbol == "KP_Subtract";
    this->StepCardField(this->CardField, down ? -1 : 1);
    return true;
  }
  else
  {
    return false;
  }
  this->UpdateCard();
  return true;
}

bool ViewerWindow::CardMouse(unsigned long event, int x, int y)
{
  if (this->OpenCard == Card::None)
  {
    return false;
  }
  const int* size = this->Window->GetSize();
  double u = 0.0, v = 0.0;
  const bool inside = ToViewport(this->CardPane, size, x, y, u, v);
  auto& p = this->Session.Parameters();
  // The chart month and value under the pointer (clamped to the chart).
  auto setBar = [&](int c)
  {
    double box[4];
    CardLayout::Chart(c, box);
    const int m = std::max(
      0, std::min(11, static_cast<int>(std::floor((u - box[0]) / (box[2] - box[0]) * 12.0))));
    const double f = std::max(0.0, std::min(1.0, (v - box[1]) / (box[3] - box[1])));
    const double unit = c == 0 ? 1.0 : 0.1;
    (c == 0 ? p.Precipitation : p.PrecipitationIntensity)[static_cast<std::size_t>(m)] =
      unit * std::round(f * this->ChartTops[c] / unit);
    this->CardField = c;
    this->CardMonth = m;
  };
  if (event == vtkCommand::LeftButtonPressEvent)
  {
    if (!inside)
    {
      return false;
    }
    if (this->OpenCard == Card::Climate)
    {
      double save[4];
      CardLayout::SaveButton(save);
      if (CardLayout::Inside(save, u, v))
      {
        std::string error;
        const std::string path = this->NextScreenshotName("csv");
        this->Message =
          this->Session.SaveClimate(path, error) ? "Saved the climate to " + path : error;
        return true;
      }
      for (int c = 0; c < 2; ++c)
      {
        double box[4];
        CardLayout::Chart(c, box);
        const double grown[4] = { box[0], box[1] - 0.03, box[2], box[3] + 0.02 };
        if (CardLayout::Inside(grown, u, v))
        {
          this->DraggingChart = c;
          setBar(c);
          this->UpdateCard();
          return true;
        }
      }
    }
    const int first = this->OpenCard == Card::Climate ? 2 : 0;
    for (int r = 0; r < this->CardFieldCount() - first; ++r)
    {
      const double y = CardLayout::Row(this->OpenCard, r);
      for (int sign : { -1, 1 })
      {
        double box[4];
        CardLayout::StepButton(this->OpenCard, y, sign, box);
        if (CardLayout::Inside(box, u, v))
        {
          this->CardField = first + r;
          this->StepCardField(first + r, sign);
          return true;
        }
      }
    }
    return true; // the card is not the terrain
  }
  if (this->DraggingChart < 0)
  {
    return false;
  }
  ToViewport(this->CardPane, size, x, y, u, v); // u, v even outside the card
  setBar(this->DraggingChart);
  if (event == vtkCommand::LeftButtonReleaseEvent)
  {
    this->DraggingChart = -1;
    this->ClimateEdited(); // the overlay is recomputed once, at the release
  }
  else
  {
    this->UpdateCard();
  }
  return true;
}

} // namespace viewer
} // namespace terroir
