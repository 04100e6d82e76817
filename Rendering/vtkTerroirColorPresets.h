/**
 * @class   vtkTerroirColorPresets
 * @brief   Builds the named overlay colour presets of Terroir as lookup tables.
 *
 * Each terrain resource has one preset (DESIGN.md, "Rendering and image tests"). A preset
 * fixes the colours, the default array it colours, its units and legend title, and either a
 * fixed default range or "use the data range":
 *
 * - `Elevation`: `Elevation` (m); terrain colours: dark green, green, yellow, brown, white;
 *   data range.
 * - `Slope`: `Slope` (°); black → white; 0 – 60°.
 * - `Illumination`: `IlluminationHours` (h/day); black → white; data range.
 * - `Temperature`: `Temperature` (°C); blue → white → red, white at 0 °C when the range
 *   contains 0, else at its middle; data range.
 * - `Humidity`: `SoilHumidity` (mm); black → blue; data range.
 * - `Water`: `WaterHeight` (m); first of 256 bins transparent (dry), then light → dark blue;
 *   data range.
 * - `Clusters`: `ClusterId`; categorical, 12 fixed distinct colours (cycled), indexed lookup;
 *   ids present.
 * - `Sunlit`: `Illuminated` (0/1); categorical, 0 "shadow" black, 1 "lit" white; 0 – 1.
 * - `Incidence`: `SunIncidence` (cosine, no units); black → white; 0 – 1.
 * - `Insolation`: `Insolation` (Wh/m²/day); black → dark red → orange → pale yellow; data
 *   range.
 * - `WaterBodies`: `WaterDepth` (m) of lakes from vtkTerroirFloodFill; light → dark blue, every
 *   bin opaque (a hydro-flattened lake has depth 0 and must still show); cells whose mask
 *   array `WaterBody` is 0 (dry) are left transparent by the overlay view; data range of the
 *   wet cells.
 * - `RiverComparison`: `RiverComparison` (unsigned char classes of
 *   terroir::hydrology::RiverComparisonCategories, `terroir validate`); categorical, Okabe-Ito
 *   colours safe for colour-blind readers: 1 "map only" (mapped river with no simulated river
 *   within the tolerance) blue (0, 114, 178), 2 "model only" (simulated river with no mapped
 *   river within the tolerance) vermillion (213, 94, 0), 3 "both" black; class 0 (no river,
 *   or outside the scored area) is left transparent by the overlay view (the mask array is
 *   `RiverComparison` itself); 0 – 3.
 * - `Rivers`: `RiverNetwork` (unsigned char, `terroir run`): categorical, 1 "river" Okabe-Ito
 *   blue (0, 114, 178), 2 "lake" sky blue (86, 180, 233); class 0 (dry land) is left
 *   transparent by the overlay view (the mask array is `RiverNetwork` itself); 0 – 2.
 * - `Erosion`: `ErosionDepth` (m); brown → near-white at 0 m → blue-green; data range.
 * - `Vegetation`: `VegetationDensity` (0–1, vtkTerroirErosion with Vegetation); pale sand →
 *   olive → dark green; 0 – 1.
 *
 * Continuous presets are 256-entry vtkLookupTable objects sampled from a
 * vtkColorTransferFunction (RGB interpolation, diverging space for Temperature); values
 * outside the range clamp to the end colours; NaN maps to the NaN colour (grey 0.5, opaque).
 * `Clusters` is an indexed (categorical) table with one annotated value per cluster id
 * `min..max` ("Cluster i"), colours from a fixed palette (Tableau 10 plus two), so cluster 0 is
 * always the same blue. `Sunlit` is an indexed table of two annotated values, 0 "shadow" and
 * 1 "lit", whatever the range asked for, and `RiverComparison` one of three annotated values
 * 1, 2, 3. Everything is deterministic (no random colours).
 *
 * All methods are static. Preset names are case-sensitive.
 *
 * @par Correctness
 * TerroirColorPresets.* in Testing/Rendering/TestColorPresets.cxx (end colours, mid colours,
 * NaN colour, water transparency, categorical order, shadow/lit classes, river comparison
 * classes).
 */
