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
 * Band-interleaved. Layout options (all off by default, like gdaldem: uncompressed strips):
 * `Compression` (NONE, DEFLATE, ZSTD or LZW, each with GDAL's default level, the
 * floating-point predictor (3) for float bands and the horizontal one (2) for integers: lossless),
 * `Tiled` (256 × 256 tiles instead of strips: QGIS reads a window without whole rows, and
 * GDAL compresses the tiles in parallel), `Threads` (GDAL's NUM_THREADS for compression: 0 its
 * default, one thread; -1 all cores) and `Overviews` (internal overviews at 2, 4, 8, ... until
 * the smaller side is under 256 cells: AVERAGE for float bands, NEAREST for integer classes).
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

  enum CompressionType
  {
    COMPRESSION_NONE = 0,
    COMPRESSION_DEFLATE = 1,
    COMPRESSION_ZSTD = 2,
    COMPRESSION_LZW = 3
  };

  ///@{
  /// The compression (CompressionType), default COMPRESSION_NONE.
  vtkSetClampMacro(Compression, int, COMPRESSION_NONE, COMPRESSION_LZW);
  vtkGetMacro(Compression, int);
  ///@}

  /// The compression's name ("none", "deflate", "zstd", "lzw"); nullptr for an unknown value.
  static const char* GetCompressionName(int compression);
  /// The CompressionType of a name of GetCompressionName(); -1 when unknown.
  static int GetCompressionFromName(const char* name);

  ///@{
  /// DEFLATE on or off (Compression DEFLATE or NONE); kept for scripts written before the
  /// other compressions.
  void SetCompress(bool on) { this->SetCompression(on ? COMPRESSION_DEFLATE : COMPRESSION_NONE); }
  bool GetCompress() { return this->Compression != COMPRESSION_NONE; }
  void CompressOn() { this->SetCompress(true); }
  void CompressOff() { this->SetCompress(false); }
  ///@}

  ///@{
  /// 256 × 256 tiles instead of strips. Default off.
  vtkSetMacro(Tiled, bool);
  vtkGetMacro(Tiled, bool);
  vtkBooleanMacro(Tiled, bool);
  ///@}

  ///@{
  /// Threads GDAL compresses with (NUM_THREADS): 0 its default (one), -1 all cores. Default 0.
  vtkSetClampMacro(Threads, int, -1, 1024);
  vtkGetMacro(Threads, int);
  ///@}

  ///@{
  /// Internal overviews (see the class comment). Default off.
  vtkSetMacro(Overviews, bool);
  vtkGetMacro(Overviews, bool);
  vtkBooleanMacro(Overviews, bool);
  ///@}

protected:
  vtkTerroirGeoTIFFWriter();
  ~vtkTerroirGeoTIFFWriter() override;

  void WriteData() override;

  int Compression = COMPRESSION_NONE;
  bool Tiled = false;
  int Threads = 0;
  bool Overviews = false;

private:
  vtkTerroirGeoTIFFWriter(const vtkTerroirGeoTIFFWriter&) = delete;
  void operator=(const vtkTerroirGeoTIFFWriter&) = delete;
};

#endif
