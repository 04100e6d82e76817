#include "vtkTerroirFloodFill.h"

#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkFloatArray.h"
#include "vtkIdTypeArray.h"
#include "vtkImageData.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkIntArray.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkSmartPointer.h"
#include "vtkStreamingDemandDrivenPipeline.h"
#include "vtkStringArray.h"
#include "vtkTerroirTerrainInput.h"

#include "DepressionWaterBodies.h"
#include "DistributedPriorityFlood.h"
#include "FloodFill.h"
#include "PriorityFlood.h"

#include "NumberText.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <new>
#include <sstream>
#include <stdexcept>

#include "vtkTerroirFiltersHydrologyModule.h" // For VTK_MODULE_ENABLE_VTK_ParallelCore
#if VTK_MODULE_ENABLE_VTK_ParallelCore
#include "vtkMultiProcessController.h"
#include "vtkTerroirControllerTileExchange.h"
#endif

vtkStandardNewMacro(vtkTerroirFloodFill);

namespace
{
vtkSmartPointer<vtkDoubleArray> BodyArray(const char* name,
  const char* units,
  const std::vector<terroir::hydrology::WaterBodyStats>& bodies,
  double terroir::hydrology::WaterBodyStats::*member)
{
  auto a = vtkSmartPointer<vtkDoubleArray>::New();
  a->SetName(name);
  a->SetNumberOfTuples(static_cast<vtkIdType>(bodies.size()));
  for (std::size_t b = 0; b < bodies.size(); ++b)
  {
    a->SetValue(static_cast<vtkIdType>(b), bodies[b].*member);
  }
  a->GetInformation()->Set(vtkDataArray::UNITS_LABEL(), units);
  return a;
}
} // namespace

//------------------------------------------------------------------------------
vtkTerroirFloodFill::vtkTerroirFloodFill() = default;

//------------------------------------------------------------------------------
vtkTerroirFloodFill::~vtkTerroirFloodFill() = default;

//------------------------------------------------------------------------------
void vtkTerroirFloodFill::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Mode: " << this->GetModeAsString() << "\n";
  os << indent << "Seeds: " << this->SeedList.size() << "\n";
  for (std::size_t s = 0; s < this->SeedList.size(); ++s)
  {
    const Seed& seed = this->SeedList[s];
    os << indent.GetNextIndent() << this->DescribeSeed(s) << ", level "
       << (seed.HasLevel ? terroir::NumberText(seed.Level) + " m" : std::string("terrain")) << "\n";
  }
  os << indent << "MinimumArea: " << this->MinimumArea << "\n";
  os << indent << "IncludeFlatSurfaces: " << (this->IncludeFlatSurfaces ? "On" : "Off") << "\n";
}

//------------------------------------------------------------------------------
const char* vtkTerroirFloodFill::GetModeAsString()
{
  return this->Mode == FillDepressions ? "FillDepressions" : "Seeds";
}

//------------------------------------------------------------------------------
void vtkTerroirFloodFill::AddSeed(const Seed& seed)
{
  this->SeedList.push_back(seed);
  this->Modified();
}

void vtkTerroirFloodFill::AddSeedPoint(double x, double y)
{
  this->AddSeed(Seed{ false, x, y, 0, 0, false, 0.0 });
}

void vtkTerroirFloodFill::AddSeedPoint(double x, double y, double level)
{
  this->AddSeed(Seed{ false, x, y, 0, 0, true, level });
}

void vtkTerroirFloodFill::AddSeedCell(int i, int j)
{
  this->AddSeed(Seed{ true, 0.0, 0.0, i, j, false, 0.0 });
}

void vtkTerroirFloodFill::AddSeedCell(int i, int j, double level)
{
  this->AddSeed(Seed{ true, 0.0, 0.0, i, j, true, level });
}

void vtkTerroirFloodFill::RemoveAllSeeds()
{
  if (!this->SeedList.empty())
  {
    this->SeedList.clear();
    this->Modified();
  }
}

