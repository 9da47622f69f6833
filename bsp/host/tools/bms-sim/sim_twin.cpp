// bms-sim binding of the twin: the ELF runs on a twin MSPM0 (bsp/twin) wired to the same device emulators the
// host bindings use, and the scenario moves the same emulated pack. Everything reported comes from what the
// board does where a user could see it: the frames on CAN or the SLCAN text, the bus traffic, the FETs of the
// monitor or the fault output pin, the watchdog restarts. Nothing is read out of the firmware's memory.
//
// Protection events come from what the board publishes and does (TwinSim::protectionLog).
#include "sim_twin.hpp"

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <initializer_list>
#include <optional>

#include "app/protection/default_limits.hpp"
#include "app/protection/protection.hpp"
#include "board/board.hpp"
#include "can/bms.hpp"
#include "drivers/bq769x2/measurement.hpp"
#include "flash_file.hpp"
#include "pack_figures.hpp"
#include "power.hpp"
#include "profiler.hpp"
#include "sim/peripherals.hpp"

namespace bmssim {
namespace {

using twin::Family;
namespace bms = fw::can::bms;
namespace b769 = fw::drivers::bq769x2;

constexpr uint32_t kScanPeriodMs =
    fw::app::kScanPeriod.us / 1000;  // every image's scan period (app configs' default)

// "t<iii><l><dd..>" / "T<iiiiiiii><l><dd..>" (firmware/app/publish/slcan.hpp) back into a frame; nullopt if
// malformed.
std::optional<SentFrame> decodeSlcan(const std::string& line, uint64_t timeUs) {
  if (line.empty() || (line[0] != 't' && line[0] != 'T')) return std::nullopt;
  const bool ext = line[0] == 'T';
  const size_t idLen = ext ? 8 : 3;
  auto hexAt = [&](size_t at, size_t n, uint32_t& out) {
    if (at + n > line.size()) return false;
    out = 0;
    for (size_t i = at; i < at + n; ++i) {
      const char c = line[i];
      const int v = c >= '0' && c <= '9' ? c - '0' : c >= 'A' && c <= 'F' ? c - 'A' + 10 : -1;
      if (v < 0) return false;
      out = out << 4 | static_cast<uint32_t>(v);
    }
    return true;
  };
  SentFrame f{timeUs, 0, ext, {}};
  uint32_t dlc = 0;
  if (!hexAt(1, idLen, f.id) || !hexAt(1 + idLen, 1, dlc) || dlc > 8) return std::nullopt;
  for (uint32_t i = 0; i < dlc; ++i) {
    uint32_t b = 0;
    if (!hexAt(2 + idLen + 2 * i, 2, b)) return std::nullopt;
    f.data.push_back(static_cast<uint8_t>(b));
  }
  return f;
}

fw::hal::CanFrame toCanFrame(const SentFrame& s) {
  fw::hal::CanFrame f{s.id, s.extended, static_cast<uint8_t>(s.data.size()), {}};
  std::copy(s.data.begin(), s.data.end(), f.data.begin());
  return f;
}

class TwinSim final : public ImageSim {
 public:
  TwinSim(const twin::ImageId& id, const SimOptions& o, std::unique_ptr<twin::ElfFile> elf)
      : id_(id),
        elf_(std::move(elf)),
        devices_(id.family == Family::Bq79616 ? o.devices : 1),
        board_(id, h_.clock, devices_),
        watchdog_(h_.clock) {
    board_.onWatchdogFeed([this] { watchdog_.feed(); });
    if (o.noCrystal) board_.chip().sysctl().removeCrystal();
    if (gauge_ != nullptr) gauge_->attachClock(h_.clock);  // as the host board: the charge state is counted
    truth_.assign(static_cast<size_t>(devices_ * cellsPerBoard()), 3700);
    for (int b = 0; b < devices_; ++b) {
      for (int c = 1; c <= cellsPerBoard(); ++c)
        push(b, c);
      // As the host bindings: 25 degC on the BQ79616 dies and the BQ4050; the BQ769x2/BQ7690x emulators keep
      // their own defaults.
      if (id_.family == Family::Bq79616 || id_.family == Family::Bq4050) {
        for (int t = 1; t <= tempsPerBoard(); ++t)
          setTempDeciK(b, t, 2982);
      }
    }
  }

