/**
 * @file TerroirCommandLine.h
 * @brief The `terroir` command line parsed into plain settings (CLI11, no VTK), so that parsing
 * can be unit-tested and fuzzed on its own (Testing/Fuzz/FuzzCommandLine.cxx).
 *
 * Each command declares its options in Applications/Commands/<Name>Options.cxx
 * (TerroirCommandOptions.h); CommandDescriptions() lists the commands in --help's order.
 *
 * ParseCommandLine never prints and never exits: it fills a CommandLine, or says what to print
 * and which exit status to return (help: the text and 0; a bad option: one line and 2).
 * Every number is checked here (finite, within its documented range) and every output file
 * name must end in a format the command writes, so that a bad command line is refused before
 * any file is read or any work is done.
 */
#ifndef TerroirCommandLine_h
#define TerroirCommandLine_h

#include <cstdint>
#include <limits>
#include <string>
#include <vector>

namespace terroir
{
namespace app
{

/// Options of the temperature model (`run`, `temperature`).
struct TemperatureSettings
{
  double Coldest = 2.0;            ///< sea-level temperature of the coldest month, C
  double Warmest = 20.0;           ///< sea-level temperature of the warmest month, C
  int ColdestMonth = 0;            ///< 1..12, 0 = the hemisphere's default
  int WarmestMonth = 0;            ///< 1..12, 0 = the hemisphere's default
  std::vector<double> Monthly;     ///< 12 sea-level temperatures (--monthly), or empty
  std::string ClimateFile;         ///< --climate: a climate table with a temperature_c column
  double LapseRate = 6.4;          ///< C per km
  std::string Hemisphere = "auto"; ///< auto, north or south
};

/// Options of the solar illumination filter (`illumination`; `run` uses the Monthly defaults
/// and only Latitude/Longitude). Which options apply depends on Mode (see ParseCommandLine).
struct IlluminationSettings
{
  std::string Mode = "monthly"; ///< instant, daily or monthly
  int Year = 2025;              ///< --date (instant, daily) or --year (monthly)
  int Month = 6;                ///< --date, 1..12
  int Day = 21;                 ///< --date, 1..days in the month
  bool HasTime = false;         ///< --time given
  double Time = 12.0;           ///< --time, local clock hours [0, 24] (instant)
  double UTCOffset = 0.0;       ///< --utc-offset, hours [-14, 14]: UTC = Time - UTCOffset
  int MonthlyDay = 15;          ///< --day, day of every month used (monthly), 1..31
  double TimeStep = 10.0;       ///< --step, minutes [1, 1440] (daily, monthly)
  double Latitude = std::numeric_limits<double>::quiet_NaN();    ///< --lat (NaN: georeference)
  double Longitude = std::numeric_limits<double>::quiet_NaN();   ///< --lon (NaN: georeference)
  double Orientation = std::numeric_limits<double>::quiet_NaN(); ///< --orientation (NaN: CRS)
  std::string Method = "horizon"; ///< --method: horizon (horizon map) or raymarch
  int Sectors = 64;               ///< --sectors, [4, 1024]
  bool Curvature = false;         ///< --curvature
  double Transmittance = 0.7;     ///< --transmittance, [0.01, 1]
  bool UseSun = false;            ///< --sun given (instant)
  double SunAzimuth = 180.0;      ///< --sun AZ, degrees clockwise from true north, [0, 360]
  double SunElevation = 45.0;     ///< --sun EL, degrees, [-90, 90]
  std::string InsolationOutput;   ///< --insolation FILE (daily, monthly)
  std::string IncidenceOutput;    ///< --incidence FILE (instant)
};

/// One infiltration operation, in the order the command line gives them (infiltration,
/// humidity). Kind: fill (Value mm/h), slope-rule (Value degrees), paint-raster (File, Value:
/// cells where the raster is non-zero), paint-polygons (File, Value), soil-raster (File: codes
/// 1..5), soil-polygons (File, Attribute: a field holding codes 1..5).
struct InfiltrationOperation
{
  std::string Kind;
  double Value = 0.0;
  std::string File;
  std::string Attribute;
};

/// Options of the soil-water filters (`infiltration`, `humidity`; `run` uses the climate).
struct SoilWaterSettings
{
  std::vector<InfiltrationOperation> Operations; ///< empty: fill 15 mm/h, slope rule 30 deg
  std::vector<double> Precipitation; ///< --precip: 12 values, mm, or empty (default / climate)
  std::vector<double> Intensity;     ///< --intensity: 12 values, mm/h, or empty
  std::string ClimateFile;           ///< --climate (humidity): precipitation and intensity
  std::string InfiltrationInput;     ///< --infiltration FILE: rates instead of the operations
  std::string WeightedOutput;        ///< --weighted FILE (humidity)
  std::string StandingOutput;        ///< --standing FILE (humidity)
};

/// Options of `floodfill`.
struct FloodFillSettings
{
  /// --seed X,Y[,LEVEL] (world coordinates, metres of the DEM's CRS) or --seed-cell I,J[,LEVEL]
  /// (column and row, row 0 in the south); LEVEL NaN = --level, else the terrain at the seed.
  struct Seed
  {
    double X = 0.0;
    double Y = 0.0;
    double Level = std::numeric_limits<double>::quiet_NaN();
    bool Cell = false;
  };
  std::vector<Seed> Seeds;
  double Level = std::numeric_limits<double>::quiet_NaN(); ///< --level H, metres
  bool FillDepressions = false;                            ///< --fill-depressions
  double MinimumArea = 10000.0;                            ///< --min-area, m2
  bool FlatSurfaces = true;                                ///< off with --no-flat-surfaces
  std::string IdsOutput;                                   ///< --ids FILE: WaterBody ids
};

/// Options of `waterflow` and `validate` (the simulation).
struct WaterFlowSettings
{
  double InitialWater = 100.0;         ///< --water MM on every cell
  int Month = 0;                       ///< --month M: StandingWater of month M (soil-water chain)
  bool Annual = false;                 ///< --annual: the year's StandingWater
  long long MaximumIterations = 10000; ///< --max-iterations
  double AutoStop = 1e-3;              ///< --auto-stop RATIO (0: off)
  double Time = 0.0;                   ///< --time SECONDS (0: no limit)
  double IterationDuration = 10.0;     ///< --iteration-duration SECONDS
  double RiverThreshold = std::numeric_limits<double>::quiet_NaN(); ///< --river-threshold M3
  std::string Mode;               ///< --mode pulse|rivers; empty: the command's default
  double RainRate = 0.3;          ///< --rain MM_PER_HOUR (rivers mode)
  double BalanceTolerance = 0.02; ///< --balance TOLERANCE (rivers mode)
  double Thinning = 0.1;          ///< --thinning FACTOR (rivers mode: RiverStrength)
  bool WarmStart = true;          ///< off with --no-warm-start (rivers mode: coarse-to-fine)
  long long Settle = 100;         ///< --settle N (rivers mode, warm start)
  bool LongCapacity = false;      ///< --long-capacity: Long (2016)'s literal WEC < 0 rule
  bool CountEmptied = false;      ///< --count-emptied: Long (2016)'s emptied-cell stop count
  std::string DischargeOutput;    ///< --discharge FILE (waterflow)
  std::string RiverOutput;        ///< --river FILE (waterflow)
};

/// Options of `validate`.
struct ValidateSettings
{
  std::string Reference;          ///< --reference: river lines (any OGR format)
  std::string Mask;               ///< --mask: area (raster on the DEM grid, or polygons)
  std::vector<std::string> Peers; ///< --peer NAME=RASTER: accumulation rasters of peer tools
  std::string Json;               ///< --json FILE
  std::string Png;                ///< --png FILE (overlay)
  std::string Sweep;              ///< --sweep NAME=V1,V2,...: one simulation row per value
};

/**
 * Applies one value of a validate sweep to the simulation's settings: NAME is a water-flow
 * option without its dashes (water, rain, balance, thinning, settle, max-iterations, auto-stop,
 * time, iteration-duration, river-threshold, mode). Throws std::invalid_argument naming --sweep and
 * the bad name or value.
 */
void ApplySweepValue(WaterFlowSettings& s, const std::string& name, const std::string& value);

/// Splits "NAME=V1,V2,..." into the name and its values (checked with ApplySweepValue).
void ParseSweep(const std::string& text, std::string& name, std::vector<std::string>& values);

/// Options of the k-means clustering (`kmeans`; `run` uses Clusters only).
struct KMeansSettings
{
  int Clusters = 5; ///< -k, --clusters K, 1..64 (run: 0 skips the stage)
  /// --features NAME[:WEIGHT],...: feature arrays and weights (weight 1 when left out); empty:
  /// Long (2016)'s defaults (Slope, Temperature, IlluminationHours, WeightedSoilHumidity 0.1)
  std::vector<std::string> FeatureNames;
  std::vector<double> FeatureWeights;
  bool Standardize = false;         ///< --standardize: z-scores before weighting
  std::string Seeding = "diagonal"; ///< --seeding diagonal or kmeans++
  int Seed = 0;                     ///< --seed N (kmeans++), >= 0
  int MaximumIterations = 300;      ///< --max-iterations N, >= 1
  double Tolerance = 1e-4;          ///< --tolerance T, >= 0
  std::string Csv;                  ///< --csv FILE: the cluster table
  std::string Json;                 ///< --json FILE: the cluster table and the run
  std::string Png;                  ///< --png FILE: the cluster overlay
};

/// Options of `view` (the interactive window; Documentation/Viewer.md).
struct ViewSettings
{
  std::string Script; ///< --script FILE: actions to replay (checked before any work)
  std::string Curves; ///< --curves FILE: feature curves drawn over the terrain (GeoJSON, .vtp)
  int Width = 1024;   ///< --size WxH, [320, 7680]
  int Height = 768;   ///< --size WxH, [240, 4320]
  std::string Overlay = "none";  ///< --overlay NAME (see TerroirViewerScript.h)
  std::string Style = "terrain"; ///< --style terrain or first-person
  std::string ScreenshotDir;     ///< --screenshot-dir DIR (empty: the current folder)
  double Sensitivity = 1.0;      ///< --sensitivity F, mouse, [0.01, 100]
  double MoveSpeed = 1.0;        ///< --move-speed F, first-person keys, [0.01, 100]
  int Month = 6;                 ///< --month M, 1..12
  double Hour = 10.0;            ///< --hour H, [0, 24]
  double Orientation = std::numeric_limits<double>::quiet_NaN(); ///< --orientation DEG
  int Clusters = 5;                                              ///< --clusters K, 1..64
  double LakeDepth = 5.0;                                        ///< --lake-depth M, [0, 10000]
  std::string ClimateFile; ///< --climate FILE: the session's climate (CSV or JSON)
  /// --lod-points N: above N grid points the window draws a coarse surface while it is being
  /// used and the full one when it rests (0: always the full one).
  long long LodPoints = 250000;
};

/// `terroir run`'s outputs: which files (--outputs, --no-vti) and their layout.
struct RunOutputSettings
{
  std::vector<std::string> Only;        ///< --outputs: files, stages or kinds (empty: every file)
  bool NoVti = false;                   ///< --no-vti
  std::string VtiCompression = "lz4";   ///< --vti-compression: lz4, zlib or none
  std::string TiffCompression = "none"; ///< --tiff-compression: none, deflate, zstd or lzw
  std::string TiffLayout = "strips";    ///< --tiff-layout: tiles (256 x 256) or strips
  int TiffThreads = 0;                  ///< --tiff-threads: GDAL NUM_THREADS (0 its default)
  bool TiffOverviews = false;           ///< --tiff-overviews
};

/// Everything the command line says.
struct CommandLine
{
  std::string Command; ///< run, slope, temperature, illumination, infiltration, humidity,
                       ///< floodfill, waterflow, flowacc, validate, kmeans, bench, info,
                       ///< fractal, generate or view
  bool Verbose = false;
  std::string Backend = "auto"; ///< auto, cpu or gpu
  bool Overwrite = false;
  bool AllowNetwork = false;
  std::string ZUnit = "auto"; ///< --z-unit: heights of a GDAL DEM in auto, m, ft or us-ft

