/**
 * @class   vtkTerroirFloodFill
 * @brief   Finds standing water on a terrain: the lake a seed fills up to a level, or every
 *          depression and flat water surface of the DEM.
 *
 * Input: a Terroir terrain (2-D vtkImageData, point array `Elevation` in metres, optional
 * `vtkValidPointMask`, spacing or per-row spacing `TerroirRowSpacing` in metres). Output: the
 * input's arrays plus, as point data,
 * - `WaterBody` (vtkIntArray, 1 component): water body id 1, 2, ...; 0 on dry and no-data
 *   cells;
 * - `WaterDepth` (float32, 1 component, metres, UNITS_LABEL "m"): level - elevation on water
 *   cells, 0 on dry cells, NaN on no-data cells;
 * and as field data, one tuple per water body (tuple id - 1): `WaterBodyLevel` (m, double),
 * `WaterBodyArea` (m^2), `WaterBodyVolume` (m^3), `WaterBodyCells` (vtkIdTypeArray) and
 * `WaterBodyMaxDepth` (m), plus `FloodFillMode` (vtkStringArray, "Seeds" or
 * "FillDepressions").
 *
 * Modes:
 * - Seeds (0, default): every cell 8-connected to a seed through cells at or below the seed's
 *   level (inclusive) is water (terroir::hydrology::FloodFillSeeds). Seeds are given in world
 *   coordinates of the image (AddSeedPoint; the nearest cell is used) or as cells of the
 *   input extent (AddSeedCell); a seed's level defaults to the terrain height at its cell.
 *   Body id = seed number (1 = first seed added); seeds are filled from the highest level
 *   down, a seed inside an earlier body joins it (its own body is empty), a seed below the
 *   terrain fills nothing (with a warning). The fill stops at the edge of the terrain and at
 *   no-data cells.
 * - FillDepressions (1): the DEM's depressions are filled to their spill level by the improved
 *   Priority-Flood (terroir::hydrology::PriorityFloodBarnes2014; outlets are the edge cells and
 *   the cells next to no data), and every flat of the filled surface that holds a filled cell
 *   (or, with IncludeFlatSurfaces, any flat of two or more cells: hydro-flattened lakes in
 *   USGS DEMs are flat surfaces, not depressions) and covers at least MinimumArea m^2 is a
 *   water body (terroir::hydrology::DepressionWaterBodies). Ids follow the first cell of each
 *   body in row-major order (south row first). Seeds are ignored.
 * Depths on a hydro-flattened lake are 0: the DEM records the water surface, not the bed.
 *
 * Whole extent (global filter). CPU only, sequential (results cannot depend on the thread
 * count). Distributed runs (pvbatch or pvserver under mpirun, one piece per process):
 * FillDepressions works on each piece and a one-cell ring with the parallel Priority-Flood of
 * Barnes (2016) (terroir::hydrology::FillDepressionsDistributed: only tile perimeters and
 * per-label summaries travel, to rank 0 and back); the filled surface, ids and depths equal
 * the serial run's bit for bit, the bodies' areas and volumes to ~1e-15 (order of the sums).
 * Seeds mode in pieces (terroir::hydrology::FloodFillSeedsDistributed): each piece labels the
 * parts of {z <= a seed's level} on its cells, rank 0 joins them across pieces and picks each
 * seed's; the same ids, depths and table as serially (seeds in the whole extent's cells or world
 * coordinates; a seed on no data is an error on every rank). Errors (one line,
 * empty output): Seeds mode without seeds, a seed outside the terrain or on a no-data cell, a
 * non-finite seed level or coordinate, MinimumArea < 0.
 *
 * @par Correctness
 * Testing/Unit/TestFloodFill.cxx (hand-worked grids; Priority-Flood against a brute-force
 * fixed point on 50 random terrains), Testing/Pipeline/TestTerroirFloodFill.cxx (Independence
 * Lake on the bundled Sagehen DEM found by both modes; arrays, units, errors),
 * Testing/Pipeline/TestDeterminism.cxx, Testing/Python/TestFloodFill.py (the lake equals an
 * independent breadth-first fill in Python); in pieces: Testing/Unit/
 * TestDistributedPriorityFlood.cxx (threads as ranks) and ParaView/Testing's
 * Distributed.lakes|lakesghost|seeds (mpirun -np 1, 2, 4 pvbatch against the serial run).
 *
 * @par References
 * Barnes, R., Lehman, C., Mulla, D. (2014). Priority-Flood: An optimal depression-filling and
 * watershed-labeling algorithm for digital elevation models. Computers & Geosciences
 * 62:117-127. doi:10.1016/j.cageo.2013.04.024
 * Barnes, R. (2016). Parallel priority-flood depression filling for trillion cell digital
 * elevation models on desktops or clusters. Computers & Geosciences 96:56-68.
 * doi:10.1016/j.cageo.2016.07.001
 *
 * @sa vtkTerroirImageAlgorithm
 */
#ifndef vtkTerroirFloodFill_h
#define vtkTerroirFloodFill_h

#include "vtkTerroirFiltersHydrologyModule.h" // For export macro
#include "vtkTerroirImageAlgorithm.h"

#include <cstdint> // For std::int32_t
#include <vector>  // For std::vector

namespace terroir
{
template<typename T>
struct GridView;
namespace hydrology
{
struct WaterBodyStats;
struct DistributedSeed;
}
}

