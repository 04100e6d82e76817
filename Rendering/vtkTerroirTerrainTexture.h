/**
 * @class   vtkTerroirTerrainTexture
 * @brief   Jensen's (2011) non-periodic terrain texture for a relief surface: built from a
 *          terrain and put on a vtkTerroirReliefSurface with its texture coordinates.
 *
 * Update() builds the texture of a terrain (`Elevation` in metres, optional
 * `vtkValidPointMask`, optional one-component `ClusterId` zones) with
 * terroir::rendering::BuildTerrainTexture (Rendering/Core/TriangleTexturing.h): eight
 * edge-matched right-triangle tiles per material (grass, forest floor, dry soil, rock, sand,
 * snow) blended by slope, height (sand up to 5 m above SeaLevel, snow around SnowLine; NaN: at
 * 85 % of the elevation range, a band of a tenth of it) and zone (ClusterId mod 3). It keeps
 * the texture while the terrain's arrays (by identity and modification time), grid and the
 * settings stay the same. ApplyTo() gives the relief's drawn points their texture coordinates,
 * puts the texture on its surface actor and makes its colour white (the texture replaces the
 * colours); Remove() takes them away again.
 *
 * Settings: Seed (1), TexelsPerCell (16, 2..256), MaxTextureSize (4096, 64..16384: larger grids
 * share one tile between k x k cells), SeaLevel (0 m), SnowLine (NaN). Used by
 * vtkTerroirOverlayView (Texturing) and `terroir view` (F8). Documentation/Texturing.md.
 */
#ifndef vtkTerroirTerrainTexture_h
#define vtkTerroirTerrainTexture_h

#include "vtkObject.h"
#include "vtkTerroirRenderingModule.h" // For export macro

#include <limits> // For the NaN default
#include <memory> // For std::unique_ptr
#include <string> // For the error text

class vtkImageData;
class vtkTerroirReliefSurface;
class vtkTexture;

class VTKTERROIRRENDERING_EXPORT vtkTerroirTerrainTexture : public vtkObject
{
public:
  static vtkTerroirTerrainTexture* New();
  vtkTypeMacro(vtkTerroirTerrainTexture, vtkObject);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  vtkSetMacro(Seed, int);
  vtkGetMacro(Seed, int);
  vtkSetClampMacro(TexelsPerCell, int, 2, 256);
  vtkGetMacro(TexelsPerCell, int);
  vtkSetClampMacro(MaxTextureSize, int, 64, 16384);
  vtkGetMacro(MaxTextureSize, int);
  vtkSetMacro(SeaLevel, double);
  vtkGetMacro(SeaLevel, double);
  vtkSetMacro(SnowLine, double);
  vtkGetMacro(SnowLine, double);

  /// Builds (or keeps) the texture of `terrain`; false with a one-line `error`.
  bool Update(vtkImageData* terrain, std::string& error);
  /// The last texture (null before a successful Update).
  vtkTexture* GetTexture();
  /// The last texture's size in texels and the cells each tile spans (1 unless the grid is big).
  void GetTextureSize(int size[2]) const;
  int GetCellsPerTile() const;
  /// Update(terrain), then the texture on `relief` (its geometry built from `terrain`'s grid).
  bool ApplyTo(vtkTerroirReliefSurface* relief, vtkImageData* terrain, std::string& error);
  /// Takes the texture and the texture coordinates off `relief` (its colour is the caller's).
  static void Remove(vtkTerroirReliefSurface* relief);

protected:
  vtkTerroirTerrainTexture();
  ~vtkTerroirTerrainTexture() override;

  int Seed = 1;
  int TexelsPerCell = 16;
  int MaxTextureSize = 4096;
  double SeaLevel = 0.0;
  double SnowLine = std::numeric_limits<double>::quiet_NaN();

private:
  vtkTerroirTerrainTexture(const vtkTerroirTerrainTexture&) = delete;
  void operator=(const vtkTerroirTerrainTexture&) = delete;
  struct Internals;
  std::unique_ptr<Internals> Internal;
};

#endif
