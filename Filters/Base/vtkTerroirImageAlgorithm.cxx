#include "vtkTerroirImageAlgorithm.h"

#include "vtkDataArray.h"
#include "vtkExtentTranslator.h"
#include "vtkImageData.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkLogger.h"
#include "vtkNew.h"
#include "vtkStreamingDemandDrivenPipeline.h"
#include "vtkTerroirComputeContext.h"
#include "vtkTerroirGPU.h"
#include "vtkTerroirGeoreference.h"
#include "vtkTerroirTerrainInput.h"

#include "MemoryBudget.h"

#include "vtkTerroirFiltersBaseModule.h" // For VTK_MODULE_ENABLE_VTK_ParallelCore
#if VTK_MODULE_ENABLE_VTK_ParallelCore
#include "vtkMultiProcessController.h"
#endif

#include <algorithm>
#include <cstdlib>
#include <mutex>
#include <new>
#include <set>

//------------------------------------------------------------------------------
vtkTerroirImageAlgorithm::vtkTerroirImageAlgorithm()
{
  this->SetInputArrayToProcess(
    0, 0, 0, vtkDataObject::FIELD_ASSOCIATION_POINTS, vtkTerroirGeoreference::ElevationName());
}

//------------------------------------------------------------------------------
vtkTerroirImageAlgorithm::~vtkTerroirImageAlgorithm() = default;

//------------------------------------------------------------------------------
void vtkTerroirImageAlgorithm::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Backend: " << vtkTerroirComputeContext::GetBackendName(this->Backend) << "\n";
  os << indent << "LastBackend: "
     << (this->LastBackend < 0 ? "(none)"
                               : vtkTerroirComputeContext::GetBackendName(this->LastBackend))
     << "\n";
  os << indent << "LastBackendReason: " << this->LastBackendReason << "\n";
}

//------------------------------------------------------------------------------
std::string vtkTerroirImageAlgorithm::SourcePrefix(vtkDataObject* input)
{
  const std::string file = input ? vtkTerroirGeoreference::GetSourceFile(input) : std::string();
  return file.empty() ? std::string() : file + ": ";
}

//------------------------------------------------------------------------------
vtkMultiProcessController* vtkTerroirImageAlgorithm::GetDistributedController(
  vtkInformation* outInfo)
{
#if VTK_MODULE_ENABLE_VTK_ParallelCore
  using SDDP = vtkStreamingDemandDrivenPipeline;
  vtkMultiProcessController* controller = vtkMultiProcessController::GetGlobalController();
  const int pieces = outInfo && outInfo->Has(SDDP::UPDATE_NUMBER_OF_PIECES())
    ? outInfo->Get(SDDP::UPDATE_NUMBER_OF_PIECES())
    : 1;
  return controller && controller->GetNumberOfProcesses() > 1 &&
      pieces == controller->GetNumberOfProcesses()
    ? controller
    : nullptr;
#else
  (void)outInfo;
  return nullptr;
#endif
}

//------------------------------------------------------------------------------
void vtkTerroirImageAlgorithm::GetOwnedExtent(int piece,
  int pieces,
  const int whole[6],
  int owned[6])
{
  int w[6];
  std::copy(whole, whole + 6, w);
  vtkNew<vtkExtentTranslator> translator;
  translator->PieceToExtentThreadSafe(
    piece, pieces, 0, w, owned, vtkExtentTranslator::BLOCK_MODE, 0);
  for (int a = 0; a < 3; ++a)
  {
    owned[2 * a + 1] -= owned[2 * a + 1] < whole[2 * a + 1] ? 1 : 0;
  }
}

