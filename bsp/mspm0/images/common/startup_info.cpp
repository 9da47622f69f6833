#include "startup_info.hpp"

#include "fault.hpp"

namespace image {

fw::app::StartupInfo startupInfo(uint8_t resetCause) {
  const bsp::mspm0::StartupReport r = bsp::mspm0::takeStartupReport(resetCause);
  return {r.resetCause, r.fault.valid, static_cast<uint8_t>(r.fault.module), r.fault.line};
}

}  // namespace image
