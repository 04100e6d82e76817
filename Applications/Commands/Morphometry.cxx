// `terroir morphometry`: vtkTerroirMorphometry on a DEM: prints the landscape statistics, and
// writes them as JSON (--json), the Horton table as CSV (--csv) and the per-cell arrays (OUT).
#include "TerroirCommands.h"

#include "TerroirApp.h"
#include "TerroirCommandSupport.h"

#include "vtkDataArray.h"
#include "vtkFieldData.h"
#include "vtkImageData.h"
#include "vtkNew.h"

#include "TerroirSafeOutput.h"
#include "vtkTerroirMorphometry.h"

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

namespace terroir
{
namespace app
{
namespace
{
/// Every value of a field array (empty when missing).
std::vector<double> FieldValues(vtkImageData* image, const char* name)
{
  std::vector<double> v;
  vtkDataArray* a = vtkDataArray::SafeDownCast(image->GetFieldData()->GetAbstractArray(name));
  if (a)
  {
    for (vtkIdType k = 0; k < a->GetNumberOfValues(); ++k)
    {
      v.push_back(a->GetComponent(k, 0));
    }
  }
  return v;
}

/// A number for JSON: null when not finite.
nlohmann::ordered_json Number(double x)
{
  return std::isfinite(x) ? nlohmann::ordered_json(x) : nlohmann::ordered_json();
}

std::string Fixed(double x, int digits)
{
  if (!std::isfinite(x))
  {
    return "n/a";
  }
  char buf[64];
  std::snprintf(buf, sizeof(buf), "%.*f", digits, x);
  return buf;
}

/// The statistics of the filter's field data as one JSON object.
nlohmann::ordered_json ReportJSON(vtkImageData* out, const std::string& input, double seconds)
{
  auto f = [out](const char* name) { return FieldNumber(out, name); };
  nlohmann::ordered_json j;
  j["input"] = input;
  j["valid_cells"] = static_cast<long long>(f("ValidCells"));
  j["valid_area_km2"] = Number(f("ValidArea") * 1e-6);
  j["elevation_m"] = { { "min", Number(f("ElevationMin")) },
    { "max", Number(f("ElevationMax")) },
    { "mean", Number(f("ElevationMean")) } };
  j["hypsometric_integral"] = Number(f("HypsometricIntegral"));
  nlohmann::ordered_json hist = nlohmann::ordered_json::array();
  for (double c : FieldValues(out, "SlopeHistogram"))
  {
    hist.push_back(static_cast<long long>(c));
  }
  j["slope_deg"] = { { "mean", Number(f("SlopeMean")) },
    { "median", Number(f("SlopeMedian")) },
    { "p10", Number(f("SlopeP10")) },
    { "p90", Number(f("SlopeP90")) },
    { "bin_width", Number(f("SlopeBinWidth")) },
    { "histogram", hist } };
  j["drainage"] = { { "channel_area_m2", Number(f("ChannelArea")) },
    { "channel_cells", static_cast<long long>(f("ChannelCells")) },
    { "channel_length_km", Number(f("ChannelLength") * 1e-3) },
    { "drainage_density_km_per_km2", Number(f("DrainageDensity")) } };
  const std::vector<double> counts = FieldValues(out, "HortonStreamCount");
  const std::vector<double> means = FieldValues(out, "HortonMeanLength");
  const std::vector<double> totals = FieldValues(out, "HortonTotalLength");
  nlohmann::ordered_json orders = nlohmann::ordered_json::array();
  for (std::size_t k = 0; k < counts.size(); ++k)
  {
    orders.push_back({ { "order", static_cast<int>(k + 1) },
      { "streams", static_cast<long long>(counts[k]) },
      { "mean_length_m", Number(means[k]) },
      { "total_length_m", Number(totals[k]) } });
  }
  const std::vector<double> fitted = FieldValues(out, "HortonOrdersFitted");
  nlohmann::ordered_json fittedJson = nlohmann::ordered_json::array();
  if (fitted.size() == 2 && fitted[0] > 0)
  {
    fittedJson = { static_cast<int>(fitted[0]), static_cast<int>(fitted[1]) };
  }
  j["horton"] = { { "highest_order", static_cast<int>(counts.size()) },
    { "orders_fitted", fittedJson },
    { "bifurcation_ratio", Number(f("BifurcationRatio")) },
    { "length_ratio", Number(f("LengthRatio")) },
    { "orders", orders } };
  j["hack"] = { { "exponent", Number(f("HackExponent")) },
    { "coefficient", Number(f("HackCoefficient")) },
    { "units", "L km = coefficient * (A km2)^exponent" },
    { "channel_cells_fitted", static_cast<long long>(f("HackPoints")) } };
  j["closed_depressions"] = { { "depth_threshold_m", nullptr },
    { "cells", static_cast<long long>(f("DepressionCells")) },
    { "share", Number(f("DepressionShare")) },
    { "volume_m3", Number(f("DepressionVolume")) } };
  j["seconds"] = seconds;
  return j;
}

std::string HortonCSV(const nlohmann::ordered_json& report)
{
  std::ostringstream s;
  s.precision(10);
  s << "order,streams,mean_length_m,total_length_m\n";
  for (const auto& row : report["horton"]["orders"])
  {
    s << row["order"].get<int>() << "," << row["streams"].get<long long>() << ",";
    if (!row["mean_length_m"].is_null())
    {
      s << row["mean_length_m"].get<double>();
    }
    s << "," << row["total_length_m"].get<double>() << "\n";
  }
  return s.str();
}

void PrintReport(const nlohmann::ordered_json& j)
{
  auto d = [](const nlohmann::ordered_json& x, int digits)
  { return x.is_null() ? std::string("n/a") : Fixed(x.get<double>(), digits); };
  std::cout << "terroir morphometry: " << j["input"].get<std::string>() << " ("
            << Fixed(j["seconds"].get<double>(), 3) << " s)\n"
            << "  valid cells               " << j["valid_cells"].get<long long>() << " ("
            << d(j["valid_area_km2"], 3) << " km2)\n"
            << "  elevation min/mean/max    " << d(j["elevation_m"]["min"], 1) << " / "
            << d(j["elevation_m"]["mean"], 1) << " / " << d(j["elevation_m"]["max"], 1) << " m\n"
            << "  hypsometric integral      " << d(j["hypsometric_integral"], 4) << "\n"
            << "  slope mean/median         " << d(j["slope_deg"]["mean"], 2) << " / "
            << d(j["slope_deg"]["median"], 2) << " deg (p10 " << d(j["slope_deg"]["p10"], 2)
            << ", p90 " << d(j["slope_deg"]["p90"], 2) << ")\n"
            << "  drainage density          " << d(j["drainage"]["drainage_density_km_per_km2"], 3)
            << " km/km2 (channels from " << d(j["drainage"]["channel_area_m2"], 0)
            << " m2: " << j["drainage"]["channel_cells"].get<long long>() << " cells, "
            << d(j["drainage"]["channel_length_km"], 2) << " km)\n"
            << "  Horton R_b / R_l          " << d(j["horton"]["bifurcation_ratio"], 3) << " / "
            << d(j["horton"]["length_ratio"], 3) << " (orders "
            << (j["horton"]["orders_fitted"].empty()
                   ? std::string("none")
                   : std::to_string(j["horton"]["orders_fitted"][0].get<int>()) + ".." +
                     std::to_string(j["horton"]["orders_fitted"][1].get<int>()))
            << " of " << j["horton"]["highest_order"].get<int>() << ")\n"
            << "  Hack's law L = C A^h      h " << d(j["hack"]["exponent"], 3) << ", C "
            << d(j["hack"]["coefficient"], 3) << " (L km, A km2; "
            << j["hack"]["channel_cells_fitted"].get<long long>() << " channel cells)\n"
            << "  closed depressions        " << d(j["closed_depressions"]["share"], 4)
            << " of the cells (" << j["closed_depressions"]["cells"].get<long long>()
            << "), volume " << d(j["closed_depressions"]["volume_m3"], 0) << " m3\n"
            << "  order  streams  mean length m  total length km\n";
  for (const auto& row : j["horton"]["orders"])
  {
    char line[128];
    std::snprintf(line,
      sizeof(line),
      "  %5d  %7lld  %13s  %15s\n",
      row["order"].get<int>(),
      row["streams"].get<long long>(),
      d(row["mean_length_m"], 1).c_str(),
      Fixed(row["total_length_m"].get<double>() * 1e-3, 3).c_str());
    std::cout << line;
  }
}
} // namespace

int CommandMorphometry(const CommandLine& c)
{
  const int backend = ParseBackend(c.Backend);
  std::vector<std::string> outs;
  for (const std::string* p : { &c.MorphometryOutput, &c.MorphometryJson, &c.MorphometryCsv })
  {
    if (!p->empty())
    {
      outs.push_back(*p);
    }
  }
  CheckWritable(outs, c.Overwrite);
  vtkSmartPointer<vtkImageData> terrain = ReadTerrain(c.Input, c.AllowNetwork, c.ZUnit);
  vtkNew<vtkTerroirMorphometry> filter;
  filter->SetBackend(backend);
  filter->SetChannelArea(c.MorphometryChannelArea);
  filter->SetDepressionDepth(c.MorphometryDepressionDepth);
  nlohmann::json stages;
  vtkSmartPointer<vtkImageData> result = RunStage(filter.Get(), terrain, "morphometry", stages);
  nlohmann::ordered_json report =
    ReportJSON(result, c.Input, stages["morphometry"]["seconds"].get<double>());
  report["closed_depressions"]["depth_threshold_m"] = c.MorphometryDepressionDepth;

  // Every file goes into place at the end, or none.
  HoldCommits();
  try
  {
    // The small text files first: a failure writing OUT then shows that they are withdrawn.
    if (!c.MorphometryJson.empty())
    {
      WriteTextFile(c.MorphometryJson, report.dump(2) + "\n", c.Overwrite);
    }
    if (!c.MorphometryCsv.empty())
    {
      WriteTextFile(c.MorphometryCsv, HortonCSV(report), c.Overwrite);
    }
    if (!c.MorphometryOutput.empty())
    {
      WriteStageResult(
        result, vtkTerroirMorphometry::StrahlerOrderName(), c.MorphometryOutput, c.Overwrite);
    }
  }
  catch (...)
  {
    DiscardHeldCommits();
    throw;
  }
  std::string error;
  if (!ReleaseHeldCommits(error))
  {
    throw Failure(error);
  }
  PrintReport(report);
  return 0;
}

} // namespace app
} // namespace terroir