//------------------------------------------------------------------------------
int vtkTerroirImageAlgorithm::RequestUpdateExtent(vtkInformation*,
  vtkInformationVector** inputVector,
  vtkInformationVector* outputVector)
{
  vtkInformation* inInfo = inputVector[0]->GetInformationObject(0);
  vtkInformation* outInfo = outputVector->GetInformationObject(0);
  this->DistributedRequest = GetDistributedController(outInfo) != nullptr;
  int whole[6];
  inInfo->Get(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT(), whole);
  int ext[6];
  const int halo = this->GetHaloWidth();
  if (halo < 0 || !outInfo->Has(vtkStreamingDemandDrivenPipeline::UPDATE_EXTENT()))
  {
    std::copy(whole, whole + 6, ext);
  }
  else
  {
    outInfo->Get(vtkStreamingDemandDrivenPipeline::UPDATE_EXTENT(), ext);
    for (int a = 0; a < 3; ++a)
    {
      ext[2 * a] = std::max(ext[2 * a] - halo, whole[2 * a]);
      ext[2 * a + 1] = std::min(ext[2 * a + 1] + halo, whole[2 * a + 1]);
    }
  }
  inInfo->Set(vtkStreamingDemandDrivenPipeline::UPDATE_EXTENT(), ext, 6);
  // A piece request (pvbatch + MPI) is turned into an extent by the upstream executive, from
  // the piece number and ghost levels, whatever UPDATE_EXTENT says: the halo travels as ghost
  // levels (vtkExtentTranslator grows the piece by them, clamped to the whole extent), and a
  // whole-extent filter asks for the one piece of one.
  using SDDP = vtkStreamingDemandDrivenPipeline;
  if (halo < 0)
  {
    inInfo->Set(SDDP::UPDATE_PIECE_NUMBER(), 0);
    inInfo->Set(SDDP::UPDATE_NUMBER_OF_PIECES(), 1);
    inInfo->Set(SDDP::UPDATE_NUMBER_OF_GHOST_LEVELS(), 0);
  }
  else if (halo > 0 && outInfo->Has(SDDP::UPDATE_NUMBER_OF_PIECES()))
  {
    const int ghost = outInfo->Has(SDDP::UPDATE_NUMBER_OF_GHOST_LEVELS())
      ? outInfo->Get(SDDP::UPDATE_NUMBER_OF_GHOST_LEVELS())
      : 0;
    inInfo->Set(SDDP::UPDATE_NUMBER_OF_GHOST_LEVELS(), ghost + halo);
  }
  return 1;
}

//------------------------------------------------------------------------------
namespace
{
/**
 * The extent this request asks of the output: in a piece request (UPDATE_NUMBER_OF_PIECES > 1,
 * as pvbatch + MPI makes) the piece and its ghost levels, turned into an extent as the source
 * turned them (vtkExtentTranslator in block mode, the pipeline's default); else
 * UPDATE_EXTENT. False when the request names none.
 */
bool RequestedExtent(vtkInformation* outInfo, int extent[6])
{
  using SDDP = vtkStreamingDemandDrivenPipeline;
  if (!outInfo)
  {
    return false;
  }
  const int pieces = outInfo->Has(SDDP::UPDATE_NUMBER_OF_PIECES())
    ? outInfo->Get(SDDP::UPDATE_NUMBER_OF_PIECES())
    : 1;
  if (pieces > 1 && outInfo->Has(SDDP::WHOLE_EXTENT()))
  {
    int whole[6];
    outInfo->Get(SDDP::WHOLE_EXTENT(), whole);
    const int piece = outInfo->Get(SDDP::UPDATE_PIECE_NUMBER());
    const int ghost = outInfo->Has(SDDP::UPDATE_NUMBER_OF_GHOST_LEVELS())
      ? outInfo->Get(SDDP::UPDATE_NUMBER_OF_GHOST_LEVELS())
      : 0;
    vtkNew<vtkExtentTranslator> translator;
    return translator->PieceToExtentThreadSafe(
             piece, pieces, ghost, whole, extent, vtkExtentTranslator::BLOCK_MODE, 0) == 1;
  }
  if (!outInfo->Has(SDDP::UPDATE_EXTENT()))
  {
    return false;
  }
  outInfo->Get(SDDP::UPDATE_EXTENT(), extent);
  return true;
}

/// A piece computed with its halo (or on the whole extent) is given back as exactly the extent
/// asked for, so that the pieces of a parallel run do not overlap. The serial path asks for
/// the extent it computed: nothing is copied there.
void CropToUpdateExtent(vtkInformation* outInfo, vtkImageData* output)
{
  int update[6];
  if (!RequestedExtent(outInfo, update))
  {
    return;
  }
  int extent[6];
  output->GetExtent(extent);
  bool same = true;
  bool inside = true;
  for (int a = 0; a < 3; ++a)
  {
    same = same && update[2 * a] == extent[2 * a] && update[2 * a + 1] == extent[2 * a + 1];
    inside = inside && update[2 * a] >= extent[2 * a] && update[2 * a + 1] <= extent[2 * a + 1] &&
      update[2 * a] <= update[2 * a + 1];
  }
  if (!same && inside)
  {
    output->Crop(update);
  }
}
} // namespace