  bool load(const std::string& flashFile, std::string& error) {
    if (!board_.load(*elf_)) {
      error = board_.error();
      return false;
    }
    if (flashFile.empty()) return true;
    const auto region = twin::dataRegion(*elf_);
    if (!region) {
      error = "--flash: the image has no flash data region (__record_store_start__, bsp/mspm0/linker)";
      return false;
    }
    region_ = *region;
    flashFile_ = flashFile;
    return twin::loadFlashFile(board_.chip().machine(), region_, flashFile_, error);
  }
  bool saveFlash(std::string& error) override {
    return twin::saveFlashFile(board_.chip().machine(), region_, flashFile_, error);
  }

  int boards() const override { return devices_; }
  int cellsPerBoard() const override {
    return id_.family == Family::Bq76907 ? 7 : id_.family == Family::Bq4050 ? 4 : 16;
  }
  int tempsPerBoard() const override {
    return id_.family == Family::Bq76952 ? 3 : id_.family == Family::Bq79616 ? 2 : 1;
  }
  bool hasCurrent() const override { return id_.family != Family::Bq79616; }

  // The emulated pack: the same device inputs as the host bindings (sim_bq769x2.cpp, sim_bq79616.cpp,
  // sim_bq4050.cpp), through the devices' backend faces.
  void setCellMv(int board, int cell, int mv) override {
    truth_[static_cast<size_t>(board * cellsPerBoard() + cell - 1)] = mv;
    push(board, cell);
    push(board, cell - 1);  // an open wire below `cell` makes the cell below read this cell too
  }
  // Balancing as the host bindings model it: the emulators' cells (cell_model.hpp) and what they balance.
  void setCellCapacityMah(int mAh) override {
    bsp::host::CellModel model;
    model.cellUvPerMah = bsp::host::CellModel::uvPerMah(static_cast<uint32_t>(mAh));
    if (auto* e = board_.bq769x()) e->setCellModel(model);
    if (auto* e = board_.chain()) e->setCellModel(model);
  }
  std::vector<uint16_t> balancingCells() override {
    std::vector<uint16_t> out;
    if (auto* e = board_.bq769x()) out.push_back(e->balancing());
    if (auto* e = board_.chain()) {
      for (size_t d = 0; d < e->size(); ++d)
        out.push_back(e->balancingCells(d));
    }
    return out;
  }
  int cellSpreadMv() override {
    std::vector<int> mv;
    for (int b = 0; b < devices_; ++b) {
      for (int c = 1; c <= cellsPerBoard(); ++c) {
        if (auto* e = board_.bq769x()) mv.push_back(e->cellNowMv(static_cast<uint8_t>(c)));
        if (auto* e = board_.chain()) mv.push_back(e->cellNowMicrovolts(static_cast<size_t>(b), c) / 1000);
      }
    }
    if (board_.bq4050() != nullptr) return spreadOf(truth_);
    return spreadOf(mv);
  }
  void setCurrentMa(int ma) override {
    if (auto* e = board_.bq769x()) e->setCurrentMa(ma);
    if (gauge_ != nullptr) gauge_->setCurrent(static_cast<int16_t>(ma));
  }
  // As the host bindings: the BQ769x2/BQ7690x FETs, else the fault output PB26 (with the BQ4050's own FETs).
  // Before the image first drives PB26 it counts as asserted, as the host boards' output starts.
  Paths paths() const override {
    if (const auto* e = board_.bq769x()) return {e->chgFet(), e->dsgFet()};
    const auto& out = board_.faultOutput();
    const Paths p = pathsOfFaultOutput(out.empty() || out.back().level);
    if (gauge_ == nullptr) return p;
    return {p.charge && gauge_->chgFet(), p.discharge && gauge_->dsgFet()};
  }
  void setTempDeciK(int board, int sensor, int deciK) override {
    if (auto* e = board_.bq769x()) {
      if (sensor == 1) {  // internal: BQ7690x in whole degC
        e->setIntTemp(id_.family == Family::Bq76907
                          ? b769::rawTemperature(b769::map7690x::cmd::IntTemperature, deciK)
                          : b769::rawTemperature(b769::map::cmd::IntTemperature, deciK));
      } else {
        e->setTs(static_cast<uint8_t>(sensor == 2 ? 0 : 2), static_cast<int16_t>(deciK));
      }
    }
    if (gauge_ != nullptr) gauge_->setTemperature(static_cast<uint16_t>(deciK));
    // DIETEMP: 0.025 degC per LSB around 0 degC (drivers/bq79616/measurement.hpp).
    if (auto* e = board_.chain())
      e->setDieTempRaw(static_cast<size_t>(board), sensor, static_cast<int16_t>(deciK * 4 - 10926));
  }
  void setCommLost(bool lost) override { board_.setMonitorPresent(!lost); }
  void openWire(int board, int cell) override {
    openBoard_ = board, openCell_ = cell;
    push(board, cell);
    push(board, cell - 1);
    // As the host binding: the BQ79616's own open-wire check sees the wire below `cell` (VC(cell - 1)).
    if (auto* e = board_.chain()) e->setOpenWire(static_cast<size_t>(board), cell - 1, true);
  }
  void setIntermittent(bool on) override {
    intermittent_ = on;
    if (!on) board_.setMonitorPresent(true);
  }
  bool busOff() override { return board_.injectBusOff(); }
  // Device faults (scenario.hpp) on the board's links (board.hpp).
  FaultLinks faultLinks() const override {
    return {id_.family != Family::Bq79616, id_.family == Family::Bq79616, id_.part == twin::Part::G3507};
  }
  void i2cStretch(fw::Duration perByte) override { board_.setI2cStretch(perByte); }
  void stuckScl() override { board_.holdScl(); }
  void stuckSda() override { board_.holdSda(); }
  void uartNoise(uint32_t ppm) override { board_.setUartNoise(ppm); }
  void canErrorFrames(uint32_t attempts) override { board_.injectCanErrorFrames(attempts); }
  bool canSend(const fw::hal::CanFrame& f) override { return board_.sendCan(f); }
  bool canFlood(std::function<std::optional<fw::hal::CanFrame>()> source) override {
    return board_.setCanFlood(std::move(source));
  }
  bool serialSend(std::string_view bytes) override { return board_.sendSerial(bytes); }
  size_t serialBacklog() const override { return board_.serialBacklog(); }
  std::vector<BusOffSpan> busOffLog() const override {
    std::vector<BusOffSpan> out;
    if (mcan_ == nullptr) return out;
    for (const auto& s : mcan_->busOffLog()) {
      out.push_back({us(s.startCycle),
                     s.recoveredCycle != 0 ? std::optional<uint64_t>(us(s.recoveredCycle)) : std::nullopt});
    }
    return out;
  }

