// Build options of firmware/core: every option's default, meaning and dependencies. An image sets its values
// in bsp/mspm0/images/<preset>/options.cmake; the host build uses these defaults.
#pragma once

// Statistics counters (core/stats.hpp): how many scans, transactions, frames, alerts a module has seen, for
// the host tools and a debugger. 0 keeps them at 0 and saves their code and RAM; no image ships without them.
// A counter the firmware acts on (the link's retries) is not a statistic and is always kept.
#ifndef FW_STATS
#define FW_STATS 1
#endif

// Where objects holding Zeroed<T> blocks live (core/zeroed.hpp). Not an image option: the MSPM0 BSP sets 1
// for every image (bsp/mspm0/CMakeLists.txt), whose applications are built once in static storage the reset
// handler has zeroed, so the blocks are not cleared again. 0 (host, qemu-m0): objects live anywhere and each
// block is cleared at construction.
#ifndef FW_ZEROED_STORAGE
#define FW_ZEROED_STORAGE 0
#endif
