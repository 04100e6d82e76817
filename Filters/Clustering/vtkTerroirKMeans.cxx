#include "vtkTerroirKMeans.h"
#include "vtkTerroirComputeContext.h"

#include "vtkDataArray.h"
#include "vtkDoubleArray.h"
#include "vtkExtentTranslator.h"
#include "vtkFieldData.h"
#include "vtkFloatArray.h"
#include "vtkIdTypeArray.h"
#include "vtkImageData.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkIntArray.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkSMPTools.h"
#include "vtkSmartPointer.h"
#include "vtkStreamingDemandDrivenPipeline.h"
#include "vtkStringArray.h"
#include "vtkTable.h"
#include "vtkTerroirKMeansGPU.h"
#include "vtkTerroirTerrainInput.h"

#include "KMeans.h"

#include "NumberText.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>
#include <new>
#include <sstream>
#include <stdexcept>

#if VTK_MODULE_ENABLE_VTK_ParallelCore
#include "vtkCommunicator.h"
#include "vtkMultiProcessController.h"
#endif

vtkStandardNewMacro(vtkTerroirKMeans);

namespace
{
namespace cl = terroir::clustering;

/// Long (2016)'s features and weights (Long (2016), ch. 4), used when none is added.
const struct
{
  const char* name;
  double weight;
} DefaultFeatures[] = {
  { "Slope", 1.0 },
  { "Temperature", 1.0 },
  { "IlluminationHours", 1.0 },
  { "WeightedSoilHumidity", 0.1 },
};

#if VTK_MODULE_ENABLE_VTK_ParallelCore
/// The core's all-reduce through a vtkMultiProcessController (every process calls it alike).
class ControllerReduction : public cl::KMeansReduction
{
public:
  explicit ControllerReduction(vtkMultiProcessController* controller)
    : Controller(controller)
  {
  }
  void Sum(double* v, std::size_t n) override { this->Reduce(v, n, vtkCommunicator::SUM_OP); }
  void Sum(std::int64_t* v, std::size_t n) override { this->Reduce(v, n, vtkCommunicator::SUM_OP); }
  void Max(double* v, std::size_t n) override { this->Reduce(v, n, vtkCommunicator::MAX_OP); }
  void Min(double* v, std::size_t n) override { this->Reduce(v, n, vtkCommunicator::MIN_OP); }
  void Min(std::int64_t* v, std::size_t n) override { this->Reduce(v, n, vtkCommunicator::MIN_OP); }

private:
  template<typename T>
  void Reduce(T* values, std::size_t n, int operation)
  {
    if (n == 0)
    {
      return;
    }
    const std::vector<T> local(values, values + n);
    if (!this->Controller->AllReduce(local.data(), values, static_cast<vtkIdType>(n), operation))
    {
      throw std::runtime_error("k-means: the all-reduce over the MPI processes failed");
    }
  }
  vtkMultiProcessController* Controller;
};
#endif

/// The reduction of a distributed run for `outInfo`'s request: a global controller of N > 1
/// processes and N pieces asked for; null otherwise (a serial run).
std::unique_ptr<cl::KMeansReduction> DistributedReduction(vtkInformation* outInfo)
{
#if VTK_MODULE_ENABLE_VTK_ParallelCore
  if (vtkMultiProcessController* controller =
        vtkTerroirImageAlgorithm::GetDistributedController(outInfo))
  {
    return std::unique_ptr<cl::KMeansReduction>(new ControllerReduction(controller));
  }
#else
  (void)outInfo;
#endif
  return nullptr;
}

/// vtkSMPTools over [begin, end); the ranges are disjoint, their order and count free.
cl::KMeansParallelFor SMPParallelFor()
{
  return
    [](
      std::size_t begin, std::size_t end, const std::function<void(std::size_t, std::size_t)>& body)
  {
    vtkSMPTools::For(static_cast<vtkIdType>(begin),
      static_cast<vtkIdType>(end),
      [&body](vtkIdType b, vtkIdType e)
      { body(static_cast<std::size_t>(b), static_cast<std::size_t>(e)); });
  };
}

/// A feature array of the input, resolved.
struct InputFeature
{
  std::string name;
  double weight = 1.0;
  vtkDataArray* array = nullptr;
};

/// Column name of component `c` of `array` in the cluster table.
std::string ColumnName(vtkDataArray* array, int c)
{
  const std::string name = array->GetName() ? array->GetName() : "";
  if (array->GetNumberOfComponents() == 1)
  {
    return name;
  }
  const char* component = array->GetComponentName(c);
  return name + "_" + (component && *component ? std::string(component) : std::to_string(c));
}

vtkSmartPointer<vtkDoubleArray> ScalarArray(const char* name, double value)
{
  auto a = vtkSmartPointer<vtkDoubleArray>::New();
  a->SetName(name);
  a->InsertNextValue(value);
  return a;
}

vtkSmartPointer<vtkIntArray> IntArray(const char* name, int value)
{
  auto a = vtkSmartPointer<vtkIntArray>::New();
  a->SetName(name);
  a->InsertNextValue(value);
  return a;
}

/// The core's view of feature `f` over the m = cells.size() cells that take part: the array
/// itself when it is float and no cell is left out, else a packed float copy in `packed`.
cl::KMeansInputArray PackFeature(const InputFeature& f,
  const std::vector<std::size_t>& cells,
  std::size_t n,
  std::vector<float>& packed)
{
  const std::size_t m = cells.size();
  cl::KMeansInputArray in;
  in.name = f.name;
  in.components = f.array->GetNumberOfComponents();
  in.weight = f.weight;
  if (f.array->GetDataType() == VTK_FLOAT && m == n)
  {
    in.values = static_cast<const float*>(f.array->GetVoidPointer(0));
    return in;
  }
  const int nc = in.components;
  packed.resize(m * static_cast<std::size_t>(nc));
  vtkSMPTools::For(0,
    static_cast<vtkIdType>(m),
    [&](vtkIdType b, vtkIdType e)
    {
      for (vtkIdType i = b; i < e; ++i)
      {
        for (int j = 0; j < nc; ++j)
        {
          packed[static_cast<std::size_t>(i) * nc + j] =
            static_cast<float>(f.array->GetComponent(static_cast<vtkIdType>(cells[i]), j));
        }
      }
    });
  in.values = packed.data();
  return in;
}

/// The columns ClusterId, Color, Cells and Share of the cluster table (k rows, m cells in all);
/// returns the Share column.
vtkSmartPointer<vtkDoubleArray> AddMemberColumns(vtkTable* table,
  const std::vector<std::int64_t>& counts,
  int k,
  std::size_t m)
{
  auto idColumn = vtkSmartPointer<vtkIntArray>::New();
  idColumn->SetName("ClusterId");
  auto colorColumn = vtkSmartPointer<vtkStringArray>::New();
  colorColumn->SetName("Color");
  auto cellColumn = vtkSmartPointer<vtkIdTypeArray>::New();
  cellColumn->SetName("Cells");
  auto shareColumn = vtkSmartPointer<vtkDoubleArray>::New();
  shareColumn->SetName("Share");
  for (int c = 0; c < k; ++c)
  {
    idColumn->InsertNextValue(c);
    colorColumn->InsertNextValue(cl::KMeansClusterColor(c));
    cellColumn->InsertNextValue(static_cast<vtkIdType>(counts[c]));
    shareColumn->InsertNextValue(static_cast<double>(counts[c]) / static_cast<double>(m));
  }
  table->AddColumn(idColumn);
  table->AddColumn(colorColumn);
  table->AddColumn(cellColumn);
  table->AddColumn(shareColumn);
  return shareColumn;
}

/// A column per component of feature `f` in the cluster table: its mean over each cluster's
/// members (finite values only, double sums in cell order), in the array's units.
void AddFeatureMeanColumns(vtkTable* table,
  const InputFeature& f,
  const std::vector<std::size_t>& cells,
  const std::vector<std::int32_t>& labels,
  int k,
  cl::KMeansReduction* reduction)
{
  const std::size_t m = cells.size();
  const int nc = f.array->GetNumberOfComponents();
  std::vector<double> sum(static_cast<std::size_t>(k) * nc, 0.0);
  std::vector<std::int64_t> count(static_cast<std::size_t>(k) * nc, 0);
  for (std::size_t i = 0; i < m; ++i)
  {
    const std::size_t base = static_cast<std::size_t>(labels[i]) * nc;
    for (int j = 0; j < nc; ++j)
    {
      const double value = f.array->GetComponent(static_cast<vtkIdType>(cells[i]), j);
      if (std::isfinite(value))
      {
        sum[base + j] += value;
        ++count[base + j];
      }
    }
  }
  if (reduction)
  {
    reduction->Sum(sum.data(), sum.size());
    reduction->Sum(count.data(), count.size());
  }
  const char* units = f.array->GetInformation()->Has(vtkDataArray::UNITS_LABEL())
    ? f.array->GetInformation()->Get(vtkDataArray::UNITS_LABEL())
    : nullptr;
  for (int j = 0; j < nc; ++j)
  {
    auto column = vtkSmartPointer<vtkDoubleArray>::New();
    column->SetName(ColumnName(f.array, j).c_str());
    if (units)
    {
      column->GetInformation()->Set(vtkDataArray::UNITS_LABEL(), units);
    }
    for (int c = 0; c < k; ++c)
    {
      const std::size_t s = static_cast<std::size_t>(c) * nc + j;
      column->InsertNextValue(count[s] > 0 ? sum[s] / static_cast<double>(count[s]) : NAN);
    }
    table->AddColumn(column);
  }
}
} // namespace

