/**
 * @file TerroirFlowCommands.h
 * @brief The water-flow commands of `terroir`: waterflow (the hydrostatic simulation), flowacc
 * (the D8 baseline) and validate (both scored against mapped rivers).
 */
#ifndef TerroirFlowCommands_h
#define TerroirFlowCommands_h

#include "TerroirCommandLine.h"

#include <functional>
#include <string>

class vtkImageData;
class vtkImageAlgorithm;

namespace terroir
{
namespace app
{

/// Writes a PNG overlay: (image, array, preset, title, path). Throws Failure.
using OverlayWriterFunction = std::function<void(vtkImageData*,
  const std::string&,
  const std::string&,
  const std::string&,
  const std::string&)>;

int CommandWaterFlow(const CommandLine& c);
int CommandFlowAccumulation(const CommandLine& c);
int CommandValidate(const CommandLine& c, const OverlayWriterFunction& writeOverlay);

} // namespace app
} // namespace terroir

#endif
