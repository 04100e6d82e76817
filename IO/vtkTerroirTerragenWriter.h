/**
 * @class   vtkTerroirTerragenWriter
 * @brief   Writes a terrain's elevation as a Terragen terrain file (`.ter`), without GDAL.
 *
 * Input: a 2-D vtkImageData with a one-component point array (`ArrayName`, default
 * `Elevation`, metres) and optional `vtkValidPointMask`. Image spacing (metres) becomes
 * SCAL x, y; SCAL z = x spacing (as GDAL's Terragen driver writes) unless the heights need a
 * larger vertical unit to fit 16 bits. Chunks written: SIZE, XPTS, YPTS, SCAL, ALTW, EOF;
 * rows south first. BaseHeight/HeightScale are chosen to cover the data range, so the
 * round-trip error is at most range/131068 + SCAL.z/65534 metres (within 1/65536 of the
 * range whenever the range exceeds twice the x spacing). No-data cells (mask 0 or NaN) are
 * written as the minimum height, with a warning. Georeference is not stored (the format
 * has none).
 *
 * The file is written to a temporary name in the target folder and renamed on success, so
 * a failed write leaves no file and never damages an existing one. With `Overwrite` off
 * (default) an existing target is an error. Errors: one line "<file>: <problem>" from
 * GetErrorMessage() and vtkErrorMacro; Write() returns 0.
 *
 * @par Correctness
 * TerroirTerragen.RoundTrip* unit tests; TerroirTerragenWriter.* pipeline tests.
 *
 * @sa vtkTerroirTerragenReader
 */
#ifndef vtkTerroirTerragenWriter_h
#define vtkTerroirTerragenWriter_h

#include "vtkTerroirIOModule.h" // For export macro
#include "vtkTerroirImageWriter.h"

class vtkImageData;

class VTKTERROIRIO_EXPORT vtkTerroirTerragenWriter : public vtkTerroirImageWriter
{
public:
  static vtkTerroirTerragenWriter* New();
  vtkTypeMacro(vtkTerroirTerragenWriter, vtkTerroirImageWriter);
  void PrintSelf(ostream& os, vtkIndent indent) override;

protected:
  vtkTerroirTerragenWriter();
  ~vtkTerroirTerragenWriter() override;

  void WriteData() override;

private:
  vtkTerroirTerragenWriter(const vtkTerroirTerragenWriter&) = delete;
  void operator=(const vtkTerroirTerragenWriter&) = delete;
};

#endif