/// The state of one RequestTerrainData, from its steps to the next.
struct vtkTerroirKMeans::Clustering
{
  std::string prefix;                       ///< SourcePrefix of the input, for messages
  std::size_t n = 0;                        ///< cells of the terrain
  int k = 0;                                ///< clusters
  std::vector<InputFeature> features;       ///< the feature arrays, resolved
  std::vector<std::uint8_t> valid;          ///< per terrain cell: takes part
  std::vector<std::size_t> cells;           ///< the terrain cells that take part, in order (m)
  std::vector<std::vector<float>> packed;   ///< packed float copies, until the matrix is made
  std::vector<cl::KMeansInputArray> inputs; ///< the core's view of the features
  /// vtkSMPTools over blocks of cells, for the core
  cl::KMeansParallelFor parallelFor = SMPParallelFor();
  std::vector<float> matrix;          ///< the prepared, weighted feature matrix
  cl::KMeansFeatures x;               ///< its view
  int uncollapsed = 0;                ///< the features without the storage trick
  std::vector<std::string> collapsed; ///< arrays stored as one feature
  std::vector<float> centres;         ///< initial centres (k * x.features)
  cl::KMeansResult result;            ///< final centres, counts, inertia, iterations, stop reason
  std::vector<std::int32_t> labels;   ///< per cell that takes part
  std::vector<float> distances;       ///< per cell that takes part (GPU path)
  vtkSmartPointer<vtkDoubleArray> share; ///< the table's Share column
  /// A distributed run's all-reduce (null: serial)
  std::unique_ptr<cl::KMeansReduction> reduction;
  std::size_t totalCells = 0;            ///< cells taking part on every process
  std::vector<std::int64_t> globalCells; ///< distributed: each packed cell's whole-grid index
  int pieceExtent[6] = { 0, -1, 0, -1, 0, -1 }; ///< the input's extent
  /// Distributed: the cells that would take part but whose point the next piece owns (image
  /// pieces share their boundary points); labelled from the final centres, counted nowhere.
  std::vector<std::size_t> shared;
  std::vector<cl::KMeansPreparedArray> prepared; ///< what PrepareMatrix did with each array
};

