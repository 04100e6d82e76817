// `terroir info`: grid, georeference and elevation range of a DEM
#include "TerroirCommands.h"

#include "TerroirApp.h"
#include "TerroirCommandSupport.h"

#include "vtkDataArray.h"
#include "vtkImageData.h"
#include "vtkPointData.h"

#include "vtkTerroirGeoreference.h"

#include <nlohmann/json.hpp>

#include <filesystem>
#include <iomanip>
#include <iostream>
#include <string>
#include <vector>

using json = nlohmann::json;

namespace terroir
{
namespace app
{
namespace
{
int Info(const std::string& in, bool allowNetwork, const std::string& zUnit)
{
  vtkSmartPointer<vtkImageData> terrain = terroir::app::ReadTerrain(in, allowNetwork, zUnit);
  int dims[3];
  double spacing[3], origin[3];
  terrain->GetDimensions(dims);
  terrain->GetSpacing(spacing);
  terrain->GetOrigin(origin);
  std::cout << std::setprecision(10) << "file: " << in << "\n"
            << "cells: " << dims[0] << " x " << dims[1] << "\n"
            << "spacing (m): " << spacing[0] << " x " << spacing[1] << "\n"
            << "origin: " << origin[0] << ", " << origin[1] << "\n";
  double ll[2];
  if (vtkTerroirGeoreference::GetCenterLatLon(terrain, ll))
  {
    std::cout << "centre (lat, lon): " << ll[0] << ", " << ll[1] << "\n";
  }
  std::cout << "meridian convergence (deg): "
            << vtkTerroirGeoreference::GetMeridianConvergence(terrain) << "\n";
  std::cout << "geographic grid: "
            << (vtkTerroirGeoreference::GetRowSpacing(terrain) ? "yes" : "no") << "\n";
  if (vtkDataArray* z = terrain->GetPointData()->GetArray("Elevation"))
  {
    const Statistics s = ArrayStatistics(z, 0);
    std::cout << "elevation (m): min " << s.Min << ", mean " << s.Mean << ", max " << s.Max
              << ", valid cells " << s.Valid << "\n";
  }
  return 0;
}
} // namespace

int CommandInfo(const CommandLine& c)
{
  return Info(c.Input, c.AllowNetwork, c.ZUnit);
}

} // namespace app
} // namespace terroir