  void runFor(fw::Duration d) override { board_.runUntilUs(h_.nowUs() + d.us); }
  void startProfile() override {
    profiler_ = std::make_unique<twin::Profiler>(*elf_);
    board_.machine().setProfiler(profiler_.get());
  }
  bool writeProfile(const std::string& path, std::string& error) override {
    std::ofstream out(path);
    const twin::Machine& m = board_.machine();
    if (profiler_) profiler_->write(out, id_.preset, m.clockHz(), m.now(), m.busyCycles());
    out.close();
    if (!out) error = "the file could not be written";
    return static_cast<bool>(out);
  }
  std::string failure() const override {
    return board_.machine().stopped() ? "the twin stopped: " + board_.machine().stopReason() : "";
  }
  const bsp::host::SimWatchdog* boardWatchdog() const override { return &watchdog_; }

  void afterStep() override {
    pumpSerialFlood();
    // The same intermittent link as the host bindings: the I2C monitor drops off the bus for 250 ms of every
    // 350 ms; the BQ79616 base corrupts every other millisecond's response.
    if (intermittent_) {
      if (auto* e = board_.chain()) {
        if (++tick_ % 2 == 0) e->corruptResponse(0, 6, 0x10, 3);
      } else {
        board_.setMonitorPresent((tick_++ % 350) >= 250);
      }
    }
    observeScans();
    takeSlcanLines();
  }

  std::optional<SentText> slcanText() const override {
    if (id_.part == twin::Part::G3507) return std::nullopt;
    return SentText{slcanText_, slcanEndsUs_};
  }

  bsp::host::Harness& harness() override { return h_; }
  SimFigures figures() override;
  std::vector<fw::app::ProtectionRecord> protectionLog() const override;
  std::vector<SentFrame> frames() const override;

