// Runs the motionbus CLI (MOTIONBUS_CLI_PATH) through the shell for the CLI tests.
#ifndef MOTIONBUS_TESTS_RUN_CLI_HPP
#define MOTIONBUS_TESTS_RUN_CLI_HPP

#include <doctest/doctest.h>
#include <sys/wait.h>

#include <cstdio>
#include <string>

namespace testcli {

/// Stdout of `motionbus <args>` (args already shell-quoted); stderr is discarded. `stdin_text`,
/// when given, is piped in through printf (so \\n and \\r escapes are expanded).
inline std::string run_as_is(const std::string& args, int* status = nullptr,
                             const std::string& stdin_text = "") {
  std::string command;
  if (!stdin_text.empty()) {
    command = "printf '" + stdin_text + "' | ";
  }
  command += std::string("'") + MOTIONBUS_CLI_PATH + "' " + args + " 2>/dev/null";
  FILE* pipe = popen(command.c_str(), "r");
  REQUIRE(pipe != nullptr);
  std::string out;
  char buffer[512];
  std::size_t n = 0;
  while ((n = std::fread(buffer, 1, sizeof buffer, pipe)) > 0) {
    out.append(buffer, n);
  }
  const int s = pclose(pipe);
  if (status != nullptr) {
    *status = WIFEXITED(s) ? WEXITSTATUS(s) : -1;
  }
  return out;
}

/// run_as_is with --json: one JSON object per line, as scripts read the tool.
inline std::string run(const std::string& args, int* status = nullptr,
                       const std::string& stdin_text = "") {
  return run_as_is(args + " --json", status, stdin_text);
}

}  // namespace testcli

#endif
