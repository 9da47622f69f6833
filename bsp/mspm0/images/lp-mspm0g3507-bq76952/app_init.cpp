// Application of the lp-mspm0g3507-bq76952 image: the BQ76952 monitor (probe, one CONFIG_UPDATE, FET enable,
// scans), the firmware protection (FETs through the BQ76952, the fault output PB26 high while it holds a
// path off) and CAN publishing (firmware/app/monitors/bq769x_app.hpp).
// The BQ76952's CFETOFF and DFETOFF inputs on PB2 and PB3 (bsp/mspm0/README.md "Connections"; PINCM15 and
// PINCM16, mspm0g350x.h IOMUX_PINCM15_PF_GPIOB_DIO02 / PINCM16_PF_GPIOB_DIO03): protection drives them high
// while it holds that path off, so a path opens without I2C (app/monitors/fet_mailbox.hpp). Asserted from
// start-up until protection's first request. While the record store programs or erases the flash, its
// driver's wait watches ALERT (PB0's edge) and drives both pins high itself (bsp/mspm0/flashctl.hpp).
#include <string_view>

#include "app/monitors/bq769x_app.hpp"
#include "app/monitors/bq769x_settings.hpp"
#include "board.hpp"
#include "chip/mspm0g3507.hpp"
#include "common/construct_once.hpp"
#include "common/kept_records.hpp"
#include "gpio.hpp"
#include "packs/selected.hpp"
#include "sched/scheduler.hpp"

namespace {

// The device settings of the pack this image is built from (BMS_PACK: regmaps/CMakeLists.txt).
static_assert(std::string_view(fw::pack::kDevice) == "bq76952", "BMS_PACK names a pack for another device");
constexpr auto kSettingRows = fw::app::bq76952Settings(fw::pack::kDeviceSettings);
// Packed as the driver walks it (drivers/bq769x2 SettingsTable): only the packed bytes are in the image.
constexpr auto& kSettings = fw::drivers::bq769x2::packedSettings<kSettingRows>;

using App = fw::app::Bq769xApp<fw::drivers::bq769x2::Bq769x2, fw::drivers::bq769x2::Bq769x2Measurement,
                               fw::app::CanPublisher>;

constexpr bsp::mspm0::Pin kChargeOff{1, 2, 15};     // PB2 -> CFETOFF
constexpr bsp::mspm0::Pin kDischargeOff{1, 3, 16};  // PB3 -> DFETOFF
constinit bsp::mspm0::GpioOut chargeOff(kChargeOff);
constinit bsp::mspm0::GpioOut dischargeOff(kDischargeOff);
// ALERT (PB0, the board's monitor signal: board_g3507_can.hpp) during a flash program or erase: both paths
// off, as protection does on the fault line before a scan says which fault. In SRAM (the wait reads it).
static_assert(kChargeOff.port == kDischargeOff.port);
constinit bsp::mspm0::FlashFaultWatch alertWatch = bsp::mspm0::faultLineWatch(
    bsp::mspm0::chip::Mspm0g3507::kPb0, kChargeOff.port, kChargeOff.mask() | kDischargeOff.mask());

}  // namespace

void appInit(image::Board& board, fw::sched::Scheduler& scheduler) {
  chargeOff.init(true);
  dischargeOff.init(true);
  // The board holds the fault output asserted from reset until protection first decides (bringUp()).
  static constinit fw::app::Bq769xAppConfig config{.settings = kSettings,
                                                   .cells = fw::pack::kCells,
                                                   .soc = fw::app::kSoc ? &fw::pack::kSoc : nullptr,
                                                   .currentLsbTenthMa = fw::pack::kCurrentLsbTenthMa,
                                                   .storage = fw::pack::kStorage};
  config.faultIndicator = &board.faultOut;
  config.chargeOffPin = &chargeOff;
  config.dischargeOffPin = &dischargeOff;
  App& app = image::constructOnce<App>(scheduler, board.i2c, board.alert, board.can, board.system, config);
  // Records kept in flash restored, this reset's fault record written; the Startup message: the reset cause
  // the board read, version, fault record, protection-log entries
  alertWatch.armed = &app.pack().monitorRunning;  // the fault line is a fault exactly then (ProtectionTask)
  image::startKeptRecords(app, scheduler, board.system.identity().resetCause, &alertWatch);
  app.start();
}
