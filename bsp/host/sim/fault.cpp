// Host fault handler: report the failed check and abort, so a test fails loudly (or a death test matches).
#include <cstdio>
#include <cstdlib>

#include "core/assert.hpp"

namespace fw {

void onFault(Module module, uint16_t line) {
  std::fprintf(stderr, "FW_ASSERT failed: module %u line %u\n", static_cast<unsigned>(module),
               static_cast<unsigned>(line));
  std::abort();
}

}  // namespace fw
