// `terroir run`'s writer thread and its copies (Applications/Commands/RunWriter.h): jobs run in
// the order they were posted, a failure stops the writer and comes back to the poster, the
// queue's bytes stay under the bound, and a snapshot shares no array with the run.
#include "RunWriter.h"

#include "vtkFloatArray.h"
#include "vtkImageData.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkUnsignedCharArray.h"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <future>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

using terroir::app::RunSnapshot;
using terroir::app::RunWriter;

TEST(RunWriter, RunsJobsInOrderOnItsOwnThread)
{
  RunWriter writer(1024);
  std::vector<int> order;
  std::thread::id writerThread;
  for (int k = 0; k < 20; ++k)
  {
    writer.Post(10,
      [&order, &writerThread, k]
      {
        order.push_back(k);
        writerThread = std::this_thread::get_id();
      });
  }
  writer.Finish();
  ASSERT_EQ(order.size(), 20u);
  for (int k = 0; k < 20; ++k)
  {
    EXPECT_EQ(order[k], k);
  }
  EXPECT_NE(writerThread, std::this_thread::get_id());
}

TEST(RunWriter, FirstFailureDropsLaterJobsAndReachesThePoster)
{
  RunWriter writer(1024);
  std::atomic<int> ran{ 0 };
  std::promise<void> release;
  std::shared_future<void> go = release.get_future().share();
  writer.Post(1, [go] { go.wait(); });
  writer.Post(1, [] { throw std::runtime_error("disk full"); });
  writer.Post(1, [&ran] { ++ran; });
  release.set_value();
  try
  {
    writer.Finish();
    FAIL() << "Finish() did not rethrow the job's failure";
  }
  catch (const std::runtime_error& e)
  {
    EXPECT_EQ(std::string(e.what()), "disk full");
  }
  EXPECT_EQ(ran.load(), 0);
  // A later Post rethrows too, and queues nothing.
  EXPECT_THROW(writer.Post(1, [&ran] { ++ran; }), std::runtime_error);
  EXPECT_EQ(ran.load(), 0);
}

TEST(RunWriter, PostWaitsWhileTheQueueHoldsTooManyBytes)
{
  RunWriter writer(100);
  std::promise<void> release;
  std::shared_future<void> go = release.get_future().share();
  writer.Post(80, [go] { go.wait(); });
  // 80 + 30 > 100: the second Post must wait until the first job is done.
  std::atomic<bool> posted{ false };
  std::thread poster(
    [&]
    {
      writer.Post(30, [] {});
      posted = true;
    });
  std::this_thread::sleep_for(std::chrono::milliseconds(100));
  EXPECT_FALSE(posted.load()) << "Post() went past the 100-byte bound";
  release.set_value();
  poster.join();
  EXPECT_TRUE(posted.load());
  // A job larger than the bound alone is accepted once the queue is empty.
  writer.Post(500, [] {});
  writer.Finish();
}

TEST(RunSnapshot, CopiesOnlyNewOrChangedArraysAndSharesNone)
{
  vtkNew<vtkImageData> run;
  run->SetDimensions(4, 3, 1);
  const vtkIdType n = 12;
  auto add = [&](const char* name, float value)
  {
    vtkNew<vtkFloatArray> a;
    a->SetName(name);
    a->SetNumberOfTuples(n);
    a->FillValue(value);
    run->GetPointData()->AddArray(a);
    return a.Get();
  };
  add("Elevation", 100.0f);
  vtkNew<vtkUnsignedCharArray> mask;
  mask->SetName("vtkValidPointMask");
  mask->SetNumberOfTuples(n);
  mask->FillValue(1);
  run->GetPointData()->AddArray(mask);
  vtkFloatArray* slope = add("Slope", 5.0f);

  RunSnapshot snapshots;
  std::size_t bytes = 0;
  vtkSmartPointer<vtkImageData> first = snapshots.Take(run, bytes);
  // Elevation (48 B), the mask (12 B) and Slope (48 B), each copied.
  EXPECT_EQ(bytes, 48u + 12u + 48u);
  ASSERT_NE(first->GetPointData()->GetArray("Slope"), nullptr);
  EXPECT_NE(first->GetPointData()->GetArray("Slope"), slope);
  EXPECT_NE(
    first->GetPointData()->GetArray("Elevation"), run->GetPointData()->GetArray("Elevation"));
  int dims[3];
  first->GetDimensions(dims);
  EXPECT_EQ(dims[0] * dims[1] * dims[2], 12);

  // The next stage adds Temperature: only it is copied; Elevation's copy is shared.
  add("Temperature", -3.0f);
  vtkSmartPointer<vtkImageData> second = snapshots.Take(run, bytes);
  EXPECT_EQ(bytes, 48u);
  EXPECT_EQ(second->GetPointData()->GetArray("Slope"), nullptr);
  EXPECT_EQ(
    second->GetPointData()->GetArray("Elevation"), first->GetPointData()->GetArray("Elevation"));
  EXPECT_FLOAT_EQ(second->GetPointData()->GetArray("Temperature")->GetComponent(7, 0), -3.0f);

  // A stage that changes Slope in place: it is copied again, with its new values, and the first
  // snapshot keeps the old ones.
  slope->SetValue(2, 42.0f);
  slope->Modified();
  vtkSmartPointer<vtkImageData> third = snapshots.Take(run, bytes);
  EXPECT_EQ(bytes, 48u);
  EXPECT_FLOAT_EQ(third->GetPointData()->GetArray("Slope")->GetComponent(2, 0), 42.0f);
  EXPECT_FLOAT_EQ(first->GetPointData()->GetArray("Slope")->GetComponent(2, 0), 5.0f);
}
