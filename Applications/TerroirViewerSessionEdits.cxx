// The model of `terroir view` (TerroirViewerSessionPrivate.h): its changes, each one undo step:
// a lake filled at a cell, the infiltration brush, fill and slope rule, and Undo.
#include "TerroirViewerSessionPrivate.h"

#include "vtkDataArray.h"
#include "vtkFieldData.h"

#include "vtkTerroirFloodFill.h"
#include "vtkTerroirGeoreference.h"

#include <cmath>
#include <cstdio>
#include <limits>

namespace terroir
{
namespace viewer
{

//------------------------------------------------------------------------------
bool ViewerSession::FloodFillAt(int i, int j, std::string& error)
{
  Internals& in = *this->Impl;
  if (!in.Terrain)
  {
    error = "no terrain";
    return false;
  }
  int dims[3];
  in.Terrain->GetDimensions(dims);
  if (i < 0 || j < 0 || i >= dims[0] || j >= dims[1])
  {
    error = "cell (" + std::to_string(i) + ", " + std::to_string(j) + ") lies outside the terrain";
    return false;
  }
  const vtkIdType k = static_cast<vtkIdType>(j) * dims[0] + i;
  vtkPointData* pd = in.Terrain->GetPointData();
  const double z = pd->GetArray(vtkTerroirGeoreference::ElevationName())->GetComponent(k, 0);
  vtkDataArray* mask = pd->GetArray(vtkTerroirGeoreference::ValidMaskName());
  if (!std::isfinite(z) || (mask && mask->GetComponent(k, 0) == 0.0))
  {
    error = "cell (" + std::to_string(i) + ", " + std::to_string(j) + ") has no data";
    return false;
  }
  auto input = vtkSmartPointer<vtkImageData>::New();
  input->ShallowCopy(in.Terrain);
  // The depression that holds the cell, filled to its spill level: water poured in rises no
  // higher (above it, it runs out over the pass), and none on a slope stays.
  vtkNew<vtkTerroirFloodFill> depressions;
  depressions->SetInputData(input);
  depressions->SetModeToFillDepressions();
  depressions->SetIncludeFlatSurfaces(false);
  depressions->SetMinimumArea(0.0);
  JobMonitor monitor;
  if (!RunFilter(depressions, monitor, 0.0, 0.5))
  {
    error = monitor.Error;
    return false;
  }
  vtkImageData* filled = depressions->GetOutput();
  vtkDataArray* body = filled->GetPointData()->GetArray(vtkTerroirFloodFill::WaterBodyName());
  vtkDataArray* levels =
    filled->GetFieldData()->GetArray(vtkTerroirFloodFill::WaterBodyLevelName());
  const int id = body ? static_cast<int>(body->GetComponent(k, 0)) : 0;
  if (id <= 0 || !levels || id > levels->GetNumberOfTuples())
  {
    error = "cell (" + std::to_string(i) + ", " + std::to_string(j) +
      ") is not in a depression: water poured there runs off";
    return false;
  }
  const double spill = levels->GetComponent(id - 1, 0);
  const double level = std::min(z + in.Params.LakeDepth, spill);
  vtkSmartPointer<vtkDataArray> depth;
  if (level >= spill)
  {
    // The whole depression, as FillDepressions filled it.
    vtkDataArray* full = filled->GetPointData()->GetArray(vtkTerroirFloodFill::WaterDepthName());
    depth.TakeReference(vtkFloatArray::New());
    depth->SetNumberOfTuples(body->GetNumberOfTuples());
    for (vtkIdType m = 0; m < body->GetNumberOfTuples(); ++m)
    {
      depth->SetComponent(
        m, 0, static_cast<int>(body->GetComponent(m, 0)) == id ? full->GetComponent(m, 0) : 0.0);
    }
  }
  else
  {
    // Below the spill level every path out of the depression climbs above the level, so the
    // seed's fill (cells connected to the click at or below the level) stays inside it.
    vtkNew<vtkTerroirFloodFill> flood;
    flood->SetInputData(input);
    flood->SetModeToSeeds();
    flood->AddSeedCell(i, j, level);
    if (!RunFilter(flood, monitor, 0.5, 0.5))
    {
      error = monitor.Error;
      return false;
    }
    depth = flood->GetOutput()->GetPointData()->GetArray(vtkTerroirFloodFill::WaterDepthName());
  }
  return in.MergeWater(depth, error);
}

bool ViewerSession::Internals::MergeWater(vtkDataArray* depth, std::string& error)
{
  if (!depth || depth->GetNumberOfTuples() != this->Water->GetNumberOfTuples())
  {
    error = "the flood fill gave no WaterDepth";
    return false;
  }
  std::vector<float> before = Internals::CopyOf(this->Water);
  float* w = this->Water->GetPointer(0);
  for (vtkIdType m = 0; m < this->Water->GetNumberOfValues(); ++m)
  {
    const double d = depth->GetComponent(m, 0);
    if (std::isfinite(d) && d > w[m])
    {
      w[m] = static_cast<float>(d);
    }
  }
  this->Record(true, std::move(before));
  return true;
}

long long ViewerSession::FloodSea(double level, std::string& error)
{
  // Every border cell with data at or below the level seeds the fill: the sea is what those
  // cells reach through cells at or below the level (8-connected), as water from beyond the
  // edge of the map would.
  Internals& in = *this->Impl;
  if (!in.Terrain)
  {
    error = "no terrain";
    return -1;
  }
  int dims[3];
  in.Terrain->GetDimensions(dims);
  vtkDataArray* z = in.Terrain->GetPointData()->GetArray(vtkTerroirGeoreference::ElevationName());
  auto input = vtkSmartPointer<vtkImageData>::New();
  input->ShallowCopy(in.Terrain);
  vtkNew<vtkTerroirFloodFill> flood;
  flood->SetInputData(input);
  flood->SetModeToSeeds();
  double lowest = std::numeric_limits<double>::infinity();
  for (int j = 0; j < dims[1]; ++j)
  {
    const bool edgeRow = j == 0 || j == dims[1] - 1;
    for (int i = 0; i < dims[0]; i += edgeRow ? 1 : dims[0] - 1)
    {
      const double h = z->GetComponent(static_cast<vtkIdType>(j) * dims[0] + i, 0);
      if (std::isfinite(h) && h <= level)
      {
        flood->AddSeedCell(i, j, level);
      }
      lowest = std::isfinite(h) ? std::min(lowest, h) : lowest;
    }
  }
  if (flood->GetNumberOfSeeds() == 0)
  {
    char line[160];
    std::snprintf(line,
      sizeof(line),
      "no edge cell lies at or below %.2f m (the lowest is %.2f m): the sea stays off the map",
      level,
      lowest);
    error = line;
    return -1;
  }
  JobMonitor monitor;
  if (!RunFilter(flood, monitor, 0.0, 1.0))
  {
    error = monitor.Error;
    return -1;
  }
  vtkDataArray* depth =
    flood->GetOutput()->GetPointData()->GetArray(vtkTerroirFloodFill::WaterDepthName());
  if (!in.MergeWater(depth, error))
  {
    return -1;
  }
  long long cells = 0;
  for (vtkIdType m = 0; m < depth->GetNumberOfTuples(); ++m)
  {
    cells += depth->GetComponent(m, 0) > 0.0 ? 1 : 0;
  }
  return cells;
}

bool ViewerSession::Undo()
{
  Internals& in = *this->Impl;
  if (in.InStroke)
  {
    this->EndStroke();
  }
  if (in.UndoStack.empty())
  {
    return false;
  }
  const Internals::Change& c = in.UndoStack.back();
  vtkFloatArray* a = c.IsWater ? in.Water.Get() : in.Infiltration.Get();
  float* values = a->GetPointer(0);
  if (c.Whole)
  {
    std::memcpy(values, c.Values.data(), c.Values.size() * sizeof(float));
  }
  else
  {
    for (std::size_t k = 0; k < c.Cells.size(); ++k)
    {
      values[c.Cells[k]] = c.Values[k];
    }
  }
  a->Modified();
  ++(c.IsWater ? in.WaterVersion : in.InfiltrationVersion);
  in.UndoStack.pop_back();
  return true;
}

void ViewerSession::BeginStroke()
{
  Internals& in = *this->Impl;
  if (in.InStroke)
  {
    this->EndStroke();
  }
  if (in.Infiltration)
  {
    in.StrokeBefore = Internals::CopyOf(in.Infiltration);
    in.InStroke = true;
  }
}

long long ViewerSession::EndStroke()
{
  Internals& in = *this->Impl;
  if (!in.InStroke)
  {
    return 0;
  }
  in.InStroke = false;
  return in.Record(false, std::move(in.StrokeBefore));
}

int ViewerSession::PaintInfiltration(int i, int j)
{
  return this->PaintInfiltrationAlong(i, j, i, j);
}

int ViewerSession::PaintInfiltrationAlong(double i0, double j0, double i1, double j1)
{
  Internals& in = *this->Impl;
  if (!in.Terrain || !std::isfinite(i0) || !std::isfinite(j0) || !std::isfinite(i1) ||
    !std::isfinite(j1))
  {
    return 0;
  }
  const bool alone = !in.InStroke;
  if (alone)
  {
    this->BeginStroke();
  }
  int dims[3];
  in.Terrain->GetDimensions(dims);
  const double r = std::max(0.0, std::min(1000.0, in.Params.BrushRadius));
  const float rate = in.BrushRate();
  // Every cell within r of the segment (a capsule), clipped to the grid.
  const double di = i1 - i0, dj = j1 - j0;
  const double length2 = di * di + dj * dj;
  const double lo[2] = { std::max(0.0, std::ceil(std::min(i0, i1) - r)),
    std::max(0.0, std::ceil(std::min(j0, j1) - r)) };
  const double hi[2] = { std::min(dims[0] - 1.0, std::floor(std::max(i0, i1) + r)),
    std::min(dims[1] - 1.0, std::floor(std::max(j0, j1) + r)) };
  int painted = 0;
  float* values = in.Infiltration->GetPointer(0);
  for (double jj = lo[1]; jj <= hi[1]; ++jj)
  {
    for (double ii = lo[0]; ii <= hi[0]; ++ii)
    {
      double t = length2 > 0.0 ? ((ii - i0) * di + (jj - j0) * dj) / length2 : 0.0;
      t = std::max(0.0, std::min(1.0, t));
      const double ei = ii - (i0 + t * di), ej = jj - (j0 + t * dj);
      const vtkIdType k = static_cast<vtkIdType>(jj) * dims[0] + static_cast<vtkIdType>(ii);
      if (ei * ei + ej * ej <= r * r && in.HasData(k))
      {
        values[k] = rate;
        ++painted;
      }
    }
  }
  in.Infiltration->Modified();
  if (alone)
  {
    this->EndStroke();
  }
  return painted;
}

long long ViewerSession::FillInfiltration()
{
  Internals& in = *this->Impl;
  if (!in.Terrain)
  {
    return 0;
  }
  if (in.InStroke)
  {
    this->EndStroke();
  }
  std::vector<float> before = Internals::CopyOf(in.Infiltration);
  const float rate = in.BrushRate();
  float* values = in.Infiltration->GetPointer(0);
  for (vtkIdType k = 0; k < in.Infiltration->GetNumberOfValues(); ++k)
  {
    if (in.HasData(k))
    {
      values[k] = rate;
    }
  }
  return in.Record(false, std::move(before));
}

long long ViewerSession::ApplySlopeRule(std::string& error)
{
  Internals& in = *this->Impl;
  if (!in.Terrain)
  {
    error = "no terrain";
    return -1;
  }
  if (in.InStroke)
  {
    this->EndStroke();
  }
  // vtkTerroirInfiltration's rule on a map of ones: 0 marks the cells it applies to.
  auto input = vtkSmartPointer<vtkImageData>::New();
  input->ShallowCopy(in.Terrain);
  vtkNew<vtkTerroirInfiltration> rule;
  rule->SetInputData(input);
  rule->AddFill(1.0);
  rule->AddSlopeRule(std::max(0.0, std::min(90.0, in.Params.SlopeThreshold)));
  JobMonitor monitor;
  if (!RunFilter(rule, monitor, 0.0, 1.0))
  {
    error = monitor.Error;
    return -1;
  }
  vtkDataArray* steep =
    rule->GetOutput()->GetPointData()->GetArray(vtkTerroirInfiltration::InfiltrationRateName());
  if (!steep || steep->GetNumberOfTuples() != in.Infiltration->GetNumberOfTuples())
  {
    error = "the slope rule gave no InfiltrationRate";
    return -1;
  }
  std::vector<float> before = Internals::CopyOf(in.Infiltration);
  float* values = in.Infiltration->GetPointer(0);
  for (vtkIdType k = 0; k < steep->GetNumberOfTuples(); ++k)
  {
    if (steep->GetComponent(k, 0) == 0.0)
    {
      values[k] = 0.0f;
    }
  }
  return in.Record(false, std::move(before));
}

} // namespace viewer
} // namespace terroir
