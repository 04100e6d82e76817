#include "vtkTerroirTerragenWriter.h"

#include "Terragen.h"
#include "TerroirSafeOutput.h"

#include "MemoryBudget.h"
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

vtkTerroirTerragenWriter::vtkTerroirTerragenWriter() {}

vtkTerroirTerragenWriter::~vtkTerroirTerragenWriter() {}

void vtkTerroirTerragenWriter::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
}

void vtkTerroirTerragenWriter::WriteData()
{
  vtkDataArray* array = nullptr;
  vtkImageData* input = this->ValidatedInput(array);
  if (!input)
  {
    return;
  }
  if (array->GetNumberOfComponents() != 1)
  {
    this->Fail(std::string("array '") + this->ArrayName + "' has " +
      std::to_string(array->GetNumberOfComponents()) + " components, Terragen stores one");
    return;
  }
  vtkDataArray* mask = input->GetPointData()->GetArray(vtkTerroirGeoreference::ValidMaskName());
  const vtkIdType n = array->GetNumberOfTuples();
  // A float copy of the heights (4 B per cell) and the encoded file (2 B per cell).
  const std::string memory = terroir::CheckMemory(6.0 * n, "encoding the Terragen file");
  if (!memory.empty())
  {
    this->Fail(memory);
    return;
  }
  std::vector<float> heights(static_cast<std::size_t>(n));
  for (vtkIdType k = 0; k < n; ++k)
  {
    const bool valid = !mask || mask->GetComponent(k, 0) != 0.0;
    heights[k] = valid ? static_cast<float>(array->GetComponent(k, 0))
                       : std::numeric_limits<float>::quiet_NaN();
  }
  int dims[3];
  input->GetDimensions(dims);
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
  const std::string temp = terroir::TemporaryNameFor(target);
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
    terroir::DiscardTemporary(temp);
    this->Fail(std::string("write failed (") + std::strerror(writeErrno) + ")");
    return;
  }
  if (!terroir::CommitTemporary(temp, target, error))
  {
    this->Fail(error);
  }
}
