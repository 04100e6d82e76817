/**
 * @class   vtkTerroirFractalTerrainSource
 * @brief   Generates a seeded synthetic DEM of any size from summed gradient noise.
 *
 * Output: vtkImageData (Dimensions[0], Dimensions[1], 1), spacing (Spacing, Spacing, 1)
 * metres, origin (0, 0, 0), point array `Elevation` (float32, metres), no georeference
 * (grid north = true north). Height of cell (i, j):
 *
 *   h = BaseHeight + Amplitude * sum_{o<Octaves} Persistence^o *
 *       noise((i+0.5)/L_o + offx_o, (j+0.5)/L_o + offy_o)
 *
 * with L_o = FeatureSize / 2^o cells, per-octave offsets from the hash (FractalNoise.h), and
 * `noise` the 2-D gradient noise of Perlin (1985) with the quintic fade of Perlin (2002),
 * normalised to [-1, 1], driven by our own 32-bit integer hash
 * (terroir::io::FractalNoisePerlin2002, IO/Core). So |h - BaseHeight| <= Amplitude * sum_o
 * Persistence^o.
 *
 * Generation runs over rows with vtkSMPTools; every value depends only on the parameters and
 * (i, j), so the output is bit-identical for every thread count, backend and platform.
 * RequestInformation sets the extent without generating anything. One float per cell is
 * allocated (8192 x 8192 = 256 MiB).
 *
 * @par Correctness
 * TerroirFractal.* unit tests (determinism, seeds, bound, continuity) and
 * TerroirFractalTerrainSource.* pipeline tests (dimensions, thread-count independence).
 *
 * @par References
 * K. Perlin, "An image synthesizer", SIGGRAPH 1985, doi:10.1145/325165.325247;
 * K. Perlin, "Improving noise", SIGGRAPH 2002, doi:10.1145/566570.566636.
 */
#ifndef vtkTerroirFractalTerrainSource_h
#define vtkTerroirFractalTerrainSource_h

#include "vtkImageAlgorithm.h"
#include "vtkTerroirIOModule.h" // For export macro

#include <string> // For std::string

class VTKTERROIRIO_EXPORT vtkTerroirFractalTerrainSource : public vtkImageAlgorithm
{
public:
  static vtkTerroirFractalTerrainSource* New();
  vtkTypeMacro(vtkTerroirFractalTerrainSource, vtkImageAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /// Number of points (nx, ny). Default: 512 x 512. Each in [1, 65536], nx*ny < 2^31.
  vtkSetVector2Macro(Dimensions, int);
  vtkGetVector2Macro(Dimensions, int);
  ///@}

  ///@{
  /// Cell size in metres (both directions). Default: 10.
  vtkSetMacro(Spacing, double);
  vtkGetMacro(Spacing, double);
  ///@}

  ///@{
  /// Seed; different seeds give unrelated terrains. Default: 1.
  vtkSetMacro(Seed, unsigned int);
  vtkGetMacro(Seed, unsigned int);
  ///@}

  ///@{
  /// Number of octaves summed. Default: 8, range [1, 30].
  vtkSetClampMacro(Octaves, int, 1, 30);
  vtkGetMacro(Octaves, int);
  ///@}

  ///@{
  /// Largest wavelength in cells (> 0). Default: 256.
  vtkSetMacro(FeatureSize, double);
  vtkGetMacro(FeatureSize, double);
  ///@}

  ///@{
  /// Amplitude ratio between successive octaves. Default: 0.5.
  vtkSetMacro(Persistence, double);
  vtkGetMacro(Persistence, double);
  ///@}

  ///@{
  /// Amplitude of the first octave, metres. Default: 500.
  vtkSetMacro(Amplitude, double);
  vtkGetMacro(Amplitude, double);
  ///@}

  ///@{
  /// Mean height, metres. Default: 1500.
  vtkSetMacro(BaseHeight, double);
  vtkGetMacro(BaseHeight, double);
  ///@}

  /// The last error as one line, or "" after a successful run.
  const char* GetErrorMessage() const { return this->ErrorMessage.c_str(); }

protected:
  vtkTerroirFractalTerrainSource();
  ~vtkTerroirFractalTerrainSource() override = default;

  int RequestInformation(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  int Dimensions[2] = { 512, 512 };
  double Spacing = 10.0;
  unsigned int Seed = 1;
  int Octaves = 8;
  double FeatureSize = 256.0;
  double Persistence = 0.5;
  double Amplitude = 500.0;
  double BaseHeight = 1500.0;
  std::string ErrorMessage;

private:
  vtkTerroirFractalTerrainSource(const vtkTerroirFractalTerrainSource&) = delete;
  void operator=(const vtkTerroirFractalTerrainSource&) = delete;

  bool CheckParameters();
};

#endif
