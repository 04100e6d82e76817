/**
 * @class   vtkTerroirWaterFlow
 * @brief   Lets the rain that the soil did not absorb run over the terrain: Long (2016)'s
 *          hydrostatic water flow, which forms rivers and lakes.
 *
 * Input: a Terroir terrain (2-D vtkImageData, point array `Elevation` in metres, optional
 * `vtkValidPointMask`, spacing or per-row spacing in metres) and, for the StandingWater sources,
 * a point array `StandingWater` (12 components, mm, from vtkTerroirSoilHumidity; input array
 * to process 1). Output: the input's arrays plus, as point data,
 * - `WaterHeight` (float32, m): water depth on each cell when the run stopped (NaN on no data);
 * - `Discharge` (float64, m^3): all the water that left each cell during the run (NaN on no
 *   data): large along the paths water takes, so rivers stand out;
 * - `River` (unsigned char): Pulse mode: 1 where Discharge >= RiverThreshold; Rivers mode: 1 on
 *   the channel cells (crests, ChannelCells in RiverValidation.h) of DischargeRate that carry
 *   the rain of at least RiverArea m^2 (DischargeRate >= RiverArea x RainRate);
 * - Rivers mode only: `DischargeRate` (float64, m^3/s): the water leaving each cell per second
 *   at steady state, averaged over RateIterations iterations after the stop (at steady state,
 *   the rain on the cell's upstream area); `LakeMask` (unsigned char): 1 on the lakes: the
 *   depressions the still water fills and the flat water surfaces of the DEM, of LakeArea or
 *   more (DepressionWaterBodies; kept apart from rivers);
 * and as field data `WaterFlowIterations` (iterations run on the grid), `WaterFlowStopReason`
 * ("AutoStop", "NoMovement", "MaximumIterations", "Balanced", "SimulatedTime" or "RequestedTime"),
 * `WaterFlowSimulatedTime` (s), and the volumes (m^3) `WaterFlowInitialVolume`,
 * `WaterFlowStoredVolume`, `WaterFlowOutflowVolume` (left through the border or into no-data cells)
 * and `WaterFlowMovedVolume` (sum over iterations of the water that moved).
 *
 * The model (terroir::hydrology::WaterFlowSimulation, WaterFlow.h): each iteration every cell
 * hands water to its 8 neighbours according to its evacuation capacity (Long (2016)'s cases all /
 * part / none): only to neighbours whose absolute height (terrain + water) is lower, never
 * lifting a receiver above the giver's new level, split in proportion to the drop weighted by
 * closeness (diagonals by distance); every iteration reads only the previous state; volume is
 * conserved apart from what leaves through Long (2016)'s one-cell border (heights continue the
 * slope) or into no-data cells, which count as outflow.
 *
 * Modes (Mode, default Pulse):
 * - Pulse: Long (2016)'s run: the source's water once, then the stop rules below.
 * - Rivers (river-forming): every depression first holds still water up to its spill level
 *   (Priority-Flood, Barnes et al. 2014: the state steady rain reaches), then RainRate mm/h
 *   (default 0.3) falls on every cell each iteration (RainRate x IterationDuration) until the
 *   outflow through the border reaches 1 - BalanceTolerance (default 0.02) of the rain (stop
 *   reason "Balanced"; Long (2016)'s auto-stop is off). With the StandingWater sources the rain
 *   is per cell instead: the month's (or the year's) `StandingWater` spread evenly over its
 *   hours (31 x 24 h for January, 365 x 24 h for the year). With WarmStart (default on) the
 *   initial water is the steady state of coarser grids refined (WaterFlowWarmStart.h: 2 x 2
 *   averages while the shorter side keeps WarmStartSide = 128 cells; each level and then the
 *   grid settle SettleIterations = 100 before the balance may stop them); field data
 *   `WaterFlowWarmStartIterations` (3 components: iterations, nx, ny of each level, coarsest
 *   first; no tuples without a warm start). Both backends (the GPU kernel adds the rain and the
 *   edge sums too, bit for bit; the levels run on the chosen backend).
 *
 * Parameters (defaults):
 * - WaterSource: Constant (0, default; InitialWater mm on every cell, default 100),
 *   StandingWaterMonth (1; component Month (1..12, default 1) of `StandingWater`),
 *   StandingWaterAnnual (2; the sum of the 12 months).
 * - Stopping: Long (2016)'s rule stops after the first iteration that moved less than
 *   AutoStopRatio (default 0.001; 0 disables it) of all the water moved so far; also when
 *   nothing moved, after MaximumIterations (default 10000), or after MaximumSimulatedTime
 *   seconds (default 0: no limit) at IterationDuration seconds per iteration (default 10 s:
 *   water travels at most one cell per iteration, 1 m/s on 10 m cells).
 * - RiverThreshold: m^3, default 10000 (the 100 mm of 1000 cells of 10 m).
 * - VTK time: the output announces TIME_STEPS 0, TimeStepStride, 2 TimeStepStride, ... up to
 *   MaximumIterations (stride default 10); a request for time t returns the state after
 *   round(t) iterations (the stop rules then do not apply). The state is cached: a later time
 *   continues from the cached one, an earlier time restarts from the nearest checkpoint (one
 *   every CheckpointInterval iterations, default 100, while they fit in CheckpointMemory MiB,
 *   default 256). Changing a parameter or the input discards the cache.
 * - Watching: IterationEventInterval k > 0 (default 0) invokes IterationEvent every k
 *   computed iterations; GetCurrentWaterHeight() then reads the state (`terroir view`).
 *
 * Backends: CPU (rows in parallel with vtkSMPTools) and GPU (Shaders/WaterFlow.comp, a gather
 * with ping-pong buffers in double precision; the stop test reads back every 16 iterations and
 * replays a block from its snapshot so that both stop after the same iteration).
 *
 * Distributed runs (pvbatch + MPI): in Pulse mode, when a global vtkMultiProcessController
 * has N > 1 processes and N pieces are asked for, each process iterates on its piece grown by
 * 3 cells and, after every iteration, receives the water of the cells within 2 (plus the ghost
 * levels asked of it) of the cells it owns from the processes that own them, and all-gathers
 * the iteration's moved, outflow and emptied sums over the cells it owns, added in rank order:
 * every process records the same iteration and stops at the same one (CPU path; no
 * checkpoints). The cells' values are the serial run's bits; the volumes (field data) are the
 * same sums in another order. Rivers mode runs in pieces too: its still water and lakes from
 * FillDepressionsDistributed (Barnes 2016), the rain's totals summed over the pieces, the
 * halo's DischargeRate, RiverStrength and net Discharge from their owners, and with WarmStart
 * the coarse levels in pieces too (DistributedWaterFlowWarmStart.h: each level tiled by the
 * halved pieces, its own halo and parallel fill; the serial levels' bits). Only when a coarse
 * level would leave a piece without a cell (tiny pieces) does it compute the whole grid on
 * every process, as a serial run does (Documentation/ParaView.md).
 *
 * Errors (one line, empty output): negative, NaN or infinite water on a cell with data,
 * missing or not 12-component `StandingWater` for the StandingWater sources, parameters out of
 * range.
 *
 * @par Correctness
 * Testing/Unit/TestWaterFlow.cxx (the model: Long (2016)'s 1-D cases, conservation, draining, one
 * flat level in a bowl, symmetry, no uphill flow, the stop rule), Testing/Pipeline/
 * TestTerroirWaterFlow.cxx (arrays, units, sources, stop reasons, time steps against fresh
 * runs, errors), Testing/GPU/TestWaterFlowGPU.cxx, Testing/Pipeline/TestDeterminism.cxx.
 *
 * @par Reference
 * Long, H. (2016). Using procedural methods to generate realistic virtual rural worlds. MSc
 * minor dissertation (Computer Science), supervised by J. Gain and M.-P. Cani; section 3.3
 * (hydrostatic water flow, table 3.3, equations 3.8-3.12, the 1-D form generalised in WaterFlow.h).
 *
 * @sa vtkTerroirSoilHumidity vtkTerroirFlowAccumulation
 */
