#include "vtkTerroirFeatureCurveTerrain.h"

#include "vtkCellArray.h"
#include "vtkDataArray.h"
#include "vtkFloatArray.h"
#include "vtkIdList.h"
#include "vtkImageData.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkLogger.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkSMPTools.h"
#include "vtkStreamingDemandDrivenPipeline.h"
#include "vtkTerroirComputeContext.h"
#include "vtkTerroirFeatureCurveMultigridCS.h"
#include "vtkTerroirGPU.h"
#include "vtkUnsignedCharArray.h"

#include "FeatureCurves.h"
#include "MemoryBudget.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

vtkStandardNewMacro(vtkTerroirFeatureCurveTerrain);

namespace
{
namespace tt = terroir::terrain;

/// The curves of the polydata's lines and polylines, with the point arrays of the class comment.
std::vector<tt::FeatureCurve> CurvesFromPolyData(vtkPolyData* pd)
{
  std::vector<tt::FeatureCurve> curves;
  vtkPointData* a = pd->GetPointData();
  auto array = [a](const char* name) { return a->GetArray(name); };
  vtkDataArray* elevation = array("Elevation");
  vtkDataArray* plateau = array("PlateauWidth");
  vtkDataArray* slopeL = array("SlopeLeft");
  vtkDataArray* slopeR = array("SlopeRight");
  vtkDataArray* widthL = array("SlopeLeftWidth");
  vtkDataArray* widthR = array("SlopeRightWidth");
  vtkDataArray* envL = array("EnvelopeLeft");
  vtkDataArray* envR = array("EnvelopeRight");
  vtkDataArray* constrain = array("ConstrainElevation");
  auto value = [](vtkDataArray* d, vtkIdType id, double fallback)
  { return d ? d->GetComponent(id, 0) : fallback; };
  vtkCellArray* lines = pd->GetLines();
  if (!lines)
  {
    return curves;
  }
  vtkNew<vtkIdList> ids;
  lines->InitTraversal();
  while (lines->GetNextCell(ids))
  {
    tt::FeatureCurve c;
    for (vtkIdType q = 0; q < ids->GetNumberOfIds(); ++q)
    {
      const vtkIdType id = ids->GetId(q);
      double xyz[3];
      pd->GetPoint(id, xyz);
      tt::FeatureControlPoint p;
      p.x = xyz[0];
      p.y = xyz[1];
      p.elevation = value(elevation, id, xyz[2]);
      p.plateauWidth = value(plateau, id, 0.0);
      p.slopeLeftAngle = value(slopeL, id, 0.0);
      p.slopeRightAngle = value(slopeR, id, 0.0);
      p.slopeLeftWidth = value(widthL, id, 0.0);
      p.slopeRightWidth = value(widthR, id, 0.0);
      p.envelopeLeft = value(envL, id, -1.0);
      p.envelopeRight = value(envR, id, -1.0);
      p.constrainElevation = value(constrain, id, 1.0) != 0.0;
      c.push_back(p);
    }
    curves.push_back(std::move(c));
  }
  return curves;
}

/// The V-cycles of SolveDiffusionMultigrid on the GPU (Shaders/FeatureCurveMultigrid.comp):
/// levels[0].h becomes the answer; the report as the CPU's.
tt::DiffusionReport SolveOnGPU(std::vector<tt::DiffusionLevel>& levels,
  const tt::FeatureSolverParameters& p)
{
  namespace gpu = terroir::gpu;
  tt::DiffusionReport report;
  report.levels = static_cast<int>(levels.size());
  auto& ctx = gpu::Context::Global();
  double work = 0.0;
  for (const auto& l : levels)
  {
    work += static_cast<double>(l.Size());
  }
  // Cells times sweeps of a cycle (about 12 per fine cell) times cycles.
  ctx.Run("feature-curves",
    gpu::Context::Budget(work * 16.0 * p.maxCycles),
    [&]
    {
      const gpu::Limits limits = ctx.GetLimits();
      for (const auto& l : levels)
      {
        if (l.coef.size() * sizeof(float) > limits.StorageBlockBytes())
        {
          throw gpu::Error("FeatureCurveMultigrid.comp: a " + std::to_string(l.nx) + " x " +
            std::to_string(l.ny) + " grid needs more than one storage buffer; use the CPU backend");
        }
      }
      struct Buffers
      {
        std::unique_ptr<gpu::StorageBuffer> coef, h, b, r;
      };
      std::vector<Buffers> buf(levels.size());
      for (std::size_t l = 0; l < levels.size(); ++l)
      {
        const auto& L = levels[l];
        const std::size_t n = L.Size();
        buf[l].coef.reset(new gpu::StorageBuffer(n * 6 * sizeof(float), L.coef.data()));
        buf[l].h.reset(new gpu::StorageBuffer(n * sizeof(double), L.h.data()));
        buf[l].b.reset(new gpu::StorageBuffer(n * sizeof(double), L.b.data()));
        buf[l].r.reset(new gpu::StorageBuffer(n * sizeof(double), gpu::Contents::Zero));
      }
      const tt::DiffusionLevel& F = levels[0];
      const unsigned fgx = static_cast<unsigned>((F.nx + 15) / 16);
      const unsigned fgy = static_cast<unsigned>((F.ny + 15) / 16);
      gpu::StorageBuffer groupMax(std::size_t(fgx) * fgy * sizeof(double), gpu::Contents::Zero);
      gpu::StorageBuffer previous(F.Size() * sizeof(double), F.h.data());
      auto& smooth = ctx.GetProgram(
        "FeatureCurveMultigrid.comp", vtkTerroirFeatureCurveMultigridCS, { "FC_SMOOTH" });
      auto& residual = ctx.GetProgram(
        "FeatureCurveMultigrid.comp", vtkTerroirFeatureCurveMultigridCS, { "FC_RESIDUAL" });
      auto& restrictP = ctx.GetProgram(
        "FeatureCurveMultigrid.comp", vtkTerroirFeatureCurveMultigridCS, { "FC_RESTRICT" });
      auto& prolong = ctx.GetProgram(
        "FeatureCurveMultigrid.comp", vtkTerroirFeatureCurveMultigridCS, { "FC_PROLONG" });
      auto& change = ctx.GetProgram(
        "FeatureCurveMultigrid.comp", vtkTerroirFeatureCurveMultigridCS, { "FC_CHANGE" });
      auto groups = [](int n) { return static_cast<unsigned>((n + 15) / 16); };
      auto sweeps = [&](std::size_t l, int count)
      {
        const auto& L = levels[l];
        smooth.SetInt("uNx", L.nx);
        smooth.SetInt("uNy", L.ny);
        buf[l].coef->Bind(0);
        buf[l].h->Bind(1);
        buf[l].b->Bind(2);
        for (int s = 0; s < count; ++s)
        {
          for (int colour = 0; colour < 2; ++colour)
          {
            smooth.SetInt("uColour", colour);
            smooth.Dispatch(groups(L.nx), groups(L.ny));
          }
        }
      };
      auto residualOf = [&](std::size_t l)
      {
        const auto& L = levels[l];
        residual.SetInt("uNx", L.nx);
        residual.SetInt("uNy", L.ny);
        buf[l].coef->Bind(0);
        buf[l].h->Bind(1);
        buf[l].b->Bind(2);
        buf[l].r->Bind(3);
        groupMax.Bind(4);
        residual.Dispatch(groups(L.nx), groups(L.ny));
      };
      auto largest = [&]()
      {
        std::vector<double> m(std::size_t(fgx) * fgy);
        groupMax.Download(m.data(), m.size() * sizeof(double));
        return *std::max_element(m.begin(), m.end());
      };
      std::function<void(std::size_t)> vcycle = [&](std::size_t l)
      {
        if (l + 1 == levels.size())
        {
          sweeps(l, p.coarsestSweeps);
          return;
        }
        sweeps(l, p.preSmooth);
        residualOf(l);
        const auto& L = levels[l];
        const auto& C = levels[l + 1];
        restrictP.SetInt("uNx", L.nx);
        restrictP.SetInt("uNy", L.ny);
        restrictP.SetInt("uCx", C.nx);
        restrictP.SetInt("uCy", C.ny);
        buf[l + 1].h->Bind(1);
        buf[l + 1].b->Bind(2);
        buf[l].r->Bind(3);
        restrictP.Dispatch(groups(C.nx), groups(C.ny));
        vcycle(l + 1);
        prolong.SetInt("uNx", L.nx);
        prolong.SetInt("uNy", L.ny);
        prolong.SetInt("uCx", C.nx);
        prolong.SetInt("uCy", C.ny);
        buf[l].h->Bind(1);
        buf[l + 1].h->Bind(5);
        prolong.Dispatch(groups(L.nx), groups(L.ny));
        sweeps(l, p.postSmooth);
      };
      residualOf(0);
      report.initialResidual = largest();
      while (report.cycles < p.maxCycles)
      {
        vcycle(0);
        ++report.cycles;
        change.SetInt("uNx", F.nx);
        change.SetInt("uNy", F.ny);
        buf[0].h->Bind(1);
        groupMax.Bind(4);
        previous.Bind(6);
        change.Dispatch(fgx, fgy);
        const double c = largest();
        report.history.push_back(c);
        if (c <= p.tolerance)
        {
          report.converged = true;
          break;
        }
      }
      residualOf(0);
      report.residual = largest();
      buf[0].h->Download(levels[0].h.data(), F.Size() * sizeof(double));
    });
  return report;
}
} // namespace

