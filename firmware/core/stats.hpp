// Statistics counters: how many scans, transactions, frames, alerts... a module has seen. They feed the host
// tools (bms-sim's figures, bmsctl) and a debugger; nothing in the firmware acts on them.
//
// They are kept unless FW_STATS is 0 (core/config.hpp); with 0 the counters stay 0. A counter the firmware
// does act on (the link's retries, which make a scan start over) is not a statistic and is always kept.
#pragma once

#include "core/config.hpp"

namespace fw {

inline constexpr bool kStats = FW_STATS != 0;

}  // namespace fw
