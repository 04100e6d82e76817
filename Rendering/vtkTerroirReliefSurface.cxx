#include "vtkTerroirReliefSurface.h"

#include "vtkActor.h"
#include "vtkCamera.h"
#include "vtkCellArray.h"
#include "vtkDataArray.h"
#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkLight.h"
#include "vtkLookupTable.h"
#include "vtkMath.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkPolyDataMapper.h"
#include "vtkProperty.h"
#include "vtkShaderProperty.h"
#include "vtkSmartPointer.h"
#include "vtkTerroirGeoreference.h"
#include "vtkUniforms.h"
#include "vtkUnsignedCharArray.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

vtkStandardNewMacro(vtkTerroirReliefSurface);

namespace
{
// Blinn-Phong lighting, appended after VTK's own light code (which uses Phong's reflection
// vector) and overwriting its result. Uses VTK's declarations for lighting complexity 2 (one
// directional scene light): normalVCVSOutput, vertexVC, lightDirectionVC0, lightColor0,
// ambientColor/diffuseColor (= coefficient x vertex colour), specularColor, specularPower.
const char* BlinnPhongImpl = R"(//VTK::Light::Impl
  {
    vec3 tN = normalize(normalVCVSOutput);
    vec3 tL = normalize(-lightDirectionVC0);
    vec3 tV = (terroirParallel != 0) ? vec3(0.0, 0.0, 1.0) : normalize(-vertexVC.xyz);
    vec3 tH = normalize(tL + tV);
    float tDf = max(0.0, dot(tN, tL));
    float tSf = (tDf > 0.0) ? pow(max(0.0, dot(tN, tH)), specularPower) : 0.0;
    gl_FragData[0] = vec4(ambientColor + tDf * lightColor0 * diffuseColor +
      tSf * lightColor0 * specularColor, opacity);
  }
)";

/// Centre and extents of `bounds`; returns the radius of the bounding sphere.
double CentreAndSize(const double bounds[6], double center[3], double size[3])
{
  for (int a = 0; a < 3; ++a)
  {
    center[a] = 0.5 * (bounds[2 * a] + bounds[2 * a + 1]);
    size[a] = std::abs(bounds[2 * a + 1] - bounds[2 * a]);
  }
  return 0.5 * std::sqrt(size[0] * size[0] + size[1] * size[1] + size[2] * size[2]);
}
}

struct vtkTerroirReliefSurface::Internals
{
  vtkSmartPointer<vtkImageData> Input;
  std::vector<unsigned char> Valid; ///< per grid point
  std::vector<vtkIdType> Index;     ///< drawn point -> grid point; empty when every one is drawn
  double Bounds[6] = { 0, 1, 0, 1, 0, 1 };
  bool HasHoles = false;
  vtkNew<vtkPolyData> Surface;
  vtkNew<vtkPolyData> Holes;
  vtkNew<vtkUnsignedCharArray> Colors;
  vtkNew<vtkActor> SurfaceActor;
  vtkNew<vtkActor> HoleActor;
};

//------------------------------------------------------------------------------
vtkTerroirReliefSurface::vtkTerroirReliefSurface()
  : Internal(new Internals)
{
  Internals& in = *this->Internal;
  in.Colors->SetName("OverlayColors");
  in.Colors->SetNumberOfComponents(3);
  vtkNew<vtkPolyDataMapper> surfaceMapper;
  surfaceMapper->SetInputData(in.Surface);
  surfaceMapper->SetColorModeToDirectScalars();
  surfaceMapper->SetScalarModeToUsePointData();
  surfaceMapper->ScalarVisibilityOn();
  in.SurfaceActor->SetMapper(surfaceMapper);
  in.SurfaceActor->GetShaderProperty()->AddFragmentShaderReplacement(
    "//VTK::Light::Impl", false, BlinnPhongImpl, false);
  vtkNew<vtkPolyDataMapper> holeMapper;
  holeMapper->SetInputData(in.Holes);
  holeMapper->ScalarVisibilityOff();
  in.HoleActor->SetMapper(holeMapper);
  in.HoleActor->GetProperty()->LightingOff();
}

