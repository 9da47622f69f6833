// libFuzzer target: bms-sim's scenario parser (bsp/host/tools/bms-sim/scenario.*) on arbitrary bytes.
//
// Beyond not crashing under ASan + UBSan, every input must end in one of two ways: an error that names the
// source, line and column, or a scenario whose steps are in time order with every value inside the range
// scenario.hpp promises (the run loop relies on both). The image checks then run against a two-board pack.
// Seeds: tests/fuzz/corpus/scenario/ (the built-ins as files and the inputs that once crashed or misread).
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string_view>

// Relative to this file, so the target needs no include directory of its own.
#include "../../bsp/host/tools/bms-sim/scenario.hpp"

namespace {

using namespace bmssim;

void require(bool ok) {
  if (!ok) std::abort();
}

bool within(int32_t v, ValueRange r) {
  return v >= r.lo && v <= r.hi;
}

void checkStep(const Step& st) {
  require(st.timeMs <= kMaxTimeMs && st.line >= 1);
  switch (st.action) {
    case Action::Current:
      require(within(st.value, kCurrentMaRange));
      break;
    case Action::Cell:
    case Action::AllCells:
      require(within(st.value, kCellMvRange));
      break;
    case Action::Temp:
      require(within(st.value, kTempDeciKRange));
      break;
    case Action::RampCell:
    case Action::RampAll:
      require(within(st.value, {-kCellMvRange.hi, kCellMvRange.hi}));
      break;
    case Action::RampTemp:
      require(within(st.value, {-2050, 2050}));
      break;
    case Action::Expect:
      require(!st.fault.empty() && (!st.hasLimit || st.watch != Watch::None));
      break;
    default:
      break;
  }
  const bool indexed = st.action == Action::Cell || st.action == Action::RampCell ||
                       st.action == Action::OpenWire || st.action == Action::Temp ||
                       st.action == Action::RampTemp;
  if (indexed) require(st.board >= 0 && st.board <= 63 && st.index >= 1 && st.index <= 16);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  Diagnostics diag;
  const auto scenario = parseScenario(text, "fuzz", diag);
  if (!scenario) {
    require(diag.error.starts_with("fuzz:") && diag.error.find(": error: ") != std::string::npos);
    return 0;
  }
  for (size_t i = 0; i < scenario->steps.size(); ++i) {
    checkStep(scenario->steps[i]);
    if (i > 0) require(scenario->steps[i - 1].timeMs <= scenario->steps[i].timeMs);
  }
  Diagnostics check;
  if (!checkScenario(*scenario, {2, 16, 2, false}, 10000, check)) {
    require(check.error.starts_with("fuzz:") && check.error.find(": error: ") != std::string::npos);
  }
  return 0;
}
