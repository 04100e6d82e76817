// Shared by the fuzz harnesses that go through GDAL and VTK: register GDAL's drivers once and
// silence GDAL's and VTK's messages (the harnesses check the readers' own error strings).
#ifndef FuzzQuietGDAL_h
#define FuzzQuietGDAL_h

#include "vtkLogger.h"
#include "vtkObject.h"

#include <cpl_conv.h>
#include <cpl_error.h>
#include <gdal.h>

namespace terroir_fuzz
{
/// Call once per process: `static const bool quiet = QuietGDALAndVTK();`.
inline bool QuietGDALAndVTK()
{
  GDALAllRegister();
  CPLSetConfigOption("GDAL_PAM_ENABLED", "NO");
  CPLSetErrorHandler(CPLQuietErrorHandler);
  vtkObject::GlobalWarningDisplayOff();
  vtkLogger::SetStderrVerbosity(vtkLogger::VERBOSITY_OFF);
  return true;
}
} // namespace terroir_fuzz

#endif
