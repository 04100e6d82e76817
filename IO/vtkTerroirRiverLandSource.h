/**
 * @class   vtkTerroirRiverLandSource
 * @brief   Generates seeded river-first terrain after Jensen (2011)'s RiverLand 2.0: rivers
 *          grown inland from mouths on a coast, land shaped between the rivers and the ridges
 *          (medial-axis cells found by distance propagation, pruned), with user-defined slope
 *          profiles blended in.
 *
 * Output 0: vtkImageData (Dimensions[0], Dimensions[1], 1), spacing (Spacing, Spacing, 1)
 * metres, origin Origin. Point arrays: `Elevation` (float32, m; 0 = sea level, sea cells at
 * -seaDepth), `River` (uint8, 1 on river cells), `RiverId` (int32, the river or tributary of
 * a river cell, -1 elsewhere), `MedialAxis` (uint8, 1 medial-axis (ridge) cell, 2 pruned,
 * 0 otherwise), `DistanceToRiver` (float32, m, Jensen's d to the nearest river or coast cell;
 * -1 at sea), `CellClass` (uint8, 0 sea, 1 land, 2 coast, 3 river), `SlopeWeight` (float32,
 * the user slopes' summed influence fraction). Output 1: the rivers as vtkPolyData, one
 * polyline per river from its mouth (or the parent's cell it joins) upstream through cell
 * centres, cell arrays `RiverId`, `Parent` (-1 for main rivers) and `Level` (0 main river).
 *
 * Parameters: the properties below (defaults those of terroir::generation::RiverLandParameters:
 * 512 x 512, 30 m, seed 1, 12 rivers, island coast, pruning with Jensen's threshold 20,
 * hill slope 0.25, no fractal overlay) and `ParametersJSON`, a JSON object of parameters in
 * the format of `terroir generate riverland --params` (IO/vtkTerroirRiverLandSource.md; it
 * also holds the user slopes): its keys override the properties.
 *
 * Algorithm, and where it departs from the paper: IO/Core/RiverLand.h. Bit-identical for a
 * seed on any number of Threads.
 *
 * @par Correctness
 * RiverLand.* unit tests (medial axis of a strip and a ring, pruning worked by hand, profile
 * values, Jensen's blending examples, rivers, seeds and threads) and
 * TerroirRiverLandSource.* pipeline tests.
 *
 * @par References
 * J. Jensen, "RiverLand 2.0: Blending of Multiple User-defined Slopes in a Procedurally
 * Modeled Terrain", MS project, San Jose State University, 2011.
 */
#ifndef vtkTerroirRiverLandSource_h
#define vtkTerroirRiverLandSource_h

#include "vtkImageAlgorithm.h"
#include "vtkTerroirIOModule.h" // For export macro

#include <string> // For std::string

class VTKTERROIRIO_EXPORT vtkTerroirRiverLandSource : public vtkImageAlgorithm
{
public:
  static vtkTerroirRiverLandSource* New();
  vtkTypeMacro(vtkTerroirRiverLandSource, vtkImageAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /// Number of points (nx, ny), each in [8, 65536]. Default: 512 x 512.
  vtkSetVector2Macro(Dimensions, int);
  vtkGetVector2Macro(Dimensions, int);
  ///@}
  ///@{
  /// Cell size, metres. Default: 30.
  vtkSetMacro(Spacing, double);
  vtkGetMacro(Spacing, double);
  ///@}
  ///@{
  /// Seed (64-bit). Default: 1.
  vtkSetMacro(Seed, unsigned long long);
  vtkGetMacro(Seed, unsigned long long);
  ///@}
  ///@{
  /// River mouths. Default: 12.
  vtkSetMacro(Rivers, int);
  vtkGetMacro(Rivers, int);
  ///@}
  ///@{
  /// True: a noise island; false: the map's border is the coast. Default: true.
  vtkSetMacro(Island, bool);
  vtkGetMacro(Island, bool);
  vtkBooleanMacro(Island, bool);
  ///@}
  ///@{
  /// Prune medial-axis cells (Jensen 3), and the threshold in cells along the rivers.
  /// Defaults: on, 20.
  vtkSetMacro(Prune, bool);
  vtkGetMacro(Prune, bool);
  vtkBooleanMacro(Prune, bool);
  vtkSetMacro(PruneThreshold, double);
  vtkGetMacro(PruneThreshold, double);
  ///@}
  ///@{
  /// Ridge rise above its river per metre of distance (Jensen's slope). Default: 0.25.
  vtkSetMacro(HillSlope, double);
  vtkGetMacro(HillSlope, double);
  ///@}
  ///@{
  /// Amplitude of the fractal overlay, metres (0: none). Default: 0.
  vtkSetMacro(NoiseAmplitude, double);
  vtkGetMacro(NoiseAmplitude, double);
  ///@}
  ///@{
  /// Threads for the per-cell passes (the output does not depend on it); 0: vtkSMPTools'
  /// estimated number of threads. Default: 0.
  vtkSetMacro(Threads, int);
  vtkGetMacro(Threads, int);
  ///@}
  ///@{
  /// A JSON object of parameters (`terroir generate riverland --params`'s format); its keys
  /// override the properties. Empty by default.
  vtkSetStdStringFromCharMacro(ParametersJSON);
  vtkGetCharFromStdStringMacro(ParametersJSON);
  ///@}
  ///@{
  /// A projected CRS (any definition GDAL takes; empty: none) and the world coordinates of
  /// the first cell's centre (default 0, 0), as vtkTerroirPolygonIslandSource.
  vtkSetStdStringFromCharMacro(CRS);
  vtkGetCharFromStdStringMacro(CRS);
  vtkSetVector2Macro(Origin, double);
  vtkGetVector2Macro(Origin, double);
  ///@}

  /// Port 0: the image; port 1: the rivers (vtkPolyData).
  int FillOutputPortInformation(int port, vtkInformation* info) override;

  /// The last error as one line, or "" after a successful run.
  const char* GetErrorMessage() const { return this->ErrorMessage.c_str(); }
  /// Medial-axis cells before and after pruning, and the pruning's seconds, of the last run.
  int GetMedialCellsBefore() const { return this->MedialBefore; }
  int GetMedialCellsAfter() const { return this->MedialAfter; }
  double GetPruneSeconds() const { return this->PruneSeconds; }
  /// User slopes of the last run that found a plain land cell (at or within 8 cells of x, y).
  int GetSlopesApplied() const { return this->SlopesApplied; }

protected:
  vtkTerroirRiverLandSource();
  ~vtkTerroirRiverLandSource() override = default;

  int RequestInformation(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  int Dimensions[2] = { 512, 512 };
  double Spacing = 30.0;
  unsigned long long Seed = 1;
  int Rivers = 12;
  bool Island = true;
  bool Prune = true;
  double PruneThreshold = 20.0;
  double HillSlope = 0.25;
  double NoiseAmplitude = 0.0;
  int Threads = 0;
  std::string ParametersJSON;
  std::string CRS;
  double Origin[2] = { 0.0, 0.0 };
  std::string ErrorMessage;
  int MedialBefore = 0, MedialAfter = 0;
  double PruneSeconds = 0.0;
  int SlopesApplied = 0;

private:
  vtkTerroirRiverLandSource(const vtkTerroirRiverLandSource&) = delete;
  void operator=(const vtkTerroirRiverLandSource&) = delete;
};

#endif
