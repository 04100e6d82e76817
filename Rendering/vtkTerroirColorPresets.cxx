#include "vtkTerroirColorPresets.h"

#include "vtkColorTransferFunction.h"
#include "vtkLookupTable.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkVariant.h"

#include "ClusterPalette.h"

#include <cmath>
#include <cstring>
#include <string>

vtkStandardNewMacro(vtkTerroirColorPresets);

namespace
{
struct PresetInfo
{
  const char* Name;
  const char* ArrayName;
  const char* Units;
  const char* Title;
  bool HasDefaultRange;
  double DefaultRange[2];
};

// Fixed order; documented in the header and in Documentation/Rendering.md.
const PresetInfo Presets[] = {
  { "Elevation", "Elevation", "m", "Elevation", false, { 0, 0 } },
  { "Slope", "Slope", "\xC2\xB0", "Slope", true, { 0.0, 60.0 } },
  { "Illumination", "IlluminationHours", "h/day", "Illumination", false, { 0, 0 } },
  { "Temperature",
    "Temperature",
    "\xC2\xB0"
    "C",
    "Temperature",
    false,
    { 0, 0 } },
  { "Humidity", "SoilHumidity", "mm", "Soil humidity", false, { 0, 0 } },
  { "Water", "WaterHeight", "m", "Water depth", false, { 0, 0 } },
  { "Clusters", "ClusterId", "", "Cluster", false, { 0, 0 } },
  { "Sunlit", "Illuminated", "", "Direct sun", true, { 0.0, 1.0 } },
  { "Incidence", "SunIncidence", "", "Sun incidence (cosine)", true, { 0.0, 1.0 } },
  { "Insolation", "Insolation", "Wh/m\xC2\xB2/day", "Insolation", false, { 0, 0 } },
  { "WaterBodies", "WaterDepth", "m", "Lake depth", false, { 0, 0 } },
  { "RiverComparison", "RiverComparison", "", "Rivers", true, { 0.0, 3.0 } },
  { "Rivers", "RiverNetwork", "", "Rivers and lakes", true, { 0.0, 2.0 } },
  { "Erosion", "ErosionDepth", "m", "Erosion (-) / deposition (+)", false, { 0, 0 } },
  { "Vegetation", "VegetationDensity", "", "Vegetation density", true, { 0.0, 1.0 } },
};
constexpr int NumberOfPresets = static_cast<int>(sizeof(Presets) / sizeof(Presets[0]));

// RiverComparison classes 1..3 (terroir::hydrology::RiverComparisonCategories), colours of the
// Okabe-Ito palette (Okabe & Ito 2008, "Color Universal Design"), told apart with every common
// colour-vision deficiency and from grey relief: blue and vermillion differ in hue and
// lightness for deuteranopes and protanopes, and black matches by luminance alone. The names
// fit the 400 x 400 legend column (about 10 characters): "map only" is a mapped river with no
// simulated one within the tolerance, "model only" a simulated river with no mapped one.
struct RiverClass
{
  int Value;
  const char* Name;
  double Color[3];
};
const RiverClass RiverClasses[3] = {
  { 1, "map only", { 0.000, 0.447, 0.698 } },   // Okabe-Ito blue (0, 114, 178)
  { 2, "model only", { 0.835, 0.369, 0.000 } }, // Okabe-Ito vermillion (213, 94, 0)
  { 3, "both", { 0.000, 0.000, 0.000 } },       // black
};

// RiverNetwork classes 1..2 (`terroir run`): Okabe-Ito blue rivers and sky-blue water bodies.
const RiverClass NetworkClasses[2] = {
  { 1, "river", { 0.000, 0.447, 0.698 } }, // Okabe-Ito blue (0, 114, 178)
  { 2, "lake", { 0.337, 0.706, 0.914 } },  // Okabe-Ito sky blue (86, 180, 233)
};

const PresetInfo* Find(const char* name)
{
  if (!name)
  {
    return nullptr;
  }
  for (const PresetInfo& p : Presets)
  {
    if (std::strcmp(p.Name, name) == 0)
    {
      return &p;
    }
  }
  return nullptr;
}

// Samples a colour transfer function defined on [0, 1] into the 256 entries of `lut`.
void SampleInto(vtkLookupTable* lut, vtkColorTransferFunction* ctf)
{
  const int n = 256;
  lut->SetNumberOfTableValues(n);
  for (int i = 0; i < n; ++i)
  {
    double rgb[3];
    ctf->GetColor(static_cast<double>(i) / (n - 1), rgb);
    lut->SetTableValue(i, rgb[0], rgb[1], rgb[2], 1.0);
  }
}
}

