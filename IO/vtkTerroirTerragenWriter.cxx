#include "vtkTerroirTerragenWriter.h"

#include "Terragen.h"
#include "vtkDataArray.h"
#include "vtkErrorCode.h"
#include "vtkImageData.h"
#include "vtkInformation.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkTerroirGeoreference.h"
#include "vtkTerroirIOPrivate.h"

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <vector>

vtkStandardNewMacro(vtkTerroirTerragenWriter);

vtkTerroirTerragenWriter::vtkTerroirTerragenWriter()
{
  this->SetArrayName(vtkTerroirGeoreference::ElevationName());
}

vtkTerroirTerragenWriter::~vtkTerroirTerragenWriter()
{
  this->SetFileName(nullptr);
  this->SetArrayName(nullptr);
}

void vtkTerroirTerragenWriter::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "FileName: " << (this->FileName ? this->FileName : "(none)") << "\n";
  os << indent << "ArrayName: " << (this->ArrayName ? this->ArrayName : "(none)") << "\n";
  os << indent << "Overwrite: " << this->Overwrite << "\n";
}

int vtkTerroirTerragenWriter::FillInputPortInformation(int, vtkInformation* info)
{
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkImageData");
  return 1;
}

void vtkTerroirTerragenWriter::Fail(const std::string& problem)
{
  this->ErrorMessage =
    std::string(this->FileName && *this->FileName ? this->FileName : "(no file name)") + ": " +
    problem;
  this->SetErrorCode(vtkErrorCode::UserError);
  vtkErrorMacro(<< this->ErrorMessage);
}

void vtkTerroirTerragenWriter::WriteData()
{
  this->ErrorMessage.clear();
  this->SetErrorCode(vtkErrorCode::NoError);
  if (!this->FileName || !*this->FileName)
  {
    this->Fail("no file name set");
    return;
  }
  vtkImageData* input = vtkImageData::SafeDownCast(this->GetInput());
  if (!input)
  {
    this->Fail("input is not a vtkImageData");
    return;
  }
  int dims[3];
  input->GetDimensions(dims);
  if (dims[2] != 1)
  {
    this->Fail("input is not a 2-D image (" + std::to_string(dims[2]) + " slices)");
    return;
  }
  vtkDataArray* array =
    this->ArrayName ? input->GetPointData()->GetArray(this->ArrayName) : nullptr;
  if (!array)
  {
    this->Fail(
      std::string("input has no point array '") + (this->ArrayName ? this->ArrayName : "") + "'");
    return;
  }
  if (array->GetNumberOfComponents() != 1)
  {
    this->Fail(std::string("array '") + this->ArrayName + "' has " +
      std::to_string(array->GetNumberOfComponents()) + " components, Terragen stores one");
    return;
  }
  if (!this->Overwrite && terroir::io::detail::FileExists(this->FileName))
  {
    this->Fail("file exists (turn Overwrite on to replace it)");
    return;
  }
  vtkDataArray* mask = input->GetPointData()->GetArray(vtkTerroirGeoreference::ValidMaskName());
  const vtkIdType n = array->GetNumberOfTuples();
  std::vector<float> heights(static_cast<std::size_t>(n));
  for (vtkIdType k = 0; k < n; ++k)
  {
    const bool valid = !mask || mask->GetComponent(k, 0) != 0.0;
    heights[k] = valid ? static_cast<float>(array->GetComponent(k, 0))
                       : std::numeric_limits<float>::quiet_NaN();
  }
  double spacing[3];
  input->GetSpacing(spacing);
  std::vector<std::uint8_t> bytes;
  std::string warning, error;
  if (!terroir::io::WriteTerragen(heights.data(),
        dims[0],
        dims[1],
        std::fabs(spacing[0]),
        std::fabs(spacing[1]),
        bytes,
        warning,
        error))
  {
    this->Fail(error);
    return;
  }
  if (!warning.empty())
  {
    vtkWarningMacro(<< this->FileName << ": " << warning);
  }
  const std::string target = this->FileName;
  const std::string temp = terroir::io::detail::TemporaryNameFor(target);
  FILE* f = std::fopen(temp.c_str(), "wb");
  if (!f)
  {
    this->Fail(std::string("cannot create a file in folder '") +
      terroir::io::detail::DirectoryOf(target) + "' (" + std::strerror(errno) + ")");
    return;
  }
  const bool written = std::fwrite(bytes.data(), 1, bytes.size(), f) == bytes.size();
  const int writeErrno = errno;
  const bool closed = std::fclose(f) == 0;
  if (!written || !closed)
  {
    std::remove(temp.c_str());
    this->Fail(std::string("write failed (") + std::strerror(writeErrno) + ")");
    return;
  }
  if (!terroir::io::detail::CommitTemporary(temp, target, error))
  {
    this->Fail(error);
  }
}
