// `terroir kmeans`: ecological zones: k-means of the resource arrays, the zone table
#include "TerroirCommands.h"

#include "TerroirApp.h"
#include "TerroirClusterSupport.h"
#include "TerroirCommandSupport.h"

#include "NumberText.h"
#include "TerroirApp.h"
#include "vtkImageData.h"
#include "vtkNew.h"
#include "vtkTable.h"
#include "vtkTerroirKMeans.h"
#include "vtkTerroirSlope.h"
#include "vtkTerroirTemperature.h"
#include <iomanip>
#include <iostream>

namespace terroir
{
namespace app
{

//------------------------------------------------------------------------------
int CommandKMeans(const CommandLine& c)
{
  const OverlayWriterFunction writeOverlay = CommandOverlayWriter(c);
  const KMeansSettings& s = c.KMeans;
  std::vector<std::string> outs = { c.Output };
  for (const std::string* extra : { &s.Csv, &s.Json, &s.Png })
  {
    if (!extra->empty())
    {
      outs.push_back(*extra);
    }
  }
  CheckWritable(outs, c.Overwrite);
  vtkSmartPointer<vtkImageData> terrain = ReadTerrain(c.Input, c.AllowNetwork, c.ZUnit);

  // A bare DEM (none of the four resources) gets the two that need no location: slope and
  // temperature (Long (2016)'s default climate), as `terroir slope` and `terroir temperature`
  // compute them; --features may then name them.
  if (HasNoDefaultFeature(terrain))
  {
    std::cout << "terroir kmeans: note: " << c.Input
              << " has no resource arrays: Slope and Temperature are computed first, with "
                 "their defaults (cluster terroir run's terrain.vti for all four resources)\n";
    vtkNew<vtkTerroirSlope> slope;
    slope->SetBackend(ParseBackend(c.Backend));
    slope->SetInputData(terrain);
    vtkNew<vtkTerroirTemperature> temperature;
    temperature->SetBackend(ParseBackend(c.Backend));
    temperature->SetInputConnection(slope->GetOutputPort());
    UpdateOrThrow(temperature, "temperature");
    terrain = vtkSmartPointer<vtkImageData>::New();
    terrain->ShallowCopy(temperature->GetOutput());
  }

  vtkNew<vtkTerroirKMeans> kmeans;
  ApplyKMeans(s, c.Backend, kmeans);
  kmeans->SetInputData(terrain);
  WatchProgress(kmeans, "kmeans");
  const double t0 = Now();
  UpdateOrThrow(kmeans, "k-means");
  const double seconds = Now() - t0;
  vtkImageData* out = kmeans->GetOutput();
  vtkTable* table = kmeans->GetClusterTable();

  WriteStageResult(out, vtkTerroirKMeans::ClusterIdName(), c.Output, c.Overwrite);
  if (!s.Csv.empty())
  {
    WriteTextFile(s.Csv, ClusterTableCSV(table), c.Overwrite);
  }
  const nlohmann::ordered_json summary = ClusterTableJSON(table, out);
  if (!s.Json.empty())
  {
    WriteTextFile(s.Json, summary.dump(2) + "\n", c.Overwrite);
  }
  if (!s.Png.empty())
  {
    writeOverlay(out,
      vtkTerroirKMeans::ClusterIdName(),
      "Clusters",
      std::to_string(s.Clusters) + " ecological zones (k-means)",
      s.Png,
      false);
  }

  std::cout << "terroir kmeans (" << std::fixed << std::setprecision(3) << seconds << " s, "
            << summary["iterations"].get<int>() << " iterations, "
            << summary["stop_reason"].get<std::string>() << "): K = " << s.Clusters
            << ", within-cluster sum of squares " << std::setprecision(6) << std::defaultfloat
            << summary["within_cluster_sum_of_squares"].get<double>() << "\n";
  for (const auto& name : summary["collapsed_arrays"])
  {
    std::cout << "  " << name.get<std::string>()
              << ": its months differ by constants, stored as one feature (Long (2016)'s trick)\n";
  }
  for (const auto& row : summary["clusters"])
  {
    std::cout << "  cluster " << row["ClusterId"].get<long long>() << "  "
              << row["Color"].get<std::string>() << "  " << std::setw(9)
              << row["Cells"].get<long long>() << " cells  " << std::fixed << std::setprecision(1)
              << std::setw(5) << 100.0 * row["Share"].get<double>() << " %\n";
  }
  return 0;
}

} // namespace app
} // namespace terroir