//------------------------------------------------------------------------------
vtkTerroirKMeans::vtkTerroirKMeans()
{
  this->SetNumberOfOutputPorts(2);
}

//------------------------------------------------------------------------------
vtkTerroirKMeans::~vtkTerroirKMeans() = default;

//------------------------------------------------------------------------------
void vtkTerroirKMeans::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "NumberOfClusters: " << this->NumberOfClusters << "\n";
  os << indent << "Features:";
  if (this->Features.empty())
  {
    os << " (defaults)";
  }
  for (const Feature& f : this->Features)
  {
    os << " " << f.name << "=" << f.weight;
  }
  os << "\n";
  os << indent << "Standardize: " << (this->Standardize ? "on" : "off") << "\n";
  os << indent << "Seeding: " << (this->Seeding == Diagonal ? "Diagonal" : "KMeansPlusPlus")
     << "\n";
  os << indent << "RandomSeed: " << this->RandomSeed << "\n";
  os << indent << "MaximumIterations: " << this->MaximumIterations << "\n";
  os << indent << "Tolerance: " << this->Tolerance << "\n";
  os << indent << "CollapseConstantOffsets: " << (this->CollapseConstantOffsets ? "on" : "off")
     << "\n";
}

//------------------------------------------------------------------------------
void vtkTerroirKMeans::AddFeature(const char* arrayName, double weight)
{
  const std::string name = arrayName ? arrayName : "";
  for (Feature& f : this->Features)
  {
    if (f.name == name)
    {
      if (f.weight != weight)
      {
        f.weight = weight;
        this->Modified();
      }
      return;
    }
  }
  this->Features.push_back({ name, weight });
  this->Modified();
}

//------------------------------------------------------------------------------
void vtkTerroirKMeans::RemoveAllFeatures()
{
  if (!this->Features.empty())
  {
    this->Features.clear();
    this->Modified();
  }
}

