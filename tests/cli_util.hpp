// Runs the `dloam` command-line tool (DLOAM_BINARY, set by tests/CMakeLists.txt) and captures its
// exit code and its stdout + stderr, for the tests of the command-line front-end.
#pragma once

#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <string>

namespace dloam::test {

struct CliRun {
  int status = -1;  ///< exit code, -1 when the tool did not exit normally
  std::string output;
};

inline CliRun run_dloam(const std::string& args) {
  CliRun run;
  FILE* pipe = popen((std::string(DLOAM_BINARY) + " " + args + " 2>&1").c_str(), "r");
  if (!pipe) return run;
  std::array<char, 4096> buf{};
  while (std::fgets(buf.data(), buf.size(), pipe)) run.output += buf.data();
  const int status = pclose(pipe);
  run.status = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return run;
}

}  // namespace dloam::test
