#include "vtkTerroirSlope.h"

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

/// Runs Shaders/Slope.comp (bindings documented there) on the compute context.
void RunSlopeGPU(const terroir::GridView<float>& v,
  const terroir::terrain::SlopeParams& params,
  float* slope,
  float* aspect,
  float* normals)
{
  const std::size_t n = v.Size();
  // Per-row coefficients, as the core computes them (double, then float).
  std::vector<float> coef(4 * static_cast<std::size_t>(v.ny));
  for (int j = 0; j < v.ny; ++j)
  {
    const int jn = std::min(j + 1, v.ny - 1);
    const int js = std::max(j - 1, 0);
    coef[4 * j + 0] = static_cast<float>(params.zFactor / (8.0 * v.DxAt(jn)));
    coef[4 * j + 1] = static_cast<float>(params.zFactor / (8.0 * v.DxAt(j)));
    coef[4 * j + 2] = static_cast<float>(params.zFactor / (8.0 * v.DxAt(js)));
    coef[4 * j + 3] = static_cast<float>(params.zFactor / (8.0 * v.DyAt(j)));
  }
  // Validity packed four cells per uint (byte k of word w is cell 4w + k).
  std::vector<std::uint32_t> mask(v.valid ? (n + 3) / 4 : 1, 0u);
  if (v.valid)
  {
    for (std::size_t k = 0; k < n; ++k)
    {
      mask[k / 4] |= static_cast<std::uint32_t>(v.valid[k] ? 1u : 0u) << (8 * (k % 4));
    }
  }
  auto& ctx = terroir::gpu::Context::Global();
  const long long maxBlock = ctx.GetLimits().MaxShaderStorageBlockSize;
  const long long largest = static_cast<long long>((normals ? 3 : 1) * n * sizeof(float));
  if (maxBlock > 0 && largest > maxBlock)
  {
    throw terroir::gpu::Error("grid too large for one GPU storage buffer (" +
      std::to_string(largest) + " > " + std::to_string(maxBlock) + " bytes)");
  }
  ctx.Run(
    [&]
    {
      terroir::gpu::StorageBuffer bz(n * sizeof(float), v.data);
      terroir::gpu::StorageBuffer bmask(mask.size() * sizeof(std::uint32_t), mask.data());
      terroir::gpu::StorageBuffer bcoef(coef.size() * sizeof(float), coef.data());
      terroir::gpu::StorageBuffer bslope(n * sizeof(float));
      terroir::gpu::StorageBuffer baspect(aspect ? n * sizeof(float) : sizeof(float));
      terroir::gpu::StorageBuffer bnormals(normals ? 3 * n * sizeof(float) : sizeof(float));
      auto& prog = ctx.GetProgram("Slope.comp", vtkTerroirSlopeCS, { "LOCAL_X 16", "LOCAL_Y 16" });
      prog.Use();
      prog.SetInt("uNx", v.nx);
      prog.SetInt("uNy", v.ny);
      prog.SetInt("uHasMask", v.valid ? 1 : 0);
      prog.SetInt("uPercent", params.units == terroir::terrain::SlopeUnits::Percent ? 1 : 0);
      prog.SetInt("uAspect", aspect ? 1 : 0);
      prog.SetInt("uNormals", normals ? 1 : 0);
      prog.SetFloat("uConvergence", static_cast<float>(params.convergenceDeg));
      bz.Bind(0);
      bmask.Bind(1);
      bcoef.Bind(2);
      bslope.Bind(3);
      baspect.Bind(4);
      bnormals.Bind(5);
      prog.Dispatch((v.nx + 15) / 16, (v.ny + 15) / 16);
      bslope.Download(slope, n * sizeof(float));
      if (aspect)
      {
        baspect.Download(aspect, n * sizeof(float));
      }
      if (normals)
      {
        bnormals.Download(normals, 3 * n * sizeof(float));
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
  if (backend == 2)
  {
    backend = this->RunGPUPath([&] { RunSlopeGPU(v, params, pSlope, pAspect, pNormals); });
    if (backend < 0)
    {
      return 0;
    }
    this->UpdateProgress(0.9);
  }
  if (backend == 1)
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
