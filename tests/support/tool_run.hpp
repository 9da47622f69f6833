// Runs a host tool as a user would and captures what it printed: stdout as lines, stderr as text, and the
// exit status. For tests of command-line contracts (bmsctl, regmapgen, bms-sim).
#pragma once

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>
#include <vector>

namespace test {

struct ToolRun {
  int status = -1;  // exit status, -1 if the tool did not exit normally
  std::vector<std::string> out;
  std::string text;  // stdout exactly as printed (for checks of the whole output, final newline included)
  std::string err;

  bool has(const std::string& line) const {
    for (const auto& l : out) {
      if (l == line) return true;
    }
    return false;
  }
  // The stdout lines that start with `prefix`.
  std::vector<std::string> lines(const std::string& prefix) const {
    std::vector<std::string> v;
    for (const auto& l : out) {
      if (l.rfind(prefix, 0) == 0) v.push_back(l);
    }
    return v;
  }
};

// Runs `command` through the shell. stderr goes to a file unique to this process and call, because ctest runs
// tests as parallel processes.
inline ToolRun runTool(const std::string& command) {
  static int calls = 0;
  const std::string errFile = ::testing::TempDir() + "tool_" + std::to_string(getpid()) + "_" +
                              std::to_string(++calls) + "_stderr.txt";
  ToolRun run;
  FILE* p = popen((command + " 2>" + errFile).c_str(), "r");
  if (p == nullptr) return run;
  char buf[4096];
  std::string text;
  for (size_t n; (n = fread(buf, 1, sizeof buf, p)) > 0;)
    text.append(buf, n);
  const int raw = pclose(p);
  run.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
  run.text = text;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);)
    run.out.push_back(line);
  std::ifstream err(errFile);
  run.err.assign(std::istreambuf_iterator<char>(err), std::istreambuf_iterator<char>());
  std::remove(errFile.c_str());
  return run;
}

}  // namespace test
