/**
 * @class   vtkTerroirOverlayView
 * @brief   Renders a terrain coloured by one resource array over Blinn-Phong relief shading.
 *
 * Input: a Terroir terrain (see vtkTerroirGeoreference): a 2-D vtkImageData (nx, ny, 1),
 * spacing in metres, point data `Elevation` (metres) and optionally `vtkValidPointMask`
 * (unsigned char, 0 = no data). The overlay colours one component of one point-data array
 * (`ArrayName`, `ArrayComponent`, e.g. `Temperature` component 6 = July) with a preset of
 * vtkTerroirColorPresets (`Preset`; by default the preset whose default array is `ArrayName`,
 * else `Elevation`).
 *
 * Output: an RGB image of Width × Height pixels (default 800 × 600), from `Render()`,
 * `GetImage()` or `WritePNG()`.
 *
 * Surface and shading: the image grid is warped to z = Elevation × VerticalExaggeration
 * (default 1); point normals come from central differences of z on the grid (one-sided next
 * to edges and no-data points). One directional light shines from `LightAzimuth` (degrees
 * clockwise from grid north, default 315) and `LightElevation` (degrees above the horizon,
 * default 45), as in a hillshade. Each fragment gets the Blinn–Phong model (Blinn 1977) with
 * Phong (per-fragment) interpolation:
 *
 *   colour = Ambient·C + Diffuse·max(0, N·L)·C + Specular·max(0, N·H)^SpecularPower
 *
 * with C the overlay colour, L the direction to the light, V the direction to the viewer and
 * H = normalize(L + V). VTK 9.1's own shader uses Phong's reflection vector, so the view
 * replaces its lighting with the half-vector formula above (a fragment shader replacement).
 * Defaults: Ambient 0.25, Diffuse 0.75, Specular 0.15, SpecularPower 20.
 * Overlay colours with alpha < 1 (the dry cells of the `Water` preset) are blended over
 * `BaseColor` (light grey, the bare terrain) before shading.
 *
 * No-data: a grid cell with any corner that is masked or has a non-finite elevation is drawn
 * flat, unlit, in `NanColor` (default opaque grey 0.5, 0.5, 0.5; alpha 0 shows the background),
 * at the lowest valid elevation. Finite elevations with a NaN overlay value get the lookup
 * table's NaN colour (the same grey), shaded.
 *
 * Views (`Mode`):
 * - `Map` (default): top-down parallel projection, grid north up, the whole terrain fitted to
 *   the frame (it fills the frame along its limiting side, centred).
 * - `Relief`: 3-D oblique perspective. Fixed camera: view angle 30°, looking at the centre of
 *   the terrain's bounds from azimuth 157.5° (south-south-east) and 35° above the horizon, at
 *   the distance where the bounding sphere just fits the frame; view up = +z.
 *
 * Legend (`ShowLegend`, default on): the right quarter of the frame holds a scalar bar titled
 * "<preset title>" / "(<units>)" (e.g. "Slope" / "(°)"), or for a categorical preset
 * (`Clusters`, `Sunlit`) one colour swatch and name per class ("Cluster i"; "shadow", "lit";
 * for clusters of vtkTerroirKMeans, whose field data `KMeansClusterShare` holds each cluster's
 * share of the cells, "i: p%" under the title "Cluster (share)"),
 * outlined in the text colour when it is close to the background colour. `Title` (default none) is
 * drawn centred in a strip at the top (8% of the height, at least 24 pixels). Text is black on
 * light backgrounds and white on dark ones. `Background` default white.
 *
 * Rendering is offscreen (`OffScreenRenderingOn()`, `SetMultiSamples(0)`) through VTK's X/GLX
 * window. VTK 9.1 aborts the process when that window cannot open its X display, so the view
 * opens the connection itself (retrying for about 2 s, as Xvfb refuses connections while it
 * resets) and gives it to the window (`SetDisplayId`); without one it fails with "no X display
 * (DISPLAY unset); run under xvfb-run -a" or "cannot connect to the X display ...". Results are
 * deterministic for one Mesa (llvmpipe) version.
 *
 * Errors (bad input, missing arrays, unknown preset, no display, unwritable file) set
 * `GetLastError()`, are reported once with vtkErrorMacro, and make the method return false.
 *
 * @par Correctness
 * Testing/Rendering/TestOverlayView.cxx (analytic Blinn–Phong intensities of a ridge, NaN
 * hole colour, map framing, PNG export failure modes) and TestOverlayImages.cxx (baseline
 * images of the bundled DEM, Testing/Rendering/TerroirImageCompare.h).
 *
 * @par References
 * J. F. Blinn, "Models of light reflection for computer synthesized pictures", SIGGRAPH 1977,
 * doi:10.1145/563858.563893.
 *
 * @sa vtkTerroirColorPresets
 */
