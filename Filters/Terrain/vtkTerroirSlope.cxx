#include "vtkTerroirSlope.h"
#include "vtkTerroirComputeContext.h"

#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkSMPTools.h"
#include "vtkSmartPointer.h"
#include "vtkTerroirGPU.h"
#include "vtkTerroirGeoreference.h"
#include "vtkTerroirSlopeCS.h"
#include "vtkTerroirTerrainInput.h"

#include "SlopeHorn1981.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

vtkStandardNewMacro(vtkTerroirSlope);

namespace
{
/// Row blocks run by vtkSMPTools; each writes only its own rows, so results do not depend on
/// the number of threads.
struct SlopeFunctor
{
  const terroir::GridView<float>* View;
  const terroir::terrain::SlopeParams* Params;
  float* Slope;
  float* Aspect;
  float* Normals;
  void operator()(vtkIdType begin, vtkIdType end) const
  {
    terroir::terrain::SlopeHorn1981Rows(*this->View,
      *this->Params,
      this->Slope,
      this->Aspect,
      this->Normals,
      static_cast<int>(begin),
      static_cast<int>(end));
  }
};

/// Runs Shaders/Slope.comp (bindings documented there) on the compute context: the interior
/// kernel, then the border kernel, per band of rows; the elevation and mask stay resident.
void RunSlopeGPU(const terroir::TerrainInput& terrain,
  const terroir::terrain::SlopeParams& params,
  float* slope,
  float* aspect,
  float* normals)
{
  const terroir::GridView<float>& v = terrain.view;
  const std::size_t n = v.Size();
  // Per-row coefficients, the core's own.
  std::vector<float> coef(4 * static_cast<std::size_t>(v.ny));
  for (int j = 0; j < v.ny; ++j)
  {
    const auto c = terroir::terrain::SlopeHorn1981RowCoefficients(v, j, params.zFactor);
    coef[4 * j + 0] = c.cN;
    coef[4 * j + 1] = c.cC;
    coef[4 * j + 2] = c.cS;
    coef[4 * j + 3] = c.cY;
  }
  auto& ctx = terroir::gpu::Context::Global();
  const long long maxBlock = ctx.GetLimits().MaxShaderStorageBlockSize;
  if (maxBlock > 0 && static_cast<long long>(n * sizeof(float)) > maxBlock)
  {
    throw terroir::gpu::Error("grid too large for one GPU storage buffer (elevation " +
      std::to_string(n * sizeof(float)) + " > " + std::to_string(maxBlock) + " bytes)");
  }
  // Outputs are computed in bands of rows that fit one storage buffer each (the normals need
  // 12 B per cell: 4096^2 cells exceed llvmpipe's 128 MiB limit). Inputs stay whole.
  const long long bytesPerRow = static_cast<long long>((normals ? 3 : 1) * v.nx * sizeof(float));
  int bandRows = v.ny;
  if (maxBlock > 0 && bytesPerRow * v.ny > maxBlock)
  {
    bandRows = std::max(16, static_cast<int>(maxBlock / bytesPerRow) / 16 * 16);
  }
  std::vector<std::string> outputs;
  if (params.units == terroir::terrain::SlopeUnits::Percent)
  {
    outputs.push_back("SLOPE_PERCENT");
  }
  if (aspect)
  {
    outputs.push_back("SLOPE_ASPECT");
  }
  if (normals)
  {
    outputs.push_back("SLOPE_NORMALS");
  }
  std::vector<std::string> inner = { "LOCAL_X 16", "LOCAL_Y 16" };
  std::vector<std::string> border = { "LOCAL_X 64", "LOCAL_Y 1", "SLOPE_BORDER" };
  inner.insert(inner.end(), outputs.begin(), outputs.end());
  border.insert(border.end(), outputs.begin(), outputs.end());
  if (v.valid)
  {
    inner.push_back("SLOPE_MASK");
  }
  ctx.Run("slope",
    terroir::gpu::Context::Budget(static_cast<double>(n)),
    [&]
    {
      const terroir::GPUTerrain t = terroir::ResidentTerrain(terrain);
      terroir::gpu::StorageBuffer bcoef(coef.size() * sizeof(float), coef.data());
      const std::size_t bandCells = static_cast<std::size_t>(bandRows) * v.nx;
      const auto undefined = terroir::gpu::Contents::Undefined;
      terroir::gpu::StorageBuffer bslope(bandCells * sizeof(float), undefined);
      terroir::gpu::StorageBuffer baspect(aspect ? bandCells * sizeof(float) : 4, undefined);
      terroir::gpu::StorageBuffer bnormals(normals ? 3 * bandCells * sizeof(float) : 4, undefined);
      auto& interior = ctx.GetProgram("Slope.comp", vtkTerroirSlopeCS, inner);
      auto& edges = ctx.GetProgram("Slope.comp", vtkTerroirSlopeCS, border);
      for (auto* prog : { &interior, &edges })
      {
        prog->SetInt("uNx", v.nx);
        prog->SetInt("uNy", v.ny);
        prog->SetInt("uHasMask", v.valid ? 1 : 0);
        prog->SetFloat("uConvergence", static_cast<float>(params.convergenceDeg));
      }
      t.elevation->Bind(0);
      t.mask->Bind(1);
      bcoef.Bind(2);
      bslope.Bind(3);
      baspect.Bind(4);
      bnormals.Bind(5);
      for (int j0 = 0; j0 < v.ny; j0 += bandRows)
      {
        const int j1 = std::min(v.ny, j0 + bandRows);
        const std::size_t cells = static_cast<std::size_t>(j1 - j0) * v.nx;
        const std::size_t first = static_cast<std::size_t>(j0) * v.nx;
        // Interior: columns 1 .. nx-2, rows max(j0, 1) .. min(j1, ny-1) - 1.
        const int innerRows = std::max(0, std::min(j1, v.ny - 1) - std::max(j0, 1));
        const int innerCols = std::max(0, v.nx - 2);
        for (auto* prog : { &interior, &edges })
        {
          prog->SetInt("uRowStart", j0);
          prog->SetInt("uRowEnd", j1);
        }
        interior.Dispatch(static_cast<unsigned>((innerCols + 15) / 16),
          static_cast<unsigned>((innerRows + 15) / 16));
        // Border: rows 0 and ny-1 when in the band, columns 0 and nx-1 of the other rows.
        const int borderCells = (j0 == 0 ? v.nx : 0) + (j1 == v.ny && v.ny > 1 ? v.nx : 0) +
          2 * std::max(0, std::min(j1, v.ny - 1) - std::max(j0, 1));
        edges.Dispatch(static_cast<unsigned>((borderCells + 63) / 64));
        bslope.Download(slope + first, cells * sizeof(float));
        if (aspect)
        {
          baspect.Download(aspect + first, cells * sizeof(float));
        }
        if (normals)
        {
          bnormals.Download(normals + 3 * first, 3 * cells * sizeof(float));
        }
      }
    });
}
} // namespace