int vtkTerroirFloodFill::GetNumberOfSeeds()
{
  return static_cast<int>(this->SeedList.size());
}

//------------------------------------------------------------------------------
std::string vtkTerroirFloodFill::DescribeSeed(std::size_t s) const
{
  const Seed& seed = this->SeedList[s];
  return "seed " + std::to_string(s + 1) +
    (seed.IsCell
        ? " at cell (" + std::to_string(seed.I) + ", " + std::to_string(seed.J) + ")"
        : " at (" + terroir::NumberText(seed.X) + ", " + terroir::NumberText(seed.Y) + ")");
}

//------------------------------------------------------------------------------
double vtkTerroirFloodFill::EstimateMemory(double nx, double ny)
{
  // Outputs: WaterBody 4 B + WaterDepth 4 B per cell. Seeds: the fill stack holds each wet cell
  // once (4 B), up to twice that while std::vector grows. FillDepressions, at its peak during
  // Priority-Flood: the filled surface (4 B), visited flags (1 B), the priority queue (8 B per
  // queued cell, up to twice that while growing; at worst every cell) and the pit FIFO (4 B);
  // the labelling that follows needs less (1 B flags, 4-8 B queue) after those are freed.
  const double perCell = this->Mode == FillDepressions ? 8.0 + 4.0 + 1.0 + 16.0 + 4.0 : 8.0 + 8.0;
  return nx * ny * perCell;
}

//------------------------------------------------------------------------------
std::string vtkTerroirFloodFill::CheckParameters()
{
  if (!(this->MinimumArea >= 0.0) || !std::isfinite(this->MinimumArea))
  {
    return "MinimumArea " + terroir::NumberText(this->MinimumArea) +
      " m2 must be a finite number >= 0";
  }
  if (this->Mode != Seeds)
  {
    return std::string();
  }
  if (this->SeedList.empty())
  {
    return "Seeds mode needs at least one seed (AddSeedPoint or AddSeedCell)";
  }
  for (std::size_t s = 0; s < this->SeedList.size(); ++s)
  {
    const Seed& seed = this->SeedList[s];
    if (!seed.IsCell && !(std::isfinite(seed.X) && std::isfinite(seed.Y)))
    {
      return this->DescribeSeed(s) + " has non-finite coordinates";
    }
    if (seed.HasLevel && !std::isfinite(seed.Level))
    {
      return this->DescribeSeed(s) + " has a non-finite level " + terroir::NumberText(seed.Level);
    }
  }
  return std::string();
}

