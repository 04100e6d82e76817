#include "vtkTerroirImageWriter.h"

#include "vtkDataArray.h"
#include "vtkErrorCode.h"
#include "vtkImageData.h"
#include "vtkInformation.h"
#include "vtkPointData.h"
#include "vtkTerroirGeoreference.h"
#include "vtkTerroirIOPrivate.h"

vtkTerroirImageWriter::vtkTerroirImageWriter()
{
  this->SetArrayName(vtkTerroirGeoreference::ElevationName());
}

vtkTerroirImageWriter::~vtkTerroirImageWriter()
{
  this->SetFileName(nullptr);
  this->SetArrayName(nullptr);
}

void vtkTerroirImageWriter::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "FileName: " << (this->FileName ? this->FileName : "(none)") << "\n";
  os << indent << "ArrayName: " << (this->ArrayName ? this->ArrayName : "(none)") << "\n";
  os << indent << "Overwrite: " << this->Overwrite << "\n";
}

int vtkTerroirImageWriter::FillInputPortInformation(int, vtkInformation* info)
{
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkImageData");
  return 1;
}

void vtkTerroirImageWriter::Fail(const std::string& problem)
{
  this->ErrorMessage = terroir::io::detail::FileError(this->FileName, problem);
  this->SetErrorCode(vtkErrorCode::UserError);
  vtkErrorMacro(<< this->ErrorMessage);
}

vtkImageData* vtkTerroirImageWriter::ValidatedInput(vtkDataArray*& array)
{
  array = nullptr;
  this->ErrorMessage.clear();
  this->SetErrorCode(vtkErrorCode::NoError);
  if (!this->FileName || !*this->FileName)
  {
    this->Fail("no file name set");
    return nullptr;
  }
  vtkImageData* input = vtkImageData::SafeDownCast(this->GetInput());
  if (!input)
  {
    this->Fail("input is not a vtkImageData");
    return nullptr;
  }
  int dims[3];
  input->GetDimensions(dims);
  if (dims[2] != 1 || dims[0] < 1 || dims[1] < 1)
  {
    this->Fail("input is not a 2-D image (dimensions " + std::to_string(dims[0]) + " x " +
      std::to_string(dims[1]) + " x " + std::to_string(dims[2]) + ")");
    return nullptr;
  }
  array = this->ArrayName ? input->GetPointData()->GetArray(this->ArrayName) : nullptr;
  if (!array)
  {
    this->Fail(
      std::string("input has no point array '") + (this->ArrayName ? this->ArrayName : "") + "'");
    return nullptr;
  }
  if (!this->Overwrite && terroir::io::detail::FileExists(this->FileName))
  {
    this->Fail("file exists (turn Overwrite on to replace it)");
    array = nullptr;
    return nullptr;
  }
  return input;
}
