/**
 * @class   vtkTerroirTerragenReader
 * @brief   Reads a Terragen terrain file (`.ter`) into a Terroir terrain, without GDAL.
 *
 * Output: vtkImageData with dimensions (XPTS, YPTS, 1), spacing (SCAL.x, SCAL.y, 1) metres,
 * origin (0, 0, 0), point array `Elevation` (float32, metres:
 * SCAL.z * (BaseHeight + raw * HeightScale / 65536)), row j = 0 = the file's first row (the
 * SOUTH edge). Terragen stores no geographic position, so no CRS is set; field data holds
 * `TerroirSourceFile` only.
 *
 * Parsing (in IO/Core, terroir::io::ReadTerragen) rejects, with one error line
 * "<file>: <problem>" (GetErrorMessage() and vtkErrorMacro) and an empty output: a wrong
 * magic, a truncated chunk, an ALTW chunk shorter than XPTS*YPTS values, invalid sizes
 * (< 2 points, SIZE not equal to min(XPTS, YPTS) - 1), unknown chunk tags and a missing ALTW.
 *
 * @par Correctness
 * TerroirTerragen.* unit tests (hand-built byte strings, bad files) and
 * TerroirTerragenReader.MatchesBundledGeoTIFF (the bundled `.ter` against the `.tif` read by
 * vtkTerroirDEMReader: max deviation 0.0123 m, the 16-bit quantisation step).
 *
 * @par References
 * Planetside Software, "Terragen Terrain File Specification" (terrain format v1).
 *
 * @sa vtkTerroirTerragenWriter vtkTerroirDEMReader
 */
#ifndef vtkTerroirTerragenReader_h
#define vtkTerroirTerragenReader_h

#include "vtkImageAlgorithm.h"
#include "vtkTerroirIOModule.h" // For export macro

#include <string> // For std::string

class VTKTERROIRIO_EXPORT vtkTerroirTerragenReader : public vtkImageAlgorithm
{
public:
  static vtkTerroirTerragenReader* New();
  vtkTypeMacro(vtkTerroirTerragenReader, vtkImageAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /// The `.ter` file to read. Default: none.
  vtkSetStringMacro(FileName);
  vtkGetStringMacro(FileName);
  ///@}

  /// The last error as one line "<file>: <problem>", or "" after a successful read.
  const char* GetErrorMessage() const { return this->ErrorMessage.c_str(); }

protected:
  vtkTerroirTerragenReader();
  ~vtkTerroirTerragenReader() override;

  int RequestInformation(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  char* FileName = nullptr;
  std::string ErrorMessage;

private:
  vtkTerroirTerragenReader(const vtkTerroirTerragenReader&) = delete;
  void operator=(const vtkTerroirTerragenReader&) = delete;

  bool Load(void* terrain);
  void Fail(const std::string& problem);
};

#endif
