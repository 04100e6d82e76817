#include "vtkTerroirTerrainInput.h"

#include "vtkDataArray.h"
#include "vtkDoubleArray.h"
#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkInformation.h"
#include "vtkPointData.h"
#include "vtkTerroirGPU.h"
#include "vtkTerroirGeoreference.h"
#include "vtkUnsignedCharArray.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <new>
#include <sstream>
#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace terroir
{

namespace
{
/// Checks that the image is 2-D with at least minSize x minSize points; fills `dims`.
bool CheckDimensions(vtkImageData* image, int minSize, int dims[3], std::string& error)
{
  image->GetDimensions(dims);
  if (dims[2] != 1 || dims[0] < 1 || dims[1] < 1)
  {
    std::ostringstream os;
    os << "input must be a 2-D image (dimensions nx, ny, 1), got " << dims[0] << " x " << dims[1]
       << " x " << dims[2];
    error = os.str();
    return false;
  }
  if (dims[0] < minSize || dims[1] < minSize)
  {
    std::ostringstream os;
    os << "input must have at least " << minSize << " x " << minSize << " points, got " << dims[0]
       << " x " << dims[1];
    error = os.str();
    return false;
  }
  return true;
}

/// Checks that `elevation` is a one-component point-data array of the image's n points.
bool CheckElevation(vtkImageData* image, vtkDataArray* elevation, vtkIdType n, std::string& error)
{
  if (!elevation)
  {
    error = "no elevation array: the input needs a point-data array named 'Elevation' (or the "
            "one chosen with SetInputArrayToProcess)";
    return false;
  }
  bool inPointData = false;
  for (int a = 0; a < image->GetPointData()->GetNumberOfArrays(); ++a)
  {
    inPointData = inPointData || image->GetPointData()->GetAbstractArray(a) == elevation;
  }
  if (!inPointData)
  {
    std::ostringstream os;
    os << "elevation array '" << (elevation->GetName() ? elevation->GetName() : "")
       << "' must be point data";
    error = os.str();
    return false;
  }
  if (elevation->GetNumberOfComponents() != 1)
  {
    std::ostringstream os;
    os << "elevation array '" << (elevation->GetName() ? elevation->GetName() : "") << "' has "
       << elevation->GetNumberOfComponents() << " components, expected 1";
    error = os.str();
    return false;
  }
  if (elevation->GetNumberOfTuples() != n)
  {
    std::ostringstream os;
    os << "elevation array has " << elevation->GetNumberOfTuples() << " values, the image has " << n
       << " points";
    error = os.str();
    return false;
  }
  return true;
}

/// Sets the view's size, spacing and elevations (float32 in place, other types copied).
bool ViewElevation(vtkImageData* image,
  vtkDataArray* elevation,
  const int dims[3],
  vtkIdType n,
  TerrainInput& out,
  std::string& error)
{
  GridView<float>& v = out.view;
  v.nx = dims[0];
  v.ny = dims[1];
  double spacing[3];
  image->GetSpacing(spacing);
  v.dx = std::fabs(spacing[0]);
  v.dy = std::fabs(spacing[1]);
  if (!(v.dx > 0.0) || !(v.dy > 0.0) || !std::isfinite(v.dx) || !std::isfinite(v.dy))
  {
    std::ostringstream os;
    os << "spacing " << spacing[0] << " x " << spacing[1] << " m: must be positive and finite";
    error = os.str();
    return false;
  }
  if (elevation->GetDataType() == VTK_FLOAT)
  {
    v.data = static_cast<const float*>(elevation->GetVoidPointer(0));
  }
  else
  {
    out.elevationCopy.resize(static_cast<size_t>(n));
    for (vtkIdType k = 0; k < n; ++k)
    {
      out.elevationCopy[k] = static_cast<float>(elevation->GetComponent(k, 0));
    }
    v.data = out.elevationCopy.data();
  }
  return true;
}

/// Sets the view's validity from the mask array and NaN elevations; `mask` is the image's
/// mask array (null when it has none).
bool ViewValidity(vtkImageData* image,
  vtkIdType n,
  TerrainInput& out,
  vtkDataArray*& mask,
  std::string& error)
{
  GridView<float>& v = out.view;
  mask = vtkArrayDownCast<vtkDataArray>(
    image->GetPointData()->GetAbstractArray(vtkTerroirGeoreference::ValidMaskName()));
  if (mask && (mask->GetNumberOfTuples() != n || mask->GetNumberOfComponents() != 1))
  {
    std::ostringstream os;
    os << "'" << vtkTerroirGeoreference::ValidMaskName() << "' has " << mask->GetNumberOfTuples()
       << " x " << mask->GetNumberOfComponents() << " values, expected " << n << " x 1";
    error = os.str();
    return false;
  }
  bool anyInvalid = false;
  for (vtkIdType k = 0; k < n && !anyInvalid; ++k)
  {
    anyInvalid = std::isnan(v.data[k]) || (mask && mask->GetComponent(k, 0) == 0.0);
  }
  if (anyInvalid)
  {
    out.valid.resize(static_cast<size_t>(n));
    vtkUnsignedCharArray* uc = vtkArrayDownCast<vtkUnsignedCharArray>(mask);
    for (vtkIdType k = 0; k < n; ++k)
    {
      const bool m = !mask || (uc ? uc->GetValue(k) != 0 : mask->GetComponent(k, 0) != 0.0);
      out.valid[k] = (m && !std::isnan(v.data[k])) ? 1 : 0;
    }
    v.valid = out.valid.data();
    out.hasNoData = true;
  }
  return true;
}

/// Sets the view's per-row spacing from the image's TerroirRowSpacing (geographic grids).
bool ViewRowSpacing(vtkImageData* image, TerrainInput& out, std::string& error)
{
  GridView<float>& v = out.view;
  vtkDoubleArray* rows = vtkTerroirGeoreference::GetRowSpacing(image);
  if (!rows)
  {
    return true;
  }
  // One (dx, dy) per row of the whole grid; a sub-extent uses its own rows of it.
  int extent[6];
  image->GetExtent(extent);
  const vtkIdType offset = rows->GetNumberOfTuples() == v.ny ? 0 : extent[2];
  if (rows->GetNumberOfComponents() != 2 || offset < 0 || offset + v.ny > rows->GetNumberOfTuples())
  {
    std::ostringstream os;
    os << "'" << vtkTerroirGeoreference::RowSpacingName() << "' has " << rows->GetNumberOfTuples()
       << " x " << rows->GetNumberOfComponents() << " values, expected " << v.ny
       << " x 2 (one (dx, dy) per row)";
    error = os.str();
    return false;
  }
  out.rowDx.resize(v.ny);
  out.rowDy.resize(v.ny);
  for (int j = 0; j < v.ny; ++j)
  {
    out.rowDx[j] = std::fabs(rows->GetComponent(offset + j, 0));
    out.rowDy[j] = std::fabs(rows->GetComponent(offset + j, 1));
    if (!(out.rowDx[j] > 0.0) || !(out.rowDy[j] > 0.0) || !std::isfinite(out.rowDx[j]) ||
      !std::isfinite(out.rowDy[j]))
    {
      std::ostringstream os;
      os << "'" << vtkTerroirGeoreference::RowSpacingName() << "' of row " << j << " is "
         << out.rowDx[j] << " x " << out.rowDy[j] << " m: must be positive and finite";
      error = os.str();
      return false;
    }
  }
  v.rowDx = out.rowDx.data();
  v.rowDy = out.rowDy.data();
  return true;
}
} // namespace

bool ExtractTerrain(vtkImageData* image,
  vtkDataArray* elevation,
  TerrainInput& out,
  std::string& error,
  int minSize)
{
  out = TerrainInput();
  if (!image)
  {
    error = "input is not a vtkImageData";
    return false;
  }
  int dims[3];
  if (!CheckDimensions(image, minSize, dims, error))
  {
    return false;
  }
  const vtkIdType n = static_cast<vtkIdType>(dims[0]) * dims[1];
  if (!CheckElevation(image, elevation, n, error) ||
    !ViewElevation(image, elevation, dims, n, out, error))
  {
    return false;
  }
  vtkDataArray* mask = nullptr;
  if (!ViewValidity(image, n, out, mask, error))
  {
    return false;
  }
  out.key = elevation;
  out.stamp = elevation->GetMTime();
  // Never dereferenced; offset by one so that it differs from any array's own key.
  out.maskKey = static_cast<const char*>(static_cast<const void*>(mask ? mask : elevation)) + 1;
  out.maskStamp = std::max<unsigned long long>(out.stamp, mask ? mask->GetMTime() : 0);
  return ViewRowSpacing(image, out, error);
}

static void AdviseHugePages(void* data, std::size_t bytes)
{
#if defined(__linux__) && defined(MADV_HUGEPAGE)
  // Large outputs are first touched by the kernels; with 4 KiB pages the page faults cost more
  // than the computation (measured: slope on 4096^2 spent ~60 of 75 ms faulting). Transparent
  // huge pages cut the fault count 512-fold where the system allows them ("madvise" mode).
  constexpr std::uintptr_t huge = std::uintptr_t(2) << 20;
  if (!data || bytes < 4 * huge)
  {
    return;
  }
  const auto begin = reinterpret_cast<std::uintptr_t>(data);
  const std::uintptr_t first = (begin + huge - 1) & ~(huge - 1);
  const std::uintptr_t last = (begin + bytes) & ~(huge - 1);
  if (last > first)
  {
    ::madvise(reinterpret_cast<void*>(first), last - first, MADV_HUGEPAGE);
  }
#else
  (void)data;
  (void)bytes;
#endif
}

vtkFloatArray* NewOutputArray(const char* name,
  int components,
  long long tuples,
  const char* units,
  const char* const* componentNames)
{
  vtkFloatArray* a = vtkFloatArray::New();
  a->SetName(name);
  a->SetNumberOfComponents(components);
  if (componentNames)
  {
    for (int c = 0; c < components; ++c)
    {
      a->SetComponentName(c, componentNames[c]);
    }
  }
  a->SetNumberOfTuples(static_cast<vtkIdType>(tuples));
  if (a->GetNumberOfTuples() != static_cast<vtkIdType>(tuples))
  {
    a->Delete();
    throw std::bad_alloc();
  }
  AdviseHugePages(a->GetVoidPointer(0), static_cast<std::size_t>(a->GetDataSize()) * sizeof(float));
  if (units)
  {
    a->GetInformation()->Set(vtkDataArray::UNITS_LABEL(), units);
  }
  return a;
}

std::vector<std::uint32_t> PackValidMask(const GridView<float>& v)
{
  return v.valid ? gpu::PackFlags(v.valid, v.Size()) : std::vector<std::uint32_t>(1, 0u);
}

GPUTerrain ResidentTerrain(const TerrainInput& terrain)
{
  auto& ctx = gpu::Context::Global();
  const GridView<float>& v = terrain.view;
  const std::size_t n = v.Size();
  GPUTerrain out;
  if (!terrain.key)
  {
    // A view made without ExtractTerrain: nothing to key a cache entry on.
    out.elevation = std::make_shared<gpu::StorageBuffer>(n * sizeof(float), v.data);
    const std::vector<std::uint32_t> mask = PackValidMask(v);
    out.mask =
      std::make_shared<gpu::StorageBuffer>(mask.size() * sizeof(std::uint32_t), mask.data());
    return out;
  }
  out.elevation = ctx.Resident(terrain.key, terrain.stamp, n * sizeof(float), v.data);
  const std::size_t maskWords = v.valid ? (n + 3) / 4 : 1;
  out.mask =
    ctx.FindResident(terrain.maskKey, terrain.maskStamp, maskWords * sizeof(std::uint32_t));
  if (!out.mask)
  {
    const std::vector<std::uint32_t> packed = PackValidMask(v);
    out.mask = ctx.Resident(
      terrain.maskKey, terrain.maskStamp, packed.size() * sizeof(std::uint32_t), packed.data());
  }
  return out;
}

} // namespace terroir
