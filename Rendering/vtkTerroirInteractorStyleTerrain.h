/**
 * @class   vtkTerroirInteractorStyleTerrain
 * @brief   Map-like navigation over a terrain: drag pans, the wheel zooms, Ctrl+drag rotates;
 *          a click without motion is reported as a ClickEvent for the viewer's tools.
 *
 * Input: mouse events of a vtkRenderWindowInteractor (through the usual vtkInteractorStyle
 * machinery). Output: moves the active camera of the renderer under the pointer.
 * - Left drag: pans; the terrain follows the pointer (the camera and its focal point move
 *   opposite to the drag, in the view plane), scaled by MouseSensitivity.
 * - Ctrl + left drag (or right drag): rotates around the focal point: horizontal motion turns
 *   the camera about the vertical (+z) axis (azimuth), vertical motion tilts it (elevation,
 *   kept between 1° and 89° above the horizon); RotationDegreesPerPixel (default 0.4) ×
 *   MouseSensitivity degrees per pixel.
 * - Wheel: zooms toward the focal point by a factor ZoomFactor^MouseSensitivity per notch
 *   (default 1.1; a parallel camera changes its parallel scale instead).
 * - A left press and release less than ClickTolerance pixels apart (default 3) with no
 *   rotation invokes ClickEvent with the display position (int[2]) as call data, and moves
 *   nothing.
 * Keys are left to the application (OnChar does nothing, so VTK's default 'w'ireframe,
 * 'q'uit, ... keys are off).
 *
 * @par Correctness
 * Testing/Python/TestViewer.py (scripted drags, Ctrl+drags and wheel turns move the camera in
 * the expected direction).
 *
 * @sa vtkTerroirInteractorStyleFirstPerson
 */
#ifndef vtkTerroirInteractorStyleTerrain_h
#define vtkTerroirInteractorStyleTerrain_h

#include "vtkCommand.h" // For vtkCommand::UserEvent
#include "vtkInteractorStyle.h"
#include "vtkTerroirRenderingModule.h" // For export macro

class vtkCamera;

class VTKTERROIRRENDERING_EXPORT vtkTerroirInteractorStyleTerrain : public vtkInteractorStyle
{
public:
  static vtkTerroirInteractorStyleTerrain* New();
  vtkTypeMacro(vtkTerroirInteractorStyleTerrain, vtkInteractorStyle);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  /// Invoked on a click (press and release without motion); call data: int[2] display x, y.
  enum
  {
    ClickEvent = vtkCommand::UserEvent + 701
  };

  ///@{
  /// Multiplies every mouse motion (pan, rotation, zoom). Default 1, range [0.01, 100].
  vtkSetClampMacro(MouseSensitivity, double, 0.01, 100.0);
  vtkGetMacro(MouseSensitivity, double);
  ///@}

  ///@{
  /// Degrees of rotation per pixel of Ctrl+drag at sensitivity 1. Default 0.4.
  vtkSetClampMacro(RotationDegreesPerPixel, double, 0.001, 10.0);
  vtkGetMacro(RotationDegreesPerPixel, double);
  ///@}

  ///@{
  /// Zoom factor of one wheel notch at sensitivity 1. Default 1.1.
  vtkSetClampMacro(ZoomFactor, double, 1.001, 10.0);
  vtkGetMacro(ZoomFactor, double);
  ///@}

  ///@{
  /// Largest press-to-release distance, pixels, that still counts as a click. Default 3.
  vtkSetClampMacro(ClickTolerance, int, 0, 100);
  vtkGetMacro(ClickTolerance, int);
  ///@}

  void OnMouseMove() override;
  void OnLeftButtonDown() override;
  void OnLeftButtonUp() override;
  void OnRightButtonDown() override;
  void OnRightButtonUp() override;
  void OnMouseWheelForward() override;
  void OnMouseWheelBackward() override;
  void OnChar() override {}

  void Pan() override;
  void Rotate() override;
  /// Zooms by `factor` (> 1 closer).
  virtual void ZoomBy(double factor);

protected:
  vtkTerroirInteractorStyleTerrain();
  ~vtkTerroirInteractorStyleTerrain() override;

  /// Starts a left-button gesture (pan, or rotate with Ctrl); shared with subclasses.
  void BeginLeftGesture(bool rotate);
  /// Ends it; invokes ClickEvent when the pointer did not move.
  void EndLeftGesture();
  /// True while the pointer stayed within ClickTolerance of the press.
  bool IsStillAClick();
  /// Turns `v` by dAzimuth degrees (clockwise about +z seen from above, azimuth measured from
  /// +y) and dElevation degrees (up from the horizontal), the elevation kept within
  /// [lowest, highest] degrees, its length kept; false (v unchanged) for a zero vector. Shared
  /// by the orbit (position about the focal point) and the first-person look (focal point
  /// about the position).
  static bool TurnVector(double v[3],
    double dAzimuth,
    double dElevation,
    double lowest,
    double highest);
  /// The last mouse move in degrees (RotationDegreesPerPixel x MouseSensitivity per pixel,
  /// x to the right, y up) and the renderer's camera; false without a renderer.
  bool DragDegrees(double& dx, double& dy, vtkCamera*& camera);
  /// After a rotation: view up +z (orthogonalised), clipping range reset, render.
  void FinishRotation(vtkCamera* camera);

  double MouseSensitivity = 1.0;
  double RotationDegreesPerPixel = 0.4;
  double ZoomFactor = 1.1;
  int ClickTolerance = 3;
  int PressPosition[2] = { 0, 0 };
  bool LeftDown = false;
  bool Moved = false;

private:
  vtkTerroirInteractorStyleTerrain(const vtkTerroirInteractorStyleTerrain&) = delete;
  void operator=(const vtkTerroirInteractorStyleTerrain&) = delete;
};

#endif