//------------------------------------------------------------------------------
int vtkTerroirFloodFill::RequestTerrainData(vtkImageData* input,
  const terroir::TerrainInput& terrain,
  vtkImageData* output)
{
  namespace hy = terroir::hydrology;
  const terroir::GridView<float>& v = terrain.view;
  const std::size_t n = v.Size();
  if (this->SelectBackend(this->HasGPUPath()) < 0)
  {
    return 0; // a GPU request: this filter has no GPU path
  }

  // Seeds to cells, with every check before anything is allocated. A distributed run places
  // them in the whole extent (every rank alike) and checks the cells it owns.
  std::vector<hy::FloodSeed> seeds;
  std::vector<hy::DistributedSeed> wholeSeeds;
  std::vector<int> noData; // distributed: per seed, 1 when this rank owns its cell and it has none
  if (this->Mode == Seeds)
  {
    int ext[6], input6[6], owned[6] = { 0, -1, 0, -1, 0, -1 };
    double origin[3], spacing[3];
    input->GetExtent(input6);
    std::copy(input6, input6 + 6, ext);
    input->GetOrigin(origin);
    input->GetSpacing(spacing);
    if (this->DistributedRequest)
    {
      using SDDP = vtkStreamingDemandDrivenPipeline;
      vtkInformation* outInfo = this->GetOutputInformation(0);
      outInfo->Get(SDDP::WHOLE_EXTENT(), ext);
      GetOwnedExtent(outInfo->Get(SDDP::UPDATE_PIECE_NUMBER()),
        outInfo->Get(SDDP::UPDATE_NUMBER_OF_PIECES()),
        ext,
        owned);
    }
    const int wnx = ext[1] - ext[0] + 1;
    const int wny = ext[3] - ext[2] + 1;
    for (std::size_t s = 0; s < this->SeedList.size(); ++s)
    {
      const Seed& seed = this->SeedList[s];
      double ci = seed.I;
      double cj = seed.J;
      if (!seed.IsCell)
      {
        ci = std::floor((seed.X - origin[0]) / spacing[0] + 0.5) - ext[0];
        cj = std::floor((seed.Y - origin[1]) / spacing[1] + 0.5) - ext[2];
      }
      if (!(ci >= 0.0 && ci < wnx && cj >= 0.0 && cj < wny))
      {
        std::string where;
        if (seed.IsCell)
        {
          where = "the terrain of " + std::to_string(wnx) + " x " + std::to_string(wny) +
            " cells (i 0.." + std::to_string(wnx - 1) + ", j 0.." + std::to_string(wny - 1) + ")";
        }
        else
        {
          const double x0 = origin[0] + (ext[0] - 0.5) * spacing[0];
          const double x1 = origin[0] + (ext[1] + 0.5) * spacing[0];
          const double y0 = origin[1] + (ext[2] - 0.5) * spacing[1];
          const double y1 = origin[1] + (ext[3] + 0.5) * spacing[1];
          where = "the terrain, which covers x " + terroir::NumberText(std::min(x0, x1)) + " .. " +
            terroir::NumberText(std::max(x0, x1)) + ", y " + terroir::NumberText(std::min(y0, y1)) +
            " .. " + terroir::NumberText(std::max(y0, y1));
        }
        vtkErrorMacro(<< this->SourcePrefix(input) << this->DescribeSeed(s) << " lies outside "
                      << where);
        return 0;
      }
      const int i = static_cast<int>(ci);
      const int j = static_cast<int>(cj);
      if (this->DistributedRequest)
      {
        // The rank that owns the cell checks it; the ranks all-reduce the answer below.
        const int gi = i + ext[0];
        const int gj = j + ext[2];
        const bool mine = gi >= owned[0] && gi <= owned[1] && gj >= owned[2] && gj <= owned[3];
        const std::size_t k = mine ? v.Index(gi - input6[0], gj - input6[2]) : 0;
        noData.push_back(mine && !hy::HasData(v, k) ? 1 : 0);
        if (mine && hy::HasData(v, k) && seed.HasLevel && seed.Level < v.data[k])
        {
          vtkWarningMacro(<< this->SourcePrefix(input) << this->DescribeSeed(s) << ": level "
                          << terroir::NumberText(seed.Level) << " m is below the terrain there ("
                          << terroir::NumberText(v.data[k]) << " m); its water body is empty");
        }
        hy::DistributedSeed ds;
        ds.cell = static_cast<std::int64_t>(j) * wnx + i;
        if (seed.HasLevel)
        {
          ds.level = seed.Level;
        }
        wholeSeeds.push_back(ds);
        continue;
      }
      const std::size_t k = v.Index(i, j);
      if (!hy::HasData(v, k))
      {
        vtkErrorMacro(<< this->SourcePrefix(input) << this->DescribeSeed(s) << " falls on cell ("
                      << i << ", " << j << "), which holds no data");
        return 0;
      }
      if (seed.HasLevel && seed.Level < v.data[k])
      {
        vtkWarningMacro(<< this->SourcePrefix(input) << this->DescribeSeed(s) << ": level "
                        << terroir::NumberText(seed.Level) << " m is below the terrain there ("
                        << terroir::NumberText(v.data[k]) << " m); its water body is empty");
      }
      hy::FloodSeed fs;
      fs.cell = k;
      if (seed.HasLevel)
      {
        fs.level = seed.Level;
      }
      seeds.push_back(fs);
    }
  }

  vtkSmartPointer<vtkFloatArray> depth = vtkSmartPointer<vtkFloatArray>::Take(
    terroir::NewOutputArray(WaterDepthName(), 1, static_cast<long long>(n), "m"));
  auto ids = vtkSmartPointer<vtkIntArray>::New();
  ids->SetName(WaterBodyName());
  if (!ids->Allocate(static_cast<vtkIdType>(n)))
  {
    throw std::bad_alloc();
  }
  ids->SetNumberOfTuples(static_cast<vtkIdType>(n));
  std::int32_t* idp = ids->GetPointer(0);
  float* dp = depth->GetPointer(0);

  std::vector<hy::WaterBodyStats> bodies;
  if (this->Mode == Seeds && this->DistributedRequest)
  {
    if (!this->FloodSeedsInPieces(input, v, wholeSeeds, noData, idp, dp, bodies))
    {
      return 0;
    }
  }
  else if (this->Mode == Seeds)
  {
    bodies = hy::FloodFillSeeds(
      v, seeds, idp, dp, [this](double f) { this->UpdateProgress(0.05 + 0.9 * f); });
  }
  else if (this->DistributedRequest)
  {
    if (!this->FillDepressionsInPieces(input, v, idp, dp, bodies))
    {
      return 0;
    }
  }
  else
  {
    vtkDebugMacro(<< "FillDepressions: improved Priority-Flood, "
                  << hy::kPriorityFloodBarnes2014Citation);
    std::vector<float> filled(n);
    hy::PriorityFloodBarnes2014(
      v, filled.data(), [this](double f) { this->UpdateProgress(0.05 + 0.7 * f); });
    hy::DepressionWaterBodyOptions options;
    options.minimumArea = this->MinimumArea;
    options.includeFlatSurfaces = this->IncludeFlatSurfaces;
    bodies = hy::DepressionWaterBodies(v,
      filled.data(),
      options,
      idp,
      dp,
      [this](double f) { this->UpdateProgress(0.75 + 0.2 * f); });
  }

  output->GetPointData()->AddArray(ids);
  output->GetPointData()->AddArray(depth);
  vtkFieldData* fd = output->GetFieldData();
  fd->AddArray(BodyArray(WaterBodyLevelName(), "m", bodies, &hy::WaterBodyStats::level));
  fd->AddArray(BodyArray(WaterBodyAreaName(), "m2", bodies, &hy::WaterBodyStats::area));
  fd->AddArray(BodyArray(WaterBodyVolumeName(), "m3", bodies, &hy::WaterBodyStats::volume));
  fd->AddArray(BodyArray(WaterBodyMaxDepthName(), "m", bodies, &hy::WaterBodyStats::maxDepth));
  auto cells = vtkSmartPointer<vtkIdTypeArray>::New();
  cells->SetName(WaterBodyCellsName());
  cells->SetNumberOfTuples(static_cast<vtkIdType>(bodies.size()));
  for (std::size_t b = 0; b < bodies.size(); ++b)
  {
    cells->SetValue(static_cast<vtkIdType>(b), static_cast<vtkIdType>(bodies[b].cells));
  }
  fd->AddArray(cells);
  auto mode = vtkSmartPointer<vtkStringArray>::New();
  mode->SetName(FloodFillModeName());
  mode->InsertNextValue(this->GetModeAsString());
  fd->AddArray(mode);
  return 1;
}

