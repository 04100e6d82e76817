#include "TerroirWaterSupport.h"

#include "TerroirApp.h"

#include "vtkCallbackCommand.h"
#include "vtkCommand.h"
#include "vtkDataArray.h"
#include "vtkFieldData.h"
#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkSmartPointer.h"

#include "vtkTerroirClimateReader.h"
#include "vtkTerroirFloodFill.h"
#include "vtkTerroirGeoreference.h"
#include "vtkTerroirInfiltration.h"
#include "vtkTerroirSoilHumidity.h"
#include "vtkTerroirVectorRasterizer.h"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <iostream>
#include <numeric>
#include <vector>

namespace terroir
{
namespace app
{
/// A raster read onto the terrain's grid: a new image with the terrain's structure and the
/// raster's values as its only (scalar) point array. The raster must have the terrain's size
/// and, when both are georeferenced, the same geotransform.
vtkSmartPointer<vtkImageData> ReadGridOperand(const std::string& path,
  vtkImageData* terrain,
  bool allowNetwork,
  const char* arrayName)
{
  vtkSmartPointer<vtkImageData> raster = ReadTerrain(path, allowNetwork);
  int a[3], b[3];
  terrain->GetDimensions(a);
  raster->GetDimensions(b);
  if (a[0] != b[0] || a[1] != b[1])
  {
    throw Failure(path + ": " + std::to_string(b[0]) + " x " + std::to_string(b[1]) +
      " cells, the DEM has " + std::to_string(a[0]) + " x " + std::to_string(a[1]) +
      "; resample it onto the DEM's grid first (gdalwarp -te ... -ts ...)");
  }
  double gtA[6], gtB[6];
  if (vtkTerroirGeoreference::GetGeoTransform(terrain, gtA) &&
    vtkTerroirGeoreference::GetGeoTransform(raster, gtB))
  {
    const double cell = std::max(std::fabs(gtA[1]), std::fabs(gtA[5]));
    for (int k = 0; k < 6; ++k)
    {
      if (std::fabs(gtA[k] - gtB[k]) > 1e-6 * std::max(1.0, cell))
      {
        throw Failure(path +
          ": its grid (origin or cell size) differs from the DEM's; resample "
          "it onto the DEM's grid first (gdalwarp -te ... -tr ...)");
      }
    }
  }
  vtkDataArray* values = raster->GetPointData()->GetArray(vtkTerroirGeoreference::ElevationName());
  if (!values)
  {
    throw Failure(path + ": no raster values");
  }
  auto out = vtkSmartPointer<vtkImageData>::New();
  out->CopyStructure(terrain);
  vtkSmartPointer<vtkDataArray> copy = vtkSmartPointer<vtkDataArray>::Take(values->NewInstance());
  copy->DeepCopy(values);
  copy->SetName(arrayName);
  out->GetPointData()->SetScalars(copy);
  return out;
}

/// Polygons burnt onto the terrain's grid: a new image whose scalars are the burnt values
/// (1 inside and 0 outside, or the attribute `field` inside and NaN outside).
vtkSmartPointer<vtkImageData> RasterizePolygons(const std::string& path,
  const std::string& field,
  vtkImageData* terrain,
  bool allowNetwork,
  bool quiet)
{
  vtkNew<vtkTerroirVectorRasterizer> rasterizer;
  vtkNew<vtkCallbackCommand> swallow; // an observed warning is not printed
  if (quiet)
  {
    rasterizer->AddObserver(vtkCommand::WarningEvent, swallow);
  }
  rasterizer->SetInputData(terrain);
  rasterizer->SetAllowNetworkPaths(allowNetwork);
  rasterizer->SetFileName(path.c_str());
  rasterizer->SetOutputArrayName("Painted");
  if (!field.empty())
  {
    rasterizer->SetAttributeName(field.c_str());
  }
  UpdateOrThrow(rasterizer, path);
  auto out = vtkSmartPointer<vtkImageData>::New();
  out->CopyStructure(terrain);
  vtkDataArray* burnt = rasterizer->GetOutput()->GetPointData()->GetArray("Painted");
  if (!burnt)
  {
    throw Failure(path + ": nothing was rasterised");
  }
  out->GetPointData()->SetScalars(burnt);
  return out;
}

void ApplyInfiltration(const SoilWaterSettings& s,
  vtkTerroirInfiltration* filter,
  vtkImageData* terrain,
  bool allowNetwork)
{
  for (const InfiltrationOperation& op : s.Operations)
  {
    if (op.Kind == "fill")
    {
      filter->AddFill(op.Value);
    }
    else if (op.Kind == "slope-rule")
    {
      filter->AddSlopeRule(op.Value);
    }
    else if (op.Kind == "paint-raster")
    {
      filter->AddPaintMask(ReadGridOperand(op.File, terrain, allowNetwork, "Mask"), op.Value);
    }
    else if (op.Kind == "paint-polygons")
    {
      filter->AddPaintMask(RasterizePolygons(op.File, "", terrain, allowNetwork), op.Value);
    }
    else if (op.Kind == "soil-raster")
    {
      filter->AddSoilTypes(ReadGridOperand(op.File, terrain, allowNetwork, "SoilType"));
    }
    else if (op.Kind == "soil-polygons")
    {
      filter->AddSoilTypes(RasterizePolygons(op.File, op.Attribute, terrain, allowNetwork));
    }
    else
    {
      throw Failure("unknown infiltration operation '" + op.Kind + "'");
    }
  }
}

void ApplyClimate(const SoilWaterSettings& s, vtkTerroirSoilHumidity* filter)
{
  // The filter's default rain is an illustrative year, not the site's: say so (stderr).
  if (s.ClimateFile.empty() && s.Precipitation.empty() && s.Intensity.empty())
  {
    double total = 0.0;
    for (int m = 0; m < 12; ++m)
    {
      total += filter->GetPrecipitation()[m];
    }
    char note[240];
    std::snprintf(note,
      sizeof(note),
      "the precipitation comes from a placeholder climate (%.0f mm a year), not this site's: "
      "give --precip and --intensity or --climate FILE",
      total);
    AddNote(note);
  }
  if (!s.ClimateFile.empty())
  {
    vtkNew<vtkTerroirClimateReader> climate;
    climate->SetFileName(s.ClimateFile.c_str());
    TakeLastVTKError();
    const bool ok = climate->Read();
    TakeLastVTKError(); // reported below, once
    if (!ok)
    {
      throw Failure(climate->GetErrorMessage());
    }
    if (!climate->HasPrecipitation() || !climate->HasPrecipitationIntensity())
    {
      throw Failure(s.ClimateFile +
        ": needs both precipitation_mm and intensity_mm_per_h for the soil-water model");
    }
    filter->SetPrecipitation(climate->GetPrecipitation());
    filter->SetPrecipitationIntensity(climate->GetPrecipitationIntensity());
    return;
  }
  if (s.Precipitation.size() == 12)
  {
    filter->SetPrecipitation(s.Precipitation.data());
  }
  if (s.Intensity.size() == 12)
  {
    filter->SetPrecipitationIntensity(s.Intensity.data());
  }
}

void ApplyFloodFill(const FloodFillSettings& s, vtkTerroirFloodFill* filter)
{
  if (s.FillDepressions)
  {
    filter->SetModeToFillDepressions();
    filter->SetMinimumArea(s.MinimumArea);
    filter->SetIncludeFlatSurfaces(s.FlatSurfaces);
    return;
  }
  filter->SetModeToSeeds();
  for (const FloodFillSettings::Seed& seed : s.Seeds)
  {
    const double level = std::isfinite(seed.Level) ? seed.Level : s.Level;
    const bool hasLevel = std::isfinite(level);
    if (seed.Cell)
    {
      const int i = static_cast<int>(seed.X);
      const int j = static_cast<int>(seed.Y);
      hasLevel ? filter->AddSeedCell(i, j, level) : filter->AddSeedCell(i, j);
    }
    else
    {
      hasLevel ? filter->AddSeedPoint(seed.X, seed.Y, level) : filter->AddSeedPoint(seed.X, seed.Y);
    }
  }
}

void PrintWaterBodies(vtkImageData* result, int limit)
{
  vtkFieldData* fd = result->GetFieldData();
  vtkDataArray* level = fd->GetArray(vtkTerroirFloodFill::WaterBodyLevelName());
  vtkDataArray* cells = fd->GetArray(vtkTerroirFloodFill::WaterBodyCellsName());
  vtkDataArray* area = fd->GetArray(vtkTerroirFloodFill::WaterBodyAreaName());
  vtkDataArray* volume = fd->GetArray(vtkTerroirFloodFill::WaterBodyVolumeName());
  vtkDataArray* depth = fd->GetArray(vtkTerroirFloodFill::WaterBodyMaxDepthName());
  if (!level || !cells || !area || !volume || !depth)
  {
    return;
  }
  const vtkIdType n = level->GetNumberOfTuples();
  std::vector<vtkIdType> order(static_cast<std::size_t>(n));
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(),
    order.end(),
    [&](vtkIdType a, vtkIdType b) { return area->GetComponent(a, 0) > area->GetComponent(b, 0); });
  std::cout << n << " water bod" << (n == 1 ? "y" : "ies") << (n > limit ? ", largest first" : "")
            << "\n";
  if (n == 0)
  {
    return;
  }
  std::cout << std::right << std::setw(6) << "id" << std::setw(12) << "level m" << std::setw(10)
            << "cells" << std::setw(12) << "area ha" << std::setw(14) << "volume m3"
            << std::setw(14) << "max depth m"
            << "\n";
  for (vtkIdType r = 0; r < std::min<vtkIdType>(n, limit); ++r)
  {
    const vtkIdType k = order[static_cast<std::size_t>(r)];
    std::cout << std::fixed << std::setw(6) << k + 1 << std::setw(12) << std::setprecision(2)
              << level->GetComponent(k, 0) << std::setw(10) << std::setprecision(0)
              << cells->GetComponent(k, 0) << std::setw(12) << std::setprecision(2)
              << area->GetComponent(k, 0) / 1e4 << std::setw(14) << std::setprecision(0)
              << volume->GetComponent(k, 0) << std::setw(14) << std::setprecision(2)
              << depth->GetComponent(k, 0) << "\n";
  }
}

} // namespace app
} // namespace terroir