#ifndef vtkTerroirOverlayView_h
#define vtkTerroirOverlayView_h

#include "vtkObject.h"
#include "vtkTerroirRenderingModule.h" // For export macro

#include "vtkSmartPointer.h" // For the plants actor

#include <limits> // For quiet_NaN
#include <memory> // For std::unique_ptr
#include <string> // For std::string

class vtkDataArray;
class vtkActor;
class vtkImageData;
class vtkPolyData;
class vtkLookupTable;
class vtkRenderWindow;
class vtkTerroirReliefSurface;

class VTKTERROIRRENDERING_EXPORT vtkTerroirOverlayView : public vtkObject
{
public:
  static vtkTerroirOverlayView* New();
  vtkTypeMacro(vtkTerroirOverlayView, vtkObject);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  enum ViewMode
  {
    Map = 0,
    Relief = 1
  };

  ///@{
  /// The terrain to render (not copied; kept by reference).
  void SetInputData(vtkImageData* terrain);
  vtkImageData* GetInputData();
  ///@}

  ///@{
  /// Point-data array and component to colour by. Default `Elevation`, component 0.
  vtkSetStringMacro(ArrayName);
  vtkGetStringMacro(ArrayName);
  vtkSetClampMacro(ArrayComponent, int, 0, VTK_INT_MAX);
  vtkGetMacro(ArrayComponent, int);
  ///@}

  ///@{
  /// Colour preset name (see vtkTerroirColorPresets). Default nullptr: the preset of
  /// `ArrayName`, or `Elevation` when the array has none.
  vtkSetStringMacro(Preset);
  vtkGetStringMacro(Preset);
  /// The preset that will be used (resolves the default).
  const char* GetEffectivePreset();
  ///@}

  ///@{
  /// Colour range. `UseCustomRange` on: `Range` is used. Off (default): the preset's default
  /// range (Slope 0–60°), or for a preset without one the range of the finite values of the
  /// array component at valid points.
  vtkSetVector2Macro(Range, double);
  vtkGetVector2Macro(Range, double);
  vtkSetMacro(UseCustomRange, bool);
  vtkGetMacro(UseCustomRange, bool);
  vtkBooleanMacro(UseCustomRange, bool);
  /// The range used by the last successful Render().
  vtkGetVector2Macro(LastRange, double);
  ///@}

  ///@{
  /// View mode, default Map.
  vtkSetClampMacro(Mode, int, Map, Relief);
  vtkGetMacro(Mode, int);
  void SetModeToMap() { this->SetMode(Map); }
  void SetModeToRelief() { this->SetMode(Relief); }
  ///@}

  ///@{
  /// Image size in pixels, default 800 × 600.
  vtkSetClampMacro(Width, int, 16, 16384);
  vtkGetMacro(Width, int);
  vtkSetClampMacro(Height, int, 16, 16384);
  vtkGetMacro(Height, int);
  ///@}

  ///@{
  /// Vertical exaggeration of the surface (and so of the shading), default 1.
  vtkSetClampMacro(VerticalExaggeration, double, 0.0, 1000.0);
  vtkGetMacro(VerticalExaggeration, double);
  ///@}

  ///@{
  /// Direction the light comes from: azimuth in degrees clockwise from grid north (default
  /// 315, north-west) and elevation in degrees above the horizon (default 45).
  vtkSetMacro(LightAzimuth, double);
  vtkGetMacro(LightAzimuth, double);
  vtkSetClampMacro(LightElevation, double, 0.0, 90.0);
  vtkGetMacro(LightElevation, double);
  ///@}

  ///@{
  /// Blinn–Phong coefficients, defaults 0.25, 0.75, 0.15, 20.
  vtkSetClampMacro(Ambient, double, 0.0, 1.0);
  vtkGetMacro(Ambient, double);
  vtkSetClampMacro(Diffuse, double, 0.0, 1.0);
  vtkGetMacro(Diffuse, double);
  vtkSetClampMacro(Specular, double, 0.0, 1.0);
  vtkGetMacro(Specular, double);
  vtkSetClampMacro(SpecularPower, double, 1.0, 1000.0);
  vtkGetMacro(SpecularPower, double);
  ///@}

