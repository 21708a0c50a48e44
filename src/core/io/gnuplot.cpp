#include "cloth_hair_sim/core/io/gnuplot.h"

#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <vector>

namespace chs {

namespace {

bool onPath(const std::string& exe) {
  if (exe.find('/') != std::string::npos) return access(exe.c_str(), X_OK) == 0;
  const char* path = std::getenv("PATH");
  std::stringstream dirs(path ? path : "");
  std::string dir;
  while (std::getline(dirs, dir, ':'))
    if (!dir.empty() && access((dir + "/" + exe).c_str(), X_OK) == 0) return true;
  return false;
}

// A file in the temp directory, removed when this goes out of scope.
struct TempFile {
  std::string path;
  explicit TempFile(const std::string& suffix) {
    std::string pattern =
        (std::filesystem::temp_directory_path() / ("chs_gnuplot_XXXXXX" + suffix)).string();
    std::vector<char> buf(pattern.begin(), pattern.end());
    buf.push_back('\0');
    const int fd = mkstemps(buf.data(), static_cast<int>(suffix.size()));
    if (fd < 0) throw std::runtime_error("gnuplot: cannot create a temporary file");
    close(fd);
    path = buf.data();
  }
  ~TempFile() {
    std::error_code ec;
    std::filesystem::remove(path, ec);
  }
};

}  // namespace

std::string gnuplotQuote(const std::string& text) {
  std::string out = "\"";
  for (char c : text) {
    if (c == '"' || c == '\\') out += '\\';
    out += c;
  }
  return out + "\"";
}

void runGnuplot(const std::string& script) {
  const char* env = std::getenv("CHS_GNUPLOT");
  const std::string exe = env && *env ? env : "gnuplot";
  if (!onPath(exe))
    throw std::runtime_error("gnuplot not found (looked for '" + exe +
                             "'; install gnuplot-nox or set CHS_GNUPLOT): no pictures written");
  TempFile script_file(".gp"), log_file(".log");
  {
    std::ofstream out(script_file.path);
    out << script;
    if (!out) throw std::runtime_error("gnuplot: cannot write " + script_file.path);
  }
  const std::string command =
      "'" + exe + "' '" + script_file.path + "' > '" + log_file.path + "' 2>&1";
  const int status = std::system(command.c_str());
  if (status != 0) {
    std::ifstream log(log_file.path);
    std::stringstream text;
    text << log.rdbuf();
    throw std::runtime_error("gnuplot failed (status " + std::to_string(status) +
                             "): " + text.str());
  }
}

}  // namespace chs
