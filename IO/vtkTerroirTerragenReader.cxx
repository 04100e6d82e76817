#include "vtkTerroirTerragenReader.h"

#include "Terragen.h"
#include "vtkDataArray.h"
#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkStreamingDemandDrivenPipeline.h"
#include "vtkTerroirGeoreference.h"
#include "vtkTerroirIOPrivate.h"

#include "MemoryBudget.h"

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <fstream>

vtkStandardNewMacro(vtkTerroirTerragenReader);

vtkTerroirTerragenReader::vtkTerroirTerragenReader()
{
  this->SetNumberOfInputPorts(0);
  this->SetNumberOfOutputPorts(1);
}

vtkTerroirTerragenReader::~vtkTerroirTerragenReader()
{
  this->SetFileName(nullptr);
}

void vtkTerroirTerragenReader::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "FileName: " << (this->FileName ? this->FileName : "(none)") << "\n";
  os << indent << "ErrorMessage: " << this->ErrorMessage << "\n";
}

void vtkTerroirTerragenReader::Fail(const std::string& problem)
{
  this->ErrorMessage = terroir::io::detail::FileError(this->FileName, problem);
  vtkErrorMacro(<< this->ErrorMessage);
}

bool vtkTerroirTerragenReader::Load(void* terrainPtr)
{
  auto& terrain = *static_cast<terroir::io::TerragenTerrain*>(terrainPtr);
  this->ErrorMessage.clear();
  if (!this->FileName || !*this->FileName)
  {
    this->Fail("no file name set");
    return false;
  }
  std::string error;
  double size = 0.0;
  if (!terroir::io::detail::CheckInputFile(this->FileName, error, &size))
  {
    this->Fail(error);
    return false;
  }
  if (size > terroir::io::kTerragenMaxFileBytes)
  {
    this->Fail("file of " + terroir::FormatBytes(size) +
      " is larger than any Terragen terrain (32767 x 32767 heights, 2.0 GiB)");
    return false;
  }
  // The file, its raw int16 values (1 B per file byte) and float heights (2 B per file byte),
  // then the output array (2 B per file byte).
  error = terroir::CheckMemory(6.0 * size, "reading the Terragen file");
  if (!error.empty())
  {
    this->Fail(error);
    return false;
  }
  std::ifstream in(this->FileName, std::ios::binary);
  std::vector<std::uint8_t> bytes(static_cast<std::size_t>(size));
  if (!in || !in.read(reinterpret_cast<char*>(bytes.data()), static_cast<std::streamsize>(size)))
  {
    this->Fail(std::string("cannot be read (") + std::strerror(errno) + ")");
    return false;
  }
  if (!terroir::io::ReadTerragen(bytes, terrain, error))
  {
    this->Fail(error);
    return false;
  }
  return true;
}

int vtkTerroirTerragenReader::RequestInformation(vtkInformation*,
  vtkInformationVector**,
  vtkInformationVector* outputVector)
{
  terroir::io::TerragenTerrain terrain;
  if (!this->Load(&terrain))
  {
    if (vtkImageData* output = vtkImageData::GetData(outputVector, 0))
    {
      output->Initialize();
    }
    return 0;
  }
  terroir::io::detail::SetTerrainInformation(outputVector->GetInformationObject(0),
    terrain.nx,
    terrain.ny,
    terrain.scale[0],
    terrain.scale[1],
    0.0,
    0.0);
  return 1;
}

int vtkTerroirTerragenReader::RequestData(vtkInformation*,
  vtkInformationVector**,
  vtkInformationVector* outputVector)
{
  vtkImageData* output = vtkImageData::GetData(outputVector, 0);
  output->Initialize();
  terroir::io::TerragenTerrain terrain;
  if (!this->Load(&terrain))
  {
    return 0;
  }
  output->SetExtent(0, terrain.nx - 1, 0, terrain.ny - 1, 0, 0);
  output->SetSpacing(terrain.scale[0], terrain.scale[1], 1.0);
  output->SetOrigin(0.0, 0.0, 0.0);
  vtkNew<vtkFloatArray> elevation;
  elevation->SetName(vtkTerroirGeoreference::ElevationName());
  elevation->SetNumberOfTuples(static_cast<vtkIdType>(terrain.heights.size()));
  std::copy(terrain.heights.begin(), terrain.heights.end(), elevation->GetPointer(0));
  elevation->GetInformation()->Set(vtkDataArray::UNITS_LABEL(), "m");
  output->GetPointData()->SetScalars(elevation);
  vtkTerroirGeoreference::SetSourceFile(output, this->FileName);
  return 1;
}