  ///@{
  /// Legend (scalar bar or categorical swatches) on the right, default on.
  vtkSetMacro(ShowLegend, bool);
  vtkGetMacro(ShowLegend, bool);
  vtkBooleanMacro(ShowLegend, bool);
  ///@}

  ///@{
  /// Title drawn at the top centre; default none.
  vtkSetStringMacro(Title);
  vtkGetStringMacro(Title);
  ///@}

  ///@{
  /// Background colour (RGB 0..1), default white.
  vtkSetVector3Macro(Background, double);
  vtkGetVector3Macro(Background, double);
  ///@}

  ///@{
  /// Colour of no-data cells (RGBA 0..1), default opaque grey (0.5, 0.5, 0.5, 1).
  vtkSetVector4Macro(NanColor, double);
  vtkGetVector4Macro(NanColor, double);
  ///@}

  ///@{
  /// Colour of the bare terrain under transparent overlay values (RGB), default 0.85 grey.
  vtkSetVector3Macro(BaseColor, double);
  vtkGetVector3Macro(BaseColor, double);
  ///@}

  ///@{
  /// Plants drawn over the terrain (optional; not copied): the points of a vtkPolyData such as
  /// vtkTerroirPlantPlacement's (x, y metres, z = ground elevation), each as a cone glyph
  /// `PlantSize` metres high (default 8) and half as wide, standing on the surface (z times
  /// VerticalExaggeration), coloured by its point array `Species` with the Clusters palette
  /// from its green (species i gets colour (i + 2) mod 12; all green without the array).
  /// Null: none.
  void SetPlantsData(vtkPolyData* plants);
  vtkPolyData* GetPlantsData();
  vtkSetClampMacro(PlantSize, double, 0.0, VTK_DOUBLE_MAX);
  vtkGetMacro(PlantSize, double);
  ///@}

  ///@{
  /// Terrain texturing (Documentation/Texturing.md), default off. On: the surface gets a
  /// texture built by terroir::rendering::BuildTerrainTexture (Rendering/Core/
  /// TriangleTexturing.h): Jensen's (2011) eight edge-matched right-triangle tiles per
  /// material, placed non-periodically, blended per point by slope (from `Elevation`, central
  /// differences), height and biome (the point array `ClusterId` when present: zone mod 3 gives
  /// grass, forest floor or dry soil; grass without it). The texture *replaces* the overlay's
  /// array colouring (the surface's colour becomes white times the texture), is lit as before
  /// (Blinn-Phong; VTK multiplies the lit colour by the texture, so the highlight takes the
  /// material's tint) and no legend is drawn (the terrain takes the whole width). No-data cells
  /// stay NanColor. Off: rendering is exactly as without this option.
  vtkSetMacro(Texturing, bool);
  vtkGetMacro(Texturing, bool);
  vtkBooleanMacro(Texturing, bool);
  /// Seed of the tile placement and tile synthesis, default 1.
  vtkSetMacro(TextureSeed, int);
  vtkGetMacro(TextureSeed, int);
  /// Texels per tile side (a tile covers one cell unless the texture would exceed
  /// MaxTextureSize; then k x k cells), default 16, range 2..256.
  vtkSetClampMacro(TexelsPerCell, int, 2, 256);
  vtkGetMacro(TexelsPerCell, int);
  /// Largest texture side in texels, default 4096 (48 MiB of RGB), range 64..16384.
  vtkSetClampMacro(MaxTextureSize, int, 64, 16384);
  vtkGetMacro(MaxTextureSize, int);
  /// Sea level (metres) of the sand rule: sand up to it, none 5 m above. Default 0.
  vtkSetMacro(TextureSeaLevel, double);
  vtkGetMacro(TextureSeaLevel, double);
  /// Snow line (metres): half snow there, none/full 1/20 of the elevation range below/above.
  /// Default NaN: 85 % of the way from the lowest to the highest valid elevation.
  vtkSetMacro(TextureSnowLine, double);
  vtkGetMacro(TextureSnowLine, double);
  /// Size of the last texture built (0 x 0 before any) and the cells each tile covers.
  vtkGetVector2Macro(LastTextureSize, int);
  vtkGetMacro(LastCellsPerTile, int);
  ///@}

  /// Renders offscreen. Returns false and sets the error on bad input or without a display.
  bool Render();

