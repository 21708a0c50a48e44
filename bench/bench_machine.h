#pragma once
// What a timing was measured on: the command-line benchmarks print this first, because wall
// times on a shared machine mean little without the core count and the load.
#include <chrono>
#include <cstdio>
#include <fstream>
#include <string>
#include <thread>

namespace chs::bench {

using Clock = std::chrono::steady_clock;

inline double secondsSince(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// The first line of /proc/cpuinfo's "model name", or "unknown".
inline std::string cpuModel() {
  std::ifstream in("/proc/cpuinfo");
  for (std::string line; std::getline(in, line);)
    if (line.rfind("model name", 0) == 0) return line.substr(line.find(':') + 2);
  return "unknown";
}

// The 1-minute load average: other processes on the same cores inflate wall times.
inline std::string loadAverage() {
  std::ifstream in("/proc/loadavg");
  std::string one;
  in >> one;
  return one.empty() ? "unknown" : one;
}

inline void printMachine(int threads) {
  std::printf("machine: %s, nproc %u, load average (1 min) %s, threads used by the core %d\n",
              cpuModel().c_str(), std::thread::hardware_concurrency(), loadAverage().c_str(),
              threads);
}

}  // namespace chs::bench