 private:
  void push(int board, int cell) {
    if (cell < 1 || cell > cellsPerBoard()) return;
    const auto truth = std::span<const int>(truth_).subspan(static_cast<size_t>(board * cellsPerBoard()),
                                                            static_cast<size_t>(cellsPerBoard()));
    const int mv = sensedMv(truth, cell, board == openBoard_ ? openCell_ : -1);
    if (auto* e = board_.bq769x()) e->setCellMv(static_cast<uint8_t>(cell), static_cast<int16_t>(mv));
    if (auto* e = board_.chain()) e->setCellMicrovolts(static_cast<size_t>(board), cell, mv * 1000);
    if (auto* e = board_.bq4050()) {
      e->setCell(cell, static_cast<uint16_t>(mv));
      int pack = 0;
      for (int t : truth)
        pack += t;
      e->setVoltage(static_cast<uint16_t>(pack));
    }
  }
  void observeScans();
  // The lines the image's UART finished since the last step, appended to the text --slcan writes.
  void takeSlcanLines() {
    const auto& lines = board_.slcanLines();
    for (; slcanLinesSeen_ < lines.size(); ++slcanLinesSeen_) {
      slcanText_ += lines[slcanLinesSeen_].text;
      slcanEndsUs_.push_back(us(lines[slcanLinesSeen_].cycle));
    }
  }
  // The first read of a scan (drivers: bq4050 gauge.cpp kScan, the bq769x2 measurement blocks): Voltage on
  // the BQ4050, the block with the cells from 0x0A (BQ76952) or 0x12 (BQ7690x).
  const char* scanMarker() const {
    return id_.family == Family::Bq4050    ? "S 16 09 "
           : id_.family == Family::Bq76907 ? "S 10 12 "
                                           : "S 10 0A ";
  }
  // The probe that starts the monitor's set-up (firmware/drivers startProbe): the subcommand DEVICE_NUMBER
  // 0x0001 written to 0x3E (regmaps/bq769x2, bq7690x subcommands.yaml), with the CRC byte after each byte
  // when the image uses CRC (as `bmsctl trace bq76952 --crc subcmd 0x0001` prints it), or the BQ4050's
  // SpecificationInfo read (0x1A).
  bool isProbe(const std::string& text) const {
    if (id_.family == Family::Bq4050) return text.rfind("S 16 1A ", 0) == 0;
    return text.rfind("S 10 3E 01 00 ", 0) == 0 || text.rfind("S 10 3E 01 8A 00 ", 0) == 0;
  }
  uint64_t us(uint64_t cycle) const { return cycle / board_.machine().cyclesPerUs(); }

