#include "vtkTerroirInteractorStyleFirstPerson.h"

#include "vtkCamera.h"
#include "vtkMath.h"
#include "vtkObjectFactory.h"
#include "vtkRenderWindowInteractor.h"
#include "vtkRenderer.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <string>

vtkStandardNewMacro(vtkTerroirInteractorStyleFirstPerson);

vtkTerroirInteractorStyleFirstPerson::vtkTerroirInteractorStyleFirstPerson() = default;
vtkTerroirInteractorStyleFirstPerson::~vtkTerroirInteractorStyleFirstPerson() = default;

void vtkTerroirInteractorStyleFirstPerson::OnLeftButtonDown()
{
  // Every left drag looks around (Ctrl+drag too).
  this->BeginLeftGesture(true);
}

void vtkTerroirInteractorStyleFirstPerson::Rotate()
{
  double dx = 0.0, dy = 0.0;
  vtkCamera* camera = nullptr;
  if (!this->DragDegrees(dx, dy, camera))
  {
    return;
  }
  double focal[3], position[3];
  camera->GetFocalPoint(focal);
  camera->GetPosition(position);
  double d[3] = { focal[0] - position[0], focal[1] - position[1], focal[2] - position[2] };
  // The direction of view turns: drag right turns right, the pitch stays within 85 degrees.
  if (!TurnVector(d, dx, dy, -85.0, 85.0))
  {
    return;
  }
  camera->SetFocalPoint(position[0] + d[0], position[1] + d[1], position[2] + d[2]);
  this->FinishRotation(camera);
}

void vtkTerroirInteractorStyleFirstPerson::Move(double forward, double right, double up)
{
  if (!this->CurrentRenderer)
  {
    return;
  }
  vtkCamera* camera = this->CurrentRenderer->GetActiveCamera();
  double focal[3], position[3];
  camera->GetFocalPoint(focal);
  camera->GetPosition(position);
  double f[3] = { focal[0] - position[0], focal[1] - position[1], 0.0 };
  if (vtkMath::Normalize(f) <= 0.0)
  {
    // Looking straight down: "forward" is the camera's view up.
    camera->GetViewUp(f);
    f[2] = 0.0;
    if (vtkMath::Normalize(f) <= 0.0)
    {
      f[1] = 1.0;
    }
  }
  const double r[3] = { f[1], -f[0], 0.0 };
  const double step = this->MoveStep * this->MoveSensitivity;
  double motion[3];
  for (int c = 0; c < 3; ++c)
  {
    motion[c] = step * (forward * f[c] + right * r[c]);
  }
  motion[2] += step * up;
  camera->SetPosition(position[0] + motion[0], position[1] + motion[1], position[2] + motion[2]);
  camera->SetFocalPoint(focal[0] + motion[0], focal[1] + motion[1], focal[2] + motion[2]);
  this->CurrentRenderer->ResetCameraClippingRange();
  this->Interactor->Render();
}

void vtkTerroirInteractorStyleFirstPerson::OnKeyPress()
{
  vtkRenderWindowInteractor* rwi = this->Interactor;
  if (rwi->GetControlKey())
  {
    return;
  }
  const char* sym = rwi->GetKeySym();
  if (!sym || std::string(sym).size() != 1)
  {
    return;
  }
  const int* p = rwi->GetEventPosition();
  this->FindPokedRenderer(p[0], p[1]);
  switch (std::tolower(static_cast<unsigned char>(sym[0])))
  {
    case 'w':
      this->Move(1.0, 0.0, 0.0);
      break;
    case 's':
      this->Move(-1.0, 0.0, 0.0);
      break;
    case 'a':
      this->Move(0.0, -1.0, 0.0);
      break;
    case 'd':
      this->Move(0.0, 1.0, 0.0);
      break;
    case 'r':
      this->Move(0.0, 0.0, 1.0);
      break;
    case 'f':
      this->Move(0.0, 0.0, -1.0);
      break;
    default:
      break;
  }
}

void vtkTerroirInteractorStyleFirstPerson::OnMouseWheelForward()
{
  const int* p = this->Interactor->GetEventPosition();
  this->FindPokedRenderer(p[0], p[1]);
  this->Move(1.0, 0.0, 0.0);
}

void vtkTerroirInteractorStyleFirstPerson::OnMouseWheelBackward()
{
  const int* p = this->Interactor->GetEventPosition();
  this->FindPokedRenderer(p[0], p[1]);
  this->Move(-1.0, 0.0, 0.0);
}

void vtkTerroirInteractorStyleFirstPerson::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "MoveStep: " << this->MoveStep << "\n";
  os << indent << "MoveSensitivity: " << this->MoveSensitivity << "\n";
}