//------------------------------------------------------------------------------
bool vtkTerroirFloodFill::FillDepressionsInPieces(vtkImageData* input,
  const terroir::GridView<float>& view,
  std::int32_t* ids,
  float* depth,
  std::vector<terroir::hydrology::WaterBodyStats>& bodies)
{
  return this->RunInPieces(input, view, nullptr, ids, depth, bodies);
}

//------------------------------------------------------------------------------
bool vtkTerroirFloodFill::FloodSeedsInPieces(vtkImageData* input,
  const terroir::GridView<float>& view,
  const std::vector<terroir::hydrology::DistributedSeed>& seeds,
  const std::vector<int>& noData,
  std::int32_t* ids,
  float* depth,
  std::vector<terroir::hydrology::WaterBodyStats>& bodies)
{
#if VTK_MODULE_ENABLE_VTK_ParallelCore
  // A seed on a no-data cell is an error, as in a serial run: its owner knows, every rank hears.
  vtkMultiProcessController* controller = GetDistributedController(this->GetOutputInformation(0));
  std::vector<int> any(noData.size(), 0);
  if (!controller ||
    (!noData.empty() &&
      !controller->AllReduce(
        noData.data(), any.data(), static_cast<vtkIdType>(noData.size()), vtkCommunicator::MAX_OP)))
  {
    vtkErrorMacro(<< this->SourcePrefix(input) << "the all-reduce of the seeds' cells failed");
    return false;
  }
  int whole[6];
  this->GetOutputInformation(0)->Get(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT(), whole);
  const long long wnx = whole[1] - whole[0] + 1;
  for (std::size_t s = 0; s < any.size(); ++s)
  {
    if (any[s])
    {
      vtkErrorMacro(<< this->SourcePrefix(input) << this->DescribeSeed(s) << " falls on cell ("
                    << seeds[s].cell % wnx << ", " << seeds[s].cell / wnx
                    << "), which holds no data");
      return false;
    }
  }
#endif
  return this->RunInPieces(input, view, &seeds, ids, depth, bodies);
}