#ifndef vtkTerroirWaterFlow_h
#define vtkTerroirWaterFlow_h

#include "vtkCommand.h"                       // For vtkCommand::UserEvent
#include "vtkTerroirFiltersHydrologyModule.h" // For export macro
#include "vtkTerroirImageAlgorithm.h"

#include <memory> // For std::unique_ptr
#include <string> // For std::string
#include <vector> // For std::vector

namespace terroir
{
template<typename T>
struct GridView;
namespace hydrology
{
struct DepressionWaterBodyOptions;
}
}

class vtkFloatArray;

class VTKTERROIRFILTERSHYDROLOGY_EXPORT vtkTerroirWaterFlow : public vtkTerroirImageAlgorithm
{
public:
  static vtkTerroirWaterFlow* New();
  vtkTypeMacro(vtkTerroirWaterFlow, vtkTerroirImageAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  static const char* WaterHeightName() { return "WaterHeight"; }
  static const char* DischargeName() { return "Discharge"; }
  static const char* RiverName() { return "River"; }
  static const char* IterationsName() { return "WaterFlowIterations"; }
  static const char* StopReasonName() { return "WaterFlowStopReason"; }
  static const char* DischargeRateName() { return "DischargeRate"; }
  static const char* LakeMaskName() { return "LakeMask"; }
  static const char* RiverStrengthName() { return "RiverStrength"; }

  enum ModeType
  {
    Pulse = 0, ///< Long (2016): the source's water once, Long (2016)'s stop rule
    Rivers = 1 ///< river-forming: rain every iteration until the outflow balances it
  };

  ///@{
  /// Pulse (default) or Rivers (see the class comment).
  vtkSetClampMacro(Mode, int, Pulse, Rivers);
  vtkGetMacro(Mode, int);
  void SetModeToPulse() { this->SetMode(Pulse); }
  void SetModeToRivers() { this->SetMode(Rivers); }
  ///@}

  ///@{
  /// Long (2016)'s literal rules, off by default (measured in Documentation/validation.md):
  /// LongCapacityRule: no water leaves a cell whose signed capacity WEC = sum c (T - H) over all
  /// 8 neighbours, higher ones included, is negative (Long (2016)'s eq. 3.8 and table 3.3;
  /// WaterFlowLongCapacity in WaterFlow.h). CountEmptiedCells: the auto-stop measures flow as
  /// the number of cells an iteration emptied completely, as Long (2016) does (its section 3.3.4),
  /// instead of the volume moved; the CPU path only (Auto runs the CPU, a GPU request is an
  /// error).
  vtkSetMacro(LongCapacityRule, vtkTypeBool);
  vtkGetMacro(LongCapacityRule, vtkTypeBool);
  vtkBooleanMacro(LongCapacityRule, vtkTypeBool);
  vtkSetMacro(CountEmptiedCells, vtkTypeBool);
  vtkGetMacro(CountEmptiedCells, vtkTypeBool);
  vtkBooleanMacro(CountEmptiedCells, vtkTypeBool);
  ///@}

  /// Rivers mode: rain on every cell, mm per hour of simulated time (finite, > 0). Default 0.3.
  vtkSetMacro(RainRate, double);
  vtkGetMacro(RainRate, double);

  /// Rivers mode: stop when the outflow reaches (1 - BalanceTolerance) of the rain, in (0, 1).
  /// Default 0.02.
  vtkSetMacro(BalanceTolerance, double);
  vtkGetMacro(BalanceTolerance, double);

  /// Rivers mode: iterations after the stop over which DischargeRate is averaged (>= 1).
  /// Default 10.
  vtkSetMacro(RateIterations, vtkIdType);
  vtkGetMacro(RateIterations, vtkIdType);

  /// Rivers mode: upstream area of the smallest river, m^2 (>= 0). Default 1e5 (0.1 km^2).
  vtkSetMacro(RiverArea, double);
  vtkGetMacro(RiverArea, double);

  /// Rivers mode: RiverStrength is DischargeRate times this factor beside the crest of a band of
  /// flow (a neighbour across the flow carries more), in [0, 1]. Default 0.1.
  vtkSetMacro(ThinningFactor, double);
  vtkGetMacro(ThinningFactor, double);

  /// Rivers mode: start from the steady state of coarser grids (WaterFlowWarmStart.h: 2 x 2
  /// averages while the shorter side keeps WarmStartSide cells, each level run to the balance,
  /// refined into the next). Default on.
  vtkSetMacro(WarmStart, vtkTypeBool);
  vtkGetMacro(WarmStart, vtkTypeBool);
  vtkBooleanMacro(WarmStart, vtkTypeBool);

  /// Rivers mode, WarmStart: shorter side of the coarsest level, cells (>= 2). Default 128.
  vtkSetMacro(WarmStartSide, int);
  vtkGetMacro(WarmStartSide, int);

  /// Rivers mode, WarmStart: iterations a warm-started grid runs before the balance may stop it
  /// (>= 0). Default 100.
  vtkSetMacro(SettleIterations, vtkIdType);
  vtkGetMacro(SettleIterations, vtkIdType);

  /// Rivers mode: smallest lake of LakeMask, m^2 (>= 0): filled depressions and flat water
  /// surfaces (hydro-flattened lakes), as vtkTerroirFloodFill finds them. Default 1e4 (1 ha).
  vtkSetMacro(LakeArea, double);
  vtkGetMacro(LakeArea, double);

  enum WaterSourceType
  {
    Constant = 0,
    StandingWaterMonth = 1,
    StandingWaterAnnual = 2
  };

  ///@{
  /// Where the initial water comes from (see the class comment). Default Constant.
  vtkSetClampMacro(WaterSource, int, Constant, StandingWaterAnnual);
  vtkGetMacro(WaterSource, int);
  void SetWaterSourceToConstant() { this->SetWaterSource(Constant); }
  void SetWaterSourceToStandingWaterMonth() { this->SetWaterSource(StandingWaterMonth); }
  void SetWaterSourceToStandingWaterAnnual() { this->SetWaterSource(StandingWaterAnnual); }
  ///@}

  /// Constant source: the water put on every cell at the start, mm (>= 0, finite; `--water`).
  /// Default 100. The simulation holds water in metres; its output is `WaterHeight` (m).
  vtkSetMacro(InitialWater, double);
  vtkGetMacro(InitialWater, double);

  /// StandingWaterMonth source: the month, 1 (January) to 12. Default 1.
  vtkSetMacro(Month, int);
  vtkGetMacro(Month, int);

  /// Long (2016)'s stop rule (fraction of the water moved so far); 0 disables. Default 0.001.
  vtkSetMacro(AutoStopRatio, double);
  vtkGetMacro(AutoStopRatio, double);

  /// Iteration limit (>= 0); also the last announced time step. Default 10000.
  vtkSetMacro(MaximumIterations, vtkIdType);
  vtkGetMacro(MaximumIterations, vtkIdType);

  /// Simulated-time limit, seconds (0: none). Default 0.
  vtkSetMacro(MaximumSimulatedTime, double);
  vtkGetMacro(MaximumSimulatedTime, double);

  /// Simulated seconds per iteration (> 0). Default 10.
  vtkSetMacro(IterationDuration, double);
  vtkGetMacro(IterationDuration, double);

  /// Discharge (m^3) from which a cell is a river. Default 10000.
  vtkSetMacro(RiverThreshold, double);
  vtkGetMacro(RiverThreshold, double);

  /// Iterations between announced time steps (>= 1). Default 10.
  vtkSetMacro(TimeStepStride, vtkIdType);
  vtkGetMacro(TimeStepStride, vtkIdType);

  /// Iterations between cached checkpoints (>= 1). Default 100.
  vtkSetMacro(CheckpointInterval, vtkIdType);
  vtkGetMacro(CheckpointInterval, vtkIdType);

  /// Memory for checkpoints, MiB (>= 0). Default 256.
  vtkSetMacro(CheckpointMemory, double);
  vtkGetMacro(CheckpointMemory, double);

  /// Iterations computed (not restored from the cache) by the last update; for tests.
  vtkGetMacro(LastComputedIterations, vtkIdType);

  ///@{
  /// Watching a run: with IterationEventInterval k > 0 (default 0: off), an update invokes
  /// IterationEvent (call data: a `vtkIdType*`, the iterations done) after every multiple of k
  /// iterations it computes (not those restored from the cache). An observer may then call
  /// GetCurrentWaterHeight() to read the state (a viewer draws it while the run goes on). The
  /// events do not change the result: the run pauses at the multiples of k on both paths (on
  /// the GPU path each pause reads the state back, so a small k costs time there).
  enum
  {
    IterationEvent = vtkCommand::UserEvent + 731
  };
  /// Does not call Modified(): watching does not change the result, so the cache is kept.
  void SetIterationEventInterval(vtkIdType k) { this->IterationEventInterval = k > 0 ? k : 0; }
  vtkGetMacro(IterationEventInterval, vtkIdType);
  /// Copies the current water depth (m, one value per point, as the `WaterHeight` output) into
  /// `out` (resized to the number of points). Valid during an IterationEvent and after an
  /// update; false (and `out` untouched) when no simulation exists.
  bool GetCurrentWaterHeight(vtkFloatArray* out);
  ///@}

protected:
  vtkTerroirWaterFlow();
  ~vtkTerroirWaterFlow() override;

  /// Decides whether this request is a piece of a distributed run (Pulse mode, a global
  /// controller of N > 1 processes and N pieces asked for), then asks for the input.
  int RequestUpdateExtent(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  /// The whole extent in a serial run (and in Rivers mode); in a distributed run the piece
  /// grown by 3 cells (2 exchanged with the neighbours every iteration, 1 more for the
  /// heights of no-data cells beside them).
  int GetHaloWidth() override { return this->DistributedRun ? 3 : -1; }
  bool HasGPUPath() override { return true; }
  double EstimateMemory(double nx, double ny) override;
  std::string CheckParameters() override;
  int RequestInformation(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
#ifndef __VTK_WRAP__
  int RequestTerrainData(vtkImageData* input,
    const terroir::TerrainInput& terrain,
    vtkImageData* output) override;
#endif

  int Mode = Pulse;
  vtkTypeBool LongCapacityRule = 0;
  vtkTypeBool CountEmptiedCells = 0;
  double RainRate = 0.3;
  double BalanceTolerance = 0.02;
  vtkIdType RateIterations = 10;
  double LakeArea = 1e4;
  vtkTypeBool WarmStart = 1;
  int WarmStartSide = 128;
  vtkIdType SettleIterations = 100;
  double RiverArea = 1e5;
  double ThinningFactor = 0.1;
  int WaterSource = Constant;
  double InitialWater = 100.0;
  int Month = 1;
  double AutoStopRatio = 1e-3;
  vtkIdType MaximumIterations = 10000;
  double MaximumSimulatedTime = 0.0;
  double IterationDuration = 10.0;
  double RiverThreshold = 10000.0;
  vtkIdType TimeStepStride = 10;
  vtkIdType CheckpointInterval = 100;
  double CheckpointMemory = 256.0;
  vtkIdType LastComputedIterations = 0;
  vtkIdType IterationEventInterval = 0;
  bool DistributedRun = false;

private:
  vtkTerroirWaterFlow(const vtkTerroirWaterFlow&) = delete;
  void operator=(const vtkTerroirWaterFlow&) = delete;

  struct Cache;
  std::unique_ptr<Cache> State;

#ifndef __VTK_WRAP__
  // RequestTerrainData in steps: a new simulation in the cache (PrepareWater: its initial water,
  // rain and lakes first), the run to a time step or a stop rule, the output arrays and field data.
  struct RunInfo
  {
    std::string ReasonName; ///< StopReason's value
    bool Timed = false;     ///< a time step was requested
    double Requested = 0.0; ///< that time step
  };
  bool PrepareWater(vtkImageData* input,
    const terroir::GridView<float>& v,
    std::vector<double>& water,
    std::vector<double>& rain);
  /// Rivers mode in pieces: the filled surface (still water) and the water bodies of this
  /// piece and the halo the iterations read (FillDepressionsDistributed, Barnes 2016).
  bool StillWaterInPieces(vtkImageData* input,
    const terroir::GridView<float>& v,
    const terroir::hydrology::DepressionWaterBodyOptions& options,
    std::vector<float>& spill,
    std::vector<std::int32_t>& ids);
  /// Whether a distributed request (outInfo's pieces) runs in pieces: always, except Rivers
  /// mode with WarmStart when a coarse level would leave a piece empty.
  bool RunsInPieces(vtkInformation* outInfo) const;
  bool NewSimulation(vtkImageData* input, const terroir::TerrainInput& terrain, int backend);
  bool Simulate(vtkImageData* input,
    const terroir::TerrainInput& terrain,
    int backend,
    RunInfo& run);
  void AddOutputs(vtkImageData* output, const terroir::GridView<float>& v, const RunInfo& run);
  /// RequestTerrainData after the backend and the distributed set-up.
  bool RunTerrainData(vtkImageData* input,
    const terroir::TerrainInput& terrain,
    vtkImageData* output,
    int backend);
  /// Distributed run: the halo exchange and the reductions for this piece (Cache::Halo); false
  /// (reported) when the input does not hold the halo.
  bool SetUpDistributed(vtkImageData* input);
#endif
};

#endif
