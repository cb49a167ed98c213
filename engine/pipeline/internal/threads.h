// How the pipeline sets up its threads: names, CPU pinning, nice values, TBB's workers and OpenCV's thread
// count. Linux only; every call is best effort (a refused setting leaves the thread as it was).
#pragma once

#include <sched.h>

#include <string>
#include <vector>

namespace semap::pipeline_internal {

// "0-3, 6" for the CPUs in `set`.
std::string AvailableCpus(const cpu_set_t& set);

// Pins the calling thread to `cpus` (nothing when empty).
void PinCurrentThread(const std::vector<int>& cpus);

// Names the calling pipeline thread (as `top -H` and gdb show it; at most 15 characters), pins it, and makes
// it `nicer` steps nicer than it is (a nice value is per thread on Linux).
void SetUpThread(const char* name, const std::vector<int>& cpus, int nicer = 0);

// Starts TBB's worker threads from the calling thread. A thread takes its nice value (and CPU affinity) from
// the thread that starts it, and TBB starts its workers on first demand: started by a niced feeder (OpenCV's
// SGBM runs on TBB), they would run the map's parallel votes at the feeders' priority. A worker that does not
// start within the wait starts later, from whichever thread needs it.
void StartTbbWorkers();

// OpenCV's thread count (process-wide) for a scope, restored when it ends; 0 leaves it as it is.
class OpenCvThreads {
 public:
  explicit OpenCvThreads(int threads);
  ~OpenCvThreads();
  OpenCvThreads(const OpenCvThreads&) = delete;
  OpenCvThreads& operator=(const OpenCvThreads&) = delete;

 private:
  int previous_;
  bool set_;
};

}  // namespace semap::pipeline_internal
