// ImageSim: one firmware image running on the host BSP against its emulated devices, as bms-sim drives it.
//
// Each image family provides one (sim_<family>.cpp) and registers it by image name. The scenario engine only
// talks to this interface: it moves the emulated pack (cells, current, temperatures), injects faults, and
// reads back what the firmware did.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "app/protection/protection_task.hpp"
#include "hal/can_bus.hpp"
#include "image_description.hpp"
#include "sim/harness.hpp"
#include "sim/peripherals.hpp"
#include "slcan_output.hpp"

namespace bsp::host {
class SimSerial;
}

namespace bmssim {

struct SimOptions {
  std::string image;
  int devices = 0;  // 0 = the image's default
  bool tiLayout = false;
  uint32_t durationMs = 10000;
  std::string elf;         // --elf: run this image on the MSPM0 twin (sim_twin.hpp)
  std::string flashFile;   // --flash: the twin's flash data region kept in this file (twin/flash_file.hpp)
  bool noCrystal = false;  // --no-crystal: the twin's board has no HFXT crystal (twin/periph/sysctl.hpp)
};

// Figures every image reports (the --json summary's keys).
struct SimFigures {
  uint32_t scans = 0;
  uint32_t scanFailures = 0;
  uint32_t scanPeriodMs = 0;
  double scanBusUs = 0;         // bus time of one scan (mean over the scans since start-up)
  double scanTransactions = 0;  // bus transactions per scan (mean)
  uint64_t commErrors = 0;
  uint32_t recoveries = 0;
  uint64_t outputFrames = 0;  // CAN frames sent, or SLCAN lines written
  std::string output;         // "can" or "slcan"
  // The paths as the board confirmed them (PublishStatus::pathsKnown): unknown while nothing confirms them.
  bool chargeOn = false, dischargeOn = false, pathsKnown = false, faultOutput = false;
  uint16_t activeFaults = 0;
  int minCellMv = 0, maxCellMv = 0;
  int boards = 0, validBoards = 0;
  int32_t currentMa = 0;
  std::vector<uint16_t> balancingCells;  // ImageSim::balancingCells()
  int cellSpreadMv = 0;                  // ImageSim::cellSpreadMv()
  int stateOfChargePercent = -1;  // PackSummary.StateOfCharge as the board publishes it; -1 not available
  // The StateOfCharge message as the board publishes it (bms.yaml); -1 not available.
  int socPermille = -1;
  int64_t remainingMah = -1, fullChargeMah = -1;
  int socBasis = -1;  // StateOfCharge.Basis (fw::app::SocBasis)
  // The charge the emulated device let flow since the run began, in mAh (positive charging), where the
  // emulator counts it (the BQ769x2/BQ7690x emulator: the truth the state of charge is checked against).
  std::optional<double> emulatorChargeMah;
  std::vector<std::pair<std::string, std::string>>
      extra;  // more --json keys and values (the twin's CPU figures)
};

// A bus-off of the board's CAN controller: when it began and when the controller was error active again (its
// ISO 11898-1 recovery done), in microseconds of simulated time; no recovery yet: nullopt.
struct BusOffSpan {
  uint64_t startUs = 0;
  std::optional<uint64_t> recoveredUs;
};

// The pack's current paths as the emulated device has them (its FETs, or the fault output where that stands
// for them): a load or charger drives current only through a closed one.
struct Paths {
  bool charge = true, discharge = true;
};

struct SentFrame {
  uint64_t timeUs;
  uint32_t id;
  bool extended;
  std::vector<uint8_t> data;
};

class ImageSim {
 public:
  virtual ~ImageSim() = default;

  virtual int boards() const = 0;
  virtual int cellsPerBoard() const = 0;
  virtual int tempsPerBoard() const = 0;
  virtual bool hasCurrent() const = 0;

  // The emulated pack (scenario inputs). setCurrentMa is the current that flows (ScenarioPlayer gives the
  // load's or charger's current only while paths() has its direction closed).
  virtual void setCellMv(int board, int cell, int mv) = 0;
  virtual void setCurrentMa(int ma) = 0;
  virtual Paths paths() const { return {}; }
  virtual void setTempDeciK(int board, int sensor, int deciK) = 0;
  // Balancing (scenario cell-capacity; the emulators' cell_model.hpp): the capacity of every emulated cell,
  // and what the emulated devices do: per board the cells they balance now (bit c = cell c + 1), and the
  // spread (highest minus lowest) of the cells as they are now. An image without balancing ignores the first
  // and reports no cells.
  virtual void setCellCapacityMah(int) {}
  virtual std::vector<uint16_t> balancingCells() { return {}; }
  virtual int cellSpreadMv() = 0;
  // Faults.
  virtual void setCommLost(bool lost) = 0;         // the monitor stops answering
  virtual void openWire(int board, int cell) = 0;  // the sense line below `cell` is disconnected
  virtual void setIntermittent(bool on) = 0;       // most monitor transactions are corrupted
  virtual bool busOff() = 0;                       // false when the image has no CAN
  // Every bus-off so far, in order (empty on an image without CAN).
  virtual std::vector<BusOffSpan> busOffLog() const { return {}; }
  // Device faults (scenario.hpp: stretch, stuck-scl, stuck-sda, uart-noise, can-error-frames) on the
  // board's links; faultLinks() says which links the board has (a step on another does nothing).
  struct FaultLinks {
    bool i2c = false, uart = false, can = false;
  };
  virtual FaultLinks faultLinks() const { return {}; }
  virtual void i2cStretch(fw::Duration) {}
  virtual void stuckScl() {}
  virtual void stuckSda() {}
  virtual void uartNoise(uint32_t) {}
  virtual void canErrorFrames(uint32_t) {}
  // --profile (the twin only): count cycles per function from now on, then write them (profiler.hpp).
  virtual void startProfile() {}
  // --flash: writes the flash data region back to its file at the end of the run (twin runs only).
  virtual bool saveFlash(std::string& error) {
    error = "no flash to save";
    return false;
  }
  virtual bool writeProfile(const std::string& path, std::string& error) {
    error = path + ": only a run on the twin (--elf) is profiled";
    return false;
  }
  // --can-layout ti is honoured: the run sends seed 001's layout (only the BQ79616 image builds it).
  virtual bool sendsTiLayout() const { return false; }