//------------------------------------------------------------------------------
vtkTerroirFeatureCurveTerrain::vtkTerroirFeatureCurveTerrain()
{
  this->SetNumberOfInputPorts(2);
  this->SetNumberOfOutputPorts(1);
}

//------------------------------------------------------------------------------
vtkTerroirFeatureCurveTerrain::~vtkTerroirFeatureCurveTerrain() = default;

//------------------------------------------------------------------------------
void vtkTerroirFeatureCurveTerrain::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Dimensions: " << this->Dimensions[0] << " x " << this->Dimensions[1] << "\n";
  os << indent << "Spacing: " << this->Spacing << " m\n";
  os << indent << "Origin: " << this->Origin[0] << ", " << this->Origin[1] << "\n";
  os << indent << "BaseElevation: " << this->BaseElevation << " m\n";
  os << indent << "PlateauWeight: " << this->PlateauWeight << "\n";
  os << indent << "SlopeWeight: " << this->SlopeWeight << "\n";
  os << indent << "Tolerance: " << this->Tolerance << " m\n";
  os << indent << "MaximumCycles: " << this->MaximumCycles << "\n";
  os << indent << "Backend: " << vtkTerroirComputeContext::GetBackendName(this->Backend) << "\n";
  os << indent << "LastBackend: " << this->LastBackend << "\n";
  os << indent << "LastCycles: " << this->LastCycles << "\n";
  os << indent << "LastLevels: " << this->LastLevels << "\n";
  os << indent << "LastChange: " << this->LastChange << " m\n";
  os << indent << "LastResidual: " << this->LastResidual << " m\n";
  os << indent << "LastConverged: " << this->LastConverged << "\n";
}

