// Helpers for regmapgen tests: run the reader / builder / checker on in-memory files and collect the rendered
// diagnostics.
#pragma once

#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "check/check.hpp"
#include "diag/diag.hpp"
#include "model/model.hpp"
#include "yaml/yaml.hpp"

namespace regmapgen::test {

struct Checked {
  Model model;
  std::size_t errors = 0;
  std::size_t warnings = 0;
  std::string text;  // rendered diagnostics
};

// Builds and checks the given (path, text) files.
inline Checked checkFiles(const std::vector<std::pair<std::string, std::string>>& files) {
  Sources sources;
  for (const auto& [path, text] : files)
    sources.add(path, text);
  Diagnostics diag(sources);
  Checked c;
  c.model = build(sources, diag);
  check(c.model, diag);
  std::ostringstream out;
  diag.render(out);
  c.errors = diag.errorCount();
  c.warnings = diag.warningCount();
  c.text = out.str();
  return c;
}

inline Checked checkText(const std::string& text) {
  return checkFiles({{"t.yaml", text}});
}

// A minimal valid file with one extra list appended.
inline std::string withHeader(const std::string& body) {
  return "family: t\n" + body;
}

}  // namespace regmapgen::test