//------------------------------------------------------------------------------
const char* vtkTerroirKMeans::GetFeatureName(int i)
{
  return i >= 0 && i < this->GetNumberOfFeatures() ? this->Features[i].name.c_str() : nullptr;
}

//------------------------------------------------------------------------------
double vtkTerroirKMeans::GetFeatureWeight(int i)
{
  return i >= 0 && i < this->GetNumberOfFeatures() ? this->Features[i].weight : 0.0;
}

//------------------------------------------------------------------------------
vtkTable* vtkTerroirKMeans::GetClusterTable()
{
  return vtkTable::SafeDownCast(this->GetOutputDataObject(1));
}

//------------------------------------------------------------------------------
int vtkTerroirKMeans::FillOutputPortInformation(int port, vtkInformation* info)
{
  if (port == 1)
  {
    info->Set(vtkDataObject::DATA_TYPE_NAME(), "vtkTable");
    return 1;
  }
  return this->Superclass::FillOutputPortInformation(port, info);
}

//------------------------------------------------------------------------------
double vtkTerroirKMeans::EstimateMemory(double nx, double ny)
{
  // Per cell with F feature components: packed copies of the inputs (4F B, when not float or
  // with no data), the prepared matrix (4F B), labels and distances (8 B), ClusterId (4 B),
  // the packed index and the mask (9 B).
  const double f = std::max(this->InputComponents, 1);
  return nx * ny * (8.0 * f + 21.0);
}

//------------------------------------------------------------------------------
std::string vtkTerroirKMeans::CheckParameters()
{
  bool anyPositive = this->Features.empty();
  for (const Feature& f : this->Features)
  {
    if (f.name.empty())
    {
      return "a feature has an empty array name";
    }
    if (!(f.weight >= 0.0) || !std::isfinite(f.weight))
    {
      return "feature '" + f.name + "' has weight " + terroir::NumberText(f.weight) +
        "; weights must be finite and >= 0";
    }
    anyPositive = anyPositive || f.weight > 0.0;
  }
  if (!anyPositive)
  {
    return "every feature weight is 0: nothing to cluster on";
  }
  if (!(this->Tolerance >= 0.0) || !std::isfinite(this->Tolerance))
  {
    return "Tolerance " + terroir::NumberText(this->Tolerance) + " must be a finite number >= 0";
  }
  return std::string();
}

//------------------------------------------------------------------------------
int vtkTerroirKMeans::RequestData(vtkInformation* request,
  vtkInformationVector** inputVector,
  vtkInformationVector* outputVector)
{
  vtkTable* table = vtkTable::GetData(outputVector, 1);
  if (table)
  {
    table->Initialize();
  }
  vtkInformation* inInfo = inputVector[0]->GetInformationObject(0);
  if (inInfo && inInfo->Has(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT()))
  {
    inInfo->Get(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT(), this->WholeExtent);
  }
  vtkInformation* outInfo = outputVector->GetInformationObject(0);
  this->DistributedRun = DistributedReduction(outInfo) != nullptr;
  if (this->DistributedRun)
  {
    // This piece without ghost levels, as the pipeline cut it (vtkExtentTranslator, block mode).
    using SDDP = vtkStreamingDemandDrivenPipeline;
    vtkNew<vtkExtentTranslator> translator;
    translator->PieceToExtentThreadSafe(outInfo->Get(SDDP::UPDATE_PIECE_NUMBER()),
      outInfo->Get(SDDP::UPDATE_NUMBER_OF_PIECES()),
      0,
      this->WholeExtent,
      this->OwnedExtent,
      vtkExtentTranslator::BLOCK_MODE,
      0);
  }
  // The feature components of this input size the memory estimate.
  this->InputComponents = 0;
  if (vtkImageData* input = vtkImageData::GetData(inputVector[0]))
  {
    vtkPointData* pd = input->GetPointData();
    if (this->Features.empty())
    {
      for (const auto& d : DefaultFeatures)
      {
        vtkDataArray* a = pd->GetArray(d.name);
        this->InputComponents += a ? a->GetNumberOfComponents() : 0;
      }
    }
    for (const Feature& f : this->Features)
    {
      vtkDataArray* a = pd->GetArray(f.name.c_str());
      this->InputComponents += a ? a->GetNumberOfComponents() : 0;
    }
  }
  return this->Superclass::RequestData(request, inputVector, outputVector);
}

//------------------------------------------------------------------------------
int vtkTerroirKMeans::RequestUpdateExtent(vtkInformation* request,
  vtkInformationVector** inputVector,
  vtkInformationVector* outputVector)
{
  // A piece of a distributed run asks for its piece (GetHaloWidth 0), a serial run for all.
  this->DistributedRun = DistributedReduction(outputVector->GetInformationObject(0)) != nullptr;
  return this->Superclass::RequestUpdateExtent(request, inputVector, outputVector);
}