//------------------------------------------------------------------------------
bool vtkTerroirFloodFill::RunInPieces(vtkImageData* input,
  const terroir::GridView<float>& view,
  const std::vector<terroir::hydrology::DistributedSeed>* seeds,
  std::int32_t* ids,
  float* depth,
  std::vector<terroir::hydrology::WaterBodyStats>& bodies)
{
  namespace hy = terroir::hydrology;
#if VTK_MODULE_ENABLE_VTK_ParallelCore
  using SDDP = vtkStreamingDemandDrivenPipeline;
  vtkInformation* outInfo = this->GetOutputInformation(0);
  vtkMultiProcessController* controller = GetDistributedController(outInfo);
  if (!controller || !outInfo->Has(SDDP::WHOLE_EXTENT()))
  {
    vtkErrorMacro(<< this->SourcePrefix(input) << "a distributed run without its controller");
    return false;
  }
  vtkDebugMacro(<< "flood fill in pieces: " << hy::kPriorityFloodBarnes2016Citation);
  const hy::DistributedFillInput in =
    vtkTerroirControllerTileExchange::TileInput(outInfo, input, view);
  hy::DepressionWaterBodyOptions options;
  options.minimumArea = this->MinimumArea;
  options.includeFlatSurfaces = this->IncludeFlatSurfaces;
  vtkTerroirControllerTileExchange exchange(controller);
  std::string error;
  const bool ok = vtkTerroirControllerTileExchange::Run(
    [&]
    {
      hy::DistributedFillResult result = seeds
        ? hy::FloodFillSeedsDistributed(in, *seeds, exchange)
        : hy::FillDepressionsDistributed(in, options, exchange);
      std::copy(result.bodyId.begin(), result.bodyId.end(), ids);
      std::copy(result.depth.begin(), result.depth.end(), depth);
      bodies = std::move(result.bodies);
    },
    error);
  if (!ok)
  {
    vtkErrorMacro(<< this->SourcePrefix(input) << error);
  }
  return ok;
#else
  (void)view;
  (void)seeds;
  (void)ids;
  (void)depth;
  (void)bodies;
  vtkErrorMacro(<< this->SourcePrefix(input) << "built without VTK::ParallelCore");
  return false;
#endif
}
