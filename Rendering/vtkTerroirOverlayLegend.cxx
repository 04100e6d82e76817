#include "vtkTerroirOverlayLegend.h"

#include "vtkActor2D.h"
#include "vtkCellArray.h"
#include "vtkCoordinate.h"
#include "vtkDataArray.h"
#include "vtkFieldData.h"
#include "vtkImageData.h"
#include "vtkLookupTable.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkPolyDataMapper2D.h"
#include "vtkProperty2D.h"
#include "vtkRenderer.h"
#include "vtkScalarBarActor.h"
#include "vtkTerroirColorPresets.h"
#include "vtkTextActor.h"
#include "vtkTextProperty.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>

vtkStandardNewMacro(vtkTerroirOverlayLegend);

//------------------------------------------------------------------------------
void vtkTerroirOverlayLegend::AddLegend(vtkRenderer* renderer,
  vtkLookupTable* lut,
  const char* preset,
  const std::string& title,
  int fontSize,
  double grey,
  const double background[3])
{
  if (vtkTerroirColorPresets::IsCategorical(preset))
  {
    AddCategoricalLegend(renderer,
      lut,
      title.empty() ? std::string(vtkTerroirColorPresets::GetTitle(preset)) : title,
      fontSize,
      grey,
      background);
  }
  else
  {
    AddScalarBar(renderer, lut, preset, fontSize, grey);
  }
}

//------------------------------------------------------------------------------
std::string vtkTerroirOverlayLegend::ApplyClusterShares(vtkLookupTable* lut,
  const char* preset,
  vtkImageData* image)
{
  // Clusters from vtkTerroirKMeans: each zone's share of the cells (field data
  // KMeansClusterShare, one fraction per cluster id) goes into its legend label, "i: p%", under
  // the title "Cluster (share)" (short enough for the legend column at 400 pixels).
  const char* title = vtkTerroirColorPresets::GetTitle(preset);
  std::string categoricalTitle = title ? title : "";
  vtkDataArray* shares = image && preset && std::strcmp(preset, "Clusters") == 0
    ? image->GetFieldData()->GetArray("KMeansClusterShare")
    : nullptr;
  if (shares && shares->GetNumberOfComponents() == 1)
  {
    categoricalTitle = "Cluster (share)";
    for (vtkIdType k = 0; k < lut->GetNumberOfAnnotatedValues(); ++k)
    {
      const vtkIdType id = lut->GetAnnotatedValue(k).ToInt();
      if (id >= 0 && id < shares->GetNumberOfTuples())
      {
        char label[64];
        std::snprintf(
          label, sizeof(label), "%d: %.0f%%", static_cast<int>(id), 100.0 * shares->GetTuple1(id));
        lut->SetAnnotation(lut->GetAnnotatedValue(k), label);
      }
    }
  }
  return categoricalTitle;
}

//------------------------------------------------------------------------------
void vtkTerroirOverlayLegend::AddScalarBar(vtkRenderer* legendRenderer,
  vtkLookupTable* lut,
  const char* preset,
  int fontSize,
  double grey)
{
  vtkNew<vtkScalarBarActor> bar;
  bar->SetLookupTable(lut);
  // Title on two lines ("Temperature" / "(°C)") so that it fits the narrow legend column.
  std::string legendTitle = vtkTerroirColorPresets::GetTitle(preset);
  const std::string units = vtkTerroirColorPresets::GetUnits(preset);
  if (!units.empty())
  {
    legendTitle += "\n(" + units + ")";
  }
  bar->SetTitle(legendTitle.c_str());
  bar->SetNumberOfLabels(5);
  // Large values (insolation in Wh/m²/day, elevations in m) as whole numbers, not "7.76e+03".
  const double* tableRange = lut->GetTableRange();
  if (std::max(std::fabs(tableRange[0]), std::fabs(tableRange[1])) >= 1000.0)
  {
    bar->SetLabelFormat("%-6.0f");
  }
  bar->SetMaximumNumberOfColors(256);
  bar->SetDrawNanAnnotation(0);
  bar->SetDrawAnnotations(0);
  bar->GetPositionCoordinate()->SetCoordinateSystemToNormalizedViewport();
  bar->SetPosition(0.04, 0.06);
  bar->SetWidth(0.92);
  bar->SetHeight(0.80);
  bar->SetBarRatio(0.22);
  bar->SetTextPositionToSucceedScalarBar(); // labels right of the bar
  bar->UnconstrainedFontSizeOn();
  for (vtkTextProperty* tp : { bar->GetTitleTextProperty(), bar->GetLabelTextProperty() })
  {
    tp->SetColor(grey, grey, grey);
    tp->ShadowOff();
    tp->ItalicOff();
    tp->BoldOff();
    tp->SetFontSize(fontSize);
  }
  bar->GetTitleTextProperty()->BoldOn();
  legendRenderer->AddActor2D(bar);
}