vtkTerroirReliefSurface::~vtkTerroirReliefSurface() = default;

void vtkTerroirReliefSurface::SetInputData(vtkImageData* terrain)
{
  if (this->Internal->Input != terrain)
  {
    this->Internal->Input = terrain;
    this->Modified();
  }
}

vtkImageData* vtkTerroirReliefSurface::GetInputData()
{
  return this->Internal->Input;
}

vtkActor* vtkTerroirReliefSurface::GetSurfaceActor()
{
  return this->Internal->SurfaceActor;
}

vtkActor* vtkTerroirReliefSurface::GetHoleActor()
{
  return this->Internal->HoleActor;
}

void vtkTerroirReliefSurface::GetBounds(double bounds[6])
{
  std::copy(this->Internal->Bounds, this->Internal->Bounds + 6, bounds);
}

bool vtkTerroirReliefSurface::IsValidPoint(vtkIdType k)
{
  const auto& valid = this->Internal->Valid;
  return k >= 0 && static_cast<std::size_t>(k) < valid.size() && valid[k] != 0;
}

namespace
{
/// The grid indices drawn along an axis of `n` points: every `stride`-th, and the last.
std::vector<int> DrawnIndices(int n, int stride)
{
  std::vector<int> indices;
  for (int i = 0; i < n; i += stride)
  {
    indices.push_back(i);
  }
  if (indices.back() != n - 1)
  {
    indices.push_back(n - 1);
  }
  return indices;
}

/// The points of a grid that are drawn: every `stride`-th row and column and the last ones
/// (IX, IY: their grid indices), each one's grid point (Index; empty when every point is
/// drawn), validity and height.
struct DrawnGrid
{
  std::vector<int> IX, IY;
  std::vector<vtkIdType> Index;
  std::vector<unsigned char> Valid;
  std::vector<double> Z;
};

/// The drawn grid of an nx x ny grid with `valid` and heights `z` (taken when every point is
/// drawn).
DrawnGrid DrawGrid(int nx,
  int ny,
  int stride,
  const std::vector<unsigned char>& valid,
  std::vector<double>& z)
{
  DrawnGrid d;
  d.IX = DrawnIndices(nx, stride);
  d.IY = DrawnIndices(ny, stride);
  const int mx = static_cast<int>(d.IX.size());
  const int my = static_cast<int>(d.IY.size());
  if (mx == nx && my == ny)
  {
    d.Valid = valid;
    d.Z.swap(z);
    return d;
  }
  const vtkIdType m = static_cast<vtkIdType>(mx) * my;
  d.Index.resize(m);
  d.Valid.resize(m);
  d.Z.resize(m);
  for (int j = 0; j < my; ++j)
  {
    for (int i = 0; i < mx; ++i)
    {
      const vtkIdType k = static_cast<vtkIdType>(j) * mx + i;
      d.Index[k] = static_cast<vtkIdType>(d.IY[j]) * nx + d.IX[i];
      d.Valid[k] = valid[d.Index[k]];
      d.Z[k] = z[d.Index[k]];
    }
  }
  return d;
}

/// The surface's points (x, y of the drawn grid indices `ix`, `iy`, z = `z`) and normals:
/// central differences where both drawn neighbours are valid, else one-sided, else flat (also
/// at invalid points). `z` and `valid` hold the drawn points, row by row.
void FillPointsAndNormals(const std::vector<int>& ix,
  const std::vector<int>& iy,
  const double origin[3],
  const double spacing[3],
  const std::vector<double>& z,
  const std::vector<unsigned char>& valid,
  vtkPoints* points,
  vtkFloatArray* normals)
{
  const int nx = static_cast<int>(ix.size());
  const int ny = static_cast<int>(iy.size());
  for (int j = 0; j < ny; ++j)
  {
    for (int i = 0; i < nx; ++i)
    {
      const vtkIdType k = static_cast<vtkIdType>(j) * nx + i;
      points->SetPoint(k, origin[0] + ix[i] * spacing[0], origin[1] + iy[j] * spacing[1], z[k]);
      // hMinus, hPlus: the distances to the neighbours (one cell each when every point is drawn).
      auto derivative = [&](vtkIdType kMinus,
                          bool hasMinus,
                          double hMinus,
                          vtkIdType kPlus,
                          bool hasPlus,
                          double hPlus) -> double
      {
        hasMinus = hasMinus && valid[kMinus];
        hasPlus = hasPlus && valid[kPlus];
        if (!valid[k])
        {
          return 0.0;
        }
        if (hasMinus && hasPlus)
        {
          return (z[kPlus] - z[kMinus]) / (hMinus + hPlus);
        }
        if (hasPlus)
        {
          return (z[kPlus] - z[k]) / hPlus;
        }
        if (hasMinus)
        {
          return (z[k] - z[kMinus]) / hMinus;
        }
        return 0.0;
      };
      const double dzdx = derivative(k - 1,
        i > 0,
        i > 0 ? (ix[i] - ix[i - 1]) * spacing[0] : 0.0,
        k + 1,
        i < nx - 1,
        i < nx - 1 ? (ix[i + 1] - ix[i]) * spacing[0] : 0.0);
      const double dzdy = derivative(k - nx,
        j > 0,
        j > 0 ? (iy[j] - iy[j - 1]) * spacing[1] : 0.0,
        k + nx,
        j < ny - 1,
        j < ny - 1 ? (iy[j + 1] - iy[j]) * spacing[1] : 0.0);
      double nrm[3] = { -dzdx, -dzdy, 1.0 };
      vtkMath::Normalize(nrm);
      normals->SetTuple(k, nrm);
    }
  }
}
} // namespace

