/**
 * @file RunWriter.h
 * @brief `terroir run`'s writer: one thread that writes the files of finished stages, in the
 * order they were posted, while later stages compute.
 *
 * Each job carries what it writes (RunSnapshot: copies of the arrays, so that the stages that
 * follow never share an array with the writer) and its size in bytes; Post() waits while the
 * jobs queued hold more than `maxQueuedBytes` (a job larger than that alone waits for an empty
 * queue), which bounds the memory the copies take. The PNG overlays of the thread share one
 * window (OverlayBatch). The first failure stops the writer: the jobs after it are dropped, and
 * Post() and Finish() rethrow it.
 */
#ifndef TerroirRunWriter_h
#define TerroirRunWriter_h

#include "vtkImageData.h"
#include "vtkSmartPointer.h"

#include <condition_variable>
#include <cstddef>
#include <deque>
#include <exception>
#include <functional>
#include <map>
#include <mutex>
#include <string>
#include <thread>
#include <utility>

namespace terroir
{
namespace app
{

class RunWriter
{
public:
  explicit RunWriter(std::size_t maxQueuedBytes);
  /// Waits for the job being written; drops the others (after a failure of the run).
  ~RunWriter();
  RunWriter(const RunWriter&) = delete;
  RunWriter& operator=(const RunWriter&) = delete;

  /// Queues `job` (holding `bytes` of data); rethrows the writer's failure if there was one.
  void Post(std::size_t bytes, std::function<void()> job);
  /// Waits until every job is written; rethrows the first failure.
  void Finish();

private:
  void Loop();
  void RethrowFailure();

  struct Job
  {
    std::size_t Bytes;
    std::function<void()> Run;
  };
  const std::size_t MaxQueuedBytes;
  std::mutex Lock;
  std::condition_variable Changed;
  std::deque<Job> Queue;
  std::size_t QueuedBytes = 0;
  bool Busy = false;
  bool Closing = false;
  std::exception_ptr Failure;
  std::thread Thread;
};

/// Copies of a run's arrays for the writer: Take() returns a terrain with the grid, a copy of
/// the field data, copies of Elevation and the valid mask (made once, shared by every terrain
/// it returns) and copies of the point arrays added or changed since the last Take().
class RunSnapshot
{
public:
  /// The arrays of `result` new since the last call; `bytes` is what the copies hold.
  vtkSmartPointer<vtkImageData> Take(vtkImageData* result, std::size_t& bytes);

private:
  vtkSmartPointer<vtkImageData> Base; ///< the grid with the shared Elevation and mask copies
  /// Each array copied so far: the original it came from and that original's time then.
  std::map<std::string, std::pair<const void*, unsigned long long>> Copied;
};

} // namespace app
} // namespace terroir

#endif
