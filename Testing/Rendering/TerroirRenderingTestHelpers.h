// Helpers for the rendering tests (Testing/Rendering only; header-only so that the other test
// executables never see rendering symbols).
//
// - TERROIR_SKIP_WITHOUT_DISPLAY(): VTK 9.1 aborts the process when it opens a render window
//   without an X display, so every test that renders calls this first. It skips the test, or
//   fails it when TERROIR_REQUIRE_GPU=1 (CI, where xvfb-run is always used).
// - CompareWithBaseline(view): renders the view at 400 x 400, writes the image to
//   TERROIR_TEMP_DIR/<Suite>_<Test>.png and compares it with
//   Testing/Baselines/<Suite>_<Test>.png by TerroirImageCompare.h's rule (every pixel within 8
//   levels of a pixel within one pixel of it, both ways; at most 16 pixels otherwise; the
//   alternates <name>_1.png, <name>_2.png, ... are tried in turn). On
//   failure the rendered image and <name>.diff.png (the differing pixels in red) stay in
//   TERROIR_TEMP_DIR and their paths are printed; a missing baseline fails with the path of the
//   rendered image to review and copy in. Map views are probed too: the pixels under cells of
//   uniform colour show the colour table's colour, lit by the view's model
//   (TerroirOverlayProbes.h).
#ifndef TerroirRenderingTestHelpers_h
#define TerroirRenderingTestHelpers_h

#include "TerroirImageCompare.h"
#include "TerroirOverlayProbes.h"

#include "vtkImageData.h"
#include "vtkNew.h"
#include "vtkPNGReader.h"
#include "vtkPNGWriter.h"
#include "vtkPointData.h"
#include "vtkSmartPointer.h"
#include "vtkTerroirOverlayView.h"
#include "vtkUnsignedCharArray.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <cstring>
#include <iostream>
#include <sstream>
#include <string>

#include <sys/stat.h>

