#include "vtkTerroirFractalTerrainSource.h"

#include "FractalNoise.h"
#include "vtkDataArray.h"
#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkSMPTools.h"
#include "vtkStreamingDemandDrivenPipeline.h"
#include "vtkTerroirGeoreference.h"
#include "vtkTerroirIOPrivate.h"

#include "MemoryBudget.h"

#include <cmath>

vtkStandardNewMacro(vtkTerroirFractalTerrainSource);

vtkTerroirFractalTerrainSource::vtkTerroirFractalTerrainSource()
{
  this->SetNumberOfInputPorts(0);
  this->SetNumberOfOutputPorts(1);
}

void vtkTerroirFractalTerrainSource::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Dimensions: " << this->Dimensions[0] << " x " << this->Dimensions[1] << "\n";
  os << indent << "Spacing: " << this->Spacing << " m\n";
  os << indent << "Seed: " << this->Seed << "\n";
  os << indent << "Octaves: " << this->Octaves << "\n";
  os << indent << "FeatureSize: " << this->FeatureSize << " cells\n";
  os << indent << "Persistence: " << this->Persistence << "\n";
  os << indent << "Amplitude: " << this->Amplitude << " m\n";
  os << indent << "BaseHeight: " << this->BaseHeight << " m\n";
}

bool vtkTerroirFractalTerrainSource::CheckParameters()
{
  this->ErrorMessage.clear();
  const int nx = this->Dimensions[0];
  const int ny = this->Dimensions[1];
  if (nx < 1 || ny < 1 || nx > 65536 || ny > 65536 || static_cast<double>(nx) * ny > 2147483647.0)
  {
    this->ErrorMessage = "vtkTerroirFractalTerrainSource: invalid Dimensions " +
      std::to_string(nx) + " x " + std::to_string(ny) +
      " (each in [1, 65536], at most 2^31 - 1 cells)";
  }
  else if (!(this->Spacing > 0.0) || !std::isfinite(this->Spacing))
  {
    this->ErrorMessage = "vtkTerroirFractalTerrainSource: Spacing must be positive";
  }
  else if (!(this->FeatureSize > 0.0) || !std::isfinite(this->FeatureSize))
  {
    this->ErrorMessage = "vtkTerroirFractalTerrainSource: FeatureSize must be positive";
  }
  else if (!std::isfinite(this->Amplitude) || !std::isfinite(this->BaseHeight) ||
    !std::isfinite(this->Persistence))
  {
    this->ErrorMessage = "vtkTerroirFractalTerrainSource: non-finite parameter";
  }
  if (!this->ErrorMessage.empty())
  {
    vtkErrorMacro(<< this->ErrorMessage);
    return false;
  }
  return true;
}

int vtkTerroirFractalTerrainSource::RequestInformation(vtkInformation*,
  vtkInformationVector**,
  vtkInformationVector* outputVector)
{
  if (!this->CheckParameters())
  {
    if (vtkImageData* output = vtkImageData::GetData(outputVector, 0))
    {
      output->Initialize();
    }
    return 0;
  }
  terroir::io::detail::SetTerrainInformation(outputVector->GetInformationObject(0),
    this->Dimensions[0],
    this->Dimensions[1],
    this->Spacing,
    this->Spacing,
    0.0,
    0.0);
  return 1;
}

int vtkTerroirFractalTerrainSource::RequestData(vtkInformation*,
  vtkInformationVector**,
  vtkInformationVector* outputVector)
{
  vtkImageData* output = vtkImageData::GetData(outputVector, 0);
  output->Initialize();
  if (!this->CheckParameters())
  {
    return 0;
  }
  const int nx = this->Dimensions[0];
  const int ny = this->Dimensions[1];
  const std::string memory = terroir::CheckMemory(4.0 * nx * ny, "the fractal terrain");
  if (!memory.empty())
  {
    this->ErrorMessage = "vtkTerroirFractalTerrainSource: " + memory;
    vtkErrorMacro(<< this->ErrorMessage);
    return 0;
  }
  output->SetExtent(0, nx - 1, 0, ny - 1, 0, 0);
  output->SetSpacing(this->Spacing, this->Spacing, 1.0);
  output->SetOrigin(0.0, 0.0, 0.0);

  terroir::io::FractalNoiseParameters p;
  p.seed = this->Seed;
  p.octaves = this->Octaves;
  p.featureSize = this->FeatureSize;
  p.persistence = this->Persistence;
  p.amplitude = this->Amplitude;
  p.baseHeight = this->BaseHeight;

  vtkNew<vtkFloatArray> elevation;
  elevation->SetName(vtkTerroirGeoreference::ElevationName());
  elevation->SetNumberOfTuples(static_cast<vtkIdType>(nx) * ny);
  elevation->GetInformation()->Set(vtkDataArray::UNITS_LABEL(), "m");
  float* out = elevation->GetPointer(0);
  vtkSMPTools::For(0,
    ny,
    16,
    [&](vtkIdType j0, vtkIdType j1)
    {
      terroir::io::FractalNoisePerlin2002Rows(
        p, nx, static_cast<int>(j0), static_cast<int>(j1), out);
    });
  output->GetPointData()->SetScalars(elevation);
  return 1;
}