//------------------------------------------------------------------------------
bool vtkTerroirReliefSurface::BuildGeometry(std::string& error)
{
  Internals& in = *this->Internal;
  vtkImageData* image = in.Input;
  if (!image)
  {
    error = "no input terrain (call SetInputData)";
    return false;
  }
  int dims[3];
  image->GetDimensions(dims);
  if (dims[2] != 1 || dims[0] < 2 || dims[1] < 2)
  {
    error = "the terrain must be a 2-D image of at least 2x2 points, got " +
      std::to_string(dims[0]) + "x" + std::to_string(dims[1]) + "x" + std::to_string(dims[2]);
    return false;
  }
  vtkPointData* pd = image->GetPointData();
  vtkDataArray* elevation = pd->GetArray(vtkTerroirGeoreference::ElevationName());
  if (!elevation || elevation->GetNumberOfComponents() != 1)
  {
    error = "the terrain has no one-component 'Elevation' point array";
    return false;
  }
  vtkDataArray* mask = pd->GetArray(vtkTerroirGeoreference::ValidMaskName());

  const int nx = dims[0];
  const int ny = dims[1];
  const vtkIdType n = static_cast<vtkIdType>(nx) * ny;
  double spacing[3], origin[3];
  image->GetSpacing(spacing);
  image->GetOrigin(origin);
  const double ve = this->VerticalExaggeration;

  std::vector<unsigned char> valid(n);
  std::vector<double> z(n);
  double zFill = std::numeric_limits<double>::infinity();
  double zMax = -std::numeric_limits<double>::infinity();
  for (vtkIdType k = 0; k < n; ++k)
  {
    const double e = elevation->GetComponent(k, 0);
    const bool ok = std::isfinite(e) && (!mask || mask->GetComponent(k, 0) != 0.0);
    valid[k] = ok ? 1 : 0;
    z[k] = e * ve;
    if (ok)
    {
      zFill = std::min(zFill, z[k]);
      zMax = std::max(zMax, z[k]);
    }
  }
  if (!std::isfinite(zFill))
  {
    error = "the terrain has no valid elevation";
    return false;
  }
  for (vtkIdType k = 0; k < n; ++k)
  {
    if (!valid[k])
    {
      z[k] = zFill;
    }
  }

  // The drawn grid: every point, or every Stride-th row and column (and the last ones).
  DrawnGrid drawn = DrawGrid(nx, ny, this->Stride, valid, z);
  const std::vector<int>& ix = drawn.IX;
  const std::vector<int>& iy = drawn.IY;
  const int mx = static_cast<int>(ix.size());
  const int my = static_cast<int>(iy.size());
  const vtkIdType m = static_cast<vtkIdType>(mx) * my;
  const std::vector<unsigned char>& drawnValid = drawn.Valid;

  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  points->SetNumberOfPoints(m);
  vtkNew<vtkFloatArray> normals;
  normals->SetName("Normals");
  normals->SetNumberOfComponents(3);
  normals->SetNumberOfTuples(m);
  FillPointsAndNormals(ix, iy, origin, spacing, drawn.Z, drawnValid, points, normals);

  // Valid quads are shaded, the others drawn flat in the NaN colour.
  vtkNew<vtkCellArray> surfaceCells;
  vtkNew<vtkCellArray> holeCells;
  for (int j = 0; j + 1 < my; ++j)
  {
    for (int i = 0; i + 1 < mx; ++i)
    {
      const vtkIdType k = static_cast<vtkIdType>(j) * mx + i;
      const vtkIdType quad[4] = { k, k + 1, k + 1 + mx, k + mx };
      const bool ok =
        drawnValid[quad[0]] && drawnValid[quad[1]] && drawnValid[quad[2]] && drawnValid[quad[3]];
      (ok ? surfaceCells : holeCells)->InsertNextCell(4, quad);
    }
  }

  in.Valid.swap(valid);
  in.Index.swap(drawn.Index);
  in.Colors->SetNumberOfTuples(m);
  in.Surface->Initialize();
  in.Surface->SetPoints(points);
  in.Surface->SetPolys(surfaceCells);
  in.Surface->GetPointData()->SetNormals(normals);
  in.Surface->GetPointData()->SetScalars(in.Colors);
  in.Holes->Initialize();
  in.Holes->SetPoints(points);
  in.Holes->SetPolys(holeCells);

  in.Bounds[0] = origin[0];
  in.Bounds[1] = origin[0] + (nx - 1) * spacing[0];
  in.Bounds[2] = origin[1];
  in.Bounds[3] = origin[1] + (ny - 1) * spacing[1];
  in.Bounds[4] = zFill;
  in.Bounds[5] = zMax;
  in.HasHoles = holeCells->GetNumberOfCells() > 0;
  this->ApplyAppearance();
  this->SetUniformColor();
  return true;
}

