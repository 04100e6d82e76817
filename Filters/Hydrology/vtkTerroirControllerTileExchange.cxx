#include "vtkTerroirControllerTileExchange.h"

#include "vtkTerroirFiltersHydrologyModule.h" // For VTK_MODULE_ENABLE_VTK_ParallelCore

#if VTK_MODULE_ENABLE_VTK_ParallelCore
#include "vtkImageData.h"
#include "vtkInformation.h"
#include "vtkMultiProcessController.h"
#include "vtkStreamingDemandDrivenPipeline.h"
#include "vtkTerroirImageAlgorithm.h"

#include <new>
#include <stdexcept>

//------------------------------------------------------------------------------
vtkTerroirControllerTileExchange::vtkTerroirControllerTileExchange(
  vtkMultiProcessController* controller)
  : Controller(controller)
{
}

//------------------------------------------------------------------------------
int vtkTerroirControllerTileExchange::Rank() const
{
  return this->Controller->GetLocalProcessId();
}

//------------------------------------------------------------------------------
int vtkTerroirControllerTileExchange::Size() const
{
  return this->Controller->GetNumberOfProcesses();
}

//------------------------------------------------------------------------------
std::vector<std::vector<char>> vtkTerroirControllerTileExchange::Gather(
  const std::vector<char>& mine)
{
  const std::size_t ranks = static_cast<std::size_t>(this->Size());
  const long length = static_cast<long>(mine.size());
  std::vector<long> lengths(ranks, 0);
  Check(this->Controller->Gather(&length, lengths.data(), 1, 0));
  std::vector<vtkIdType> counts(lengths.begin(), lengths.end());
  std::vector<vtkIdType> offsets(ranks, 0);
  for (std::size_t r = 1; r < ranks; ++r)
  {
    offsets[r] = offsets[r - 1] + counts[r - 1];
  }
  std::vector<char> all(
    this->Rank() == 0 ? static_cast<std::size_t>(offsets.back() + counts.back()) : 0);
  Check(this->Controller->GatherV(
    mine.data(), all.data(), static_cast<vtkIdType>(length), counts.data(), offsets.data(), 0));
  std::vector<std::vector<char>> parts;
  for (std::size_t r = 0; r < ranks && this->Rank() == 0; ++r)
  {
    parts.emplace_back(all.begin() + offsets[r], all.begin() + offsets[r] + counts[r]);
  }
  return parts;
}

//------------------------------------------------------------------------------
std::vector<char> vtkTerroirControllerTileExchange::Scatter(
  const std::vector<std::vector<char>>& parts)
{
  const int ranks = this->Size();
  if (this->Rank() == 0)
  {
    for (int r = 1; r < ranks; ++r)
    {
      const std::vector<char>& part = parts.at(static_cast<std::size_t>(r));
      const long length = static_cast<long>(part.size());
      Check(this->Controller->Send(&length, 1, r, kTag));
      Check(this->Controller->Send(part.data(), static_cast<vtkIdType>(length), r, kTag));
    }
    return parts.at(0);
  }
  long length = 0;
  Check(this->Controller->Receive(&length, 1, 0, kTag));
  if (length < 0)
  {
    throw std::runtime_error("a negative message length from rank 0");
  }
  std::vector<char> mine(static_cast<std::size_t>(length));
  Check(this->Controller->Receive(mine.data(), static_cast<vtkIdType>(length), 0, kTag));
  return mine;
}

//------------------------------------------------------------------------------
void vtkTerroirControllerTileExchange::Check(int ok)
{
  if (!ok)
  {
    throw std::runtime_error("an MPI gather or scatter failed");
  }
}

//------------------------------------------------------------------------------
bool vtkTerroirControllerTileExchange::Run(const std::function<void()>& job, std::string& error)
{
  try
  {
    job();
  }
  catch (const std::bad_alloc&)
  {
    throw;
  }
  catch (const std::exception& x)
  {
    error = x.what();
    return false;
  }
  return true;
}

//------------------------------------------------------------------------------
terroir::hydrology::DistributedFillInput vtkTerroirControllerTileExchange::TileInput(
  vtkInformation* outInfo,
  vtkImageData* input,
  const terroir::GridView<float>& view)
{
  using SDDP = vtkStreamingDemandDrivenPipeline;
  int whole[6], owned[6], e[6];
  outInfo->Get(SDDP::WHOLE_EXTENT(), whole);
  vtkTerroirImageAlgorithm::GetOwnedExtent(outInfo->Get(SDDP::UPDATE_PIECE_NUMBER()),
    outInfo->Get(SDDP::UPDATE_NUMBER_OF_PIECES()),
    whole,
    owned);
  input->GetExtent(e);
  terroir::hydrology::DistributedFillInput in;
  in.view = view;
  in.gi0 = e[0] - whole[0];
  in.gj0 = e[2] - whole[2];
  in.owned = terroir::hydrology::TileBox{
    owned[0] - whole[0], owned[1] - whole[0], owned[2] - whole[2], owned[3] - whole[2]
  };
  in.wholeNx = whole[1] - whole[0] + 1;
  in.wholeNy = whole[3] - whole[2] + 1;
  in.reach = 1 +
    (outInfo->Has(SDDP::UPDATE_NUMBER_OF_GHOST_LEVELS())
        ? outInfo->Get(SDDP::UPDATE_NUMBER_OF_GHOST_LEVELS())
        : 0);
  return in;
}
#endif
