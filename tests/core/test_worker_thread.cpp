#include "core/worker_thread.h"

#include <gtest/gtest.h>

#include <stdexcept>
#include <thread>
#include <vector>

namespace plslam {
namespace {

TEST(WorkerThread, RunsEveryJobInOrderOnOneThreadThatIsNotTheCallers) {
  std::vector<std::thread::id> ran_on;
  std::vector<int> order;
  std::vector<std::future<int>> results;
  {
    WorkerThread worker("test-worker");
    for (int i = 0; i < 50; ++i)
      results.push_back(worker.submit([i, &order, &ran_on] {
        order.push_back(i);  // only the worker touches these, one job at a time
        ran_on.push_back(std::this_thread::get_id());
        return i * i;
      }));
    for (int i = 0; i < 50; ++i) EXPECT_EQ(results[i].get(), i * i);
  }
  ASSERT_EQ(order.size(), 50u);
  for (int i = 0; i < 50; ++i) EXPECT_EQ(order[i], i);
  for (const auto& id : ran_on) {
    EXPECT_EQ(id, ran_on.front());
    EXPECT_NE(id, std::this_thread::get_id());
  }
}

TEST(WorkerThread, AJobsExceptionReachesItsFutureAndTheWorkerGoesOn) {
  WorkerThread worker;
  auto failing = worker.submit([]() -> int { throw std::runtime_error("bad frame"); });
  auto next = worker.submit([] { return 7; });
  EXPECT_THROW(failing.get(), std::runtime_error);
  EXPECT_EQ(next.get(), 7);
}

TEST(WorkerThread, JobsStillQueuedRunBeforeTheDestructorReturns) {
  std::vector<int> done;
  std::future<void> last;
  {
    WorkerThread worker;
    worker.submit([] { std::this_thread::sleep_for(std::chrono::milliseconds(20)); });
    for (int i = 0; i < 5; ++i) last = worker.submit([i, &done] { done.push_back(i); });
  }
  EXPECT_EQ(done.size(), 5u);
  EXPECT_EQ(last.wait_for(std::chrono::seconds(0)), std::future_status::ready);
}

}  // namespace
}  // namespace plslam
