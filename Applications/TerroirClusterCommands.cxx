#include "TerroirClusterCommands.h"

#include "TerroirApp.h"

#include "vtkAbstractArray.h"
#include "vtkDataArray.h"
#include "vtkFieldData.h"
#include "vtkImageData.h"
#include "vtkInformation.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkStringArray.h"
#include "vtkTable.h"
#include "vtkVariant.h"

#include "vtkTerroirKMeans.h"
#include "vtkTerroirSlope.h"
#include "vtkTerroirTemperature.h"

#include "NumberText.h"

#include <cmath>
#include <iomanip>
#include <iostream>
#include <sstream>

namespace terroir
{
namespace app
{
namespace
{
/// A CSV field: quoted when it holds a comma, a quote or a line break.
std::string CsvField(const std::string& text)
{
  if (text.find_first_of(",\"\n") == std::string::npos)
  {
    return text;
  }
  std::string q = "\"";
  for (char ch : text)
  {
    q += ch == '"' ? std::string("\"\"") : std::string(1, ch);
  }
  return q + "\"";
}

double FieldNumber(vtkImageData* image, const char* name)
{
  vtkDataArray* a = vtkDataArray::SafeDownCast(image->GetFieldData()->GetAbstractArray(name));
  return a && a->GetNumberOfTuples() > 0 ? a->GetComponent(0, 0) : std::nan("");
}

/// True when `image` has none of the default features (a bare DEM).
bool HasNoDefaultFeature(vtkImageData* image)
{
  for (const char* name : { "Slope", "Temperature", "IlluminationHours", "WeightedSoilHumidity" })
  {
    if (image->GetPointData()->GetArray(name))
    {
      return false;
    }
  }
  return true;
}
} // namespace

//------------------------------------------------------------------------------
void ApplyKMeans(const KMeansSettings& s, const std::string& backend, vtkTerroirKMeans* filter)
{
  filter->SetBackend(ParseBackend(backend));
  filter->SetNumberOfClusters(s.Clusters);
  filter->RemoveAllFeatures();
  for (std::size_t i = 0; i < s.FeatureNames.size(); ++i)
  {
    filter->AddFeature(s.FeatureNames[i].c_str(), s.FeatureWeights[i]);
  }
  filter->SetStandardize(s.Standardize);
  filter->SetSeeding(
    s.Seeding == "kmeans++" ? vtkTerroirKMeans::KMeansPlusPlus : vtkTerroirKMeans::Diagonal);
  filter->SetRandomSeed(s.Seed);
  filter->SetMaximumIterations(s.MaximumIterations);
  filter->SetTolerance(s.Tolerance);
}

//------------------------------------------------------------------------------
std::string ClusterTableCSV(vtkTable* table)
{
  std::ostringstream os;
  const vtkIdType columns = table->GetNumberOfColumns();
  for (vtkIdType c = 0; c < columns; ++c)
  {
    const char* name = table->GetColumnName(c);
    os << (c ? "," : "") << CsvField(name ? name : "");
  }
  os << "\n";
  for (vtkIdType r = 0; r < table->GetNumberOfRows(); ++r)
  {
    for (vtkIdType c = 0; c < columns; ++c)
    {
      vtkAbstractArray* column = table->GetColumn(c);
      const vtkVariant v = table->GetValue(r, c);
      os << (c ? "," : "");
      if (vtkDataArray::SafeDownCast(column))
      {
        os << terroir::NumberText(v.ToDouble(), 9);
      }
      else
      {
        os << CsvField(v.ToString());
      }
    }
    os << "\n";
  }
  return os.str();
}

//------------------------------------------------------------------------------
nlohmann::ordered_json ClusterTableJSON(vtkTable* table, vtkImageData* image)
{
  nlohmann::ordered_json clusters = nlohmann::ordered_json::array();
  nlohmann::ordered_json units = nlohmann::ordered_json::object();
  for (vtkIdType r = 0; r < table->GetNumberOfRows(); ++r)
  {
    nlohmann::ordered_json row = nlohmann::ordered_json::object();
    for (vtkIdType c = 0; c < table->GetNumberOfColumns(); ++c)
    {
      vtkAbstractArray* column = table->GetColumn(c);
      const std::string name = column->GetName() ? column->GetName() : "";
      const vtkVariant v = table->GetValue(r, c);
      if (auto* numbers = vtkDataArray::SafeDownCast(column))
      {
        const double x = v.ToDouble();
        if (numbers->GetDataType() != VTK_FLOAT && numbers->GetDataType() != VTK_DOUBLE)
        {
          row[name] = static_cast<long long>(x);
        }
        else
        {
          row[name] =
            std::isfinite(x) ? nlohmann::ordered_json(x) : nlohmann::ordered_json(nullptr);
        }
        if (r == 0 && column->GetInformation()->Has(vtkDataArray::UNITS_LABEL()))
        {
          units[name] = column->GetInformation()->Get(vtkDataArray::UNITS_LABEL());
        }
      }
      else
      {
        row[name] = v.ToString();
      }
    }
    clusters.push_back(row);
  }
  nlohmann::ordered_json collapsed = nlohmann::ordered_json::array();
  auto* names =
    vtkStringArray::SafeDownCast(image->GetFieldData()->GetAbstractArray("KMeansCollapsedArrays"));
  for (vtkIdType i = 0; names && i < names->GetNumberOfValues(); ++i)
  {
    collapsed.push_back(names->GetValue(i));
  }
  auto* reason =
    vtkStringArray::SafeDownCast(image->GetFieldData()->GetAbstractArray("KMeansStopReason"));
  return { { "clusters", clusters },
    { "units", units },
    { "within_cluster_sum_of_squares", FieldNumber(image, "KMeansWithinClusterSumOfSquares") },
    { "iterations", static_cast<int>(FieldNumber(image, "KMeansIterations")) },
    { "stop_reason", reason && reason->GetNumberOfValues() ? reason->GetValue(0) : "" },
    { "relocated_clusters", static_cast<int>(FieldNumber(image, "KMeansRelocatedClusters")) },
    { "collapsed_arrays", collapsed } };
}

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