//------------------------------------------------------------------------------
void vtkTerroirReliefSurface::ApplyAppearance()
{
  Internals& in = *this->Internal;
  vtkProperty* prop = in.SurfaceActor->GetProperty();
  prop->SetInterpolationToPhong();
  prop->SetAmbient(this->Ambient);
  prop->SetDiffuse(this->Diffuse);
  prop->SetSpecular(this->Specular);
  prop->SetSpecularPower(this->SpecularPower);
  prop->SetSpecularColor(1.0, 1.0, 1.0);
  in.SurfaceActor->GetShaderProperty()->GetFragmentCustomUniforms()->SetUniformi(
    "terroirParallel", this->ParallelView ? 1 : 0);
  in.HoleActor->GetProperty()->SetColor(this->NanColor[0], this->NanColor[1], this->NanColor[2]);
  in.HoleActor->GetProperty()->SetOpacity(this->NanColor[3]);
  in.HoleActor->SetVisibility(in.HasHoles && this->NanColor[3] > 0.0);
}

//------------------------------------------------------------------------------
bool vtkTerroirReliefSurface::ComputeDataRange(vtkDataArray* values,
  int component,
  vtkDataArray* mask,
  double range[2])
{
  const auto& valid = this->Internal->Valid;
  if (!values || component < 0 || component >= values->GetNumberOfComponents())
  {
    return false;
  }
  const vtkIdType n =
    std::min<vtkIdType>(values->GetNumberOfTuples(), static_cast<vtkIdType>(valid.size()));
  double lo = std::numeric_limits<double>::infinity();
  double hi = -std::numeric_limits<double>::infinity();
  for (vtkIdType k = 0; k < n; ++k)
  {
    const double v = values->GetComponent(k, component);
    if (valid[k] && std::isfinite(v) && (!mask || mask->GetComponent(k, 0) != 0.0))
    {
      lo = std::min(lo, v);
      hi = std::max(hi, v);
    }
  }
  if (!std::isfinite(lo))
  {
    return false;
  }
  range[0] = lo;
  range[1] = hi;
  return true;
}

