/**
 * @file vtkTerroirTerrainInput.h
 * @brief Turns a Terroir terrain (vtkImageData + Elevation) into a terroir::GridView<float>
 *        for the algorithm cores, and makes the filters' output arrays (not wrapped).
 *
 * `ExtractTerrain` validates the input and fills a `TerrainInput`:
 * - the image must be 2-D: dimensions (nx, ny, 1) with nx, ny >= `minSize` (1 by default;
 *   stencil filters such as vtkTerroirSlope ask for 2);
 * - the elevation array must be point data with one component and nx*ny tuples;
 * - float32 elevations are viewed in place (no copy); any other type is copied to float;
 * - the validity mask is `vtkValidPointMask` (unsigned char, 1 = valid) when present, and a
 *   cell whose elevation is NaN is invalid too; when neither occurs `view.valid` is null;
 * - spacing: `vtkImageData::GetSpacing()` (metres), or per row `TerroirRowSpacing` (field
 *   data, ny tuples of (dx, dy) metres, rows of the input extent) for geographic grids; every
 *   spacing must be positive and finite (its sign is ignored).
 * On failure it returns false and fills `error` with one line naming the problem.
 */
#ifndef vtkTerroirTerrainInput_h
#define vtkTerroirTerrainInput_h

#include "GridView.h"                    // For terroir::GridView
#include "vtkTerroirFiltersBaseModule.h" // For export macro

#include <cstdint> // For std::uint8_t
#include <memory>  // For std::shared_ptr
#include <string>  // For std::string
#include <vector>  // For std::vector

class vtkDataArray;
class vtkFloatArray;
class vtkImageData;

namespace terroir
{

/// A terrain ready for a core: the view plus whatever storage it points into.
struct VTKTERROIRFILTERSBASE_EXPORT TerrainInput
{
  GridView<float> view;
  std::vector<float> elevationCopy; ///< used when the input is not float32
  std::vector<std::uint8_t> valid;  ///< used when there is a mask or a NaN
  std::vector<double> rowDx;        ///< used for geographic grids (TerroirRowSpacing)
  std::vector<double> rowDy;
  bool hasNoData = false; ///< true when some cell is invalid
  /// Identity and version of the data behind `view`, under which its device copies are cached
  /// (ResidentTerrain): the elevation array and its MTime; for the validity, the mask array
  /// (or the elevation array when there is none) and the larger of the two MTimes.
  const void* key = nullptr;
  unsigned long long stamp = 0;
  const void* maskKey = nullptr;
  unsigned long long maskStamp = 0;
};

namespace gpu
{
class StorageBuffer;
}

/// Device copies of a terrain for GPU kernels, kept resident between jobs and filters.
struct GPUTerrain
{
  std::shared_ptr<gpu::StorageBuffer> elevation; ///< float, nx * ny (the view's values)
  std::shared_ptr<gpu::StorageBuffer> mask;      ///< validity packed four cells per uint (byte
                                                 ///< k of word w = cell 4w + k); one zero word
                                                 ///< when the terrain has no no-data
};

/**
 * The device copies of `terrain`'s elevation and validity, uploaded only when the compute
 * context has no copy of the same array at the same modification time (gpu::Context::Resident):
 * a chain of GPU filters on one terrain uploads it once. Only inside gpu::Context::Run.
 */
VTKTERROIRFILTERSBASE_EXPORT GPUTerrain ResidentTerrain(const TerrainInput& terrain);

/// The view's validity packed four cells per uint, as the kernels read it (one zero word when
/// the view has no mask).
VTKTERROIRFILTERSBASE_EXPORT std::vector<std::uint32_t> PackValidMask(const GridView<float>& v);

/// Validates `image` and `elevation` and fills `out` (see the file comment).
VTKTERROIRFILTERSBASE_EXPORT bool ExtractTerrain(vtkImageData* image,
  vtkDataArray* elevation,
  TerrainInput& out,
  std::string& error,
  int minSize = 1);

/// A new float array named `name` with `components` components and `tuples` tuples, with
/// component names (may be null) and `vtkDataArray::UNITS_LABEL()` set to `units`. Throws
/// std::bad_alloc when the values cannot be allocated.
VTKTERROIRFILTERSBASE_EXPORT vtkFloatArray* NewOutputArray(const char* name,
  int components,
  long long tuples,
  const char* units,
  const char* const* componentNames = nullptr);

} // namespace terroir

#endif