#ifndef vtkTerroirColorPresets_h
#define vtkTerroirColorPresets_h

#include "vtkObject.h"
#include "vtkTerroirRenderingModule.h" // For export macro
#include "vtkWrappingHints.h"          // For VTK_NEWINSTANCE

#include <string> // For std::string

class vtkLookupTable;

class VTKTERROIRRENDERING_EXPORT vtkTerroirColorPresets : public vtkObject
{
public:
  static vtkTerroirColorPresets* New();
  vtkTypeMacro(vtkTerroirColorPresets, vtkObject);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /// The presets, in a fixed order: Elevation, Slope, Illumination, Temperature, Humidity,
  /// Water, Clusters, Sunlit, Incidence, Insolation, WaterBodies, RiverComparison, Rivers.
  static int GetNumberOfPresets();
  static const char* GetPresetName(int index);
  static bool HasPreset(const char* preset);
  ///@}

  ///@{
  /// Metadata of a preset (nullptr for an unknown preset). Units are UTF-8 ("°", "°C",
  /// "Wh/m²/day") and empty for Clusters, Sunlit, Incidence and RiverComparison.
  static const char* GetDefaultArrayName(const char* preset);
  static const char* GetUnits(const char* preset);
  static const char* GetTitle(const char* preset);
  /// Legend title "Title (units)", or "Title" when the preset has no units.
  static std::string GetLegendTitle(const char* preset);
  ///@}

  /// The preset whose default array is `arrayName`, or nullptr (`Illuminated` → Sunlit,
  /// `SunIncidence` → Incidence, `IlluminationHours` → Illumination, `Insolation` →
  /// Insolation). Also maps the sibling arrays `WeightedSoilHumidity` and `StandingWater` (mm)
  /// to Humidity.
  static const char* GetPresetForArray(const char* arrayName);

  /// True when the preset has a fixed default range (Slope: 0–60; Sunlit, Incidence: 0–1;
  /// RiverComparison: 0–3); false when the data range should be used.
  static bool GetDefaultRange(const char* preset, double range[2]);

  /// The point array whose zero cells a preset leaves uncoloured (transparent over the bare
  /// terrain), or nullptr: `WaterBody` for WaterBodies (dry cells), `RiverComparison` for
  /// RiverComparison (class 0: no river), none for the others.
  static const char* GetMaskArrayName(const char* preset);

  /// True for categorical presets (Clusters, Sunlit, RiverComparison, Rivers).
  static bool IsCategorical(const char* preset);

  /// Fills `lut` with the preset over [minValue, maxValue] (for Clusters: ids minValue..maxValue,
  /// rounded; for Sunlit always the classes 0 and 1; for RiverComparison always 1, 2, 3). Returns
  /// false (leaving `lut` unchanged) for an unknown preset, a null table or a range that is not
  /// finite or has maxValue < minValue. An empty range (min == max) is widened by 0.5 on each side.
  static bool ConfigureLookupTable(vtkLookupTable* lut,
    const char* preset,
    double minValue,
    double maxValue);

  /// A new lookup table with the preset over [minValue, maxValue], or nullptr on bad input.
  /// The caller owns the returned reference.
  VTK_NEWINSTANCE
  static vtkLookupTable* CreateLookupTable(const char* preset, double minValue, double maxValue);

  /// Same with the preset's default range; nullptr when it has none (use the data range).
  VTK_NEWINSTANCE
  static vtkLookupTable* CreateLookupTable(const char* preset);

  /// Colour used for NaN values and no-data cells (RGBA 0..1): opaque grey 0.5.
  static void GetNanColor(double rgba[4]);

protected:
  vtkTerroirColorPresets() = default;
  ~vtkTerroirColorPresets() override = default;

private:
  vtkTerroirColorPresets(const vtkTerroirColorPresets&) = delete;
  void operator=(const vtkTerroirColorPresets&) = delete;
};

#endif
