// Fuzz target: `regmapgen import` (codegen/src/import) on any text, for each family's table kinds.
// Properties checked besides the sanitizers: an import that succeeds prints YAML the reader parses without a
// single syntax error (whatever the cells held: quotes, colons, control characters, long values), and that
// YAML then builds and checks without crashing.
#include <cstdint>
#include <sstream>
#include <string>

#include "check/check.hpp"
#include "diag/diag.hpp"
#include "import/import.hpp"
#include "model/model.hpp"
#include "yaml/yaml.hpp"

using namespace regmapgen;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size == 0) return 0;
  static const char* const families[] = {"", "bq769x2", "bq79616", "bq4050"};
  ImportOptions opts;
  opts.family = families[data[0] % 4];
  const std::string text(reinterpret_cast<const char*>(data) + 1, size - 1);
  std::ostringstream out, err;
  if (runImport("fuzz.txt", text, opts, out, err) != 0) return 0;

  Sources sources;
  const int file = sources.add("imported.yaml", out.str());
  Diagnostics syntax(sources);
  (void)yaml::parse(sources, file, syntax);
  if (syntax.errorCount() != 0) {
    syntax.render(err);
    __builtin_trap();  // import wrote YAML its own reader refuses
  }
  Diagnostics diag(sources);
  const Model model = build(sources, diag);
  check(model, diag);
  return 0;
}