//------------------------------------------------------------------------------
vtkTerroirSlope::vtkTerroirSlope() = default;

//------------------------------------------------------------------------------
vtkTerroirSlope::~vtkTerroirSlope() = default;

//------------------------------------------------------------------------------
void vtkTerroirSlope::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "ZFactor: " << this->ZFactor << "\n";
  os << indent << "SlopeUnits: " << (this->SlopeUnits == Percent ? "Percent" : "Degrees") << "\n";
  os << indent << "ComputeAspect: " << (this->ComputeAspect ? "On" : "Off") << "\n";
  os << indent << "ComputeNormals: " << (this->ComputeNormals ? "On" : "Off") << "\n";
}

//------------------------------------------------------------------------------
double vtkTerroirSlope::EstimateMemory(double nx, double ny)
{
  // Outputs (Slope 4 B, Aspect 4 B, Normals 12 B per cell); the GPU path adds a packed mask
  // (1 B) and, on a software rasterizer, elevation and mask storage buffers in host memory.
  const double perCell = 4.0 + (this->ComputeAspect ? 4.0 : 0.0) +
    (this->ComputeNormals ? 12.0 : 0.0) +
    (this->Backend == vtkTerroirComputeContext::CPU ? 0.0 : 6.0);
  return nx * ny * perCell;
}