//------------------------------------------------------------------------------
void vtkTerroirFeatureCurveTerrain::SetCurvesData(vtkPolyData* curves)
{
  this->SetInputDataObject(0, curves);
}

//------------------------------------------------------------------------------
std::string vtkTerroirFeatureCurveTerrain::CheckCurves(vtkPolyData* curves)
{
  if (!curves)
  {
    return "no curves";
  }
  // The checks run before any rasterising: a 2 x 2 grid of huge cells costs nothing.
  terroir::terrain::FeatureGrid grid;
  grid.nx = grid.ny = 2;
  grid.dx = grid.dy = 1e9;
  terroir::terrain::FeatureConstraints c;
  std::string error;
  terroir::terrain::RasterizeFeatureCurves(
    CurvesFromPolyData(curves), grid, terroir::terrain::FeatureSolverParameters(), c, error);
  return error;
}

//------------------------------------------------------------------------------
void vtkTerroirFeatureCurveTerrain::SampleCurves(vtkPolyData* curves,
  double flatness,
  vtkPolyData* out)
{
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  vtkNew<vtkCellArray> lines;
  if (curves && flatness > 0.0)
  {
    for (const auto& c : CurvesFromPolyData(curves))
    {
      const auto s = terroir::terrain::SampleFeatureCurveFlat(c, flatness, 1e300);
      if (s.size() < 2)
      {
        continue;
      }
      lines->InsertNextCell(static_cast<int>(s.size()));
      for (const auto& p : s)
      {
        lines->InsertCellPoint(points->InsertNextPoint(p.x, p.y, p.elevation));
      }
    }
  }
  out->Initialize();
  out->SetPoints(points);
  out->SetLines(lines);
}

//------------------------------------------------------------------------------
int vtkTerroirFeatureCurveTerrain::FillInputPortInformation(int port, vtkInformation* info)
{
  if (port == 0)
  {
    info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkPolyData");
  }
  else
  {
    info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkImageData");
    info->Set(vtkAlgorithm::INPUT_IS_OPTIONAL(), 1);
  }
  return 1;
}

