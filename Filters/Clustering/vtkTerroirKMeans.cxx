#include "vtkTerroirKMeans.h"
#include "vtkTerroirComputeContext.h"

#include "vtkDataArray.h"
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
#include "vtkSMPTools.h"
#include "vtkSmartPointer.h"
#include "vtkStringArray.h"
#include "vtkTable.h"
#include "vtkTerroirKMeansGPU.h"
#include "vtkTerroirTerrainInput.h"

#include "KMeans.h"

#include "NumberText.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <new>
#include <sstream>
#include <stdexcept>

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
} // namespace

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
int vtkTerroirKMeans::RequestTerrainData(vtkImageData* input,
  const terroir::TerrainInput& terrain,
  vtkImageData* output)
{
  const terroir::GridView<float>& v = terrain.view;
  const std::size_t n = v.Size();
  const int k = this->NumberOfClusters;
  const std::string prefix = this->SourcePrefix(input);
  vtkPointData* inPD = input->GetPointData();

  // 1. The features.
  std::vector<InputFeature> features;
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
      return 0;
    }
  }
  for (const Feature& f : this->Features)
  {
    vtkAbstractArray* abstract = inPD->GetAbstractArray(f.name.c_str());
    if (!abstract)
    {
      vtkErrorMacro(<< prefix << "feature '" << f.name << "' names no point array of the input");
      return 0;
    }
    vtkDataArray* a = vtkDataArray::SafeDownCast(abstract);
    if (!a)
    {
      vtkErrorMacro(<< prefix << "feature '" << f.name << "' is not numeric ("
                    << abstract->GetClassName() << ")");
      return 0;
    }
    features.push_back({ f.name, f.weight, a });
  }
  for (const InputFeature& f : features)
  {
    if (f.array->GetNumberOfTuples() != static_cast<vtkIdType>(n))
    {
      vtkErrorMacro(<< prefix << "feature '" << f.name << "' has " << f.array->GetNumberOfTuples()
                    << " tuples, the terrain " << n << " cells");
      return 0;
    }
  }

  const int backend = this->SelectBackend(this->HasGPUPath());
  if (backend < 0)
  {
    return 0;
  }

  // 2. Cells that take part: valid terrain and finite values of every weighted feature.
  std::vector<std::uint8_t> valid(n, 1);
  if (v.valid)
  {
    std::copy(v.valid, v.valid + n, valid.begin());
  }
  for (const InputFeature& f : features)
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
        for (vtkIdType c = b; c < e; ++c)
        {
          for (int j = 0; j < nc && valid[c]; ++j)
          {
            if (!std::isfinite(f.array->GetComponent(c, j)))
            {
              valid[c] = 0;
            }
          }
        }
      });
  }
  std::vector<std::size_t> cells;
  cells.reserve(n);
  for (std::size_t c = 0; c < n; ++c)
  {
    if (valid[c])
    {
      cells.push_back(c);
    }
  }
  const std::size_t m = cells.size();
  if (m < static_cast<std::size_t>(k))
  {
    vtkErrorMacro(<< prefix << m << " cell(s) have data for every feature, fewer than the " << k
                  << " clusters asked for");
    return 0;
  }
  this->UpdateProgress(0.05);

  // 3. Packed float copies (float arrays without excluded cells are used in place), then the
  // prepared, weighted feature matrix.
  std::vector<std::vector<float>> packed(features.size());
  std::vector<cl::KMeansInputArray> inputs;
  for (std::size_t a = 0; a < features.size(); ++a)
  {
    const InputFeature& f = features[a];
    cl::KMeansInputArray in;
    in.name = f.name;
    in.components = f.array->GetNumberOfComponents();
    in.weight = f.weight;
    if (f.array->GetDataType() == VTK_FLOAT && m == n)
    {
      in.values = static_cast<const float*>(f.array->GetVoidPointer(0));
    }
    else
    {
      std::vector<float>& p = packed[a];
      const int nc = in.components;
      p.resize(m * static_cast<std::size_t>(nc));
      vtkSMPTools::For(0,
        static_cast<vtkIdType>(m),
        [&](vtkIdType b, vtkIdType e)
        {
          for (vtkIdType i = b; i < e; ++i)
          {
            for (int j = 0; j < nc; ++j)
            {
              p[static_cast<std::size_t>(i) * nc + j] =
                static_cast<float>(f.array->GetComponent(static_cast<vtkIdType>(cells[i]), j));
            }
          }
        });
      in.values = p.data();
    }
    inputs.push_back(in);
  }
  std::vector<float> matrix;
  std::vector<cl::KMeansPreparedArray> prepared;
  cl::KMeansResult result;
  std::vector<std::int32_t> labels;
  std::vector<float> distances;
  std::vector<std::string> collapsed;
  try
  {
    const cl::KMeansParallelFor parallelFor = SMPParallelFor();
    prepared = cl::KMeansPrepareFeatures(
      inputs, m, this->Standardize, this->CollapseConstantOffsets, matrix, parallelFor);
    packed.clear();
    packed.shrink_to_fit();
    int total = 0;
    int uncollapsed = 0; // the features without the storage trick
    for (const cl::KMeansPreparedArray& p : prepared)
    {
      total += p.features;
      uncollapsed += p.features > 0 ? p.components : 0;
      if (p.collapsed)
      {
        collapsed.push_back(p.name);
        vtkDebugMacro(<< "storage trick: '" << p.name << "' (" << p.components
                      << " components) differs by constants; stored as one feature");
      }
    }
    cl::KMeansFeatures x;
    x.data = matrix.data();
    x.cells = m;
    x.features = total;
    this->UpdateProgress(0.15);

    // 4. Seeds.
    std::vector<std::size_t> seeds;
    if (this->Seeding == Diagonal)
    {
      vtkDebugMacro(<< "seeds: Long (2016)'s diagonal cells (Long (2016))");
      for (std::size_t g : cl::KMeansDiagonalSeedCells(v.nx, v.ny, valid.data(), k))
      {
        seeds.push_back(static_cast<std::size_t>(
          std::lower_bound(cells.begin(), cells.end(), g) - cells.begin()));
      }
    }
    else
    {
      vtkDebugMacro(<< "seeds: k-means++ (Arthur & Vassilvitskii 2007), seed " << this->RandomSeed);
      seeds =
        cl::KMeansPlusPlusSeeds(x, k, static_cast<std::uint64_t>(this->RandomSeed), parallelFor);
    }
    const std::vector<float> centres = cl::KMeansCentresFromCells(x, seeds);
    this->UpdateProgress(0.2);

    // 5. Lloyd iterations.
    cl::KMeansOptions options;
    options.maximumIterations = this->MaximumIterations;
    // Tolerance is relative to the mean variance per feature of the uncollapsed features (as
    // scikit-learn would see them): a collapsed array carries its components' total variance
    // in one feature, so the core's mean over `total` features is scaled back.
    options.tolerance = this->Tolerance * static_cast<double>(total) / uncollapsed;
    vtkDebugMacro(<< "Lloyd (1982) iterations, K = " << k << ", " << total << " features, " << m
                  << " cells");
    int ran = backend;
    if (backend == vtkTerroirComputeContext::GPU)
    {
      ran = this->RunGPUPath(
        [&] { result = cl::RunKMeansGPU(x, centres, k, options, labels, distances); });
      if (ran < 0)
      {
        return 0;
      }
    }
    if (ran == 1)
    {
      cl::KMeansCPUEngine engine(x, parallelFor);
      const double maxIterations = this->MaximumIterations;
      result = cl::KMeansLloyd(engine,
        x,
        centres,
        k,
        options,
        [this, maxIterations](int it, std::size_t)
        { this->UpdateProgress(0.2 + 0.7 * std::min(1.0, it / maxIterations)); });
      labels.assign(engine.Labels(), engine.Labels() + m);
    }
  }
  catch (const std::invalid_argument& e)
  {
    vtkErrorMacro(<< prefix << e.what());
    return 0;
  }

  // 6. ClusterId.
  auto ids = vtkSmartPointer<vtkIntArray>::New();
  ids->SetName(ClusterIdName());
  ids->SetNumberOfTuples(static_cast<vtkIdType>(n));
  int* id = ids->GetPointer(0);
  std::fill(id, id + n, -1);
  for (std::size_t i = 0; i < m; ++i)
  {
    id[cells[i]] = labels[i];
  }
  output->GetPointData()->AddArray(ids);
  this->UpdateProgress(0.92);

  // 7. The cluster table: id, colour, members, share, and the mean of every component of every
  // feature array over the members, in its own units (double sums in cell order).
  vtkTable* table = this->GetClusterTable();
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
    cellColumn->InsertNextValue(static_cast<vtkIdType>(result.counts[c]));
    shareColumn->InsertNextValue(static_cast<double>(result.counts[c]) / static_cast<double>(m));
  }
  table->AddColumn(idColumn);
  table->AddColumn(colorColumn);
  table->AddColumn(cellColumn);
  table->AddColumn(shareColumn);
  for (const InputFeature& f : features)
  {
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

  // 8. Field data.
  vtkFieldData* fd = output->GetFieldData();
  fd->AddArray(ScalarArray("KMeansWithinClusterSumOfSquares", result.inertia));
  fd->AddArray(IntArray("KMeansIterations", result.iterations));
  fd->AddArray(IntArray("KMeansRelocatedClusters", result.relocated));
  auto share = vtkSmartPointer<vtkDoubleArray>::New();
  share->SetName("KMeansClusterShare");
  share->DeepCopy(shareColumn);
  share->SetName("KMeansClusterShare");
  fd->AddArray(share);
  auto reason = vtkSmartPointer<vtkStringArray>::New();
  reason->SetName("KMeansStopReason");
  reason->InsertNextValue(cl::KMeansStopReasonName(result.reason));
  fd->AddArray(reason);
  auto collapsedArray = vtkSmartPointer<vtkStringArray>::New();
  collapsedArray->SetName("KMeansCollapsedArrays");
  for (const std::string& name : collapsed)
  {
    collapsedArray->InsertNextValue(name);
  }
  fd->AddArray(collapsedArray);
  return 1;
}
