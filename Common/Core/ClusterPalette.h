/**
 * @file ClusterPalette.h
 * @brief The colours of ecological zones (k-means clusters): Tableau 10, then navy and black.
 * Zone i gets entry i mod 12 (negative ids wrap too). The one palette the zone tables
 * (KMeansClusterColor, `Color` in clusters.csv/json) and the `Clusters` overlay preset
 * (vtkTerroirColorPresets) both use. Plain C++, header only.
 */
#ifndef terroir_ClusterPalette_h
#define terroir_ClusterPalette_h

namespace terroir
{

constexpr int kClusterPaletteSize = 12;

/// sRGB, 0..255.
constexpr unsigned char kClusterPalette[kClusterPaletteSize][3] = {
  { 0x1f, 0x77, 0xb4 }, // blue
  { 0xff, 0x7f, 0x0e }, // orange
  { 0x2c, 0xa0, 0x2c }, // green
  { 0xd6, 0x27, 0x28 }, // red
  { 0x94, 0x67, 0xbd }, // purple
  { 0x8c, 0x56, 0x4b }, // brown
  { 0xe3, 0x77, 0xc2 }, // pink
  { 0x7f, 0x7f, 0x7f }, // grey
  { 0xbc, 0xbd, 0x22 }, // olive
  { 0x17, 0xbe, 0xcf }, // cyan
  { 0x00, 0x00, 0x80 }, // navy
  { 0x00, 0x00, 0x00 }, // black
};

/// The colour of zone `id` (three values, 0..255).
inline const unsigned char* ClusterColorRGB(int id)
{
  return kClusterPalette[((id % kClusterPaletteSize) + kClusterPaletteSize) % kClusterPaletteSize];
}

} // namespace terroir

#endif
