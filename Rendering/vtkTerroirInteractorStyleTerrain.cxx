#include "vtkTerroirInteractorStyleTerrain.h"

#include "vtkCallbackCommand.h"
#include "vtkCamera.h"
#include "vtkMath.h"
#include "vtkObjectFactory.h"
#include "vtkRenderWindowInteractor.h"
#include "vtkRenderer.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>

vtkStandardNewMacro(vtkTerroirInteractorStyleTerrain);

vtkTerroirInteractorStyleTerrain::vtkTerroirInteractorStyleTerrain() = default;
vtkTerroirInteractorStyleTerrain::~vtkTerroirInteractorStyleTerrain() = default;

bool vtkTerroirInteractorStyleTerrain::IsStillAClick()
{
  const int* p = this->Interactor->GetEventPosition();
  return std::abs(p[0] - this->PressPosition[0]) <= this->ClickTolerance &&
    std::abs(p[1] - this->PressPosition[1]) <= this->ClickTolerance;
}

void vtkTerroirInteractorStyleTerrain::BeginLeftGesture(bool rotate)
{
  const int* p = this->Interactor->GetEventPosition();
  this->FindPokedRenderer(p[0], p[1]);
  if (!this->CurrentRenderer)
  {
    return;
  }
  this->PressPosition[0] = p[0];
  this->PressPosition[1] = p[1];
  this->LeftDown = true;
  this->Moved = false;
  this->GrabFocus(this->EventCallbackCommand);
  if (rotate)
  {
    this->StartRotate();
  }
  else
  {
    this->StartPan();
  }
}

void vtkTerroirInteractorStyleTerrain::EndLeftGesture()
{
  if (!this->LeftDown)
  {
    return;
  }
  this->LeftDown = false;
  const bool click = !this->Moved && this->IsStillAClick();
  switch (this->State)
  {
    case VTKIS_PAN:
      this->EndPan();
      break;
    case VTKIS_ROTATE:
      this->EndRotate();
      break;
    default:
      break;
  }
  this->ReleaseFocus();
  if (click)
  {
    int position[2] = { this->PressPosition[0], this->PressPosition[1] };
    this->InvokeEvent(ClickEvent, position);
  }
}

void vtkTerroirInteractorStyleTerrain::OnLeftButtonDown()
{
  this->BeginLeftGesture(this->Interactor->GetControlKey() != 0);
}

void vtkTerroirInteractorStyleTerrain::OnLeftButtonUp()
{
  this->EndLeftGesture();
}

void vtkTerroirInteractorStyleTerrain::OnRightButtonDown()
{
  const int* p = this->Interactor->GetEventPosition();
  this->FindPokedRenderer(p[0], p[1]);
  if (!this->CurrentRenderer)
  {
    return;
  }
  this->GrabFocus(this->EventCallbackCommand);
  this->StartRotate();
}

void vtkTerroirInteractorStyleTerrain::OnRightButtonUp()
{
  if (this->State == VTKIS_ROTATE)
  {
    this->EndRotate();
    this->ReleaseFocus();
  }
}

void vtkTerroirInteractorStyleTerrain::OnMouseMove()
{
  const int* p = this->Interactor->GetEventPosition();
  switch (this->State)
  {
    case VTKIS_PAN:
      // A press that has not left the click tolerance yet moves nothing (a click stays a click).
      if (!this->Moved && this->IsStillAClick())
      {
        return;
      }
      if (!this->Moved)
      {
        // Start the pan from the press, not from the first motion beyond the tolerance.
        this->Interactor->SetLastEventPosition(this->PressPosition);
      }
      this->Moved = true;
      this->FindPokedRenderer(p[0], p[1]);
      this->Pan();
      this->InvokeEvent(vtkCommand::InteractionEvent, nullptr);
      break;
    case VTKIS_ROTATE:
      this->Moved = true;
      this->FindPokedRenderer(p[0], p[1]);
      this->Rotate();
      this->InvokeEvent(vtkCommand::InteractionEvent, nullptr);
      break;
    default:
      break;
  }
}

void vtkTerroirInteractorStyleTerrain::Pan()
{
  if (!this->CurrentRenderer)
  {
    return;
  }
  vtkRenderWindowInteractor* rwi = this->Interactor;
  vtkCamera* camera = this->CurrentRenderer->GetActiveCamera();
  double focal[3], position[3];
  camera->GetFocalPoint(focal);
  camera->GetPosition(position);
  // The focal point in display coordinates gives the depth at which the motion is measured.
  double focalDisplay[3];
  this->ComputeWorldToDisplay(focal[0], focal[1], focal[2], focalDisplay);
  const int* now = rwi->GetEventPosition();
  const int* last = rwi->GetLastEventPosition();
  const double s = this->MouseSensitivity;
  double a[4], b[4];
  this->ComputeDisplayToWorld(focalDisplay[0] + s * (now[0] - last[0]),
    focalDisplay[1] + s * (now[1] - last[1]),
    focalDisplay[2],
    a);
  this->ComputeDisplayToWorld(focalDisplay[0], focalDisplay[1], focalDisplay[2], b);
  // The terrain follows the pointer: the camera moves the other way.
  const double motion[3] = { b[0] - a[0], b[1] - a[1], b[2] - a[2] };
  camera->SetFocalPoint(focal[0] + motion[0], focal[1] + motion[1], focal[2] + motion[2]);
  camera->SetPosition(position[0] + motion[0], position[1] + motion[1], position[2] + motion[2]);
  this->CurrentRenderer->ResetCameraClippingRange();
  rwi->Render();
}