void vtkTerroirReliefSurface::SetColors(vtkDataArray* values,
  int component,
  vtkLookupTable* lut,
  vtkDataArray* mask,
  bool overCurrent)
{
  Internals& in = *this->Internal;
  const vtkIdType n = static_cast<vtkIdType>(in.Valid.size()); // grid points
  const vtkIdType drawn = in.Colors->GetNumberOfTuples();
  if (!values || !lut || values->GetNumberOfTuples() != n || component < 0 ||
    component >= values->GetNumberOfComponents())
  {
    if (!overCurrent)
    {
      this->SetUniformColor();
    }
    return;
  }
  if (mask && (mask->GetNumberOfComponents() != 1 || mask->GetNumberOfTuples() != n))
  {
    mask = nullptr;
  }
  for (vtkIdType d = 0; d < drawn; ++d)
  {
    const vtkIdType g = in.Index.empty() ? d : in.Index[d];
    const double v = values->GetComponent(g, component);
    const unsigned char* rgba = lut->MapValue(v);
    const bool coloured = !mask || mask->GetComponent(g, 0) != 0.0;
    const double a = coloured ? rgba[3] / 255.0 : 0.0;
    if (overCurrent && a <= 0.0)
    {
      continue;
    }
    unsigned char out[3];
    for (int c = 0; c < 3; ++c)
    {
      const double under =
        overCurrent ? in.Colors->GetTypedComponent(d, c) : 255.0 * this->BaseColor[c];
      const double blended = a * rgba[c] + (1.0 - a) * under;
      out[c] = static_cast<unsigned char>(std::lround(std::min(255.0, std::max(0.0, blended))));
    }
    in.Colors->SetTypedTuple(d, out);
  }
  in.Colors->Modified();
}

void vtkTerroirReliefSurface::SetUniformColor()
{
  Internals& in = *this->Internal;
  unsigned char base[3];
  for (int c = 0; c < 3; ++c)
  {
    base[c] = static_cast<unsigned char>(
      std::lround(std::min(255.0, std::max(0.0, 255.0 * this->BaseColor[c]))));
  }
  for (vtkIdType k = 0; k < in.Colors->GetNumberOfTuples(); ++k)
  {
    in.Colors->SetTypedTuple(k, base);
  }
  in.Colors->Modified();
}