//------------------------------------------------------------------------------
bool vtkTerroirKMeans::ResolveFeatures(vtkImageData* input, Clustering& c)
{
  const std::string& prefix = c.prefix;
  vtkPointData* inPD = input->GetPointData();
  std::vector<InputFeature>& features = c.features;
  if (this->Features.empty())
  {
    for (const auto& d : DefaultFeatures)
    {
      if (vtkDataArray* a = inPD->GetArray(d.name))
      {
        features.push_back({ d.name, d.weight, a });
      }
    }
    if (features.empty())
    {
      vtkErrorMacro(<< prefix << "none of the default features (Slope, Temperature, "
                    << "IlluminationHours, WeightedSoilHumidity) is a point array of the input; "
                    << "add features with AddFeature");
      return false;
    }
  }
  for (const Feature& f : this->Features)
  {
    vtkAbstractArray* abstract = inPD->GetAbstractArray(f.name.c_str());
    if (!abstract)
    {
      vtkErrorMacro(<< prefix << "feature '" << f.name << "' names no point array of the input");
      return false;
    }
    vtkDataArray* a = vtkDataArray::SafeDownCast(abstract);
    if (!a)
    {
      vtkErrorMacro(<< prefix << "feature '" << f.name << "' is not numeric ("
                    << abstract->GetClassName() << ")");
      return false;
    }
    features.push_back({ f.name, f.weight, a });
  }
  for (const InputFeature& f : features)
  {
    if (f.array->GetNumberOfTuples() != static_cast<vtkIdType>(c.n))
    {
      vtkErrorMacro(<< prefix << "feature '" << f.name << "' has " << f.array->GetNumberOfTuples()
                    << " tuples, the terrain " << c.n << " cells");
      return false;
    }
  }
  return true;
}

//------------------------------------------------------------------------------
bool vtkTerroirKMeans::SelectCells(const terroir::GridView<float>& v, Clustering& c)
{
  const std::size_t n = c.n;
  std::vector<std::uint8_t>& valid = c.valid;
  valid.assign(n, 1);
  if (v.valid)
  {
    std::copy(v.valid, v.valid + n, valid.begin());
  }
  for (const InputFeature& f : c.features)
  {
    if (f.weight <= 0.0)
    {
      continue;
    }
    const int nc = f.array->GetNumberOfComponents();
    vtkSMPTools::For(0,
      static_cast<vtkIdType>(n),
      [&](vtkIdType b, vtkIdType e)
      {
        for (vtkIdType i = b; i < e; ++i)
        {
          for (int j = 0; j < nc && valid[i]; ++j)
          {
            if (!std::isfinite(f.array->GetComponent(i, j)))
            {
              valid[i] = 0;
            }
          }
        }
      });
  }
  c.cells.reserve(n);
  for (std::size_t i = 0; i < n; ++i)
  {
    if (valid[i])
    {
      c.cells.push_back(i);
    }
  }
  if (c.reduction)
  {
    // Each point once over the pieces: a piece owns the points of its own extent (without the
    // ghost layers a filter downstream may have asked for) but those of its upper boundary,
    // which it shares with the next piece (the last piece along an axis owns them).
    const int* e = c.pieceExtent;
    const int* p = this->OwnedExtent;
    const std::size_t pnx = static_cast<std::size_t>(e[1] - e[0] + 1);
    auto owns = [](int g, int lo, int hi, int wholeHi)
    { return g >= lo && (g < hi || (g == hi && hi == wholeHi)); };
    std::vector<std::size_t> owned;
    owned.reserve(c.cells.size());
    for (std::size_t cell : c.cells)
    {
      const int gi = static_cast<int>(cell % pnx) + e[0];
      const int gj = static_cast<int>(cell / pnx) + e[2];
      const bool mine =
        owns(gi, p[0], p[1], this->WholeExtent[1]) && owns(gj, p[2], p[3], this->WholeExtent[3]);
      (mine ? owned : c.shared).push_back(cell);
      valid[cell] = mine ? 1 : 0;
    }
    c.cells.swap(owned);
  }
  std::int64_t m = static_cast<std::int64_t>(c.cells.size());
  if (c.reduction)
  {
    // Whole-grid indices of this piece's cells, and the count over every piece.
    const int* e = c.pieceExtent;
    const std::int64_t wnx = this->WholeExtent[1] - this->WholeExtent[0] + 1;
    const std::int64_t pnx = e[1] - e[0] + 1;
    c.globalCells.resize(c.cells.size());
    for (std::size_t i = 0; i < c.cells.size(); ++i)
    {
      const std::int64_t li = static_cast<std::int64_t>(c.cells[i]) % pnx;
      const std::int64_t lj = static_cast<std::int64_t>(c.cells[i]) / pnx;
      c.globalCells[i] =
        (lj + e[2] - this->WholeExtent[2]) * wnx + (li + e[0] - this->WholeExtent[0]);
    }
    c.reduction->Sum(&m, 1);
  }
  c.totalCells = static_cast<std::size_t>(m);
  if (m < c.k)
  {
    vtkErrorMacro(<< c.prefix << m << " cell(s) have data for every feature, fewer than the " << c.k
                  << " clusters asked for");
    return false;
  }
  return true;
}

