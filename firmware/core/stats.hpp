// Statistics counters: how many scans, transactions, frames, alerts... a module has seen. They feed the host
// tools (bms-sim's figures, bmsctl) and a debugger; nothing in the firmware acts on them.
//
// They are kept unless FW_STATS is 0 (default 1: the host and the G3507 images). With 0 (the L1306 images,
// which have no output that carries them and no flash to spare) the counters stay 0. A counter the firmware
// does act on (the link's retries, which make a scan start over) is not a statistic and is always kept.
#pragma once

#ifndef FW_STATS
#define FW_STATS 1
#endif

namespace fw {

inline constexpr bool kStats = FW_STATS != 0;

}  // namespace fw