  twin::ImageId id_;
  std::unique_ptr<twin::ElfFile> elf_;
  std::unique_ptr<twin::Profiler> profiler_;
  int devices_;
  bsp::host::Harness h_;
  twin::Board board_;
  bsp::host::Bq4050Emulator* gauge_ = board_.bq4050();  // the BQ4050 image's gauge, else null
  const twin::Mcan* mcan_ = board_.chip().mcan();       // the G3507's CAN controller, else null
  bsp::host::SimWatchdog watchdog_;
  std::vector<int> truth_;
  int openBoard_ = -1, openCell_ = -1;
  bool intermittent_ = false;
  twin::FlashRegion region_;
  std::string flashFile_;
  uint64_t tick_ = 0;
  ScanMeter meter_;
  uint32_t scans_ = 0, scanFailures_ = 0, operations_ = 0;
  size_t i2cSeen_ = 0, chainSeen_ = 0, pingsSeen_ = 0;
  uint64_t failedTransactions_ = 0;
  bool scanOpen_ = false, scanFailed_ = false;
  uint64_t scanRxBytes_ = 0, lastPing_ = 0, lastProbe_ = 0;
  std::string slcanText_;
  std::vector<uint64_t> slcanEndsUs_;
  size_t slcanLinesSeen_ = 0;
};

void TwinSim::observeScans() {
  // What the wire shows of the firmware's scans, probes and recoveries (its own counters are inside the
  // image). A scan is counted when its first access appears on the wire: the block read with the cells
  // (BQ769x), the Voltage read (BQ4050), the stack read of VCELL16 (BQ79616, register 0x568). A BQ79616 scan
  // failed when no byte came back before the next one; an I2C scan when one of its transactions failed. An
  // I2C attempt whose address nobody acknowledged shows no register: it counts as a comm error only.
  uint64_t busUs = 0, transactions = 0;
  auto startScan = [this](bool previousFailed) {
    if (scanOpen_ && previousFailed) ++scanFailures_;
    scanOpen_ = true, scanFailed_ = false;
    ++scans_;
  };
  if (id_.family == Family::Bq79616) {
    const auto& cmds = board_.chainCommands();
    for (; chainSeen_ < cmds.size(); ++chainSeen_) {
      if (cmds[chainSeen_].reg != 0x568) continue;
      startScan(cmds[chainSeen_].rxBytesBefore == scanRxBytes_);
      scanRxBytes_ = cmds[chainSeen_].rxBytesBefore;
    }
    // Bring-ups and recoveries begin with a ping; inside one the longest wait between two pings is tHWRST
    // (83 ms, firmware/drivers/bq79616/chain.cpp): a ping after a longer quiet starts the next operation.
    const auto& pings = board_.chainPings();
    const uint64_t quiet = 120000 * board_.machine().cyclesPerUs();
    for (; pingsSeen_ < pings.size(); ++pingsSeen_) {
      if (operations_ == 0 || pings[pingsSeen_] - lastPing_ > quiet) ++operations_;
      lastPing_ = pings[pingsSeen_];
    }
    busUs = (board_.uartBytes() + board_.uartRxBytes()) * 10;  // 10 bit times per byte at 1 Mbaud
    transactions = cmds.size();
  } else {
    const auto& log = board_.i2cLog();
    for (; i2cSeen_ < log.size(); ++i2cSeen_) {
      const std::string& text = log[i2cSeen_].text;
      if (text.rfind(scanMarker(), 0) == 0) startScan(scanFailed_);
      if (isProbe(text)) {
        if (scanOpen_ && scanFailed_) ++scanFailures_;
        scanOpen_ = false;
        // The driver sends the subcommand again when its first read-back does not echo it: the same probe.
        if (operations_ == 0 ||
            log[i2cSeen_].startCycle - lastProbe_ > 50000 * board_.machine().cyclesPerUs())
          ++operations_;
        lastProbe_ = log[i2cSeen_].startCycle;
      }
      if (log[i2cSeen_].failed) ++failedTransactions_, scanFailed_ = true;
    }
    busUs = board_.chip().i2c0().busCycles() / board_.machine().cyclesPerUs();
    transactions = board_.chip().i2c0().transactions();
  }
  meter_.observe(scans_, operations_, busUs, transactions);
}

std::vector<SentFrame> TwinSim::frames() const {
  std::vector<SentFrame> out;
  for (const auto& f : board_.canFrames())
    out.push_back({us(f.endCycle),
                   f.frame.id,
                   f.frame.extended,
                   {f.frame.data.begin(), f.frame.data.begin() + f.frame.dlc}});
  for (const auto& line : board_.slcanLines()) {
    if (auto f = decodeSlcan(line.text, us(line.cycle))) out.push_back(*f);
  }
  return out;
}

// A trip is published: in a ProtectionEvent's NewlyTripped bits (the G3507 images), else as a bit rising in
// PackSummary.ActiveFaults (the L1306 images send nothing else). Its detection is the protection's action on
// the board in the two scan periods before that frame: the FET command on the monitor's bus (BQ76952
// subcommand 0x0093..0x0097 to 0x3E, BQ7690x FET Control 0x68) or the fault output rising; without one (the
// paths were already off) the frame's time. It took effect when the FETs left "both on" / the output rose, or
// at once if they already had.
std::vector<fw::app::ProtectionRecord> TwinSim::protectionLog() const {
  // A trip is published at the next publish slot, up to a scan period later, and the slot may just miss it.
  const uint64_t window = 2 * kScanPeriodMs * 1000;
  const bool fets = board_.bq769x() != nullptr;
  const auto& edges = fets ? board_.fetsOn() : board_.faultOutput();
  auto offSince = [&](uint64_t t) {  // the paths are off at time t: since when?
    std::optional<uint64_t> since;
    for (const auto& e : edges) {
      if (us(e.cycle) > t) break;
      const bool off = fets ? !e.level : e.level;
      if (off && !since) since = us(e.cycle);
      if (!off) since.reset();
    }
    return since;
  };
  auto actionBefore = [&](uint64_t t) -> std::optional<uint64_t> {
    std::optional<uint64_t> last;
    if (fets) {
      for (const auto& tr : board_.i2cLog()) {
        const uint64_t at = us(tr.startCycle);
        if (at > t) break;
        const bool command =
            tr.text.rfind("S 10 68 ", 0) == 0 || (tr.text.rfind("S 10 3E 9", 0) == 0 && tr.text.size() > 9 &&
                                                  tr.text[9] >= '3' && tr.text[9] <= '7');
        if (command && at + window >= t) last = at;
      }
    } else {
      for (const auto& e : edges) {
        if (us(e.cycle) <= t && us(e.cycle) + window >= t && e.level) last = us(e.cycle);
      }
    }
    return last;
  };
  const auto sent = frames();
  const bool events = std::any_of(sent.begin(), sent.end(),
                                  [](const SentFrame& s) { return s.id == bms::ProtectionEvent::kId; });
  std::vector<fw::app::ProtectionRecord> log;
  uint16_t active = 0;
  for (const SentFrame& s : sent) {
    uint16_t tripped = 0;
    if (events && s.id == bms::ProtectionEvent::kId) {
      tripped = bms::ProtectionEvent::unpack(toCanFrame(s)).newlyTripped;
    } else if (!events && s.id == bms::PackSummary::kId) {
      const uint16_t now = bms::PackSummary::unpack(toCanFrame(s)).activeFaults;
      tripped = now & ~active;
      active = now;
    }
    for (uint8_t i = 0; i < fw::app::kFaultCount; ++i) {
      if (((tripped >> i) & 1U) == 0) continue;
      fw::app::ProtectionRecord r{};
      r.fault = static_cast<fw::app::FaultId>(i);
      const uint64_t detected = actionBefore(s.timeUs).value_or(s.timeUs);
      r.detected = fw::Instant{static_cast<uint32_t>(detected)};
      // In effect: the first moment at or after detection when the paths are off.
      for (const auto& e : edges) {
        const bool off = fets ? !e.level : e.level;
        if (off && us(e.cycle) >= detected && us(e.cycle) <= s.timeUs) {
          r.actionDone = true;
          r.acted = fw::Instant{static_cast<uint32_t>(us(e.cycle))};
          break;
        }
      }
      if (!r.actionDone && offSince(detected)) {
        r.actionDone = true;  // already off for an earlier fault
        r.acted = r.detected;
      }
      // The twin sees the emulated device's own pins: what it took as acted is what happened.
      r.confirmedOff = r.actionDone;
      r.confirmed = r.acted;
      log.push_back(r);
    }
  }
  return log;
}

SimFigures TwinSim::figures() {
  SimFigures f;
  f.scans = scans_;
  f.scanFailures = scanFailures_;
  f.recoveries = operations_ > 1 ? operations_ - 1 : 0;  // the first is the bring-up
  f.scanPeriodMs = kScanPeriodMs;
  f.scanBusUs = meter_.meanBusUs();
  f.scanTransactions = meter_.meanTransactions();
  f.output = id_.part == twin::Part::G3507 ? "can" : "slcan";
  const auto sent = frames();
  f.outputFrames = sent.size();
  f.boards = devices_;
  f.commErrors = failedTransactions_;
  for (const SentFrame& s : sent) {
    const fw::hal::CanFrame c = toCanFrame(s);
    if (s.id == bms::PackSummary::kId) {
      const auto p = bms::PackSummary::unpack(c);
      f.pathsKnown = p.chargeFet != bms::PackSummary::kChargeFetNotAvailable;
      f.chargeOn = p.chargeFet == 1;
      f.dischargeOn = p.dischargeFet == 1;
      f.faultOutput = p.faultOutput != 0;
      f.activeFaults = p.activeFaults;
      f.validBoards = p.dataValid ? devices_ : 0;
      f.currentMa = hasCurrent() ? p.packCurrent * 10 : 0;
      f.stateOfChargePercent =
          p.stateOfCharge != bms::PackSummary::kStateOfChargeNotAvailable ? p.stateOfCharge : -1;
    } else if (s.id == bms::StateOfCharge::kId) {
      const auto q = bms::StateOfCharge::unpack(c);
      const bool known = q.soc != bms::StateOfCharge::kSocNotAvailable;
      f.socPermille = known ? q.soc : -1;
      f.remainingMah = known ? q.remainingCapacity : -1;
      f.fullChargeMah = known ? q.fullChargeCapacity : -1;
      f.socBasis = known ? q.basis : -1;
    } else if (s.id == bms::CellExtremes::kId) {
      const auto e = bms::CellExtremes::unpack(c);
      f.maxCellMv = e.maxCellVoltage, f.minCellMv = e.minCellVoltage;
    } else if (s.id == bms::ProtectionEvent::kId) {
      f.commErrors = bms::ProtectionEvent::unpack(c).commErrors;  // the board's own count
    }
  }
  f.balancingCells = balancingCells();
  f.cellSpreadMv = cellSpreadMv();
  if (auto* e = board_.bq769x()) f.emulatorChargeMah = static_cast<double>(e->trueChargeMaUs()) / 3.6e9;
  // CPU figures: the twin's own measurements.
  twin::Machine& m = board_.machine();
  const double perUs = static_cast<double>(m.cyclesPerUs());
  uint64_t latency = 0, handler = 0;
  for (const auto& irq : m.interrupts()) {
    latency = std::max(latency, irq.worstLatencyCycles);
    handler = std::max(handler, irq.worstHandlerCycles);
  }
  char buf[64];
  auto add = [&](const char* key, double value) {
    std::snprintf(buf, sizeof buf, "%.3f", value);
    f.extra.emplace_back(key, buf);
  };
  add("cpu_load_pct",
      m.now() ? 100.0 * static_cast<double>(m.busyCycles()) / static_cast<double>(m.now()) : 0.0);
  // Computed from residency and TI's data-sheet currents, not measured (bsp/twin/power.hpp).
  const twin::Residency r = m.residency();
  const uint64_t run = m.now();
  auto pct = [&](std::initializer_list<twin::PowerMode> modes) {
    uint64_t cycles = 0;
    for (const twin::PowerMode mode : modes)
      cycles += r[static_cast<size_t>(mode)];
    return run ? 100.0 * static_cast<double>(cycles) / static_cast<double>(run) : 0.0;
  };
  using twin::PowerMode;
  add("residency_run_pct", pct({PowerMode::Run}));
  add("residency_sleep_pct", pct({PowerMode::Sleep}));
  add("residency_stop_pct", pct({PowerMode::Stop0, PowerMode::Stop1, PowerMode::Stop2}));
  add("residency_standby_pct", pct({PowerMode::Standby0, PowerMode::Standby1}));
  f.extra.emplace_back("mcu_current_ua",
                       std::to_string(twin::averageCurrentUa(twin::powerTable(id_.part), r)));
  add("isr_max_us", static_cast<double>(handler) / perUs);
  add("wake_latency_max_us", static_cast<double>(latency) / perUs);
  f.extra.emplace_back("twin_instructions", std::to_string(m.core().instructions()));
  f.extra.emplace_back("twin_resets", std::to_string(m.resets().size() - 1));  // the power-on is not counted
  f.extra.emplace_back("twin_hard_faults", std::to_string(m.hardFaults().size()));
  std::string warnings = "[";
  for (const std::string& w : board_.warnings()) {
    warnings += warnings.size() > 1 ? ", \"" : "\"";
    for (char c : w)
      warnings += (c == '"' || c == '\\') ? std::string("\\") + c : std::string(1, c);
    warnings += '"';
  }
  f.extra.emplace_back("twin_warnings", warnings + "]");
  return f;
}

}  // namespace

std::unique_ptr<ImageSim> makeTwinSim(SimOptions& options, std::string& error) {
  auto elf = std::make_unique<twin::ElfFile>();
  if (!elf->load(options.elf)) {
    error = elf->error();
    return nullptr;
  }
  const std::optional<twin::ImageId> id = twin::identify(*elf, error);
  if (!id) return nullptr;
  if (!options.image.empty() && options.image != id->preset) {
    error = options.elf + " is the " + id->preset + " image, not " + options.image;
    return nullptr;
  }
  options.image = id->preset;
  if (id->family == Family::Bq79616 && (options.devices < 1 || options.devices > 64)) {
    error = "--devices must be 1..64 for a BQ79616 chain";
    return nullptr;
  }
  auto sim = std::make_unique<TwinSim>(*id, options, std::move(elf));
  if (!sim->load(options.flashFile, error)) return nullptr;
  return sim;
}

}  // namespace bmssim
