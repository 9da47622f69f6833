// Fuzz target: regmapgen's YAML reader, model builder and checker (codegen/src/yaml, model, check) on any
// bytes, as `regmapgen check` runs them; the generators too when a file checks clean.
// Properties checked besides the sanitizers: every diagnostic has a position inside the file
// (line 1..lines+1, column >= 1), and rendering them all works.
#include <cstdint>
#include <sstream>
#include <string>

#include "check/check.hpp"
#include "diag/diag.hpp"
#include "emit/emit.hpp"
#include "model/model.hpp"

using namespace regmapgen;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  std::string text(reinterpret_cast<const char*>(data), size);
  long lines = 1;
  for (char c : text)
    lines += c == '\n';
  Sources sources;
  sources.add("fuzz.yaml", std::move(text));
  Diagnostics diag(sources);
  const Model model = build(sources, diag);
  check(model, diag);
  for (const Diagnostic& d : diag.all()) {
    if (d.loc.file == 0 && (d.loc.line < 1 || d.loc.line > lines || d.loc.col < 1)) __builtin_trap();
  }
  std::ostringstream rendered;
  diag.render(rendered);
  if (diag.errorCount() == 0) {
    for (const Family& fam : model.families) {
      (void)emitCode(fam, sources);
      (void)emitMarkdown(fam, sources);
    }
    (void)emitList(model);
  }
  return 0;
}
