/**
 * @class   vtkTerroirReliefSurface
 * @brief   Builds the shaded terrain surface shared by the overlay view and the viewer: the
 *          warped grid, its normals, the overlay colours and the Blinn-Phong actors.
 *
 * Input: a Terroir terrain (2-D vtkImageData, point array `Elevation` in metres, optional
 * `vtkValidPointMask`). `BuildGeometry()` turns the grid into a surface with z = Elevation ×
 * VerticalExaggeration (default 1) and point normals from central differences of z (one-sided
 * next to edges and no-data points); cells with a no-data corner go to a flat, unlit "hole"
 * actor in `NanColor` at the lowest valid elevation. `SetColors()` colours the surface by one
 * component of a point array through a lookup table, blending values whose alpha is below 1
 * (and cells left out by a mask array) over `BaseColor`; `SetUniformColor()` paints it
 * `BaseColor` (no overlay). Colours can change without rebuilding the geometry.
 *
 * Shading: one directional scene light (`ConfigureLight`) and the Blinn–Phong model with
 * Phong interpolation, appended as a fragment-shader replacement after VTK 9.1's own light
 * code (which uses Phong's reflection vector):
 *
 *   colour = Ambient·C + Diffuse·max(0, N·L)·C + Specular·max(0, N·H)^SpecularPower
 *
 * with H = normalize(L + V); V is (0, 0, 1) in a parallel view (`ParallelView`). Defaults:
 * Ambient 0.25, Diffuse 0.75, Specular 0.15, SpecularPower 20, BaseColor 0.85 grey, NanColor
 * opaque grey 0.5.
 *
 * Cameras: `FitMapCamera` (top-down parallel projection, grid north up, the terrain fitted)
 * and `FitReliefCamera` (perspective, view angle 30°, from azimuth 157.5° and 35° above the
 * horizon, at the smallest distance where the 8 corners of the bounds fit the frame, +3 %).
 *
 * @par Correctness
 * Testing/Rendering/TestOverlayView.cxx (analytic Blinn–Phong intensities, no-data colours)
 * and the baselines of TestOverlayImages.cxx, through vtkTerroirOverlayView.
 *
 * @sa vtkTerroirOverlayView vtkTerroirOverlayLegend
 */
#ifndef vtkTerroirReliefSurface_h
#define vtkTerroirReliefSurface_h

#include "vtkObject.h"
#include "vtkTerroirRenderingModule.h" // For export macro

#include <memory> // For std::unique_ptr
#include <string> // For std::string

class vtkActor;
class vtkCamera;
class vtkDataArray;
class vtkImageData;
class vtkLight;
class vtkLookupTable;

class VTKTERROIRRENDERING_EXPORT vtkTerroirReliefSurface : public vtkObject
{
public:
  static vtkTerroirReliefSurface* New();
  vtkTypeMacro(vtkTerroirReliefSurface, vtkObject);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /// The terrain (kept by reference).
  void SetInputData(vtkImageData* terrain);
  vtkImageData* GetInputData();
  ///@}

  ///@{
  /// Vertical exaggeration of the surface, default 1 (applies at the next BuildGeometry).
  vtkSetClampMacro(VerticalExaggeration, double, 0.0, 1000.0);
  vtkGetMacro(VerticalExaggeration, double);
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
  /// Draw every Stride-th grid point along each axis (and the last row and column), default 1
  /// (every point). A grid with more points than its picture has pixels gains nothing from the
  /// others: the overlay view sets it from its frame size. Colours and data ranges still come
  /// from the whole grid's values at the drawn points. Applies at the next BuildGeometry.
  vtkSetClampMacro(Stride, int, 1, 1 << 20);
  vtkGetMacro(Stride, int);
  ///@}

  ///@{
  /// Parallel (map) view: the viewer direction of the specular term is (0, 0, 1). Default off.
  vtkSetMacro(ParallelView, bool);
  vtkGetMacro(ParallelView, bool);
  ///@}

