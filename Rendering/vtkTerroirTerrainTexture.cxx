#include "vtkTerroirTerrainTexture.h"

#include "TriangleTexturing.h"

#include "vtkActor.h"
#include "vtkDataArray.h"
#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkMapper.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPolyData.h"
#include "vtkSmartPointer.h"
#include "vtkTerroirGeoreference.h"
#include "vtkTerroirReliefSurface.h"
#include "vtkTexture.h"
#include "vtkUnsignedCharArray.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <vector>

vtkStandardNewMacro(vtkTerroirTerrainTexture);

namespace
{
/// The heights of a terrain as floats, NaN where masked.
std::vector<float> MaskedHeights(vtkDataArray* elevation, vtkDataArray* mask, vtkIdType n)
{
  std::vector<float> z(n);
  for (vtkIdType k = 0; k < n; ++k)
  {
    const bool ok = !mask || mask->GetComponent(k, 0) != 0.0;
    z[k] = ok ? static_cast<float>(elevation->GetComponent(k, 0))
              : std::numeric_limits<float>::quiet_NaN();
  }
  return z;
}

/// The biome zone of each point from a one-component `ClusterId` array (-1 where not finite
/// or negative); empty without one.
std::vector<int> ZonesOf(vtkDataArray* zones, vtkIdType n)
{
  std::vector<int> out;
  if (!zones || zones->GetNumberOfComponents() != 1 || zones->GetNumberOfTuples() != n)
  {
    return out;
  }
  out.resize(n);
  for (vtkIdType k = 0; k < n; ++k)
  {
    const double v = zones->GetComponent(k, 0);
    out[k] = std::isfinite(v) && v >= 0.0 && v < 1e9 ? static_cast<int>(v) : -1;
  }
  return out;
}

/// The material rules of the view: sea level as given; the snow line as given, or at 85 % of
/// the valid elevation range, with a band of 1/10 of the range (200 m for a flat terrain).
terroir::rendering::MaterialRules RulesFor(const std::vector<float>& z,
  double seaLevel,
  double snowLine)
{
  terroir::rendering::MaterialRules rules;
  float lo = std::numeric_limits<float>::infinity(), hi = -lo;
  for (float v : z)
  {
    if (std::isfinite(v))
    {
      lo = std::min(lo, v);
      hi = std::max(hi, v);
    }
  }
  const double range = hi > lo ? static_cast<double>(hi) - lo : 0.0;
  rules.SeaLevel = seaLevel;
  rules.SnowBand = range > 0.0 ? 0.1 * range : 200.0;
  rules.SnowLine =
    std::isfinite(snowLine) ? snowLine : (range > 0.0 ? lo + 0.85 * range : hi + 1e3);
  return rules;
}
} // namespace

/// The last texture and what it was built from.
struct vtkTerroirTerrainTexture::Internals
{
  struct Key
  {
    vtkSmartPointer<vtkDataArray> Elevation, Mask, Zones;
    vtkMTimeType ElevationTime = 0, MaskTime = 0, ZonesTime = 0;
    int Dims[2] = { 0, 0 };
    double Spacing[2] = { 0, 0 };
    int Seed = 0, Texels = 0, MaxSize = 0;
    double SeaLevel = 0, SnowLine = 0;
    bool operator==(const Key& o) const
    {
      return this->Elevation == o.Elevation && this->Mask == o.Mask && this->Zones == o.Zones &&
        this->ElevationTime == o.ElevationTime && this->MaskTime == o.MaskTime &&
        this->ZonesTime == o.ZonesTime && this->Dims[0] == o.Dims[0] &&
        this->Dims[1] == o.Dims[1] && this->Spacing[0] == o.Spacing[0] &&
        this->Spacing[1] == o.Spacing[1] && this->Seed == o.Seed && this->Texels == o.Texels &&
        this->MaxSize == o.MaxSize && this->SeaLevel == o.SeaLevel &&
        (this->SnowLine == o.SnowLine || (std::isnan(this->SnowLine) && std::isnan(o.SnowLine)));
    }
  } Built;
  vtkSmartPointer<vtkTexture> Texture;
  terroir::rendering::TextureLayout Layout;
};

//------------------------------------------------------------------------------
vtkTerroirTerrainTexture::vtkTerroirTerrainTexture()
  : Internal(new Internals)
{
}

vtkTerroirTerrainTexture::~vtkTerroirTerrainTexture() = default;

//------------------------------------------------------------------------------
void vtkTerroirTerrainTexture::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Seed: " << this->Seed << "\n";
  os << indent << "TexelsPerCell: " << this->TexelsPerCell << "\n";
  os << indent << "MaxTextureSize: " << this->MaxTextureSize << "\n";
  os << indent << "SeaLevel: " << this->SeaLevel << " m\n";
  os << indent << "SnowLine: " << this->SnowLine << " m\n";
}