namespace terroir
{
namespace testing
{

inline bool HasDisplay()
{
  const char* display = std::getenv("DISPLAY");
  return display && *display;
}

inline bool DisplayRequired()
{
  const char* require = std::getenv("TERROIR_REQUIRE_GPU");
  return require && std::strcmp(require, "1") == 0;
}

/// "<Suite>_<Test>" of the running GoogleTest test ('/' of parameterised names become '_').
inline std::string CurrentTestName()
{
  const ::testing::TestInfo* info = ::testing::UnitTest::GetInstance()->current_test_info();
  std::string name = std::string(info->test_suite_name()) + "_" + info->name();
  for (char& c : name)
  {
    if (c == '/')
    {
      c = '_';
    }
  }
  return name;
}

inline bool FileExists(const std::string& path)
{
  struct stat st;
  return ::stat(path.c_str(), &st) == 0;
}

/// RGB of pixel (x, y) of a grabbed image (y = 0 is the bottom row).
inline void PixelAt(vtkImageData* image, int x, int y, unsigned char rgb[3])
{
  auto* s = static_cast<unsigned char*>(image->GetScalarPointer(x, y, 0));
  const int nc = image->GetNumberOfScalarComponents();
  for (int c = 0; c < 3; ++c)
  {
    rgb[c] = s[c < nc ? c : 0];
  }
}

/// Mean of (R+G+B)/3 over the pixel rectangle [x0, x1) x [y0, y1).
inline double MeanIntensity(vtkImageData* image, int x0, int x1, int y0, int y1)
{
  double sum = 0.0;
  long count = 0;
  for (int y = y0; y < y1; ++y)
  {
    for (int x = x0; x < x1; ++x)
    {
      unsigned char rgb[3];
      PixelAt(image, x, y, rgb);
      sum += (rgb[0] + rgb[1] + rgb[2]) / 3.0;
      ++count;
    }
  }
  return count ? sum / count : 0.0;
}

/// Renders `view` at 400 x 400 and compares it with the test's baseline (see the file comment).
inline void CompareWithBaseline(vtkTerroirOverlayView* view)
{
  const std::string name = CurrentTestName();
  const std::string baseline = std::string(TERROIR_BASELINE_DIR) + "/" + name + ".png";
  const std::string tempDir = TERROIR_TEMP_DIR;
  const std::string rendered = tempDir + "/" + name + ".png";
  const std::string diff = tempDir + "/" + name + ".diff.png";
  std::remove(diff.c_str());

  view->SetWidth(400);
  view->SetHeight(400);
  vtkNew<vtkImageData> image;
  ASSERT_TRUE(view->GetImage(image)) << view->GetLastError();
  int dims[3];
  image->GetDimensions(dims);
  ASSERT_EQ(dims[0], 400);
  ASSERT_EQ(dims[1], 400);
  ExpectPixelsShowTheirCells(view, image); // TerroirOverlayProbes.h

  vtkNew<vtkPNGWriter> writer;
  writer->SetFileName(rendered.c_str());
  writer->SetInputData(image);
  writer->Write();
  ASSERT_EQ(writer->GetErrorCode(), 0u) << "could not write " << rendered;

  if (!FileExists(baseline))
  {
    FAIL() << "no baseline " << baseline << "\n  rendered image: " << rendered
           << "\n  look at it; if it is right, copy it to " << baseline;
  }

  // The baseline, or the first of its alternates <name>_1.png, <name>_2.png, ... that matches
  // (renderer-specific differences get an alternate, never a looser rule).
  int tw = 0, th = 0;
  const std::vector<unsigned char> got = RGBOf(image, tw, th);
  const ImageTolerance tolerance;
  std::vector<unsigned char> mask;
  ImageComparison result;
  std::string candidate = baseline;
  for (int alternate = 1; FileExists(candidate); ++alternate)
  {
    vtkNew<vtkPNGReader> reader;
    reader->SetFileName(candidate.c_str());
    reader->Update();
    int bw = 0, bh = 0;
    const std::vector<unsigned char> expected = RGBOf(reader->GetOutput(), bw, bh);
    std::vector<unsigned char> candidateMask;
    const ImageComparison r = (bw == tw && bh == th)
      ? CompareRGB(got, expected, tw, th, tolerance, &candidateMask)
      : ImageComparison();
    if (alternate == 1 || r.Passed(tolerance))
    {
      result = r;
      mask = candidateMask;
    }
    if (r.Passed(tolerance))
    {
      break;
    }
    candidate =
      std::string(TERROIR_BASELINE_DIR) + "/" + name + "_" + std::to_string(alternate) + ".png";
  }
  std::cout << "[ image ] " << name << ": " << result.Describe(tolerance) << std::endl;
  if (!result.Passed(tolerance))
  {
    // The difference image: the rendering, dimmed, with the differing pixels in red.
    vtkNew<vtkImageData> marked;
    marked->DeepCopy(image);
    if (!mask.empty())
    {
      auto* px = static_cast<unsigned char*>(marked->GetScalarPointer());
      const int nc = marked->GetNumberOfScalarComponents();
      for (std::size_t p = 0; p < mask.size(); ++p)
      {
        for (int c = 0; c < std::min(nc, 3); ++c)
        {
          px[p * nc + c] =
            mask[p] ? (c == 0 ? 255 : 0) : static_cast<unsigned char>(px[p * nc + c] / 3);
        }
      }
    }
    vtkNew<vtkPNGWriter> diffWriter;
    diffWriter->SetFileName(diff.c_str());
    diffWriter->SetInputData(marked);
    diffWriter->Write();
    ADD_FAILURE() << "image differs from " << baseline << ": " << result.Describe(tolerance)
                  << "\n  rendered image:   " << rendered << "\n  difference image: " << diff;
  }
}

} // namespace testing
} // namespace terroir

/// Skips the test without an X display, or fails it when TERROIR_REQUIRE_GPU=1.
#define TERROIR_SKIP_WITHOUT_DISPLAY()                                                             \
  do                                                                                               \
  {                                                                                                \
    if (!terroir::testing::HasDisplay())                                                           \
    {                                                                                              \
      if (terroir::testing::DisplayRequired())                                                     \
      {                                                                                            \
        FAIL() << "no X display (DISPLAY unset) and TERROIR_REQUIRE_GPU=1; run under xvfb-run -a"; \
      }                                                                                            \
      GTEST_SKIP() << "no X display (DISPLAY unset); run under xvfb-run -a";                       \
    }                                                                                              \
  } while (false)

#endif