  ///@{
  /// Colour of no-data cells (RGBA), default (0.5, 0.5, 0.5, 1); alpha 0 hides them.
  vtkSetVector4Macro(NanColor, double);
  vtkGetVector4Macro(NanColor, double);
  /// Colour of the bare terrain (RGB), default 0.85 grey.
  vtkSetVector3Macro(BaseColor, double);
  vtkGetVector3Macro(BaseColor, double);
  ///@}

  /// Builds the surface and hole geometry and the actors. Returns false with `error` set (a
  /// sentence without the class name) when the input is not a 2-D terrain of at least 2 × 2
  /// points with a one-component `Elevation` and at least one valid elevation.
  bool BuildGeometry(std::string& error);

  /// Applies the shading coefficients, ParallelView and NanColor to the built actors (done by
  /// BuildGeometry; call it after changing them when the geometry itself is kept).
  void ApplyAppearance();

  /// Colours the surface by component `component` of `values` (one tuple per point) through
  /// `lut`. Points where `mask` (optional, one component) is 0 get BaseColor, as do values
  /// with alpha 0; partial alpha is blended over BaseColor. With `overCurrent`, colours are
  /// blended over the current colours instead (a layer: the viewer's water over an overlay).
  /// Call after BuildGeometry.
  void SetColors(vtkDataArray* values,
    int component,
    vtkLookupTable* lut,
    vtkDataArray* mask,
    bool overCurrent = false);

  /// Paints the whole surface BaseColor (no overlay).
  void SetUniformColor();

  /// The range of the finite values of `values` (component) at valid points where `mask` (if
  /// any) is not 0. Returns false (range left unchanged) when there is none.
  bool ComputeDataRange(vtkDataArray* values, int component, vtkDataArray* mask, double range[2]);

  /// True when point k has a finite, unmasked elevation (after BuildGeometry).
  bool IsValidPoint(vtkIdType k);

  ///@{
  /// The shaded surface and the no-data holes (after BuildGeometry).
  vtkActor* GetSurfaceActor();
  vtkActor* GetHoleActor();
  ///@}

  /// Bounds of the built surface (x, y of the grid, z of the valid exaggerated elevations).
  void GetBounds(double bounds[6]);

  /// A white directional scene light from `azimuth` (degrees clockwise from grid north) and
  /// `elevation` (degrees above the horizon), aimed at the centre of `bounds`.
  static void ConfigureLight(vtkLight* light,
    double azimuth,
    double elevation,
    const double bounds[6]);

  /// Top-down parallel camera, grid north up, `bounds` fitted in a frame of aspect w/h.
  static void FitMapCamera(vtkCamera* camera, const double bounds[6], double aspect);

  /// Perspective camera from azimuth `azimuth` and `elevation` degrees, view angle
  /// `viewAngle`, at the smallest distance at which the corners of `bounds` fit the frame.
  static void FitReliefCamera(vtkCamera* camera,
    const double bounds[6],
    double aspect,
    double azimuth = 157.5,
    double elevation = 35.0,
    double viewAngle = 30.0);

protected:
  vtkTerroirReliefSurface();
  ~vtkTerroirReliefSurface() override;

  double VerticalExaggeration = 1.0;
  double Ambient = 0.25;
  double Diffuse = 0.75;
  double Specular = 0.15;
  double SpecularPower = 20.0;
  bool ParallelView = false;
  int Stride = 1;
  double NanColor[4] = { 0.5, 0.5, 0.5, 1.0 };
  double BaseColor[3] = { 0.85, 0.85, 0.85 };

private:
  vtkTerroirReliefSurface(const vtkTerroirReliefSurface&) = delete;
  void operator=(const vtkTerroirReliefSurface&) = delete;

  struct Internals;
  std::unique_ptr<Internals> Internal;
};

#endif
