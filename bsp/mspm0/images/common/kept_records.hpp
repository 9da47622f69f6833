// Start-up of an image's records kept in flash (app/store/persistence.hpp): restores them (the settings
// written by command, the state of charge where the image counts it), writes the
// fault record of this reset, announces the Startup message with what was restored, and hooks the store to
// the application's protection and command tasks. Call once from appInit(), before app.start(), instead of
// announcing the Startup message alone. `watch`: the fault line the flash driver watches while it programs
// or erases (data_flash.hpp; nullptr: none).
#pragma once

#include <cstdint>

#include "app/store/persistence.hpp"
#include "common/construct_once.hpp"
#include "common/data_flash.hpp"
#include "common/startup_info.hpp"
#include "sched/scheduler.hpp"

namespace image {

template <class App>
fw::app::store::Persistence& startKeptRecords(App& app, fw::sched::Scheduler& scheduler, uint8_t resetCause,
                                              const bsp::mspm0::FlashFaultWatch* watch = nullptr) {
  auto& records =
      constructOnce<fw::app::store::Persistence>(dataFlash(watch), scheduler, app.pack(), app.settings());
  fw::app::StartupInfo info = startupInfo(resetCause);
  records.start(info);
  // The kept state of charge is the counted one's starting value (the BQ4050's gauge keeps its own).
  if constexpr (requires { app.stateOfCharge().restore(uint16_t{}); }) {
    uint16_t permille = 0;
    if (records.restoredSoc(permille)) app.stateOfCharge().restore(permille);
  }
  app.attachStore(records, records);
  app.announceStartup(info);
  return records;
}

}  // namespace image
