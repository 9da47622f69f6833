// Fuzz target: `regmapgen import` (codegen/src/import) on any text, for each family's table kinds.
// Properties checked besides the sanitizers: an import that succeeds prints YAML the reader parses without a
// single syntax error (whatever the cells held: quotes, colons, control characters, long values), and that
// YAML then builds and checks without crashing.
#include <cstdint>
#include <sstream>
#include <string>
#include <vector>

#include "check/check.hpp"
#include "diag/diag.hpp"
#include "import/import.hpp"
#include "model/model.hpp"
#include "yaml/yaml.hpp"

using namespace regmapgen;

// Issue 26: this target ran ~110 inputs/s, the slowest of all. A profile (perf, 300 runs from a 250-input
// corpus) put 52 % of the time in libFuzzer's own InputCorpus::UpdateFeatureFrequency: the entropic
// schedule looks up, for every coverage feature an execution hits, whether it is one of the 100 rarest, and
// reading an 8 KB table text hits about 20 000 features (one per loop count of the line, cell and heading
// loops); the import itself took 17 %. Without the entropic schedule the same machine ran 3.1 times the
// inputs in the same 15 s (24 -> 75/s while other builds were loading it) and reached slightly more
// features. libFuzzer reads its flags after this hook, so the target sets the default here; -entropic=1 on
// the command line still wins (libFuzzer takes the last of a repeated flag).
extern "C" int LLVMFuzzerInitialize(int* argc, char*** argv) {
  static std::vector<char*> args;
  static char entropicOff[] = "-entropic=0";
  args.assign(*argv, *argv + *argc);
  args.insert(args.begin() + 1, entropicOff);
  args.push_back(nullptr);
  *argc = static_cast<int>(args.size()) - 1;
  *argv = args.data();
  return 0;
}

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