//------------------------------------------------------------------------------
void vtkTerroirOverlayLegend::AddCategoricalLegend(vtkRenderer* legendRenderer,
  vtkLookupTable* lut,
  const std::string& titleText,
  int fontSize,
  double grey,
  const double background[3])
{
  // One swatch and name per annotated value, top to bottom, under the title.
  vtkNew<vtkTextActor> title;
  title->SetInput(titleText.c_str());
  title->GetTextProperty()->SetFontSize(fontSize);
  title->GetTextProperty()->SetColor(grey, grey, grey);
  title->GetTextProperty()->BoldOn();
  title->GetTextProperty()->SetVerticalJustificationToTop();
  title->GetPositionCoordinate()->SetCoordinateSystemToNormalizedViewport();
  title->SetPosition(0.08, 0.94);
  legendRenderer->AddActor2D(title);

  const vtkIdType n = lut->GetNumberOfAnnotatedValues();
  const double rowHeight = std::min(0.07, 0.84 / std::max<vtkIdType>(n, 1));
  for (vtkIdType k = 0; k < n; ++k)
  {
    const double top = 0.88 - k * rowHeight;
    const double bottom = top - 0.75 * rowHeight;
    vtkNew<vtkPoints> corners;
    corners->InsertNextPoint(0.08, bottom, 0.0);
    corners->InsertNextPoint(0.28, bottom, 0.0);
    corners->InsertNextPoint(0.28, top, 0.0);
    corners->InsertNextPoint(0.08, top, 0.0);
    vtkNew<vtkCellArray> quad;
    const vtkIdType ids[4] = { 0, 1, 2, 3 };
    quad->InsertNextCell(4, ids);
    vtkNew<vtkPolyData> swatchData;
    swatchData->SetPoints(corners);
    swatchData->SetPolys(quad);
    vtkNew<vtkCoordinate> normalized;
    normalized->SetCoordinateSystemToNormalizedViewport();
    vtkNew<vtkPolyDataMapper2D> swatchMapper;
    swatchMapper->SetInputData(swatchData);
    swatchMapper->SetTransformCoordinate(normalized);
    vtkNew<vtkActor2D> swatch;
    swatch->SetMapper(swatchMapper);
    const unsigned char* rgba = lut->MapValue(lut->GetAnnotatedValue(k).ToDouble());
    const double rgb[3] = { rgba[0] / 255.0, rgba[1] / 255.0, rgba[2] / 255.0 };
    swatch->GetProperty()->SetColor(rgb[0], rgb[1], rgb[2]);
    legendRenderer->AddActor2D(swatch);
    // A swatch in (nearly) the background colour, such as Sunlit's white "lit" on the white
    // background, gets an outline in the text colour so that it can be seen.
    const double contrast = std::fabs(rgb[0] - background[0]) + std::fabs(rgb[1] - background[1]) +
      std::fabs(rgb[2] - background[2]);
    if (contrast < 0.3)
    {
      vtkNew<vtkCellArray> loop;
      const vtkIdType ring[5] = { 0, 1, 2, 3, 0 };
      loop->InsertNextCell(5, ring);
      vtkNew<vtkPolyData> outlineData;
      outlineData->SetPoints(corners);
      outlineData->SetLines(loop);
      vtkNew<vtkPolyDataMapper2D> outlineMapper;
      outlineMapper->SetInputData(outlineData);
      outlineMapper->SetTransformCoordinate(normalized);
      vtkNew<vtkActor2D> outline;
      outline->SetMapper(outlineMapper);
      outline->GetProperty()->SetColor(grey, grey, grey);
      outline->GetProperty()->SetLineWidth(1.0f);
      legendRenderer->AddActor2D(outline);
    }

    vtkNew<vtkTextActor> label;
    label->SetInput(lut->GetAnnotation(k).c_str());
    label->GetTextProperty()->SetFontSize(fontSize);
    label->GetTextProperty()->SetColor(grey, grey, grey);
    label->GetTextProperty()->SetVerticalJustificationToCentered();
    label->GetPositionCoordinate()->SetCoordinateSystemToNormalizedViewport();
    label->SetPosition(0.34, 0.5 * (top + bottom));
    legendRenderer->AddActor2D(label);
  }
}

//------------------------------------------------------------------------------
void vtkTerroirOverlayLegend::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
}
