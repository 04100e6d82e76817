// Helpers for the rendering tests (Testing/Rendering only; header-only so that the other test
// executables never see rendering symbols).
//
// - TERROIR_SKIP_WITHOUT_DISPLAY(): VTK 9.1 aborts the process when it opens a render window
//   without an X display, so every test that renders calls this first. It skips the test, or
//   fails it when TERROIR_REQUIRE_GPU=1 (CI, where xvfb-run is always used).
// - CompareWithBaseline(view): renders the view at 400 x 400, writes the image to
//   TERROIR_TEMP_DIR/<Suite>_<Test>.png and compares it with
//   Testing/Baselines/<Suite>_<Test>.png using vtkTesting's legacy vtkImageDifference metric and
//   the VTK 9.1 threshold 0.15 (alternates <name>_1.png ... are tried by vtkTesting). On failure
//   the rendered image and <name>.diff.png stay in TERROIR_TEMP_DIR and their paths are printed;
//   a missing baseline fails with the path of the rendered image to review and copy in.
#ifndef TerroirRenderingTestHelpers_h
#define TerroirRenderingTestHelpers_h

#include "vtkImageData.h"
#include "vtkNew.h"
#include "vtkPNGWriter.h"
#include "vtkPointData.h"
#include "vtkSmartPointer.h"
#include "vtkTerroirOverlayView.h"
#include "vtkTesting.h"
#include "vtkUnsignedCharArray.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <cstring>
#include <sstream>
#include <string>

#include <sys/stat.h>

namespace terroir
{
namespace testing
{

/// VTK 9.1's regression threshold (vtkRegressionTestImage.h); never raise it without a comment.
constexpr double ImageThreshold = 0.15;

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

  vtkNew<vtkTesting> testing;
  testing->AddArgument("-V");
  testing->AddArgument(baseline.c_str());
  testing->AddArgument("-T");
  testing->AddArgument(tempDir.c_str());
  std::ostringstream log;
  const int result = testing->RegressionTest(rendered, ImageThreshold, log);
  if (result != vtkTesting::PASSED)
  {
    std::ostringstream threshold;
    threshold << ImageThreshold;
    ADD_FAILURE() << "image differs from " << baseline << " (threshold " << threshold.str()
                  << ")\n  rendered image:   " << rendered << "\n  difference image: " << diff
                  << "\n  vtkTesting says:\n"
                  << log.str();
  }
  else
  {
    std::remove(diff.c_str());
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
