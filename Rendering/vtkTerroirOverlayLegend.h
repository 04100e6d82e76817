/**
 * @class   vtkTerroirOverlayLegend
 * @brief   Draws the legend of an overlay into a renderer: a scalar bar for continuous presets,
 *          one swatch and name per class for categorical ones.
 *
 * Input: a lookup table configured by vtkTerroirColorPresets and the preset's name. Output:
 * 2-D actors added to a (legend) renderer, in normalized viewport coordinates of that
 * renderer:
 * - continuous presets: a vertical vtkScalarBarActor (5 labels; whole numbers when the range
 *   reaches 1000) titled "Title" / "(units)" on two lines;
 * - categorical presets (Clusters, Sunlit, RiverComparison): a bold title and one colour
 *   swatch and annotation per annotated value, top to bottom; a swatch whose colour is close
 *   to the background is outlined in the text colour.
 * `ApplyClusterShares` turns the "Cluster i" annotations into "i: p%" from the field data
 * `KMeansClusterShare` of vtkTerroirKMeans and returns the title "Cluster (share)".
 *
 * All methods are static. Used by vtkTerroirOverlayView and the `terroir view` window.
 *
 * @sa vtkTerroirColorPresets vtkTerroirOverlayView
 */
#ifndef vtkTerroirOverlayLegend_h
#define vtkTerroirOverlayLegend_h

#include "vtkObject.h"
#include "vtkTerroirRenderingModule.h" // For export macro

#include <string> // For std::string

class vtkImageData;
class vtkLookupTable;
class vtkRenderer;

class VTKTERROIRRENDERING_EXPORT vtkTerroirOverlayLegend : public vtkObject
{
public:
  static vtkTerroirOverlayLegend* New();
  vtkTypeMacro(vtkTerroirOverlayLegend, vtkObject);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  /// Adds the legend of `preset` (scalar bar or swatches) to `renderer`. `title` replaces the
  /// categorical title (empty: the preset's title). Text is `grey` (0 black .. 1 white) in
  /// `fontSize` points; `background` (RGB) decides which swatches get an outline.
  static void AddLegend(vtkRenderer* renderer,
    vtkLookupTable* lut,
    const char* preset,
    const std::string& title,
    int fontSize,
    double grey,
    const double background[3]);

  /// A vertical scalar bar titled with the preset's title and units.
  static void AddScalarBar(vtkRenderer* renderer,
    vtkLookupTable* lut,
    const char* preset,
    int fontSize,
    double grey);

  /// A title and one swatch and annotation per annotated value of `lut`.
  static void AddCategoricalLegend(vtkRenderer* renderer,
    vtkLookupTable* lut,
    const std::string& title,
    int fontSize,
    double grey,
    const double background[3]);

  /// For the Clusters preset and a terrain with `KMeansClusterShare`: annotations "i: p%" and
  /// the title "Cluster (share)". Otherwise the preset's title, annotations unchanged.
  static std::string ApplyClusterShares(vtkLookupTable* lut,
    const char* preset,
    vtkImageData* image);

protected:
  vtkTerroirOverlayLegend() = default;
  ~vtkTerroirOverlayLegend() override = default;

private:
  vtkTerroirOverlayLegend(const vtkTerroirOverlayLegend&) = delete;
  void operator=(const vtkTerroirOverlayLegend&) = delete;
};

#endif
