/**
 * @file vtkTerroirControllerTileExchange.h
 * @brief The distributed hydrology cores' TileExchange over a vtkMultiProcessController, and
 *        the tile a piece request gives this process (private to Terroir::FiltersHydrology).
 *
 * DistributedPriorityFlood.h and DistributedFlowAccumulation.h talk through gathers to rank 0
 * and replies from it. Gather is the controller's Gather of the lengths then GatherV; the
 * replies go point to point (a length, then the bytes): ParaView 5.11's
 * vtkMPICommunicator::ScatterV of unequal byte counts delivered short messages (a run under
 * mpirun -np 2 hung). Any failed call throws std::runtime_error.
 */
#ifndef vtkTerroirControllerTileExchange_h
#define vtkTerroirControllerTileExchange_h

#include "DistributedPriorityFlood.h"
#include "GridView.h"

#include <functional>
#include <string>
#include <vector>

class vtkImageData;
class vtkInformation;
class vtkMultiProcessController;

class vtkTerroirControllerTileExchange : public terroir::hydrology::TileExchange
{
public:
  explicit vtkTerroirControllerTileExchange(vtkMultiProcessController* controller);
  int Rank() const override;
  int Size() const override;
  std::vector<std::vector<char>> Gather(const std::vector<char>& mine) override;
  std::vector<char> Scatter(const std::vector<std::vector<char>>& parts) override;

  /**
   * The tile of a distributed request (outInfo: piece, pieces, ghost levels, whole extent):
   * `view` on the input's extent, the owned points (vtkTerroirImageAlgorithm::GetOwnedExtent)
   * in whole-grid indices, and a reach of 1 + the output's ghost levels (the piece's upper
   * boundary points are one step beyond its owned ones).
   */
  static terroir::hydrology::DistributedFillInput TileInput(vtkInformation* outInfo,
    vtkImageData* input,
    const terroir::GridView<float>& view);

  /// Runs `job` (a call of a distributed core); false, with the exception's message in
  /// `error`, when it throws (std::bad_alloc goes on to the base class, which reports it).
  static bool Run(const std::function<void()>& job, std::string& error);

private:
  static void Check(int ok);
  static constexpr int kTag = 25016; ///< this exchange's messages (issue 25, Barnes 2016)
  vtkMultiProcessController* Controller;
};

#endif