//------------------------------------------------------------------------------
int vtkTerroirColorPresets::GetNumberOfPresets()
{
  return NumberOfPresets;
}

const char* vtkTerroirColorPresets::GetPresetName(int index)
{
  return (index >= 0 && index < NumberOfPresets) ? Presets[index].Name : nullptr;
}

bool vtkTerroirColorPresets::HasPreset(const char* preset)
{
  return Find(preset) != nullptr;
}

const char* vtkTerroirColorPresets::GetDefaultArrayName(const char* preset)
{
  const PresetInfo* p = Find(preset);
  return p ? p->ArrayName : nullptr;
}

const char* vtkTerroirColorPresets::GetUnits(const char* preset)
{
  const PresetInfo* p = Find(preset);
  return p ? p->Units : nullptr;
}

const char* vtkTerroirColorPresets::GetTitle(const char* preset)
{
  const PresetInfo* p = Find(preset);
  return p ? p->Title : nullptr;
}

std::string vtkTerroirColorPresets::GetLegendTitle(const char* preset)
{
  const PresetInfo* p = Find(preset);
  if (!p)
  {
    return std::string();
  }
  std::string title = p->Title;
  if (p->Units[0] != '\0')
  {
    title += std::string(" (") + p->Units + ")";
  }
  return title;
}

const char* vtkTerroirColorPresets::GetPresetForArray(const char* arrayName)
{
  if (!arrayName)
  {
    return nullptr;
  }
  for (const PresetInfo& p : Presets)
  {
    if (std::strcmp(p.ArrayName, arrayName) == 0)
    {
      return p.Name;
    }
  }
  if (std::strcmp(arrayName, "WeightedSoilHumidity") == 0 ||
    std::strcmp(arrayName, "StandingWater") == 0)
  {
    return "Humidity";
  }
  return nullptr;
}

bool vtkTerroirColorPresets::GetDefaultRange(const char* preset, double range[2])
{
  const PresetInfo* p = Find(preset);
  if (!p || !p->HasDefaultRange)
  {
    return false;
  }
  range[0] = p->DefaultRange[0];
  range[1] = p->DefaultRange[1];
  return true;
}

const char* vtkTerroirColorPresets::GetMaskArrayName(const char* preset)
{
  if (preset && std::strcmp(preset, "WaterBodies") == 0)
  {
    return "WaterBody";
  }
  // Category 0 (no river, or outside the scored area) shows the bare relief.
  if (preset && std::strcmp(preset, "RiverComparison") == 0)
  {
    return "RiverComparison";
  }
  if (preset && std::strcmp(preset, "Rivers") == 0)
  {
    return "RiverNetwork";
  }
  return nullptr;
}

bool vtkTerroirColorPresets::IsCategorical(const char* preset)
{
  return preset &&
    (std::strcmp(preset, "Clusters") == 0 || std::strcmp(preset, "Sunlit") == 0 ||
      std::strcmp(preset, "RiverComparison") == 0 || std::strcmp(preset, "Rivers") == 0);
}

void vtkTerroirColorPresets::GetNanColor(double rgba[4])
{
  rgba[0] = rgba[1] = rgba[2] = 0.5;
  rgba[3] = 1.0;
}

