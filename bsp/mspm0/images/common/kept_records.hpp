// Start-up of an image's records kept in flash (app/store/persistence.hpp): restores them, writes the
// fault record of this reset, announces the Startup message with what was restored, and hooks the store to
// the application's protection and command tasks. Call once from appInit(), before app.start(), instead of
// announcing the Startup message alone.
#pragma once

#include <cstdint>

#include "app/store/persistence.hpp"
#include "common/construct_once.hpp"
#include "common/data_flash.hpp"
#include "common/startup_info.hpp"
#include "sched/scheduler.hpp"

namespace image {

template <class App>
fw::app::store::Persistence& startKeptRecords(App& app, fw::sched::Scheduler& scheduler, uint8_t resetCause) {
  auto& records = constructOnce<fw::app::store::Persistence>(dataFlash(), scheduler, app.pack());
  fw::app::StartupInfo info = startupInfo(resetCause);
  records.start(info);
  app.attachStore(records, records);
  app.announceStartup(info);
  return records;
}

}  // namespace image