  std::string Input;            ///< DEM / IN (run: empty = the bundled DEM)
  std::string Output;           ///< OUT (run: --out folder)
  bool NoPng = false;           ///< run
  RunOutputSettings RunOutputs; ///< run: which files, and how they are compressed

  double ZFactor = 1.0;     ///< slope
  bool Percent = false;     ///< slope
  std::string AspectOutput; ///< slope --aspect

  TemperatureSettings Temperature; ///< run, temperature

  IlluminationSettings Illumination; ///< illumination (run: Latitude, Longitude)

  SoilWaterSettings SoilWater; ///< infiltration, humidity (run: the climate)

  FloodFillSettings FloodFill; ///< floodfill

  WaterFlowSettings WaterFlow;     ///< waterflow, validate
  ValidateSettings Validate;       ///< validate
  double FlowRiverThreshold = 1e5; ///< flowacc --river-threshold, m2
  std::string FlowMethod = "d8";   ///< flowacc --method d8|mfd|dinf
  double FlowMFDExponent = 1.1;    ///< flowacc --mfd-exponent

  KMeansSettings KMeans; ///< kmeans (run: Clusters)

  ViewSettings View; ///< view (and Illumination.Latitude/Longitude: --lat, --lon)

  int BenchSize = 2048;
  int BenchRepeat = 3;
  std::vector<std::string> BenchBackends{ "cpu", "gpu" };
  std::vector<std::string> BenchStages; ///< --stages, in the order of BenchStageNames()
  bool BenchBandwidth = false;
  bool BenchGPUBreakdown = false; ///< --gpu-breakdown
  std::string BenchJson;