//------------------------------------------------------------------------------
void vtkTerroirReliefSurface::ConfigureLight(vtkLight* light,
  double azimuth,
  double elevation,
  const double bounds[6])
{
  double center[3], size[3];
  const double radius = CentreAndSize(bounds, center, size);
  const double az = vtkMath::RadiansFromDegrees(azimuth);
  const double el = vtkMath::RadiansFromDegrees(elevation);
  const double toLight[3] = {
    std::sin(az) * std::cos(el), std::cos(az) * std::cos(el), std::sin(el)
  };
  light->SetLightTypeToSceneLight();
  light->PositionalOff();
  light->SetColor(1.0, 1.0, 1.0);
  light->SetIntensity(1.0);
  light->SetFocalPoint(center[0], center[1], center[2]);
  light->SetPosition(center[0] + toLight[0] * 10.0 * radius,
    center[1] + toLight[1] * 10.0 * radius,
    center[2] + toLight[2] * 10.0 * radius);
}

void vtkTerroirReliefSurface::FitMapCamera(vtkCamera* camera, const double bounds[6], double aspect)
{
  double center[3], size[3];
  const double radius = CentreAndSize(bounds, center, size);
  const double sizeX = size[0];
  const double sizeY = size[1];
  camera->ParallelProjectionOn();
  camera->SetFocalPoint(center[0], center[1], center[2]);
  camera->SetPosition(center[0], center[1], bounds[5] + 2.0 * radius + 1.0);
  camera->SetViewUp(0.0, 1.0, 0.0);
  camera->SetParallelScale(std::max(0.5 * sizeY, 0.5 * sizeX / aspect));
}

void vtkTerroirReliefSurface::FitReliefCamera(vtkCamera* camera,
  const double bounds[6],
  double aspect,
  double azimuth,
  double elevation,
  double viewAngle)
{
  double center[3], size[3];
  const double radius = CentreAndSize(bounds, center, size);
  const double sizeX = size[0];
  const double sizeY = size[1];
  // Fixed direction; the distance is the smallest one at which all 8 corners of the bounding
  // box project inside the frame (tighter than fitting the bounding sphere).
  const double caz = vtkMath::RadiansFromDegrees(azimuth);
  const double cel = vtkMath::RadiansFromDegrees(elevation);
  const double tanV = std::tan(vtkMath::RadiansFromDegrees(0.5 * viewAngle));
  const double tanH = tanV * aspect;
  // Unit vectors: toward the camera (back), screen right and screen up.
  const double back[3] = {
    std::sin(caz) * std::cos(cel), std::cos(caz) * std::cos(cel), std::sin(cel)
  };
  double right[3];
  const double zUp[3] = { 0.0, 0.0, 1.0 };
  vtkMath::Cross(zUp, back, right);
  vtkMath::Normalize(right);
  double up[3];
  vtkMath::Cross(back, right, up);
  double distance = 0.0;
  for (int corner = 0; corner < 8; ++corner)
  {
    const double p[3] = { bounds[corner & 1] - center[0],
      bounds[2 + ((corner >> 1) & 1)] - center[1],
      bounds[4 + ((corner >> 2) & 1)] - center[2] };
    const double w = vtkMath::Dot(p, back);
    distance = std::max(distance, w + std::abs(vtkMath::Dot(p, right)) / tanH);
    distance = std::max(distance, w + std::abs(vtkMath::Dot(p, up)) / tanV);
  }
  distance = std::max(distance * 1.03, 1e-6 + radius * 0.1);
  camera->ParallelProjectionOff();
  camera->SetViewAngle(viewAngle);
  camera->SetFocalPoint(center[0], center[1], center[2]);
  camera->SetPosition(
    center[0] + distance * back[0], center[1] + distance * back[1], center[2] + distance * back[2]);
  camera->SetViewUp(0.0, 0.0, 1.0);
}

//------------------------------------------------------------------------------
void vtkTerroirReliefSurface::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "VerticalExaggeration: " << this->VerticalExaggeration << "\n";
  os << indent << "Ambient/Diffuse/Specular/Power: " << this->Ambient << " " << this->Diffuse << " "
     << this->Specular << " " << this->SpecularPower << "\n";
  os << indent << "ParallelView: " << this->ParallelView << "\n";
}