//------------------------------------------------------------------------------
int vtkTerroirFeatureCurveTerrain::RequestInformation(vtkInformation*,
  vtkInformationVector** inputVector,
  vtkInformationVector* outputVector)
{
  vtkInformation* out = outputVector->GetInformationObject(0);
  vtkInformation* base = inputVector[1]->GetInformationObject(0);
  if (base)
  {
    // The base's grid.
    int extent[6];
    double spacing[3], origin[3];
    base->Get(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT(), extent);
    base->Get(vtkDataObject::SPACING(), spacing);
    base->Get(vtkDataObject::ORIGIN(), origin);
    out->Set(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT(), extent, 6);
    out->Set(vtkDataObject::SPACING(), spacing, 3);
    out->Set(vtkDataObject::ORIGIN(), origin, 3);
  }
  else
  {
    const int nx = this->Dimensions[0], ny = this->Dimensions[1];
    if (nx < 2 || ny < 2 || nx > 65536 || ny > 65536 || !(this->Spacing > 0.0) ||
      !std::isfinite(this->Spacing))
    {
      this->ErrorMessage =
        "vtkTerroirFeatureCurveTerrain: Dimensions must be 2 to 65536 and Spacing positive";
      vtkErrorMacro(<< this->ErrorMessage);
      return 0;
    }
    const int extent[6] = { 0, nx - 1, 0, ny - 1, 0, 0 };
    const double spacing[3] = { this->Spacing, this->Spacing, 1.0 };
    const double origin[3] = { this->Origin[0], this->Origin[1], 0.0 };
    out->Set(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT(), extent, 6);
    out->Set(vtkDataObject::SPACING(), spacing, 3);
    out->Set(vtkDataObject::ORIGIN(), origin, 3);
  }
  vtkDataObject::SetPointDataActiveScalarInfo(out, VTK_FLOAT, 1);
  return 1;
}

//------------------------------------------------------------------------------
int vtkTerroirFeatureCurveTerrain::RequestUpdateExtent(vtkInformation*,
  vtkInformationVector** inputVector,
  vtkInformationVector*)
{
  // A global solve: the whole base.
  vtkInformation* base = inputVector[1]->GetInformationObject(0);
  if (base)
  {
    base->Set(vtkStreamingDemandDrivenPipeline::UPDATE_EXTENT(),
      base->Get(vtkStreamingDemandDrivenPipeline::WHOLE_EXTENT()),
      6);
  }
  return 1;
}