  // Commands in (scenario send and flood steps). A G3507 board's CAN takes the frame from another node; an
  // L1306 board's UART takes it as an SLCAN line, the channel opened with "O" before the first one. A flood
  // keeps the bus (CAN) or the line (SLCAN) full with frames from `source` until it is cleared ({}).
  // False: the image takes no commands.
  bool sendFrame(const fw::hal::CanFrame& frame);
  bool setFlood(std::function<std::optional<fw::hal::CanFrame>()> source);
  // Bytes from the PC on an L1306 board's SLCAN line (--slcan pty); false without one.
  virtual bool serialSend(std::string_view) { return false; }

  virtual bsp::host::Harness& harness() = 0;
  virtual SimFigures figures() = 0;
  virtual std::vector<fw::app::ProtectionRecord> protectionLog() const = 0;
  virtual std::vector<SentFrame> frames() const = 0;  // CAN frames, or the SLCAN lines decoded
  // The UART that carries the SLCAN text (the L1306 images); null for CAN images.
  // The SLCAN text an L1306 board has sent, or nullopt when the image publishes on CAN.
  virtual std::optional<SentText> slcanText() const { return std::nullopt; }
  // Called after each simulation step (bookkeeping); a binding that overrides it calls pumpSerialFlood().
  virtual void afterStep() { pumpSerialFlood(); }
  // Runs the board for `d` of simulated time: the host images on the harness; the twin runs the MCU. What is
  // due at the end is left for the next run (Harness::runBefore), so a scenario step at t comes before the
  // firmware's tick at t on the host as on the twin: both see a step on the scan grid in the same scan.
  virtual void runFor(fw::Duration d) { harness().runBefore(d); }
  // Why the run cannot go on (the twin stopped on an access no model covers), or empty.
  virtual std::string failure() const { return {}; }
  // The watchdog the board itself feeds (the twin's WWDT), or null: main() then supervises one.
  virtual const bsp::host::SimWatchdog* boardWatchdog() const { return nullptr; }

 protected:
  // The board's CAN: a frame from another node now, or one always waiting (a flood); false without CAN.
  virtual bool canSend(const fw::hal::CanFrame&) { return false; }
  virtual bool canFlood(std::function<std::optional<fw::hal::CanFrame>()>) { return false; }
  // Bytes the PC has sent that have not arrived yet (for an SLCAN flood to keep the line full).
  virtual size_t serialBacklog() const { return 0; }
  // An SLCAN flood: tops the PC's line up with lines from the flood's source.
  void pumpSerialFlood();

 private:
  bool slcanOpened_ = false;
  std::function<std::optional<fw::hal::CanFrame>()> serialFlood_;
};

using SimFactory = std::unique_ptr<ImageSim> (*)(const SimOptions& options, std::string& error);

// One image bms-sim can run (every image folder of this build's families; an image's own simulator,
// bms-sim-<preset>, has that one only).
struct ImageEntry {
  std::string image;    // the preset name
  std::string summary;  // the device and the board's output, for --help
  int defaultDevices;   // --devices when not given
  SimFactory make;      // nullptr: the binding has no host board for this image (`missing` says why)
  std::string missing;
};

// What a family's binding makes of one image of its family: the factory of its host board and what the
// device is ("BQ76952 over I2C"); a factory of nullptr with `missing` for a combination it does not build.
struct ImageBinding {
  SimFactory make = nullptr;
  std::string device;
  std::string missing;
};
using BindImage = ImageBinding (*)(const ImageDescription& image);

// A family's binding (sim_<family>.cpp) registers every image of `family` in the generated list
// (image_descriptions.hpp; in an image's own simulator, BMS_SIM_IMAGE only) through `bind`.
struct ImageRegistrar {
  ImageRegistrar(std::string_view family, int defaultDevices, BindImage bind);
};
const std::vector<ImageEntry>& images();

}  // namespace bmssim
