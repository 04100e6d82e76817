#include "TerroirClusterSupport.h"

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

} // namespace

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

} // namespace app
} // namespace terroir