bool vtkTerroirInteractorStyleTerrain::DragDegrees(double& dx, double& dy, vtkCamera*& camera)
{
  if (!this->CurrentRenderer)
  {
    return false;
  }
  const int* now = this->Interactor->GetEventPosition();
  const int* last = this->Interactor->GetLastEventPosition();
  const double k = this->RotationDegreesPerPixel * this->MouseSensitivity;
  dx = k * (now[0] - last[0]);
  dy = k * (now[1] - last[1]);
  camera = this->CurrentRenderer->GetActiveCamera();
  return true;
}

void vtkTerroirInteractorStyleTerrain::Rotate()
{
  double dx = 0.0, dy = 0.0;
  vtkCamera* camera = nullptr;
  if (!this->DragDegrees(dx, dy, camera))
  {
    return;
  }
  const double dAzimuth = -dx;
  const double dElevation = -dy;
  double focal[3], position[3];
  camera->GetFocalPoint(focal);
  camera->GetPosition(position);
  double v[3] = { position[0] - focal[0], position[1] - focal[1], position[2] - focal[2] };
  // The camera stays above the horizon of the focal point and below its zenith.
  if (!TurnVector(v, dAzimuth, dElevation, 1.0, 89.0))
  {
    return;
  }
  camera->SetPosition(focal[0] + v[0], focal[1] + v[1], focal[2] + v[2]);
  this->FinishRotation(camera);
}

bool vtkTerroirInteractorStyleTerrain::TurnVector(double v[3],
  double dAzimuth,
  double dElevation,
  double lowest,
  double highest)
{
  const double distance = vtkMath::Norm(v);
  if (distance <= 0.0)
  {
    return false;
  }
  const double azimuth = std::atan2(v[0], v[1]) + vtkMath::RadiansFromDegrees(dAzimuth);
  const double elevation = std::max(vtkMath::RadiansFromDegrees(lowest),
    std::min(vtkMath::RadiansFromDegrees(highest),
      std::asin(std::max(-1.0, std::min(1.0, v[2] / distance))) +
        vtkMath::RadiansFromDegrees(dElevation)));
  v[0] = distance * std::cos(elevation) * std::sin(azimuth);
  v[1] = distance * std::cos(elevation) * std::cos(azimuth);
  v[2] = distance * std::sin(elevation);
  return true;
}

void vtkTerroirInteractorStyleTerrain::FinishRotation(vtkCamera* camera)
{
  camera->SetViewUp(0.0, 0.0, 1.0);
  camera->OrthogonalizeViewUp();
  this->CurrentRenderer->ResetCameraClippingRange();
  this->Interactor->Render();
}

void vtkTerroirInteractorStyleTerrain::ZoomBy(double factor)
{
  if (!this->CurrentRenderer || factor <= 0.0)
  {
    return;
  }
  vtkCamera* camera = this->CurrentRenderer->GetActiveCamera();
  if (camera->GetParallelProjection())
  {
    camera->SetParallelScale(camera->GetParallelScale() / factor);
  }
  else
  {
    camera->Dolly(factor);
  }
  this->CurrentRenderer->ResetCameraClippingRange();
  this->Interactor->Render();
}

void vtkTerroirInteractorStyleTerrain::OnMouseWheelForward()
{
  const int* p = this->Interactor->GetEventPosition();
  this->FindPokedRenderer(p[0], p[1]);
  this->ZoomBy(std::pow(this->ZoomFactor, this->MouseSensitivity));
}

void vtkTerroirInteractorStyleTerrain::OnMouseWheelBackward()
{
  const int* p = this->Interactor->GetEventPosition();
  this->FindPokedRenderer(p[0], p[1]);
  this->ZoomBy(1.0 / std::pow(this->ZoomFactor, this->MouseSensitivity));
}

void vtkTerroirInteractorStyleTerrain::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "MouseSensitivity: " << this->MouseSensitivity << "\n";
  os << indent << "RotationDegreesPerPixel: " << this->RotationDegreesPerPixel << "\n";
  os << indent << "ZoomFactor: " << this->ZoomFactor << "\n";
  os << indent << "ClickTolerance: " << this->ClickTolerance << "\n";
}
