// `terroir run`'s writer thread and the copies it writes from (RunWriter.h).
#include "RunWriter.h"

#include "TerroirCommandSupport.h"

#include "vtkDataArray.h"
#include "vtkFieldData.h"
#include "vtkPointData.h"

#include "vtkTerroirGeoreference.h"

namespace terroir
{
namespace app
{

RunWriter::RunWriter(std::size_t maxQueuedBytes)
  : MaxQueuedBytes(maxQueuedBytes)
{
  this->Thread = std::thread(&RunWriter::Loop, this);
}

RunWriter::~RunWriter()
{
  {
    std::lock_guard<std::mutex> lock(this->Lock);
    this->Closing = true;
    this->Queue.clear();
    this->QueuedBytes = 0;
  }
  this->Changed.notify_all();
  this->Thread.join();
}

void RunWriter::RethrowFailure()
{
  if (this->Failure)
  {
    std::rethrow_exception(this->Failure);
  }
}

void RunWriter::Post(std::size_t bytes, std::function<void()> job)
{
  std::unique_lock<std::mutex> lock(this->Lock);
  this->Changed.wait(lock,
    [&]
    {
      return this->Failure || this->QueuedBytes == 0 ||
        this->QueuedBytes + bytes <= this->MaxQueuedBytes;
    });
  this->RethrowFailure();
  this->Queue.push_back(Job{ bytes, std::move(job) });
  this->QueuedBytes += bytes;
  lock.unlock();
  this->Changed.notify_all();
}

void RunWriter::Finish()
{
  std::unique_lock<std::mutex> lock(this->Lock);
  this->Changed.wait(lock, [&] { return this->Failure || (this->Queue.empty() && !this->Busy); });
  this->RethrowFailure();
}

void RunWriter::Loop()
{
  OverlayBatch overlays; // this thread's overlays share one window
  for (;;)
  {
    Job job;
    {
      std::unique_lock<std::mutex> lock(this->Lock);
      this->Changed.wait(lock, [&] { return this->Closing || !this->Queue.empty(); });
      if (this->Queue.empty())
      {
        return;
      }
      job = std::move(this->Queue.front());
      this->Queue.pop_front();
      this->Busy = true;
    }
    std::exception_ptr failure;
    try
    {
      job.Run();
    }
    catch (...)
    {
      failure = std::current_exception();
    }
    job.Run = nullptr; // the job's copies go before the queue makes room for more
    {
      std::lock_guard<std::mutex> lock(this->Lock);
      this->Busy = false;
      this->QueuedBytes -= job.Bytes;
      if (failure && !this->Failure)
      {
        this->Failure = failure;
        this->Queue.clear();
        this->QueuedBytes = 0;
      }
    }
    this->Changed.notify_all();
  }
}

namespace
{
vtkSmartPointer<vtkDataArray> CopyOf(vtkDataArray* array, std::size_t& bytes)
{
  vtkSmartPointer<vtkDataArray> copy = vtk::TakeSmartPointer(array->NewInstance());
  copy->DeepCopy(array);
  bytes += static_cast<std::size_t>(copy->GetDataSize()) * copy->GetDataTypeSize();
  return copy;
}
} // namespace

vtkSmartPointer<vtkImageData> RunSnapshot::Take(vtkImageData* result, std::size_t& bytes)
{
  bytes = 0;
  vtkPointData* pd = result->GetPointData();
  const char* shared[] = { vtkTerroirGeoreference::ElevationName(),
    vtkTerroirGeoreference::ValidMaskName() };
  if (!this->Base)
  {
    this->Base = vtkSmartPointer<vtkImageData>::New();
    this->Base->CopyStructure(result);
    for (const char* name : shared)
    {
      if (vtkDataArray* a = pd->GetArray(name))
      {
        this->Base->GetPointData()->AddArray(CopyOf(a, bytes));
        this->Copied[name] = { a, a->GetMTime() };
      }
    }
  }
  auto snapshot = vtkSmartPointer<vtkImageData>::New();
  snapshot->CopyStructure(result);
  snapshot->GetFieldData()->DeepCopy(result->GetFieldData());
  snapshot->GetPointData()->ShallowCopy(this->Base->GetPointData());
  for (int k = 0; k < pd->GetNumberOfArrays(); ++k)
  {
    vtkDataArray* a = pd->GetArray(k);
    if (!a || !a->GetName())
    {
      continue;
    }
    const std::pair<const void*, unsigned long long> now{ a, a->GetMTime() };
    auto known = this->Copied.find(a->GetName());
    if (known != this->Copied.end() && known->second == now)
    {
      continue;
    }
    snapshot->GetPointData()->AddArray(CopyOf(a, bytes));
    this->Copied[a->GetName()] = now;
  }
  return snapshot;
}

} // namespace app
} // namespace terroir
