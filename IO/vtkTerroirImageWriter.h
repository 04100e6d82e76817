/**
 * @class   vtkTerroirImageWriter
 * @brief   Base of Terroir's terrain writers: file name, array choice, overwrite rule and
 *          one-line errors.
 *
 * Input: a 2-D vtkImageData (dimensions nx, ny, 1). Subclasses write the point array
 * `ArrayName` (default `Elevation`) to `FileName`, through a temporary file renamed on
 * success. `ValidatedInput()` performs the checks every writer shares (a file name, a 2-D
 * image, the array present, an existing target only with `Overwrite`) and reports the first
 * failure with `Fail()`: one line "<file>: <problem>" from GetErrorMessage(), vtkErrorMacro,
 * and the error code set, so `Write()` returns 0.
 *
 * @sa vtkTerroirGeoTIFFWriter vtkTerroirTerragenWriter
 */
#ifndef vtkTerroirImageWriter_h
#define vtkTerroirImageWriter_h

#include "vtkTerroirIOModule.h" // For export macro
#include "vtkWriter.h"

#include <string> // For std::string

class vtkDataArray;
class vtkImageData;

class VTKTERROIRIO_EXPORT vtkTerroirImageWriter : public vtkWriter
{
public:
  vtkTypeMacro(vtkTerroirImageWriter, vtkWriter);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /// The file to write. Default: none.
  vtkSetStringMacro(FileName);
  vtkGetStringMacro(FileName);
  ///@}

  ///@{
  /// Point array to write. Default: "Elevation".
  vtkSetStringMacro(ArrayName);
  vtkGetStringMacro(ArrayName);
  ///@}

  ///@{
  /// Replace an existing file. Default: off (an existing file is an error).
  vtkSetMacro(Overwrite, bool);
  vtkGetMacro(Overwrite, bool);
  vtkBooleanMacro(Overwrite, bool);
  ///@}

  /// The last error as one line "<file>: <problem>", or "" after a successful write.
  const char* GetErrorMessage() const { return this->ErrorMessage.c_str(); }

protected:
  vtkTerroirImageWriter();
  ~vtkTerroirImageWriter() override;

  int FillInputPortInformation(int port, vtkInformation* info) override;

  /// Clears the last error, runs the shared checks and returns the input and the array to
  /// write (nullptr after Fail()).
  vtkImageData* ValidatedInput(vtkDataArray*& array);

  /// Records and reports one error line "<file>: <problem>".
  void Fail(const std::string& problem);

  char* FileName = nullptr;
  char* ArrayName = nullptr;
  bool Overwrite = false;
  std::string ErrorMessage;

private:
  vtkTerroirImageWriter(const vtkTerroirImageWriter&) = delete;
  void operator=(const vtkTerroirImageWriter&) = delete;
};

#endif