//------------------------------------------------------------------------------
std::string vtkTerroirSlope::CheckParameters()
{
  if (!std::isfinite(this->ZFactor) || this->ZFactor <= 0.0)
  {
    return "ZFactor " + std::to_string(this->ZFactor) + " must be finite and positive";
  }
  return std::string();
}

//------------------------------------------------------------------------------
int vtkTerroirSlope::RequestTerrainData(vtkImageData* input,
  const terroir::TerrainInput& terrain,
  vtkImageData* output)
{
  const terroir::GridView<float>& v = terrain.view;
  const long long n = static_cast<long long>(v.Size());
  terroir::terrain::SlopeParams params;
  params.zFactor = this->ZFactor;
  params.units = this->SlopeUnits == Percent ? terroir::terrain::SlopeUnits::Percent
                                             : terroir::terrain::SlopeUnits::Degrees;
  params.convergenceDeg = vtkTerroirGeoreference::GetMeridianConvergence(input);

  vtkSmartPointer<vtkFloatArray> slope = vtkSmartPointer<vtkFloatArray>::Take(
    terroir::NewOutputArray(SlopeName(), 1, n, this->SlopeUnits == Percent ? "%" : "deg"));
  vtkSmartPointer<vtkFloatArray> aspect;
  vtkSmartPointer<vtkFloatArray> normals;
  if (this->ComputeAspect)
  {
    aspect =
      vtkSmartPointer<vtkFloatArray>::Take(terroir::NewOutputArray(AspectName(), 1, n, "deg"));
  }
  if (this->ComputeNormals)
  {
    static const char* const xyz[3] = { "X", "Y", "Z" };
    normals = vtkSmartPointer<vtkFloatArray>::Take(
      terroir::NewOutputArray(NormalsName(), 3, n, nullptr, xyz));
  }
  float* pSlope = slope->GetPointer(0);
  float* pAspect = aspect ? aspect->GetPointer(0) : nullptr;
  float* pNormals = normals ? normals->GetPointer(0) : nullptr;

  int backend = this->SelectBackend(this->HasGPUPath());
  if (backend < 0)
  {
    return 0;
  }
  if (backend == vtkTerroirComputeContext::GPU)
  {
    backend = this->RunGPUPath([&] { RunSlopeGPU(terrain, params, pSlope, pAspect, pNormals); });
    if (backend < 0)
    {
      return 0;
    }
    this->UpdateProgress(0.9);
  }
  if (backend == vtkTerroirComputeContext::CPU)
  {
    SlopeFunctor functor{ &v, &params, pSlope, pAspect, pNormals };
    // Ten slices on this thread (for progress), each split over the SMP threads.
    const int slices = std::min(10, v.ny);
    for (int s = 0; s < slices; ++s)
    {
      const vtkIdType r0 = static_cast<vtkIdType>(v.ny) * s / slices;
      const vtkIdType r1 = static_cast<vtkIdType>(v.ny) * (s + 1) / slices;
      vtkSMPTools::For(r0, r1, 16, functor);
      this->UpdateProgress(0.9 * (s + 1) / slices);
    }
  }
  output->GetPointData()->AddArray(slope);
  if (aspect)
  {
    output->GetPointData()->AddArray(aspect);
  }
  if (normals)
  {
    output->GetPointData()->AddArray(normals);
  }
  return 1;
}