namespace
{
/// The categorical presets (Sunlit, RiverComparison, Rivers, Clusters): an indexed table with
/// one annotated colour per class; false for any other preset (lut untouched).
bool ConfigureCategorical(vtkLookupTable* lut,
  const std::string& name,
  double minValue,
  double maxValue)
{
  if (name == "Sunlit")
  {
    // Two fixed classes whatever the range: 0 shadow (black), 1 lit (white).
    lut->SetNumberOfTableValues(2);
    lut->SetTableRange(0.0, 1.0);
    lut->SetTableValue(0, 0.0, 0.0, 0.0, 1.0);
    lut->SetTableValue(1, 1.0, 1.0, 1.0, 1.0);
    lut->SetAnnotation(vtkVariant(0), "shadow");
    lut->SetAnnotation(vtkVariant(1), "lit");
    lut->SetIndexedLookup(1);
    lut->BuildSpecialColors();
    return true;
  }
  if (name == "RiverComparison")
  {
    // Three fixed classes whatever the range; 0 is not a class (the NaN colour here, and left
    // uncoloured by the overlay view through GetMaskArrayName).
    lut->SetNumberOfTableValues(3);
    lut->SetTableRange(1.0, 3.0);
    for (int k = 0; k < 3; ++k)
    {
      const RiverClass& c = RiverClasses[k];
      lut->SetTableValue(k, c.Color[0], c.Color[1], c.Color[2], 1.0);
      lut->SetAnnotation(vtkVariant(c.Value), c.Name);
    }
    lut->SetIndexedLookup(1);
    lut->BuildSpecialColors();
    return true;
  }
  if (name == "Rivers")
  {
    // Two fixed classes; 0 (dry land) is left uncoloured through GetMaskArrayName.
    lut->SetNumberOfTableValues(2);
    lut->SetTableRange(1.0, 2.0);
    for (int k = 0; k < 2; ++k)
    {
      const RiverClass& c = NetworkClasses[k];
      lut->SetTableValue(k, c.Color[0], c.Color[1], c.Color[2], 1.0);
      lut->SetAnnotation(vtkVariant(c.Value), c.Name);
    }
    lut->SetIndexedLookup(1);
    lut->BuildSpecialColors();
    return true;
  }
  if (name == "Clusters")
  {
    const int first = static_cast<int>(std::lround(minValue));
    int last = static_cast<int>(std::lround(maxValue));
    if (last < first)
    {
      last = first;
    }
    const int n = last - first + 1;
    lut->SetNumberOfTableValues(n);
    lut->SetTableRange(first, last);
    for (int i = 0; i < n; ++i)
    {
      const int id = first + i;
      const unsigned char* c = terroir::ClusterColorRGB(id); // ClusterPalette.h
      lut->SetTableValue(i, c[0] / 255.0, c[1] / 255.0, c[2] / 255.0, 1.0);
      lut->SetAnnotation(vtkVariant(id), "Cluster " + std::to_string(id));
    }
    lut->SetIndexedLookup(1);
    lut->BuildSpecialColors();
    return true;
  }

  return false;
}

/// The control points of a continuous preset's ramp over [0, 1] of the range [minValue, maxValue].
void AddRampPoints(vtkColorTransferFunction* ctf,
  const std::string& name,
  double minValue,
  double maxValue)
{
  if (name == "Elevation")
  {
    // Hypsometric "terrain" colours (after GRASS/gdaldem elevation ramps).
    ctf->AddRGBPoint(0.00, 0.00, 0.38, 0.28);
    ctf->AddRGBPoint(0.20, 0.20, 0.62, 0.25);
    ctf->AddRGBPoint(0.45, 0.90, 0.86, 0.45);
    ctf->AddRGBPoint(0.70, 0.60, 0.42, 0.25);
    ctf->AddRGBPoint(0.90, 0.80, 0.78, 0.76);
    ctf->AddRGBPoint(1.00, 1.00, 1.00, 1.00);
  }
  else if (name == "Slope" || name == "Illumination" || name == "Incidence")
  {
    ctf->AddRGBPoint(0.0, 0.0, 0.0, 0.0);
    ctf->AddRGBPoint(1.0, 1.0, 1.0, 1.0);
  }
  else if (name == "Temperature")
  {
    // Moreland's cool-warm diverging map; the white point sits at 0 °C when the range contains
    // 0, otherwise at the middle of the range.
    double mid = 0.5;
    if (minValue < 0.0 && maxValue > 0.0)
    {
      mid = -minValue / (maxValue - minValue);
    }
    ctf->SetColorSpaceToDiverging();
    ctf->AddRGBPoint(0.0, 0.230, 0.299, 0.754);
    ctf->AddRGBPoint(mid, 0.865, 0.865, 0.865);
    ctf->AddRGBPoint(1.0, 0.706, 0.016, 0.150);
  }
  else if (name == "Erosion")
  {
    // Diverging, the white point at 0 m when the range contains it (else the middle): brown
    // where the bed lost material, blue-green where it gained (after ColorBrewer's BrBG ends).
    double mid = 0.5;
    if (minValue < 0.0 && maxValue > 0.0)
    {
      mid = -minValue / (maxValue - minValue);
    }
    ctf->SetColorSpaceToDiverging();
    ctf->AddRGBPoint(0.0, 0.549, 0.318, 0.039);
    ctf->AddRGBPoint(mid, 0.961, 0.961, 0.961);
    ctf->AddRGBPoint(1.0, 0.004, 0.400, 0.369);
  }
  else if (name == "Vegetation")
  {
    // Bare ground to full cover, luminance falling monotonically: pale sand, olive, dark
    // green (after ColorBrewer's YlGn ends, warmed at the bare end to read as soil).
    ctf->AddRGBPoint(0.0, 0.929, 0.871, 0.702);
    ctf->AddRGBPoint(0.5, 0.553, 0.702, 0.298);
    ctf->AddRGBPoint(1.0, 0.051, 0.353, 0.102);
  }
  else if (name == "Insolation")
  {
    // Dark to bright through warm colours, luminance rising monotonically (a "black body"
    // ramp): black, dark red, orange, pale yellow.
    ctf->AddRGBPoint(0.00, 0.00, 0.00, 0.00);
    ctf->AddRGBPoint(0.35, 0.55, 0.08, 0.05);
    ctf->AddRGBPoint(0.70, 0.95, 0.55, 0.10);
    ctf->AddRGBPoint(1.00, 1.00, 1.00, 0.75);
  }
  else if (name == "Humidity")
  {
    ctf->AddRGBPoint(0.0, 0.0, 0.0, 0.0);
    ctf->AddRGBPoint(1.0, 0.0, 0.35, 1.0);
  }
  else if (name == "Water" || name == "WaterBodies")
  {
    ctf->AddRGBPoint(0.0, 0.70, 0.85, 1.00);
    ctf->AddRGBPoint(1.0, 0.00, 0.12, 0.50);
  }
}
} // namespace

