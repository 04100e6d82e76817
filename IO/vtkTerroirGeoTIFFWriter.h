/**
 * @class   vtkTerroirGeoTIFFWriter
 * @brief   Writes one point-data array of a terrain as a GeoTIFF, with its CRS and
 *          geotransform.
 *
 * Input: a 2-D vtkImageData. The array `ArrayName` (default `Elevation`) is written with one
 * band per component (band descriptions = component names, or the array name): float32
 * arrays as Float32, double as Float64, char/unsigned char as Byte, other integers as
 * Int32. Rows are flipped back to north first. No-data (where `vtkValidPointMask` is 0 or
 * the value is NaN): NaN for floating bands, -9999 for Int32, 255 for Byte (set only when
 * such cells exist for Byte). Georeference: the input's `TerroirGeoTransform` and
 * `TerroirCRS` when present (as vtkTerroirDEMReader leaves them); otherwise a geotransform
 * built from the image origin and spacing (origin = south-west cell centre) and no CRS.
 * Uncompressed and band-interleaved by default, like gdaldem; `Compress` turns on DEFLATE.
 *
 * The file is written to a hidden temporary name in the target folder and renamed on
 * success: a failed write leaves no file and never damages an existing one. With
 * `Overwrite` off (default) an existing target is an error. Errors: one line
 * "<file>: <problem>" from GetErrorMessage() and vtkErrorMacro; Write() returns 0.
 *
 * @par Correctness
 * TerroirGeoTIFFWriter.* pipeline tests: round trip through vtkTerroirDEMReader (values,
 * geotransform and CRS equal), masks, multi-component arrays, temporary-file and
 * Overwrite behaviour.
 *
 * @sa vtkTerroirDEMReader vtkTerroirGeoreference
 */
#ifndef vtkTerroirGeoTIFFWriter_h
#define vtkTerroirGeoTIFFWriter_h

#include "vtkTerroirIOModule.h" // For export macro
#include "vtkTerroirImageWriter.h"

class VTKTERROIRIO_EXPORT vtkTerroirGeoTIFFWriter : public vtkTerroirImageWriter
{
public:
  static vtkTerroirGeoTIFFWriter* New();
  vtkTypeMacro(vtkTerroirGeoTIFFWriter, vtkTerroirImageWriter);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /// Compress with DEFLATE (floating-point predictor for float bands). Default off, like
  /// gdaldem: uncompressed GeoTIFFs are written about twice as fast.
  vtkSetMacro(Compress, bool);
  vtkGetMacro(Compress, bool);
  vtkBooleanMacro(Compress, bool);
  ///@}

protected:
  vtkTerroirGeoTIFFWriter();
  ~vtkTerroirGeoTIFFWriter() override;

  void WriteData() override;

  bool Compress = false;

private:
  vtkTerroirGeoTIFFWriter(const vtkTerroirGeoTIFFWriter&) = delete;
  void operator=(const vtkTerroirGeoTIFFWriter&) = delete;
};

#endif
