#include "engine/pipeline/internal/threads.h"

#include <pthread.h>
#include <sys/resource.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <opencv2/core/utility.hpp>

#include "engine/core/parallel.h"

namespace semap::pipeline_internal {

std::string AvailableCpus(const cpu_set_t& set) {
  std::string out;
  for (int c = 0; c < CPU_SETSIZE; ++c) {
    if (!CPU_ISSET(c, &set)) continue;
    int last = c;
    while (last + 1 < CPU_SETSIZE && CPU_ISSET(last + 1, &set)) ++last;
    out += (out.empty() ? "" : ", ") + std::to_string(c) + (last > c ? "-" + std::to_string(last) : "");
    c = last;
  }
  return out;
}

void PinCurrentThread(const std::vector<int>& cpus) {
  if (cpus.empty()) return;
  cpu_set_t set;
  CPU_ZERO(&set);
  for (int c : cpus) CPU_SET(c, &set);
  pthread_setaffinity_np(pthread_self(), sizeof(set), &set);  // unknown CPUs are ignored
}

void SetUpThread(const char* name, const std::vector<int>& cpus, int nicer) {
  pthread_setname_np(pthread_self(), name);
  PinCurrentThread(cpus);
  if (nicer > 0) {
    const auto tid = static_cast<id_t>(syscall(SYS_gettid));
    errno = 0;
    const int nice = getpriority(PRIO_PROCESS, tid);
    if (errno == 0) setpriority(PRIO_PROCESS, tid, nice + nicer);
  }
}

void StartTbbWorkers() {
  constexpr auto kMaxWait = std::chrono::milliseconds(200);
  OnEveryThread(kMaxWait, [] {});
}

OpenCvThreads::OpenCvThreads(int threads) : previous_(cv::getNumThreads()), set_(threads > 0) {
  if (set_) cv::setNumThreads(threads);
}

OpenCvThreads::~OpenCvThreads() {
  if (set_) cv::setNumThreads(previous_);
}

}  // namespace semap::pipeline_internal