  int FractalSize = 1024;
  int FractalSeed = 1;
  double FractalSpacing = 10.0;

  /// `generate`: the generator (island, riverland) and its settings; a JSON --params file first,
  /// then the options given (see GenerateOptions.cxx).
  struct GenerateSettings
  {
    std::string Kind = "island";
    std::string ParamsFile;
    long long Seed = 1;
    int Width = 512;
    int Height = 512;
    double Spacing = 30.0;
    int Regions = 1000;
    int Relaxations = 2;
    int Rivers = 0;
    double MaximumHeight = 1000.0;
    double MaximumDepth = 200.0;
    double NoiseScale = 0.25;
    double Perturbation = 0.02;
    std::string BiomeOutput; ///< --biome FILE
    std::string RiverOutput; ///< --river-map FILE
    std::string RiverLines;  ///< --river-lines FILE.geojson
    std::string CRS;         ///< --crs: a projected CRS GDAL takes (empty: none)
    std::vector<double> Origin{ 500000.0, 4000000.0 }; ///< --origin X,Y with --crs
    /// `generate riverland`'s own settings (GenerateRiverLandOptions.cxx).
    struct RiverLandSettings
    {
      int Threads = 1;    ///< --threads
      std::string Params; ///< the checked --params JSON, less the keys the options override
    } RiverLand;
    /// `generate features` (GenerateFeaturesOptions.cxx): Weiss (2015)'s feature curves.
    struct FeatureSettings
    {
      std::string Curves;         ///< --curves FILE (.geojson, .json or .vtp)
      std::string SaveCurves;     ///< --save-curves FILE.vtp
      std::string Base;           ///< --base DEM (empty: a flat BaseElevation)
      double Tolerance = 1e-3;    ///< --tolerance M
      int MaximumCycles = 100;    ///< --max-cycles N
      double BaseElevation = 0.0; ///< --base-elevation M
    } Features;
  } Generate;