//------------------------------------------------------------------------------
bool vtkTerroirTerrainTexture::Update(vtkImageData* image, std::string& error)
{
  Internals& in = *this->Internal;
  vtkPointData* pd = image ? image->GetPointData() : nullptr;
  vtkDataArray* elevation = pd ? pd->GetArray(vtkTerroirGeoreference::ElevationName()) : nullptr;
  if (!elevation)
  {
    error = "texturing: the terrain has no Elevation array";
    return false;
  }
  int dims[3];
  image->GetDimensions(dims);
  double spacing[3];
  image->GetSpacing(spacing);
  Internals::Key key;
  key.Elevation = elevation;
  key.Mask = pd->GetArray(vtkTerroirGeoreference::ValidMaskName());
  key.Zones = pd->GetArray("ClusterId");
  key.ElevationTime = key.Elevation->GetMTime();
  key.MaskTime = key.Mask ? key.Mask->GetMTime() : 0;
  key.ZonesTime = key.Zones ? key.Zones->GetMTime() : 0;
  key.Dims[0] = dims[0];
  key.Dims[1] = dims[1];
  key.Spacing[0] = spacing[0];
  key.Spacing[1] = spacing[1];
  key.Seed = this->Seed;
  key.Texels = this->TexelsPerCell;
  key.MaxSize = this->MaxTextureSize;
  key.SeaLevel = this->SeaLevel;
  key.SnowLine = this->SnowLine;
  if (in.Texture && in.Built == key)
  {
    return true;
  }
  const vtkIdType n = static_cast<vtkIdType>(dims[0]) * dims[1];
  const std::vector<float> z = MaskedHeights(key.Elevation, key.Mask, n);
  try
  {
    const auto rules = RulesFor(z, this->SeaLevel, this->SnowLine);
    const std::vector<float> weights = terroir::rendering::MaterialWeights(dims[0],
      dims[1],
      std::abs(spacing[0]),
      std::abs(spacing[1]),
      z,
      ZonesOf(key.Zones, n),
      rules);
    const auto built = terroir::rendering::BuildTerrainTexture(dims[0],
      dims[1],
      weights,
      terroir::rendering::DefaultMaterials(),
      this->TexelsPerCell,
      static_cast<std::uint64_t>(static_cast<std::uint32_t>(this->Seed)),
      this->MaxTextureSize);
    vtkNew<vtkImageData> picture;
    picture->SetDimensions(built.Layout.Width, built.Layout.Height, 1);
    vtkNew<vtkUnsignedCharArray> rgb;
    rgb->SetNumberOfComponents(3);
    rgb->SetNumberOfTuples(static_cast<vtkIdType>(built.Layout.Width) * built.Layout.Height);
    std::copy(built.Rgb.begin(), built.Rgb.end(), rgb->GetPointer(0));
    picture->GetPointData()->SetScalars(rgb);
    in.Texture = vtkSmartPointer<vtkTexture>::New();
    in.Texture->SetInputData(picture);
    in.Texture->InterpolateOn();
    in.Texture->MipmapOn();
    in.Texture->RepeatOff();
    in.Texture->EdgeClampOn();
    in.Layout = built.Layout;
    in.Built = key;
  }
  catch (const std::exception& e)
  {
    in.Texture = nullptr;
    error = std::string("texturing: ") + e.what();
    return false;
  }
  return true;
}

//------------------------------------------------------------------------------
vtkTexture* vtkTerroirTerrainTexture::GetTexture()
{
  return this->Internal->Texture;
}

void vtkTerroirTerrainTexture::GetTextureSize(int size[2]) const
{
  size[0] = this->Internal->Layout.Width;
  size[1] = this->Internal->Layout.Height;
}

int vtkTerroirTerrainTexture::GetCellsPerTile() const
{
  return this->Internal->Layout.CellsPerTile;
}

//------------------------------------------------------------------------------
bool vtkTerroirTerrainTexture::ApplyTo(vtkTerroirReliefSurface* relief,
  vtkImageData* image,
  std::string& error)
{
  if (!this->Update(image, error))
  {
    return false;
  }
  const Internals& in = *this->Internal;
  double spacing[3], origin[3];
  image->GetSpacing(spacing);
  image->GetOrigin(origin);
  // Texture coordinates of the drawn points (every point, or every Stride-th).
  vtkActor* actor = relief->GetSurfaceActor();
  vtkPolyData* surface = vtkPolyData::SafeDownCast(actor->GetMapper()->GetInputDataObject(0, 0));
  if (!surface)
  {
    error = "texturing: the surface has no polygons";
    return false;
  }
  vtkNew<vtkFloatArray> tcoords;
  tcoords->SetName("TextureCoordinates");
  tcoords->SetNumberOfComponents(2);
  tcoords->SetNumberOfTuples(surface->GetNumberOfPoints());
  for (vtkIdType p = 0; p < surface->GetNumberOfPoints(); ++p)
  {
    double x[3];
    surface->GetPoint(p, x);
    const double cx = spacing[0] != 0.0 ? (x[0] - origin[0]) / spacing[0] : 0.0;
    const double cy = spacing[1] != 0.0 ? (x[1] - origin[1]) / spacing[1] : 0.0;
    tcoords->SetTypedComponent(p, 0, static_cast<float>(in.Layout.TextureU(cx)));
    tcoords->SetTypedComponent(p, 1, static_cast<float>(in.Layout.TextureV(cy)));
  }
  surface->GetPointData()->SetTCoords(tcoords);
  actor->SetTexture(in.Texture);
  // The texture replaces the colours: the surface's own colour is white.
  relief->SetBaseColor(1.0, 1.0, 1.0);
  relief->SetUniformColor();
  return true;
}

//------------------------------------------------------------------------------
void vtkTerroirTerrainTexture::Remove(vtkTerroirReliefSurface* relief)
{
  vtkActor* actor = relief->GetSurfaceActor();
  actor->SetTexture(nullptr);
  if (auto* surface = vtkPolyData::SafeDownCast(actor->GetMapper()->GetInputDataObject(0, 0)))
  {
    surface->GetPointData()->SetTCoords(nullptr);
  }
}