//------------------------------------------------------------------------------
void vtkTerroirKMeans::PackFeatures(Clustering& c)
{
  c.packed.assign(c.features.size(), std::vector<float>());
  for (std::size_t a = 0; a < c.features.size(); ++a)
  {
    c.inputs.push_back(PackFeature(c.features[a], c.cells, c.n, c.packed[a]));
  }
}

//------------------------------------------------------------------------------
void vtkTerroirKMeans::PrepareMatrix(Clustering& c)
{
  const std::size_t m = c.cells.size();
  c.prepared = cl::KMeansPrepareFeatures(c.inputs,
    m,
    this->Standardize,
    this->CollapseConstantOffsets,
    c.matrix,
    c.parallelFor,
    c.reduction.get());
  c.packed.clear();
  c.packed.shrink_to_fit();
  int total = 0;
  c.uncollapsed = 0; // the features without the storage trick
  for (const cl::KMeansPreparedArray& p : c.prepared)
  {
    total += p.features;
    c.uncollapsed += p.features > 0 ? p.components : 0;
    if (p.collapsed)
    {
      c.collapsed.push_back(p.name);
      vtkDebugMacro(<< "storage trick: '" << p.name << "' (" << p.components
                    << " components) differs by constants; stored as one feature");
    }
  }
  c.x.data = c.matrix.data();
  c.x.cells = m;
  c.x.features = total;
}

//------------------------------------------------------------------------------
void vtkTerroirKMeans::SeedCentres(const terroir::GridView<float>& v, Clustering& c)
{
  std::vector<std::size_t> seeds;
  if (c.reduction)
  {
    this->SeedCentresDistributed(c);
    return;
  }
  if (this->Seeding == Diagonal)
  {
    vtkDebugMacro(<< "seeds: Long (2016)'s diagonal cells (Long (2016))");
    for (std::size_t g : cl::KMeansDiagonalSeedCells(v.nx, v.ny, c.valid.data(), c.k))
    {
      seeds.push_back(static_cast<std::size_t>(
        std::lower_bound(c.cells.begin(), c.cells.end(), g) - c.cells.begin()));
    }
  }
  else
  {
    vtkDebugMacro(<< "seeds: k-means++ (Arthur & Vassilvitskii 2007), seed " << this->RandomSeed);
    seeds = cl::KMeansPlusPlusSeeds(
      c.x, c.k, static_cast<std::uint64_t>(this->RandomSeed), c.parallelFor);
  }
  c.centres = cl::KMeansCentresFromCells(c.x, seeds);
}