class VTKTERROIRFILTERSHYDROLOGY_EXPORT vtkTerroirFloodFill : public vtkTerroirImageAlgorithm
{
public:
  static vtkTerroirFloodFill* New();
  vtkTypeMacro(vtkTerroirFloodFill, vtkTerroirImageAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /// Output array names: point data, then field data (one tuple per water body).
  static const char* WaterBodyName() { return "WaterBody"; }
  static const char* WaterDepthName() { return "WaterDepth"; }
  static const char* WaterBodyLevelName() { return "WaterBodyLevel"; }
  static const char* WaterBodyAreaName() { return "WaterBodyArea"; }
  static const char* WaterBodyVolumeName() { return "WaterBodyVolume"; }
  static const char* WaterBodyCellsName() { return "WaterBodyCells"; }
  static const char* WaterBodyMaxDepthName() { return "WaterBodyMaxDepth"; }
  static const char* FloodFillModeName() { return "FloodFillMode"; }
  ///@}

  enum ModeType
  {
    Seeds = 0,
    FillDepressions = 1
  };

  ///@{
  /// Seeds (0, default) or FillDepressions (1); see the class comment.
  vtkSetClampMacro(Mode, int, Seeds, FillDepressions);
  vtkGetMacro(Mode, int);
  void SetModeToSeeds() { this->SetMode(Seeds); }
  void SetModeToFillDepressions() { this->SetMode(FillDepressions); }
  /// "Seeds" or "FillDepressions".
  const char* GetModeAsString();
  ///@}

  ///@{
  /**
   * Adds a seed at world coordinates (x, y) of the image (origin + index * spacing; the
   * nearest cell is used; a point up to half a cell beyond the outer cell centres still
   * belongs to the outer cell). Without `level` the water surface is the terrain height at the
   * seed's cell; `level` is in metres, like the elevations. Seeds are numbered from 1 in the
   * order they are added, across AddSeedPoint and AddSeedCell.
   */
  void AddSeedPoint(double x, double y);
  void AddSeedPoint(double x, double y, double level);
  ///@}

  ///@{
  /// Adds a seed at cell (i, j) counted from the first cell of the input's extent (i east,
  /// j north), with the terrain height there or `level` (metres) as its water surface.
  void AddSeedCell(int i, int j);
  void AddSeedCell(int i, int j, double level);
  ///@}

  /// Removes every seed.
  void RemoveAllSeeds();
  /// Number of seeds added since the last RemoveAllSeeds.
  int GetNumberOfSeeds();

  ///@{
  /**
   * FillDepressions: smallest water body kept, m^2 (sum of the cell areas dx * dy). Default
   * 10000 (1 ha, 100 cells of 10 m); must be >= 0 and finite. Bodies smaller than this are
   * dropped, whether filled depressions or flat surfaces.
   */
  vtkSetMacro(MinimumArea, double);
  vtkGetMacro(MinimumArea, double);
  ///@}

  ///@{
  /**
   * FillDepressions: also report flats of the DEM that hold no filled cell (hydro-flattened
   * lakes and reservoirs). Default on. On DEMs quantised to whole metres, large equal-height
   * plateaus are reported too: raise MinimumArea or turn this off.
   */
  vtkSetMacro(IncludeFlatSurfaces, bool);
  vtkGetMacro(IncludeFlatSurfaces, bool);
  vtkBooleanMacro(IncludeFlatSurfaces, bool);
  ///@}

protected:
  vtkTerroirFloodFill();
  ~vtkTerroirFloodFill() override;

  /// A distributed run: the piece and one ring (Barnes 2016's tiles); else the whole extent.
  int GetHaloWidth() override { return this->DistributedRequest ? 1 : -1; }
  bool HasGPUPath() override { return false; }
  double EstimateMemory(double nx, double ny) override;
  std::string CheckParameters() override;
#ifndef __VTK_WRAP__
  int RequestTerrainData(vtkImageData* input,
    const terroir::TerrainInput& terrain,
    vtkImageData* output) override;
#endif

  int Mode = Seeds;
  double MinimumArea = 10000.0;
  bool IncludeFlatSurfaces = true;

private:
  vtkTerroirFloodFill(const vtkTerroirFloodFill&) = delete;
  void operator=(const vtkTerroirFloodFill&) = delete;

  struct Seed
  {
    bool IsCell;   ///< true: (I, J) is a cell; false: (X, Y) are world coordinates
    double X, Y;   ///< world coordinates (AddSeedPoint)
    int I, J;      ///< cell (AddSeedCell)
    bool HasLevel; ///< false: the terrain height at the seed
    double Level;  ///< metres
  };
  std::vector<Seed> SeedList;
  void AddSeed(const Seed& seed);
#ifndef __VTK_WRAP__
  /// FillDepressions on this process's piece (Barnes 2016 through the global controller).
  bool FillDepressionsInPieces(vtkImageData* input,
    const terroir::GridView<float>& view,
    std::int32_t* ids,
    float* depth,
    std::vector<terroir::hydrology::WaterBodyStats>& bodies);
  /// Seeds on this process's piece; `noData` flags the seeds whose cell this rank owns and
  /// has no data (all-reduced: every rank refuses them alike).
  bool FloodSeedsInPieces(vtkImageData* input,
    const terroir::GridView<float>& view,
    const std::vector<terroir::hydrology::DistributedSeed>& seeds,
    const std::vector<int>& noData,
    std::int32_t* ids,
    float* depth,
    std::vector<terroir::hydrology::WaterBodyStats>& bodies);
  /// Either distributed core (seeds null: depressions) through the global controller.
  bool RunInPieces(vtkImageData* input,
    const terroir::GridView<float>& view,
    const std::vector<terroir::hydrology::DistributedSeed>* seeds,
    std::int32_t* ids,
    float* depth,
    std::vector<terroir::hydrology::WaterBodyStats>& bodies);
#endif
  std::string DescribeSeed(std::size_t s) const;
};

#endif
