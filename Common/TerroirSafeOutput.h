/**
 * @file TerroirSafeOutput.h
 * @brief Outputs written under a temporary name and renamed into place.
 *
 * Plain C++ (no VTK types), but part of the Terroir::Common library so that one registry of
 * temporaries serves every module and program in the process.
 *
 * Every Terroir writer writes to a hidden temporary file in the target's folder
 * (".<name>.tmp<pid>_<n><ext>") and renames it onto the target only when the whole file was
 * written, so a failure midway (disk full, `ulimit -f`, an error, a signal) never leaves a
 * partial file nor damages an earlier result: rename(2) within one folder is atomic.
 *
 * The temporaries are registered while they exist. A program that calls
 * InstallSignalCleanup() (the `terroir` command does) removes them when it is interrupted
 * (SIGINT, SIGTERM, SIGHUP, SIGQUIT) before the signal ends it, and ignores SIGXFSZ, so that a
 * write past the file-size limit fails with EFBIG and is cleaned up instead of killing it.
 */
#ifndef TerroirSafeOutput_h
#define TerroirSafeOutput_h

#include "vtkTerroirCommonModule.h" // For export macro

#include <string>

namespace terroir
{

/// A new, unused temporary name beside `target` (same folder, hidden, same extension),
/// registered for removal on a signal.
VTKTERROIRCOMMON_EXPORT std::string TemporaryNameFor(const std::string& target);

/// Renames `temporary` onto `target` (replacing it). On failure removes the temporary and sets
/// `error` ("cannot rename the temporary file into place (<strerror>)"). Unregisters it.
VTKTERROIRCOMMON_EXPORT bool CommitTemporary(const std::string& temporary,
  const std::string& target,
  std::string& error);

/// Holds every CommitTemporary() from now on, from any thread: the temporary stays (registered,
/// so a signal still removes it) and its rename waits for ReleaseHeldCommits(). A job that
/// writes many files (`terroir run`) thus puts all of them in place at its end, or none:
/// a failure or an interruption midway leaves earlier results as they were. Not nested.
VTKTERROIRCOMMON_EXPORT void HoldCommits();

/// Renames every held temporary onto its target, in the order they were committed, and ends
/// the hold. On a failed rename sets `error` ("<target>: cannot rename ...") and removes the
/// temporaries not yet renamed.
VTKTERROIRCOMMON_EXPORT bool ReleaseHeldCommits(std::string& error);

/// Removes every held temporary and ends the hold (after a failure).
VTKTERROIRCOMMON_EXPORT void DiscardHeldCommits();

/// Removes a temporary after a failure and unregisters it.
VTKTERROIRCOMMON_EXPORT void DiscardTemporary(const std::string& temporary);

/// Removes every registered temporary now (async-signal-safe: unlink only).
VTKTERROIRCOMMON_EXPORT void RemoveRegisteredTemporaries();

/// Number of temporaries registered now (tests).
VTKTERROIRCOMMON_EXPORT int RegisteredTemporaryCount();

/// See the file comment. Safe to call more than once.
VTKTERROIRCOMMON_EXPORT void InstallSignalCleanup();

} // namespace terroir

#endif