  // morphometry (vtkTerroirMorphometry)
  std::string MorphometryOutput;            ///< optional OUT (Output defaults to run's folder)
  double MorphometryChannelArea = 1.0e5;    ///< --channel-area, m2
  double MorphometryDepressionDepth = 1e-3; ///< --depression-depth, m
  std::string MorphometryJson;              ///< --json FILE
  std::string MorphometryCsv;               ///< --csv FILE (the per-order Horton table)

  // erosion (vtkTerroirErosion)
  struct ErosionSettings
  {
    int Steps = 100;               ///< --steps N
    double TimeStep = 0.01;        ///< --time-step S (Weiss's dt)
    double InitialWater = 0.05;    ///< --water M on every cell at the start
    double RainRate = 0.0;         ///< --rain MM per hour
    double TalusAngle = 33.0;      ///< --talus DEG
    int ThermalInterval = 1;       ///< --thermal-interval N (0: no soil slip)
    double CapacityDepth = 0.0;    ///< --capacity-depth M (0: off)
    double Vegetation = -1.0;      ///< --vegetation V: Dunn's vegetation from density V (< 0: off)
    std::string SeaLevel;          ///< --sea M: the Sea boundary at this level (empty: Closed)
    bool Weather = false;          ///< --weather: Dunn's wind, vapour and rain
    double WindDirection = 270.0;  ///< --wind-direction DEG (blowing from)
    double WindStrength = 1.0;     ///< --wind-strength M/S
    double EvaporationScale = 1.0; ///< --evaporation-scale F
  } Erosion;