//------------------------------------------------------------------------------
void vtkTerroirKMeans::SeedCentresDistributed(Clustering& c)
{
  if (this->Seeding != Diagonal)
  {
    throw std::invalid_argument(
      "k-means++ seeding is serial only: use the Diagonal seeding in a distributed run");
  }
  // The serial rule on the whole grid's diagonal: each piece marks its own diagonal cells that
  // take part (the pieces do not overlap), the marks are summed over the processes.
  const int wnx = this->WholeExtent[1] - this->WholeExtent[0] + 1;
  const int wny = this->WholeExtent[3] - this->WholeExtent[2] + 1;
  const std::vector<std::size_t> diagonal = cl::KMeansDiagonalCells(wnx, wny);
  const int* e = c.pieceExtent;
  const std::int64_t pnx = e[1] - e[0] + 1;
  auto local = [&](std::size_t g) -> std::int64_t
  {
    const std::int64_t gi = static_cast<std::int64_t>(g % wnx) + this->WholeExtent[0];
    const std::int64_t gj = static_cast<std::int64_t>(g / wnx) + this->WholeExtent[2];
    if (gi < e[0] || gi > e[1] || gj < e[2] || gj > e[3])
    {
      return -1;
    }
    return (gj - e[2]) * pnx + (gi - e[0]);
  };
  std::vector<std::int64_t> marks(diagonal.size(), 0);
  for (std::size_t t = 0; t < diagonal.size(); ++t)
  {
    const std::int64_t l = local(diagonal[t]);
    marks[t] = l >= 0 && c.valid[static_cast<std::size_t>(l)] ? 1 : 0;
  }
  c.reduction->Sum(marks.data(), marks.size());
  std::vector<std::size_t> candidates;
  for (std::size_t t = 0; t < diagonal.size(); ++t)
  {
    if (marks[t] > 0)
    {
      candidates.push_back(diagonal[t]);
    }
  }
  if (candidates.size() < static_cast<std::size_t>(c.k))
  {
    throw std::invalid_argument(std::to_string(candidates.size()) +
      " diagonal cells have data, fewer than the " + std::to_string(c.k) +
      " clusters: the row-order fallback of the Diagonal seeding is serial only");
  }
  // Each seed's owner contributes its prepared features, the others zeros.
  const std::size_t nf = static_cast<std::size_t>(c.x.features);
  std::vector<double> centres(static_cast<std::size_t>(c.k) * nf, 0.0);
  const std::vector<std::size_t> positions =
    cl::KMeansDiagonalSeedPositions(candidates.size(), c.k);
  for (std::size_t i = 0; i < positions.size(); ++i)
  {
    // Only the owner: a point this piece shares with its neighbour, or a ghost point, is
    // another piece's (c.valid marks the cells this piece owns and that take part).
    const std::int64_t l = local(candidates[positions[i]]);
    if (l < 0 || !c.valid[static_cast<std::size_t>(l)])
    {
      continue;
    }
    const std::size_t packed = static_cast<std::size_t>(
      std::lower_bound(c.cells.begin(), c.cells.end(), static_cast<std::size_t>(l)) -
      c.cells.begin());
    for (std::size_t f = 0; f < nf; ++f)
    {
      centres[i * nf + f] = static_cast<double>(c.x.At(static_cast<int>(f), packed));
    }
  }
  c.reduction->Sum(centres.data(), centres.size());
  c.centres.assign(centres.begin(), centres.end());
}

//------------------------------------------------------------------------------
bool vtkTerroirKMeans::RunLloyd(int backend, Clustering& c)
{
  const int k = c.k;
  const std::size_t m = c.cells.size();
  const int total = c.x.features;
  cl::KMeansOptions options;
  options.maximumIterations = this->MaximumIterations;
  // Tolerance is relative to the mean variance per feature of the uncollapsed features (as
  // scikit-learn would see them): a collapsed array carries its components' total variance
  // in one feature, so the core's mean over `total` features is scaled back.
  options.tolerance = this->Tolerance * static_cast<double>(total) / c.uncollapsed;
  options.reduction = c.reduction.get();
  options.globalCells = c.reduction ? c.globalCells.data() : nullptr;
  vtkDebugMacro(<< "Lloyd (1982) iterations, K = " << k << ", " << total << " features, " << m
                << " cells");
  int ran = backend;
  if (backend == vtkTerroirComputeContext::GPU)
  {
    ran = this->RunGPUPath(
      [&] { c.result = cl::RunKMeansGPU(c.x, c.centres, k, options, c.labels, c.distances); });
    if (ran < 0)
    {
      return false;
    }
  }
  if (ran == 1)
  {
    cl::KMeansCPUEngine engine(c.x, c.parallelFor);
    const double maxIterations = this->MaximumIterations;
    c.result = cl::KMeansLloyd(engine,
      c.x,
      c.centres,
      k,
      options,
      [this, maxIterations](int it, std::size_t)
      { this->UpdateProgress(0.2 + 0.7 * std::min(1.0, it / maxIterations)); });
    c.labels.assign(engine.Labels(), engine.Labels() + m);
  }
  return true;
}

