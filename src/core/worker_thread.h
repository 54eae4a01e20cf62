// One long-lived thread that runs the jobs given to it, one at a time, in order.
#pragma once

#include <condition_variable>
#include <deque>
#include <functional>
#include <future>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <type_traits>

namespace plslam {

/// What std::async(std::launch::async, ...) does per call, without a new thread per call:
/// beside the mapping threads of a 2-core machine, a thread kept for the run is scheduled
/// better than one started per frame (the tracking p95 was lower in 12 of 12 paired runs;
/// docs/RESULTS.md, "One thread for the segments, kept"). Thread safety: submit() may be
/// called from any thread. The destructor runs the jobs still queued, then joins.
class WorkerThread {
 public:
  /// `name` (at most 15 characters) is shown by top -H and debuggers.
  explicit WorkerThread(const std::string& name = "plslam-worker");
  ~WorkerThread();
  WorkerThread(const WorkerThread&) = delete;
  WorkerThread& operator=(const WorkerThread&) = delete;

  /// Queues `job`; the future gives its result, or rethrows what it threw.
  template <class Job>
  std::future<std::invoke_result_t<Job>> submit(Job job) {
    auto task = std::make_shared<std::packaged_task<std::invoke_result_t<Job>()>>(std::move(job));
    auto result = task->get_future();
    post([task] { (*task)(); });
    return result;
  }

 private:
  void post(std::function<void()> job);
  void loop();

  std::mutex mutex_;
  std::condition_variable wake_;
  std::deque<std::function<void()>> jobs_;
  bool stopping_ = false;
  std::thread thread_;
};

}  // namespace plslam