  // plants (vtkTerroirPlantPlacement)
  struct PlantSettings
  {
    std::string Exemplar;         ///< --exemplar FILE (.csv or .vtp)
    std::vector<double> Window;   ///< --exemplar-window XMIN XMAX YMIN YMAX (empty: bounds)
    double Density = 0.01;        ///< --density, plants per m2 (no exemplar)
    double MinimumDistance = 5.0; ///< --min-distance M (no exemplar: hard core)
    double MaximumDistance = 0.0; ///< --max-distance M (0: 2 x min-distance, 10 m with one)
    int Bins = 20;                ///< --bins N
    std::uint64_t Seed = 1;       ///< --seed N
    long long Iterations = 0;     ///< --iterations N (0: 200 per expected plant)
  } Plants;
  // new-filter.sh: options
};

/// What ParseCommandLine decided.
struct ParseOutcome
{
  bool Run = false;   ///< true: carry out `CommandLine::Command`
  int ExitCode = 0;   ///< when !Run: 0 after help, 2 after an error
  std::string Stdout; ///< help text to print when !Run
  std::string Error;  ///< one line (no newline) when ExitCode != 0
};

/// Parses `argv` (argv[0] is the program name). See the file comment.
ParseOutcome ParseCommandLine(int argc, const char* const* argv, CommandLine& line);

/// One command of `terroir`: its name and the one-line summary --help shows.
struct CommandDescription
{
  const char* Name;
  const char* Summary;
};

/// Every command, in the order --help lists them. The program binds each name to its code in
/// Applications/Commands/TerroirCommands.cxx (a unit test checks that both lists agree).
const std::vector<CommandDescription>& CommandDescriptions();

/// The summary of the command `name`; throws std::logic_error for an unknown name.
const char* CommandSummary(const std::string& name);

/// The stages `terroir bench` knows, in the order it runs them (the default is all of them).
const std::vector<std::string>& BenchStageNames();

/// Parses "a,b,c" into numbers; throws std::invalid_argument with a one-line message naming
/// `option` and the first item that is not a finite number.
std::vector<double> ParseNumberList(const std::string& text, const std::string& option);

} // namespace app
} // namespace terroir

#endif