//------------------------------------------------------------------------------
bool vtkTerroirColorPresets::ConfigureLookupTable(vtkLookupTable* lut,
  const char* preset,
  double minValue,
  double maxValue)
{
  const PresetInfo* p = Find(preset);
  if (!lut || !p || !std::isfinite(minValue) || !std::isfinite(maxValue) || maxValue < minValue)
  {
    return false;
  }
  if (minValue == maxValue)
  {
    minValue -= 0.5;
    maxValue += 0.5;
  }
  double nan[4];
  vtkTerroirColorPresets::GetNanColor(nan);

  lut->SetIndexedLookup(0);
  lut->ResetAnnotations();
  lut->SetScaleToLinear();
  lut->SetRampToLinear();
  lut->SetUseBelowRangeColor(0);
  lut->SetUseAboveRangeColor(0);
  lut->SetNanColor(nan);

  const std::string name = p->Name;
  if (ConfigureCategorical(lut, name, minValue, maxValue))
  {
    return true;
  }
  vtkNew<vtkColorTransferFunction> ctf;
  ctf->SetColorSpaceToRGB();
  AddRampPoints(ctf, name, minValue, maxValue);
  SampleInto(lut, ctf);
  if (name == "Water")
  {
    // Dry: the first bin (depth below range/256 above the minimum) is fully transparent.
    double rgba[4];
    lut->GetTableValue(0, rgba);
    rgba[3] = 0.0;
    lut->SetTableValue(0, rgba);
  }
  lut->SetTableRange(minValue, maxValue);
  lut->BuildSpecialColors();
  return true;
}

vtkLookupTable* vtkTerroirColorPresets::CreateLookupTable(const char* preset,
  double minValue,
  double maxValue)
{
  vtkLookupTable* lut = vtkLookupTable::New();
  if (!vtkTerroirColorPresets::ConfigureLookupTable(lut, preset, minValue, maxValue))
  {
    lut->Delete();
    return nullptr;
  }
  return lut;
}

vtkLookupTable* vtkTerroirColorPresets::CreateLookupTable(const char* preset)
{
  double range[2];
  if (!vtkTerroirColorPresets::GetDefaultRange(preset, range))
  {
    return nullptr;
  }
  return vtkTerroirColorPresets::CreateLookupTable(preset, range[0], range[1]);
}

//------------------------------------------------------------------------------
void vtkTerroirColorPresets::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  for (const PresetInfo& p : Presets)
  {
    os << indent << p.Name << ": array " << p.ArrayName << ", units '" << p.Units << "'\n";
  }
}
