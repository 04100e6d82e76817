/**
 * @file TerroirClusterSupport.h
 * @brief The clustering command of `terroir` (kmeans) and the cluster table's CSV and JSON
 * forms, which `terroir run` writes too.
 */
#ifndef TerroirClusterSupport_h
#define TerroirClusterSupport_h

#include "TerroirCommandLine.h"
#include "TerroirFlowSupport.h" // For OverlayWriterFunction

#include "vtkSmartPointer.h"

#include <nlohmann/json.hpp>

#include <string>

class vtkImageData;
class vtkTable;
class vtkTerroirKMeans;

namespace terroir
{
namespace app
{

/// Sets up `filter` from `s` (clusters, features, seeding, stop rules) and the backend name.
void ApplyKMeans(const KMeansSettings& s, const std::string& backend, vtkTerroirKMeans* filter);

/// The cluster table as CSV: a header row of column names, one row per cluster, numbers with
/// up to 9 significant digits.
std::string ClusterTableCSV(vtkTable* table);

/**
 * The cluster table and the run as JSON: {"clusters": [{column: value, ...}, ...],
 * "units": {column: units}, "within_cluster_sum_of_squares", "iterations", "stop_reason",
 * "relocated_clusters", "collapsed_arrays"} (the last five from `image`'s field data).
 */
nlohmann::ordered_json ClusterTableJSON(vtkTable* table, vtkImageData* image);

/// True when `image` has none of the default features (a bare DEM).
bool HasNoDefaultFeature(vtkImageData* image);

} // namespace app
} // namespace terroir

#endif
