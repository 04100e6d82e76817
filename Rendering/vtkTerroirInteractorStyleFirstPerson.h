/**
 * @class   vtkTerroirInteractorStyleFirstPerson
 * @brief   First-person navigation over a terrain: W/A/S/D walk, R/F climb and descend, the
 *          mouse looks around; clicks still reach the viewer's tools.
 *
 * Input: key and mouse events of a vtkRenderWindowInteractor. Output: moves the active camera.
 * - W / S: forward / back along the horizontal direction of view; A / D: left / right;
 *   R / F: up / down; each key press moves MoveStep world units (default 10, metres on a
 *   terrain) times MoveSensitivity (default 1).
 * - Left drag: mouse look. Horizontal motion turns the view about the vertical axis through
 *   the camera (yaw), vertical motion tilts it (pitch, kept within ±85°);
 *   RotationDegreesPerPixel (inherited, default 0.4) × MouseSensitivity degrees per pixel.
 *   The camera stays where it is; its focal point moves.
 * - Wheel: moves forward / back by MoveStep × MoveSensitivity per notch.
 * - A click (press and release without motion) invokes ClickEvent, as in
 *   vtkTerroirInteractorStyleTerrain, the class it extends for those shared parts.
 * Keys with Ctrl held are left to the application.
 *
 * @par Correctness
 * Testing/Python/TestViewer.py (W moves the camera forward, a drag turns the view).
 *
 * @sa vtkTerroirInteractorStyleTerrain
 */
#ifndef vtkTerroirInteractorStyleFirstPerson_h
#define vtkTerroirInteractorStyleFirstPerson_h

#include "vtkTerroirInteractorStyleTerrain.h"
#include "vtkTerroirRenderingModule.h" // For export macro

class VTKTERROIRRENDERING_EXPORT vtkTerroirInteractorStyleFirstPerson
  : public vtkTerroirInteractorStyleTerrain
{
public:
  static vtkTerroirInteractorStyleFirstPerson* New();
  vtkTypeMacro(vtkTerroirInteractorStyleFirstPerson, vtkTerroirInteractorStyleTerrain);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /// World units moved per key press at MoveSensitivity 1. Default 10.
  vtkSetClampMacro(MoveStep, double, 1e-6, 1e12);
  vtkGetMacro(MoveStep, double);
  ///@}

  ///@{
  /// Multiplies every step of W/A/S/D/R/F and the wheel. Default 1, range [0.01, 100].
  vtkSetClampMacro(MoveSensitivity, double, 0.01, 100.0);
  vtkGetMacro(MoveSensitivity, double);
  ///@}

  void OnLeftButtonDown() override;
  void OnMouseWheelForward() override;
  void OnMouseWheelBackward() override;
  void OnKeyPress() override;
  void Rotate() override;

  /// Moves the camera (and its focal point) by `forward`, `right` and `up` steps: forward
  /// along the horizontal direction of view, right perpendicular to it, up along +z.
  void Move(double forward, double right, double up);

protected:
  vtkTerroirInteractorStyleFirstPerson();
  ~vtkTerroirInteractorStyleFirstPerson() override;

  double MoveStep = 10.0;
  double MoveSensitivity = 1.0;

private:
  vtkTerroirInteractorStyleFirstPerson(const vtkTerroirInteractorStyleFirstPerson&) = delete;
  void operator=(const vtkTerroirInteractorStyleFirstPerson&) = delete;
};

#endif
