// Private helper of Terroir::Rendering: opens the X display for VTK's render window.
// VTK 9.1's vtkXOpenGLRenderWindow aborts the whole process ("bad X server connection") when
// its own XOpenDisplay fails. The view opens the connection here instead (retrying for a
// moment: Xvfb refuses connections while it resets after its last client left, which happens
// between test processes) and hands it to the window with SetDisplayId, so VTK never opens one
// itself. Kept in its own file because <X11/Xlib.h> defines macros (Status, None, Bool,
// Success) that clash with VTK headers.
#ifndef vtkTerroirXDisplay_h
#define vtkTerroirXDisplay_h

#include <string> // For std::string

namespace terroir
{
namespace rendering
{
/// Opens a connection to $DISPLAY (an X11 `Display*`), trying for up to about 2 seconds.
/// Returns nullptr with `why` set to a one-line reason that names the display on failure.
void* OpenXDisplay(std::string& why);

/// Closes a connection returned by OpenXDisplay (nullptr is ignored).
void CloseXDisplay(void* display);
}
}

#endif