//------------------------------------------------------------------------------
int vtkTerroirImageAlgorithm::RequestData(vtkInformation*,
  vtkInformationVector** inputVector,
  vtkInformationVector* outputVector)
{
  vtkImageData* input = vtkImageData::GetData(inputVector[0]);
  vtkImageData* output = vtkImageData::GetData(outputVector);
  if (!output)
  {
    vtkErrorMacro(<< "output is not a vtkImageData");
    return 0;
  }
  output->Initialize();
  if (!input)
  {
    vtkErrorMacro(<< "input is missing or not a vtkImageData");
    return 0;
  }
  std::string error = this->CheckParameters();
  if (!error.empty())
  {
    vtkErrorMacro(<< this->SourcePrefix(input) << error);
    return 0;
  }
  vtkDataArray* elevation = this->GetInputArrayToProcess(0, inputVector);
  int dims[3];
  input->GetDimensions(dims);
  if (dims[2] == 1 && elevation)
  {
    // ExtractTerrain may copy a non-float elevation (4 B per cell) and build a mask (1 B).
    const double cells = static_cast<double>(dims[0]) * dims[1];
    const double needed = this->EstimateMemory(dims[0], dims[1]) +
      cells * ((elevation->GetDataType() == VTK_FLOAT ? 0.0 : 4.0) + 1.0);
    error = terroir::CheckMemory(needed, this->GetClassName());
    if (!error.empty())
    {
      vtkErrorMacro(<< this->SourcePrefix(input) << error);
      return 0;
    }
  }
  try
  {
    terroir::TerrainInput terrain;
    if (!terroir::ExtractTerrain(input, elevation, terrain, error, this->GetMinimumGridSize()))
    {
      vtkErrorMacro(<< this->SourcePrefix(input) << error);
      return 0;
    }
    this->UpdateProgress(0.0);
    output->ShallowCopy(input);
    if (!this->RequestTerrainData(input, terrain, output))
    {
      output->Initialize();
      return 0;
    }
    CropToUpdateExtent(outputVector->GetInformationObject(0), output);
  }
  catch (const std::bad_alloc&)
  {
    output->Initialize();
    vtkErrorMacro(<< this->SourcePrefix(input) << "out of memory in " << this->GetClassName()
                  << " (" << dims[0] << " x " << dims[1] << " cells)");
    return 0;
  }
  this->UpdateProgress(1.0);
  return 1;
}

//------------------------------------------------------------------------------
int vtkTerroirImageAlgorithm::SelectBackend(bool hasGPUPath)
{
  std::string reason;
  const int backend = vtkTerroirComputeContext::ResolveBackend(
    this->Backend, this->GetClassName(), hasGPUPath, reason);
  this->LastBackendReason = reason;
  if (backend < 0)
  {
    this->LastBackend = -1;
    vtkErrorMacro(<< "cannot run on the requested backend: " << reason);
    return -1;
  }
  this->LastBackend = backend;
  static std::mutex logMutex;
  static std::set<std::string> logged;
  const std::string key =
    std::string(this->GetClassName()) + vtkTerroirComputeContext::GetBackendName(backend);
  std::lock_guard<std::mutex> lock(logMutex);
  if (logged.insert(key).second)
  {
    // The reason starts with the backend's name: "vtkTerroirSlope: GPU (auto: llvmpipe ...)".
    vtkLog(INFO, << this->GetClassName() << ": " << reason);
  }
  return backend;
}

//------------------------------------------------------------------------------
int vtkTerroirImageAlgorithm::RunGPUPath(const std::function<void()>& gpuJob)
{
  try
  {
    gpuJob();
    return vtkTerroirComputeContext::GPU;
  }
  catch (const std::exception& e)
  {
    const char* env = std::getenv("TERROIR_BACKEND");
    const bool envGPU = env && (std::string(env) == "gpu" || std::string(env) == "GPU");
    if (this->Backend == vtkTerroirComputeContext::GPU ||
      (this->Backend == vtkTerroirComputeContext::Auto && envGPU))
    {
      this->LastBackend = -1;
      vtkErrorMacro(<< "GPU path failed: " << e.what());
      return -1;
    }
    vtkWarningMacro(<< "GPU path failed, falling back to the CPU: " << e.what());
    this->LastBackend = vtkTerroirComputeContext::CPU;
    this->LastBackendReason = std::string("auto: GPU failed (") + e.what() + "), CPU fallback";
    return vtkTerroirComputeContext::CPU;
  }
}

void vtkTerroirImageAlgorithm::SetMonthValue(double* months, int month, double value)
{
  if (month < 0 || month > 11)
  {
    vtkErrorMacro(<< "month index " << month << " outside 0..11 (0 = January)");
    return;
  }
  if (months[month] != value)
  {
    months[month] = value;
    this->Modified();
  }
}
