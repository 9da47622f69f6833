// Minimal checks for tests that run on the target under QEMU: failures are printed through semihosting and
// counted; main() returns the count, which becomes QEMU's exit code (0 = pass).
#pragma once

#include <cstdint>

#include "semihosting.hpp"

namespace qtest {

inline int& failures() {
  static int count = 0;
  return count;
}

inline void fail(const char* file, int line, const char* what) {
  bsp::qemu::print("FAIL ");
  bsp::qemu::print(file);
  bsp::qemu::print(":");
  bsp::qemu::printUnsigned(static_cast<uint32_t>(line));
  bsp::qemu::print(": ");
  bsp::qemu::print(what);
  bsp::qemu::print("\n");
  ++failures();
}

inline int finish(const char* name) {
  bsp::qemu::print(failures() == 0 ? "PASS " : "FAILED ");
  bsp::qemu::print(name);
  bsp::qemu::print("\n");
  return failures();
}

}  // namespace qtest

#define QCHECK(cond)                                       \
  do {                                                     \
    if (!(cond)) ::qtest::fail(__FILE__, __LINE__, #cond); \
  } while (0)
