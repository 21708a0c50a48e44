#pragma once
// Runs the drape executable (path from the CHS_DRAPE_EXE compile definition) for the tests of
// its command-line contract.
#include <sys/wait.h>

#include <cstdio>
#include <iostream>
#include <string>

namespace chs::testing {

struct ToolRun {
  int status = -1;
  std::string output;  // stdout and stderr
};

inline ToolRun drape(const std::string& args) {
  ToolRun r;
  const std::string cmd = std::string("'") + CHS_DRAPE_EXE + "' " + args + " 2>&1";
  FILE* pipe = popen(cmd.c_str(), "r");
  if (!pipe) return r;
  char buf[4096];
  while (size_t n = fread(buf, 1, sizeof buf, pipe)) r.output.append(buf, n);
  const int raw = pclose(pipe);
  r.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
  std::cout << "  drape " << args << " -> " << r.status << ": " << r.output;
  return r;
}

}  // namespace chs::testing