//------------------------------------------------------------------------------
void vtkTerroirKMeans::AddClusterIds(vtkImageData* output, const Clustering& c)
{
  auto ids = vtkSmartPointer<vtkIntArray>::New();
  ids->SetName(ClusterIdName());
  ids->SetNumberOfTuples(static_cast<vtkIdType>(c.n));
  int* id = ids->GetPointer(0);
  std::fill(id, id + c.n, -1);
  for (std::size_t i = 0; i < c.cells.size(); ++i)
  {
    id[c.cells[i]] = c.labels[i];
  }
  if (!c.shared.empty())
  {
    // The shared boundary points: the nearest final centre, with the arithmetic of the
    // assignment that labelled them in the piece that owns them, so the same label.
    std::vector<std::vector<float>> packed(c.features.size());
    std::vector<cl::KMeansInputArray> inputs;
    for (std::size_t a = 0; a < c.features.size(); ++a)
    {
      inputs.push_back(PackFeature(c.features[a], c.shared, c.n, packed[a]));
    }
    std::vector<float> matrix;
    cl::KMeansApplyPreparation(inputs, c.prepared, c.shared.size(), this->Standardize, matrix);
    cl::KMeansFeatures xs;
    xs.data = matrix.data();
    xs.cells = c.shared.size();
    xs.features = c.x.features;
    std::vector<std::int32_t> labels(c.shared.size(), -1);
    std::vector<float> distance(c.shared.size());
    cl::KMeansAssignRange(
      xs, c.result.centres.data(), c.k, 0, xs.cells, labels.data(), distance.data());
    for (std::size_t i = 0; i < c.shared.size(); ++i)
    {
      id[c.shared[i]] = labels[i];
    }
  }
  output->GetPointData()->AddArray(ids);
}

//------------------------------------------------------------------------------
void vtkTerroirKMeans::FillClusterTable(Clustering& c)
{
  vtkTable* table = this->GetClusterTable();
  c.share = AddMemberColumns(table, c.result.counts, c.k, c.totalCells);
  for (const InputFeature& f : c.features)
  {
    AddFeatureMeanColumns(table, f, c.cells, c.labels, c.k, c.reduction.get());
  }
}

//------------------------------------------------------------------------------
void vtkTerroirKMeans::AddFieldData(vtkImageData* output, const Clustering& c)
{
  const cl::KMeansResult& result = c.result;
  vtkFieldData* fd = output->GetFieldData();
  fd->AddArray(ScalarArray("KMeansWithinClusterSumOfSquares", result.inertia));
  fd->AddArray(IntArray("KMeansIterations", result.iterations));
  fd->AddArray(IntArray("KMeansRelocatedClusters", result.relocated));
  auto share = vtkSmartPointer<vtkDoubleArray>::New();
  share->SetName("KMeansClusterShare");
  share->DeepCopy(c.share);
  share->SetName("KMeansClusterShare");
  fd->AddArray(share);
  auto reason = vtkSmartPointer<vtkStringArray>::New();
  reason->SetName("KMeansStopReason");
  reason->InsertNextValue(cl::KMeansStopReasonName(result.reason));
  fd->AddArray(reason);
  auto collapsedArray = vtkSmartPointer<vtkStringArray>::New();
  collapsedArray->SetName("KMeansCollapsedArrays");
  for (const std::string& name : c.collapsed)
  {
    collapsedArray->InsertNextValue(name);
  }
  fd->AddArray(collapsedArray);
}

//------------------------------------------------------------------------------
int vtkTerroirKMeans::RequestTerrainData(vtkImageData* input,
  const terroir::TerrainInput& terrain,
  vtkImageData* output)
{
  const terroir::GridView<float>& v = terrain.view;
  Clustering c;
  c.n = v.Size();
  c.k = this->NumberOfClusters;
  c.prefix = this->SourcePrefix(input);
  if (this->DistributedRun)
  {
    c.reduction = DistributedReduction(this->GetOutputInformation(0));
    input->GetExtent(c.pieceExtent);
  }

  // 1. The features.
  if (!this->ResolveFeatures(input, c))
  {
    return 0;
  }
  // The distributed path all-reduces inside the CPU engine's iterations: CPU only.
  const int backend = this->SelectBackend(this->HasGPUPath() && !c.reduction);
  if (backend < 0)
  {
    return 0;
  }

  // 2. Cells that take part: valid terrain and finite values of every weighted feature.
  if (!this->SelectCells(v, c))
  {
    return 0;
  }
  this->UpdateProgress(0.05);

  // 3. Packed float copies (float arrays without excluded cells are used in place), then the
  // prepared, weighted feature matrix; 4. seeds; 5. Lloyd iterations.
  this->PackFeatures(c);
  try
  {
    this->PrepareMatrix(c);
    this->UpdateProgress(0.15);
    this->SeedCentres(v, c);
    this->UpdateProgress(0.2);
    if (!this->RunLloyd(backend, c))
    {
      return 0;
    }
  }
  catch (const std::invalid_argument& e)
  {
    vtkErrorMacro(<< c.prefix << e.what());
    return 0;
  }

  // 6. ClusterId.
  this->AddClusterIds(output, c);
  this->UpdateProgress(0.92);
  // 7. The cluster table: id, colour, members, share, and the mean of every component of every
  // feature array over the members, in its own units (double sums in cell order).
  this->FillClusterTable(c);
  // 8. Field data.
  this->AddFieldData(output, c);
  return 1;
}
