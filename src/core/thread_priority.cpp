#include "core/thread_priority.h"

#include <sys/resource.h>
#include <sys/syscall.h>
#include <unistd.h>

namespace plslam {

bool setThisThreadNice(int nice) {
  if (nice <= 0) return true;
  // On Linux a nice value belongs to a thread (its kernel task id), not to the process.
  const auto tid = static_cast<id_t>(syscall(SYS_gettid));
  return setpriority(PRIO_PROCESS, tid, nice > 19 ? 19 : nice) == 0;
}

}  // namespace plslam
