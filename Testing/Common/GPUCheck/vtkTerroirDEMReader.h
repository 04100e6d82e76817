// terroir-gpu-check only (Applications/GPUCheck.cmake): a GDAL-free stand-in for
// IO/vtkTerroirDEMReader.h. That build puts this folder first on its include path and does not
// link Terroir::IO, so that Testing/Common/TerroirFilterTestUtilities.cxx compiles unchanged and
// its ReadDEM reads the .vti copies of the DEMs that Scripts/gpu-check.sh makes with
// TerroirGPUCheckDEMToVTI (the real reader's output, georeference field data included).
#ifndef vtkTerroirDEMReader_h
#define vtkTerroirDEMReader_h

#include "vtkXMLImageDataReader.h"

#include <string> // For std::string

/**
 * @class   vtkTerroirDEMReader
 * @brief   Reads a DEM's .vti copy: a name that does not end in `.vti` is read from the file of
 * the same name ending in `.vti` (data/x/dem.tif -> data/x/dem.vti).
 */
class vtkTerroirDEMReader : public vtkXMLImageDataReader
{
public:
  static vtkTerroirDEMReader* New();
  vtkTypeMacro(vtkTerroirDEMReader, vtkXMLImageDataReader);

  /// Sets the .vti file to read: `name` itself, or `name` with its extension replaced by .vti.
  void SetFileName(const char* name) override;

  /// The .vti file read for `name` (see SetFileName).
  static std::string VTIPath(const std::string& name);

protected:
  vtkTerroirDEMReader() = default;
  ~vtkTerroirDEMReader() override = default;

private:
  vtkTerroirDEMReader(const vtkTerroirDEMReader&) = delete;
  void operator=(const vtkTerroirDEMReader&) = delete;
};

#endif