  /// Renders and copies the frame into `out` (Width × Height × 1, 3 unsigned-char
  /// components, row 0 at the bottom). Returns false on error (out is left unchanged).
  bool GetImage(vtkImageData* out);

  /// Renders and writes a PNG. The image is written to a temporary file in the same folder
  /// and renamed to `fileName` on success, so a failure never leaves a partial file.
  bool WritePNG(const char* fileName);

  /// The last error message (empty after a success).
  const char* GetLastError() { return this->LastError.c_str(); }

  ///@{
  /// Fixed relief camera (degrees): azimuth 157.5 (SSE), elevation 35, view angle 30.
  static double GetReliefCameraAzimuth() { return 157.5; }
  static double GetReliefCameraElevation() { return 35.0; }
  static double GetReliefViewAngle() { return 30.0; }
  ///@}

protected:
  vtkTerroirOverlayView();
  ~vtkTerroirOverlayView() override;

  bool Fail(const std::string& message);

  char* ArrayName = nullptr;
  int ArrayComponent = 0;
  char* Preset = nullptr;
  double Range[2] = { 0.0, 1.0 };
  bool UseCustomRange = false;
  double LastRange[2] = { 0.0, 0.0 };
  int Mode = Map;
  int Width = 800;
  int Height = 600;
  double VerticalExaggeration = 1.0;
  double LightAzimuth = 315.0;
  double LightElevation = 45.0;
  double Ambient = 0.25;
  double Diffuse = 0.75;
  double Specular = 0.15;
  double SpecularPower = 20.0;
  bool ShowLegend = true;
  char* Title = nullptr;
  double Background[3] = { 1.0, 1.0, 1.0 };
  double NanColor[4] = { 0.5, 0.5, 0.5, 1.0 };
  double BaseColor[3] = { 0.85, 0.85, 0.85 };
  double PlantSize = 8.0;
  bool Texturing = false;
  int TextureSeed = 1;
  int TexelsPerCell = 16;
  int MaxTextureSize = 4096;
  double TextureSeaLevel = 0.0;
  double TextureSnowLine = std::numeric_limits<double>::quiet_NaN();
  int LastTextureSize[2] = { 0, 0 };
  int LastCellsPerTile = 0;
  std::string LastError;

private:
  vtkTerroirOverlayView(const vtkTerroirOverlayView&) = delete;
  void operator=(const vtkTerroirOverlayView&) = delete;

  struct Internals;
  std::unique_ptr<Internals> Internal;

  // Render()'s steps (vtkTerroirOverlayView.cxx).
  /// Checks the input; sets the array to show and the preset; false after Fail().
  bool CheckInput(vtkImageData* image, vtkDataArray*& values, const char*& preset);
  /// Colours `relief` by `values` with the preset's table (into `lut`); sets LastRange and the
  /// legend title of a categorical preset; false after Fail().
  bool ColourSurface(vtkImageData* image,
    vtkDataArray* values,
    const char* preset,
    vtkTerroirReliefSurface* relief,
    vtkLookupTable* lut,
    std::string& categoricalTitle);
  /// The plants' cone glyphs (SetPlantsData), coloured by species.
  vtkSmartPointer<vtkActor> MakePlantsActor();
  /// The terrain's renderer: its viewport, the surface, the light and the fitted camera.
  void AddTerrainRenderer(vtkRenderWindow* window,
    vtkTerroirReliefSurface* relief,
    double legendWidth,
    double titleHeight);
  /// The surface for `image`: the last one when its geometry is still current, else built
  /// anew; nullptr with `why` set on bad input.
  vtkTerroirReliefSurface* PrepareSurface(vtkImageData* image, std::string& why);
  /// The offscreen window, kept while its size stays, emptied of the last frame's renderers;
  /// nullptr with `why` set without an X display.
  vtkRenderWindow* PrepareWindow(std::string& why);
  /// With Texturing: builds (or reuses) the terrain texture and puts it with texture
  /// coordinates on `relief`'s surface, coloured white; false after Fail().
  bool ApplyTexture(vtkImageData* image, vtkTerroirReliefSurface* relief);
  /// Whether the legend is drawn (ShowLegend and not Texturing).
  bool LegendShown() const { return this->ShowLegend && !this->Texturing; }
  /// The title strip at the top.
  void AddTitleRenderer(vtkRenderWindow* window, double titleHeight, double textGrey);
};

#endif
