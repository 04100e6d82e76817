#include "vtkTerroirXDisplay.h"

#include <chrono>
#include <cstdlib>
#include <thread>

#include <X11/Xlib.h>

namespace terroir
{
namespace rendering
{
void* OpenXDisplay(std::string& why)
{
  const char* name = std::getenv("DISPLAY");
  if (!name || !*name)
  {
    why = "no X display (DISPLAY unset); run under xvfb-run -a";
    return nullptr;
  }
  for (int attempt = 0; attempt < 40; ++attempt)
  {
    if (Display* display = XOpenDisplay(name))
    {
      why.clear();
      return display;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  why = std::string("cannot connect to the X display '") + name +
    "' (is the X server running?); run under xvfb-run -a";
  return nullptr;
}

void CloseXDisplay(void* display)
{
  if (display)
  {
    XCloseDisplay(static_cast<Display*>(display));
  }
}
}
}
