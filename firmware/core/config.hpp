// Build options of firmware/core: every option's default, meaning and dependencies. An image sets its values
// in bsp/mspm0/images/<preset>/options.cmake; the host build uses these defaults.
#pragma once

// Statistics counters (core/stats.hpp): how many scans, transactions, frames, alerts a module has seen, for
// the host tools and a debugger. 0 keeps them at 0 and saves their code and RAM; no image ships without them.
// A counter the firmware acts on (the link's retries) is not a statistic and is always kept.
#ifndef FW_STATS
#define FW_STATS 1
#endif
