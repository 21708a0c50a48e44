#pragma once
// Runs the drape and simulate executables (paths from the CHS_DRAPE_EXE and CHS_SIMULATE_EXE
// compile definitions) for the tests of their command-line contracts.
#include <sys/wait.h>

#include <cstdio>
#include <iostream>
#include <string>

namespace chs::testing {

struct ToolRun {
  int status = -1;
  std::string output;  // stdout and stderr
};

inline ToolRun runTool(const std::string& exe, const std::string& name, const std::string& args) {
  ToolRun r;
  const std::string cmd = "'" + exe + "' " + args + " 2>&1";
  FILE* pipe = popen(cmd.c_str(), "r");
  if (!pipe) return r;
  char buf[4096];
  while (size_t n = fread(buf, 1, sizeof buf, pipe)) r.output.append(buf, n);
  const int raw = pclose(pipe);
  r.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
  std::cout << "  " << name << " " << args << " -> " << r.status << ": " << r.output;
  return r;
}

inline ToolRun drape(const std::string& args) {
  return runTool(CHS_DRAPE_EXE, "drape", args);
}
inline ToolRun simulate(const std::string& args) {
  return runTool(CHS_SIMULATE_EXE, "simulate", args);
}

}  // namespace chs::testing
