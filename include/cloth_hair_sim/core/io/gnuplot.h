#pragma once
#include <string>

namespace chs {

// Runs a gnuplot script through the gnuplot binary (environment variable CHS_GNUPLOT, else
// `gnuplot` on PATH) via a temporary script file; data belongs in the script as datablocks.
// Throws std::runtime_error with gnuplot's own message if gnuplot is missing or fails.
void runGnuplot(const std::string& script);

// Quotes a file name or title for a gnuplot script.
std::string gnuplotQuote(const std::string& text);

}  // namespace chs