//------------------------------------------------------------------------------
int vtkTerroirFeatureCurveTerrain::RequestData(vtkInformation*,
  vtkInformationVector** inputVector,
  vtkInformationVector* outputVector)
{
  this->ErrorMessage.clear();
  this->LastBackend = -1;
  auto fail = [this](const std::string& message)
  {
    this->ErrorMessage = "vtkTerroirFeatureCurveTerrain: " + message;
    vtkErrorMacro(<< message);
    return 0;
  };
  vtkPolyData* curvesData = vtkPolyData::GetData(inputVector[0], 0);
  vtkImageData* base = vtkImageData::GetData(inputVector[1], 0);
  vtkImageData* output = vtkImageData::GetData(outputVector, 0);
  output->Initialize();
  if (!curvesData)
  {
    return fail("no curves on input port 0");
  }
  if (!(this->Tolerance > 0.0) || !std::isfinite(this->Tolerance))
  {
    return fail("Tolerance must be a positive number of metres");
  }
  terroir::terrain::FeatureGrid grid;
  std::vector<float> baseHeights;
  if (base)
  {
    int dims[3];
    base->GetDimensions(dims);
    double spacing[3], origin[3];
    base->GetSpacing(spacing);
    base->GetOrigin(origin);
    vtkDataArray* e = base->GetPointData()->GetArray("Elevation");
    if (!e)
    {
      e = base->GetPointData()->GetScalars();
    }
    if (dims[2] != 1 || dims[0] < 2 || dims[1] < 2 || !e || e->GetNumberOfComponents() != 1)
    {
      return fail("the base (port 1) must be a 2-D image with a one-component Elevation array");
    }
    grid.nx = dims[0];
    grid.ny = dims[1];
    grid.dx = spacing[0];
    grid.dy = spacing[1];
    grid.x0 = origin[0] + base->GetExtent()[0] * spacing[0];
    grid.y0 = origin[1] + base->GetExtent()[2] * spacing[1];
    baseHeights.resize(static_cast<std::size_t>(grid.nx) * grid.ny);
    for (vtkIdType k = 0; k < e->GetNumberOfTuples(); ++k)
    {
      baseHeights[k] = static_cast<float>(e->GetComponent(k, 0));
      if (!std::isfinite(baseHeights[k]))
      {
        return fail("the base has no-data cells; fill them first");
      }
    }
  }
  else
  {
    grid.nx = this->Dimensions[0];
    grid.ny = this->Dimensions[1];
    grid.dx = grid.dy = this->Spacing;
    grid.x0 = this->Origin[0];
    grid.y0 = this->Origin[1];
    baseHeights.assign(
      static_cast<std::size_t>(grid.nx) * grid.ny, static_cast<float>(this->BaseElevation));
  }
  const double n = static_cast<double>(grid.nx) * grid.ny;
  // Constraints (~33 B), six float stencils and three doubles per cell on the levels (~64 B
  // with the coarse ones), the output (5 B) and the copies (12 B); the GPU path keeps a second
  // copy of the levels (64 B) for a fallback to the CPU.
  const bool maybeGPU = this->Backend != vtkTerroirComputeContext::CPU;
  const std::string memory =
    terroir::CheckMemory((maybeGPU ? 184.0 : 120.0) * n, "the feature-curve solver");
  if (!memory.empty())
  {
    return fail(memory);
  }
  const std::vector<terroir::terrain::FeatureCurve> curves = CurvesFromPolyData(curvesData);
  terroir::terrain::FeatureSolverParameters p;
  p.plateauWeight = this->PlateauWeight;
  p.slopeWeight = this->SlopeWeight;
  p.tolerance = this->Tolerance;
  p.maxCycles = this->MaximumCycles;
  terroir::terrain::FeatureConstraints constraints;
  std::string error;
  if (!terroir::terrain::RasterizeFeatureCurves(curves, grid, p, constraints, error))
  {
    return fail(error);
  }
  this->UpdateProgress(0.1);
  std::vector<terroir::terrain::DiffusionLevel> levels =
    terroir::terrain::BuildDiffusionLevels(constraints, grid.nx, grid.ny, baseHeights.data(), p);
  this->UpdateProgress(0.2);

  std::string reason;
  int backend =
    vtkTerroirComputeContext::ResolveBackend(this->Backend, this->GetClassName(), true, reason);
  if (backend < 0)
  {
    return fail("cannot run on the requested backend: " + reason);
  }
  terroir::terrain::DiffusionReport report;
  if (backend == vtkTerroirComputeContext::GPU)
  {
    try
    {
      auto gpuLevels = levels; // the CPU keeps its copy for a fallback
      report = SolveOnGPU(gpuLevels, p);
      levels.swap(gpuLevels);
    }
    catch (const std::exception& e)
    {
      if (this->Backend == vtkTerroirComputeContext::GPU)
      {
        return fail(std::string("GPU path failed: ") + e.what());
      }
      vtkWarningMacro(<< "GPU path failed, falling back to the CPU: " << e.what());
      backend = vtkTerroirComputeContext::CPU;
    }
  }
  if (backend == vtkTerroirComputeContext::CPU)
  {
    report = terroir::terrain::SolveDiffusionMultigrid(levels,
      p,
      [](int rows, const std::function<void(int, int)>& body)
      {
        vtkSMPTools::For(0,
          rows,
          8,
          [&body](vtkIdType j0, vtkIdType j1)
          { body(static_cast<int>(j0), static_cast<int>(j1)); });
      });
  }
  this->UpdateProgress(0.9);
  this->LastBackend = backend;
  this->LastCycles = report.cycles;
  this->LastLevels = report.levels;
  this->LastChange = report.history.empty() ? 0.0 : report.history.back();
  this->LastResidual = report.residual;
  this->LastConverged = report.converged;
  if (!report.converged)
  {
    vtkWarningMacro(<< "the solve did not reach the tolerance " << this->Tolerance << " m in "
                    << report.cycles << " V-cycles (last change " << this->LastChange << " m)");
  }

  if (base)
  {
    output->ShallowCopy(base);
  }
  else
  {
    output->SetExtent(0, grid.nx - 1, 0, grid.ny - 1, 0, 0);
    output->SetSpacing(grid.dx, grid.dy, 1.0);
    output->SetOrigin(grid.x0, grid.y0, 0.0);
  }
  const vtkIdType count = static_cast<vtkIdType>(n);
  vtkNew<vtkFloatArray> elevation;
  elevation->SetName(ElevationName());
  elevation->SetNumberOfTuples(count);
  elevation->GetInformation()->Set(vtkDataArray::UNITS_LABEL(), "m");
  float* h = elevation->GetPointer(0);
  for (vtkIdType k = 0; k < count; ++k)
  {
    h[k] = static_cast<float>(levels[0].h[k]);
  }
  vtkNew<vtkUnsignedCharArray> kind;
  kind->SetName(FeatureKindName());
  kind->SetNumberOfTuples(count);
  std::copy(constraints.kind.begin(), constraints.kind.end(), kind->GetPointer(0));
  vtkPointData* pd = output->GetPointData();
  pd->RemoveArray(ElevationName());
  pd->AddArray(kind);
  pd->SetScalars(elevation);
  return 1;
}
