// The reports of `terroir run` (RunState.h): report.json, report.md and the terminal summary.
#include "RunState.h"

#include "TerroirApp.h"
#include "TerroirCommandSupport.h"

#include "vtkDataArray.h"
#include "vtkInformation.h"
#include "vtkInformationStringKey.h"
#include "vtkPointData.h"

#include "vtkTerroirTemperature.h"

#include <iomanip>
#include <iostream>
#include <sstream>

namespace fs = std::filesystem;
using json = nlohmann::json;

namespace terroir
{
namespace app
{

//------------------------------------------------------------------------------
const std::vector<const char*>& ReportedStages()
{
  static const std::vector<const char*> names = { "slope",
    "temperature",
    "illumination",
    "infiltration",
    "humidity",
    "lakes",
    "rivers",
    "clusters" };
  return names;
}

//------------------------------------------------------------------------------
/// Statistics of every point array (per month for the 12-component ones).
json ArraysReport(vtkImageData* result)
{
  json arrays;
  vtkPointData* pd = result->GetPointData();
  for (int a = 0; a < pd->GetNumberOfArrays(); ++a)
  {
    vtkDataArray* arr = pd->GetArray(a);
    if (!arr || !arr->GetName() || std::string(arr->GetName()) == "vtkValidPointMask")
    {
      continue;
    }
    json entry;
    const char* units = arr->GetInformation()->Has(vtkDataArray::UNITS_LABEL())
      ? arr->GetInformation()->Get(vtkDataArray::UNITS_LABEL())
      : "";
    entry["units"] = units;
    if (arr->GetNumberOfComponents() == 12)
    {
      for (int c = 0; c < 12; ++c)
      {
        entry[vtkTerroirTemperature::GetMonthName(c)] = StatisticsJSON(ArrayStatistics(arr, c));
      }
    }
    else if (arr->GetNumberOfComponents() == 1)
    {
      entry["all"] = StatisticsJSON(ArrayStatistics(arr, 0));
    }
    arrays[arr->GetName()] = entry;
  }
  return arrays;
}

namespace
{
/// report.md's head: the input, the grid, the stages' times and backends, the sun's settings.
void MarkdownStages(RunState& r, std::ostream& md)
{
  md << std::fixed << std::setprecision(2);
  md << "# Terroir run\n\n";
  md << "- input: `" << r.Dem << "`\n";
  md << "- grid: " << r.Dims[0] << " x " << r.Dims[1] << " cells, " << r.Spacing[0] << " x "
     << r.Spacing[1] << " m\n";
  if (r.Located)
  {
    md << std::setprecision(5) << "- centre: " << r.LatLon[0] << ", " << r.LatLon[1]
       << " (lat, lon)\n"
       << std::setprecision(2);
  }
  md << "\n| stage | seconds | backend |\n|---|---|---|\n";
  std::vector<const char*> table = ReportedStages();
  table.insert(table.begin(), "read");
  table.push_back("write");
  for (const char* s : table)
  {
    if (!r.Stages[s].contains("seconds"))
    {
      md << "| " << s << " | skipped: " << r.Stages[s]["skipped"].get<std::string>() << " | |\n";
      continue;
    }
    md << "| " << s << " | " << std::setprecision(3) << r.Stages[s]["seconds"].get<double>()
       << " | "
       << (r.Stages[s].contains("backend") ? r.Stages[s]["backend"].get<std::string>() : "")
       << " |\n";
  }
  if (r.Stages["write"].contains("seconds_by_kind"))
  {
    // Where writing goes: files are written on a second thread while the stages compute, so the
    // write row above is only what the run waited for them after its last stage.
    const json& w = r.Stages["write"];
    md << "\nWriting (a second thread, while the stages computed): busy " << std::setprecision(3)
       << w["busy_seconds"].get<double>() << " s:";
    const char* separator = " ";
    for (const auto& kind : w["seconds_by_kind"].items())
    {
      md << separator << kind.key() << " " << std::setprecision(3) << kind.value().get<double>()
         << " s";
      separator = ", ";
    }
    md << "; the run waited " << std::setprecision(3) << w["seconds"].get<double>()
       << " s for it after its last stage (`report.json`: `stages.write.files`, each file's "
          "seconds).\n";
  }
  // Why each stage ran where it did: under Auto the GPU only where its path is verified correct
  // and faster on this hardware (Documentation/Compute.md, "Verified GPU paths").
  md << "\nBackends (`--backend auto` runs a stage on the GPU only where its GPU path is verified "
        "correct and faster on this hardware; Documentation/Compute.md):\n\n";
  for (const auto& item : r.Stages.items())
  {
    if (item.value().is_object() && item.value().contains("reason") &&
      !item.value()["reason"].get<std::string>().empty())
    {
      md << "- " << item.key() << ": " << item.value()["reason"].get<std::string>() << "\n";
    }
  }
  if (r.Illuminate)
  {
    md << "\nIllumination: monthly, the 15th of each month of "
       << r.Stages["illumination"]["year"].get<int>() << ", " << std::defaultfloat
       << r.Stages["illumination"]["time_step_min"].get<double>() << std::fixed
       << "-minute steps; horizon map of " << r.Stages["illumination"]["horizon_sectors"].get<int>()
       << " sectors built in " << std::setprecision(3) << r.HorizonMapSeconds
       << " s of the stage's " << r.Stages["illumination"]["seconds"].get<double>() << " s.\n";
  }
}

/// report.md's table of arrays (the July statistics of the monthly ones).
void MarkdownArrays(json& arrays, std::ostream& md)
{
  md << std::setprecision(2) << "\n| array | units | min | mean | max |\n|---|---|---|---|---|\n";
  for (auto& [name, entry] : arrays.items())
  {
    const json& st = entry.contains("all") ? entry["all"]
      : entry.contains("Jul")              ? entry["Jul"]
                                           : json();
    if (st.is_null() || st["min"].is_null())
    {
      continue;
    }
    md << "| " << name << (entry.contains("Jul") ? " (Jul)" : "") << " | "
       << entry["units"].get<std::string>() << " | " << st["min"].get<double>() << " | "
       << st["mean"].get<double>() << " | " << st["max"].get<double>() << " |\n";
  }
}

/// report.md's paragraph on the rivers and lakes, and their scores on the bundled DEM.
void MarkdownRivers(RunState& r, std::ostream& md)
{
  const json& rs = r.Stages["rivers"];
  md << "\nRivers (water flow, river-forming mode: " << std::defaultfloat
     << rs["rain_mm_per_h"].get<double>() << " mm/h until the outflow balances the rain; "
     << rs["iterations"].get<double>() << " iterations, " << rs["stop_reason"].get<std::string>()
     << "): " << rs["river_cells"].get<long long>()
     << " river cells (upstream area >= " << rs["river_area_m2"].get<double>() << " m2), about "
     << std::fixed << std::setprecision(1) << rs["river_length_km"].get<double>() << " km; "
     << rs["lakes"].get<std::size_t>() << " lakes, " << std::setprecision(3)
     << rs["lake_area_m2"].get<double>() / 1e6 << " km2.\n";
  if (rs.contains("validation"))
  {
    const json& v = rs["validation"];
    md << "\nAgainst the bundled NHD flowlines (" << v["reference_cells"].get<std::size_t>()
       << " cells in the watershed, length-matched, channel cells): precision "
       << v["scores"][1]["precision"].get<double>() << ", recall "
       << v["scores"][1]["recall"].get<double>() << ", F1 " << v["scores"][1]["f1"].get<double>()
       << " within 60 m (F1 " << v["scores"][0]["f1"].get<double>()
       << " within 30 m); `terroir validate` compares the classic methods.\n";
  }
  md << std::setprecision(2);
}

/// report.md's table of ecological zones.
void MarkdownClusters(RunState& r, std::ostream& md)
{
  if (r.Clusters() > 0)
  {
    // The zones at a glance; clusters.csv has the mean of every feature and month.
    md << "\nEcological zones (k-means, K = " << r.Clusters() << ", "
       << r.ClusterSummary["iterations"].get<int>() << " iterations, "
       << r.ClusterSummary["stop_reason"].get<std::string>()
       << "):\n\n| zone | colour | cells | share | slope (°) | temperature Jul (°C) |\n"
       << "|---|---|---|---|---|---|\n";
    for (const auto& row : r.ClusterSummary["clusters"])
    {
      auto mean = [&row](const char* column)
      {
        std::ostringstream os;
        os << std::fixed << std::setprecision(1);
        if (row.contains(column) && row[column].is_number())
        {
          os << row[column].get<double>();
        }
        else
        {
          os << "-";
        }
        return os.str();
      };
      md << "| " << row["ClusterId"].get<long long>() << " | " << row["Color"].get<std::string>()
         << " | " << row["Cells"].get<long long>() << " | " << std::setprecision(1)
         << 100.0 * row["Share"].get<double>() << " % | " << mean("Slope") << " | "
         << mean("Temperature_Jul") << " |\n";
    }
  }
}
} // namespace

//------------------------------------------------------------------------------
/// report.json (scripts) and report.md (people), both written through a temporary file.
void WriteReports(RunState& r, json& arrays)
{
  WriteTextFile(r.File("report.json"), r.Report.dump(2) + "\n", r.Overwrite());
  std::ostringstream md;
  MarkdownStages(r, md);
  MarkdownArrays(arrays, md);
  MarkdownRivers(r, md);
  MarkdownClusters(r, md);
  md << "\nOutputs:\n\n";
  for (const auto& o : r.Outputs)
  {
    md << "- `" << fs::path(o).filename().string() << "`\n";
  }
  WriteTextFile(r.File("report.md"), md.str(), r.Overwrite());
}

//------------------------------------------------------------------------------
/// One line per stage on the terminal.
void PrintSummary(RunState& r)
{
  std::cout << "terroir run: " << r.Dims[0] << "x" << r.Dims[1] << " cells from " << r.Dem << "\n";
  for (const char* s : ReportedStages())
  {
    if (!r.Stages[s].contains("seconds"))
    {
      std::cout << "  " << std::left << std::setw(14) << s << std::right << "skipped\n";
      continue;
    }
    std::cout << "  " << std::left << std::setw(14) << s << std::right << std::fixed
              << std::setprecision(3) << r.Stages[s]["seconds"].get<double>() << " s  "
              << r.Stages[s]["backend"].get<std::string>();
    if (std::string(s) == "illumination")
    {
      std::cout << " (horizon map " << r.HorizonMapSeconds << " s)";
    }
    std::cout << "\n";
  }
  std::cout << "  outputs in " << r.Line.Output << " (report.md)\n";
}

} // namespace app
} // namespace terroir
