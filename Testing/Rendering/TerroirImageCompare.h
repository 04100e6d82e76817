// The image comparison of the rendering tests (header-only, no rendering: it compares pixels).
//
// Why not vtkTesting's legacy metric: at VTK 9.1's threshold 0.15 it passes the whole image
// 30 % darker, +100 on the red channel or green x 0.6 (it averages a thresholded difference
// over the image); only geometry changes fail it.
//
// The rule (the same in Testing/Python/TestViewer.py): a pixel of one image matches when a
// pixel of the other image within one pixel of it (its 3 x 3 neighbourhood: edges and
// antialiasing may move by a pixel) has every channel within `levels` (8 of 255); the images
// differ when more than `pixels` (16 of 160000) pixels do not match, looked at both ways (a
// test pixel against the baseline, and a baseline pixel against the test image, so a thin line
// that disappears is caught too). Sizes must be equal. TestImageComparison.cxx checks that every
// baseline passes against itself and fails when darkened, tinted, brightened, or when a 10 x 10
// block is inverted or the centre mirrored.
#ifndef TerroirImageCompare_h
#define TerroirImageCompare_h

#include "vtkImageData.h"

#include <algorithm>
#include <cstdlib>
#include <sstream>
#include <string>
#include <vector>

namespace terroir
{
namespace testing
{

struct ImageTolerance
{
  int levels = 8;   ///< per channel, of 255
  long pixels = 16; ///< pixels allowed to differ
};

struct ImageComparison
{
  bool sameSize = false;
  long differing = 0; ///< pixels that match nothing near them (either way)
  long total = 0;
  int worst = 0; ///< the largest per-channel difference to the best neighbour, over the pixels
  bool Passed(const ImageTolerance& t) const { return sameSize && differing <= t.pixels; }
  std::string Describe(const ImageTolerance& t) const
  {
    std::ostringstream os;
    if (!sameSize)
    {
      os << "the sizes differ";
      return os.str();
    }
    os << differing << " of " << total << " pixels differ by more than " << t.levels
       << " levels from every pixel within one pixel (" << t.pixels
       << " allowed); largest difference " << worst << " levels";
    return os.str();
  }
};

/// RGB bytes (3 per pixel, row-major) of an image with 1 to 4 unsigned-char components.
inline std::vector<unsigned char> RGBOf(vtkImageData* image, int& width, int& height)
{
  int dims[3];
  image->GetDimensions(dims);
  width = dims[0];
  height = dims[1];
  const int nc = image->GetNumberOfScalarComponents();
  std::vector<unsigned char> rgb(static_cast<std::size_t>(width) * height * 3);
  const auto* s = static_cast<const unsigned char*>(image->GetScalarPointer());
  for (std::size_t p = 0; p < static_cast<std::size_t>(width) * height; ++p)
  {
    for (int c = 0; c < 3; ++c)
    {
      rgb[3 * p + c] = s[p * nc + (c < nc ? c : 0)];
    }
  }
  return rgb;
}

/**
 * Compares two RGB images (3 bytes per pixel, `width` x `height`) by the rule above.
 * `mask` (optional, width * height) gets 1 on the pixels that differ.
 */
inline ImageComparison CompareRGB(const std::vector<unsigned char>& test,
  const std::vector<unsigned char>& baseline,
  int width,
  int height,
  const ImageTolerance& tolerance,
  std::vector<unsigned char>* mask = nullptr)
{
  ImageComparison r;
  r.total = static_cast<long>(width) * height;
  r.sameSize =
    test.size() == baseline.size() && test.size() == static_cast<std::size_t>(width) * height * 3;
  if (!r.sameSize)
  {
    return r;
  }
  if (mask)
  {
    mask->assign(static_cast<std::size_t>(width) * height, 0);
  }
  // The smallest, over the 3 x 3 neighbourhood of (x, y) in `other`, of the largest channel
  // difference to pixel (x, y) of `one`.
  auto nearest =
    [&](
      const std::vector<unsigned char>& one, const std::vector<unsigned char>& other, int x, int y)
  {
    const unsigned char* a = &one[(static_cast<std::size_t>(y) * width + x) * 3];
    int best = 256;
    for (int dy = -1; dy <= 1 && best > 0; ++dy)
    {
      for (int dx = -1; dx <= 1 && best > 0; ++dx)
      {
        const int qx = x + dx;
        const int qy = y + dy;
        if (qx < 0 || qy < 0 || qx >= width || qy >= height)
        {
          continue;
        }
        const unsigned char* b = &other[(static_cast<std::size_t>(qy) * width + qx) * 3];
        int d = 0;
        for (int c = 0; c < 3; ++c)
        {
          d = std::max(d, std::abs(static_cast<int>(a[c]) - static_cast<int>(b[c])));
        }
        best = std::min(best, d);
      }
    }
    return best;
  };
  for (int y = 0; y < height; ++y)
  {
    for (int x = 0; x < width; ++x)
    {
      const int d = std::max(nearest(test, baseline, x, y), nearest(baseline, test, x, y));
      r.worst = std::max(r.worst, d);
      if (d > tolerance.levels)
      {
        ++r.differing;
        if (mask)
        {
          (*mask)[static_cast<std::size_t>(y) * width + x] = 1;
        }
      }
    }
  }
  return r;
}

} // namespace testing
} // namespace terroir

#endif
