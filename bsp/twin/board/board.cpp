#include "board/board.hpp"

#include <cstdio>

#include "sim/sim_irq.hpp"

namespace twin {

namespace {

// PINCM indices of the board's signals (tsv pin rows, mspm0g350x.h / mspm0l130x.h IOMUX_PINCMn).
constexpr int kPa0 = 1, kPa1 = 2, kPf2 = 2;
constexpr int kL1306Pa8 = 9, kL1306Pa9 = 10, kL1306Pa10 = 11, kL1306Pa11 = 12, kL1306Pa15 = 16;
constexpr uint64_t kSlcanBaud = 115200;
constexpr int kG3507Pa10 = 21, kG3507Pa11 = 22, kG3507Pa13 = 35, kG3507Pb0 = 12, kG3507Pb2 = 15,
              kG3507Pb3 = 16, kG3507Pb26 = 57;
constexpr uint8_t kBq769xAddress = 0x08;

}  // namespace

std::optional<ImageId> imageByPreset(const std::string& preset) {
  static constexpr struct {
    const char* chip;
    Part part;
  } kParts[] = {{"mspm0l1306", Part::L1306}, {"mspm0g3507", Part::G3507}};
  static constexpr struct {
    const char* device;
    Family family;
  } kDevices[] = {{"bq76952", Family::Bq76952},
                  {"bq76907", Family::Bq76907},
                  {"bq79616", Family::Bq79616},
                  {"bq4050", Family::Bq4050}};
  for (const auto& p : kParts) {
    for (const auto& d : kDevices) {
      if (preset == std::string("lp-") + p.chip + "-" + d.device) return ImageId{p.part, d.family, preset};
    }
  }
  return std::nullopt;
}

std::optional<ImageId> identify(const ElfFile& elf, std::string& error) {
  const std::string& name = elf.imageName();
  if (name.empty()) {
    error = elf.path() + ": no .bms_image section: not an MSPM0 image of this repository (bsp/mspm0)";
    return std::nullopt;
  }
  std::optional<ImageId> id = imageByPreset(name);
  if (!id) error = elf.path() + ": the image " + name + " has a part or monitor the twin cannot wire up";
  return id;
}

// The I2C device as the controller sees it: the emulator's replies, plus the SCL stretch the scenario puts on
// every byte and, while the device holds SCL, a stretch to the end of the hold.
class Board::DeviceLine final : public bsp::host::I2cTarget {
 public:
  DeviceLine(bsp::host::I2cTarget& device, bsp::host::SimClock& clock) : device_(device), clock_(clock) {}
  bsp::host::I2cReply onStart(bool read) override { return more(device_.onStart(read)); }
  bsp::host::I2cReply onWrite(uint8_t byte) override { return more(device_.onWrite(byte)); }
  uint8_t onRead(fw::Duration& stretch) override {
    const uint8_t byte = device_.onRead(stretch);
    stretch = stretch + extra();
    return byte;
  }
  void onStop() override { device_.onStop(); }
  void onBusRecovery() override { device_.onBusRecovery(); }

  fw::Duration stretch{};
  uint64_t holdUntilUs = 0;

 private:
  fw::Duration extra() const {
    const uint64_t now = clock_.nowUs();
    return stretch + fw::us(holdUntilUs > now ? static_cast<uint32_t>(holdUntilUs - now) : 0);
  }
  bsp::host::I2cReply more(bsp::host::I2cReply reply) const {
    reply.stretch = reply.stretch + extra();
    return reply;
  }
  bsp::host::I2cTarget& device_;
  bsp::host::SimClock& clock_;
};

Board::Board(const ImageId& image, bsp::host::SimClock& world, int devices)
    : image_(image), world_(world), chip_(image.part) {
  Machine& m = chip_.machine();
  m.attachWorld(world);
  chip_.wwdt0().onRestart([this] {
    watchdogFeeds_.push_back(chip_.machine().now());
    chip_.machine().syncWorld();
    if (feedHook_) feedHook_();
  });
  m.onEvents([this] { samplePins(); });
  if (image.family == Family::Bq79616) {
    wireChain(devices);
  } else {
    wireI2cMonitor();
  }
  if (image.part == Part::G3507) {
    // The LaunchPad's 40 MHz crystal (tsv "HFXT" example row; LP-MSPM0G3507 user's guide).
    chip_.sysctl().setHfxtCrystalHz(40000000);
    wireCan();
    faultPincm_ = kG3507Pb26;
    chip_.pins().onChange(faultPincm_, [this](bool level) {
      faultOutput_.push_back({chip_.machine().now(), level});
    });
  } else {
    // The XDS110 back-channel receives on PA8 (tsv note "LP-MSPM0L1306 backchannel UART"): SLCAN text, at
    // 115 200 Bd. Its tolerance is not documented: half the margin of a 16x-oversampling receiver (sampling
    // mid-bit, 7/16 of a bit over the 9.5 bits to the stop bit: 4.6 %), the other half left to our clock.
    // Its frame is the PC's 8N1 (bsp/mspm0/README.md: the back-channel at 115200 8N1; Link's default).
    chip_.uart(0).setLink(
        {"XDS110 back-channel", 115200, 23000,
         "computed: half a 16x receiver's 4.6 % margin; bsp/twin/README.md open questions"});
    chip_.uart(0).onTransmit([this](uint8_t byte) {
      ++uartBytes_;
      if (!chip_.pins().routed(kL1306Pa8, kPf2)) {
        ++unroutedBytes_;
        unrouted("UART0 TX", kL1306Pa8, byte, true);
        return;
      }
      slcanPending_ += static_cast<char>(byte);
      if (byte == '\r' || byte == 0x07) {  // CR, or BEL (the answer to a refused line)
        slcanLines_.push_back({chip_.machine().now(), slcanPending_});
        slcanPending_.clear();
      }
    });
    // A reset cuts the line it interrupts: a reader drops that fragment at the next line, so it is not
    // glued to the restarted image's first line.
    chip_.machine().onReset([this](ResetKind) { slcanPending_.clear(); });
  }
  if (signalPincm_ != 0) {
    chip_.pins().onChange(signalPincm_, [this](bool level) {
      monitorSignal_.push_back({chip_.machine().now(), level});
      if (!level) checkSignalEdge();
    });
  }
}

Board::~Board() = default;

bool Board::load(const ElfFile& elf) {
  return chip_.load(elf);
}

void Board::runUntilUs(uint64_t us) {
  chip_.machine().run(us * chip_.machine().cyclesPerUs());
}

void Board::wireI2cMonitor() {
  Pins& pins = chip_.pins();
  pins.setBoardPullUp(kPa0, true);
  pins.setBoardPullUp(kPa1, true);
  // A device holding SDA lets go once the controller has clocked SCL kHeldSdaClocks times (holdSda).
  pins.onChange(kPa1, [this](bool level) {
    if (level || sdaHeldClocks_ == 0 || --sdaHeldClocks_ != 0) return;
    chip_.pins().setExternal(kPa0, Drive::None);
    line_->onBusRecovery();
  });
  chip_.i2c0().onTransaction([this](const I2cWireLog& t) { i2cLog_.push_back(t); });
  if (image_.family == Family::Bq4050) {
    bq4050_ = std::make_unique<bsp::host::Bq4050Emulator>();
    i2cAddress_ = bsp::host::Bq4050Emulator::kAddress;
    line_ = std::make_unique<DeviceLine>(*bq4050_, world_);
    chip_.i2c0().attach(i2cAddress_, *line_);
    // SMBus: 10..100 kHz (SLUSC67A SMBus timing, fSMB; SMBus 2.0 3.1.1).
    // Clock stretching: SMBus 2.0 lets a target stretch (tLOW:SEXT up to 25 ms), and the BQ4050 does (the
    // project's 25 ms stretch limit, bsp/host/emul/bq4050).
    chip_.i2c0().setTargetRange(i2cAddress_, {"BQ4050", 10000, 100000, "SLUSC67A fSMB 10..100 kHz",
                                              "SMBus 2.0 tLOW:SEXT, a target may stretch up to 25 ms"});
    return;
  }
  using Model = bsp::host::Bq769xEmulator::Model;
  bq769x_ = std::make_unique<bsp::host::Bq769xEmulator>(
      world_, image_.family == Family::Bq76907 ? Model::Bq76907 : Model::Bq76952);
  i2cAddress_ = kBq769xAddress;
  line_ = std::make_unique<DeviceLine>(*bq769x_, world_);
  chip_.i2c0().attach(i2cAddress_, *line_);
  // BQ76952: "supports rates up to 400 kHz" (SLUSE13B 14, I2C Communications Subsystem); the BQ7690x data
  // sheet (SLUSE97) gives the same 400 kHz maximum.
  // Clock stretching: the BQ76952 stretches SCL (SLUUBY2B 9, its I2C interface), and TI's BQ769x2 example
  // for the L1306 (bq769x2_control_i2c ti_msp_dl_config.c) enables the controller's clock stretching. For
  // the BQ7690x no TI source was checked (open question in bsp/twin/README.md): not required there.
  const bool bq76907 = image_.family == Family::Bq76907;
  chip_.i2c0().setTargetRange(
      i2cAddress_, {bq76907 ? "BQ76907" : "BQ76952", 1, 400000, "SLUSE13B 14 / SLUSE97: I2C up to 400 kHz",
                    bq76907 ? "" : "SLUUBY2B 9; TI bq769x2_control_i2c enables controller clock stretching"});
  // ALERT: the line as the device's ALERT Pin Config drives it (the emulator's alertLine()); where it drives
  // nothing or high, the MCU's own pull-up must make the high (an input left floating is a twin warning).
  signalPincm_ = image_.part == Part::L1306 ? kL1306Pa15 : kG3507Pb0;
  bq769x_->onAlertLine(
      [this](bool high) { chip_.pins().setExternal(signalPincm_, high ? Drive::None : Drive::Low); });
  // CFETOFF / DFETOFF: on the BQ76952 boards they come from MCU outputs (bsp/mspm0/README.md "Connections":
  // PA10 / PA11 on the L1306, PB2 / PB3 on the G3507, mspm0l130x.h / mspm0g350x.h PINCM11/12 and 15/16), and
  // the device turns the gate off while a pin is asserted as its Pin Config says (SLUAAQ5: "when that pin is
  // asserted from an external source, the corresponding gate is then disabled"; the emulator's
  // setFetOffPins, wired as the host board wires it). A pin the MCU does not drive reads low: not asserted.
  // The BQ7690x has no such pins.
  if (!bq76907) {
    const bool l1306 = image_.part == Part::L1306;
    const int cfetoff = l1306 ? kL1306Pa10 : kG3507Pb2;
    const int dfetoff = l1306 ? kL1306Pa11 : kG3507Pb3;
    const auto drive = [this, cfetoff, dfetoff](bool) {
      bq769x_->setFetOffPins(chip_.pins().level(cfetoff), chip_.pins().level(dfetoff));
    };
    chip_.pins().onChange(cfetoff, drive);
    chip_.pins().onChange(dfetoff, drive);
  }
}

void Board::wireChain(int devices) {
  chainUart_ = std::make_unique<bsp::host::SimUart>(world_, bsp::host::simIrq(), 1000000);
  chain_ =
      std::make_unique<bsp::host::Bq79616ChainEmulator>(world_, *chainUart_, static_cast<size_t>(devices));
  nfault_ = std::make_unique<bsp::host::SimEdgeInput>(bsp::host::simIrq(), "nfault",
                                                      bsp::host::SimEdgeInput::Edge::Falling, true);
  chain_->attachFaultPin(*nfault_);
  signalPincm_ = kG3507Pb0;
  chip_.pins().setExternal(signalPincm_, Drive::High);  // nFAULT is driven by the base device
  Pins& pins = chip_.pins();
  Uart& uart = chip_.uart(0);
  // "The device supports 1-Mbps baud rate" (SLUSE81E 9.3.6.1.1, UART); the host's baud error must lie within
  // +-1 % (SLUSE81E electrical characteristics, "UART RX baud rate error"). Its frame is 8N1 (Link's
  // default): 8 data bits, no parity, one stop bit unless DEV_CONF.TWO_STOP_EN (SLUSE81E DEV_CONF), as TI's
  // BQ79616 example configures the MSPM0 (ti_msp_dl_config.c: 8 bits, no parity, one stop bit).
  uart.setLink({"BQ79616", 1000000, 10000, "SLUSE81E: 1 Mbps, UART RX baud rate error +-1 %"});
  uart.onTransmit([this](uint8_t byte) {
    ++uartBytes_;
    if (!chip_.pins().routed(kG3507Pa10, kPf2)) {
      ++unroutedBytes_;
      unrouted("UART0 TX", kG3507Pa10, byte, true);
      return;
    }
    bool lost = false;  // the line's noise (setUartNoise); the chain's side is SimUart's
    byte = chainUart_->noise().pass(byte, lost);
    if (lost) return;
    noteChainByte(byte);
    chain_->onHostBytes(std::span<const uint8_t>(&byte, 1), world_.nowUs());
  });
  chainUart_->onPeerByte([this](uint8_t byte, bool framingError) {
    ++uartRxBytes_;
    if (!chip_.pins().routed(kG3507Pa11, kPf2)) {
      if (chip_.uart(0).receiving()) unrouted("UART0 RX", kG3507Pa11, byte, false);
    } else if (chip_.pins().requireInput(kG3507Pa11, "UART0 RX")) {
      chip_.uart(0).receive(byte, framingError);
    }
  });
  // A ping: the TX line low (the firmware drives it as a GPIO) for its length, measured on the line.
  pins.onChange(kG3507Pa10, [this](bool level) {
    const uint64_t now = chip_.machine().now();
    if (!level) {
      pingStart_ = now;
    } else if (pingStart_ != 0) {
      const auto us = static_cast<uint32_t>((now - pingStart_) / chip_.machine().cyclesPerUs());
      chain_->onPing(fw::us(us), world_.nowUs());
      chainPings_.push_back(now);
      pingStart_ = 0;
    }
  });
}

// Command frames (SLUSE81E §9.3.6.1.1): INIT (bit 7 set, request type 6:4, data length - 1 in 2:0), the
// device address for single-device requests (types 0 and 1), the register (2 bytes), data (1 byte for reads),
// CRC.
void Board::noteChainByte(uint8_t byte) {
  if (chainFrame_.empty() && (byte & 0x80) == 0) return;
  chainFrame_.push_back(byte);
  const uint8_t init = chainFrame_[0], type = (init >> 4) & 7U;
  const bool single = type == 0 || type == 1, read = type == 0 || type == 2 || type == 4;
  const size_t header = single ? 2 : 1;
  if (chainFrame_.size() < header + 2 + (read ? 1U : (init & 7U) + 1U) + 2) return;
  chainCommands_.push_back({chip_.machine().now(), init,
                            static_cast<uint16_t>(chainFrame_[header] << 8 | chainFrame_[header + 1]),
                            uartRxBytes_});
  chainFrame_.clear();
}

void Board::wireCan() {
  chip_.mcan()->onFrame([this](const CanWireFrame& f) {
    if (canFrames_.empty()) checkFaultOutputAsserted();
    canFrames_.push_back(f);
  });
  chip_.mcan()->setBus(500000);                       // the product's CAN bus (README "The five images")
  chip_.pins().setExternal(kG3507Pa13, Drive::High);  // the transceiver's RXD: recessive while idle
}

void Board::samplePins() {
  const uint64_t now = chip_.machine().now();
  if (nfault_) {
    const Drive d = nfault_->level() ? Drive::High : Drive::Low;
    if ((d == Drive::High) != chip_.pins().level(signalPincm_)) chip_.pins().setExternal(signalPincm_, d);
  }
  if (bq769x_) {
    const bool on = bq769x_->chgFet() && bq769x_->dsgFet();
    if (on != fets_ || fetsOn_.empty()) {
      fets_ = on;
      fetsOn_.push_back({now, on});
    }
  }
}

void Board::setMonitorPresent(bool present) {
  if (bq4050_) {
    if (present) {
      chip_.i2c0().attach(i2cAddress_, *line_);
    } else {
      chip_.i2c0().detach(i2cAddress_);
    }
  }
  if (bq769x_) bq769x_->setMuted(!present);
  if (chain_) {
    for (size_t d = 0; d < chain_->size(); ++d)
      chain_->setMuted(d, !present);
  }
}

void Board::driveMonitorSignal(bool level) {
  if (nfault_) {
    nfault_->drive(level);  // the chain's own output: the sampler keeps the pin in step
    samplePins();
  } else if (signalPincm_ != 0) {
    chip_.pins().setExternal(signalPincm_, level ? Drive::None : Drive::Low);  // open drain
  }
}

void Board::checkSignalEdge() {
  // SIGNAL-EDGE (rules.hpp): the signal asserts by falling; an edge interrupt set for rising only comes late.
  const bool l1306 = image_.part == Part::L1306;
  const int port = l1306 ? 0 : 1, bit = l1306 ? 15 : 0;  // PA15 on the L1306, PB0 on the G3507
  const Gpio& gpio = chip_.gpio(port);
  if (!gpio.powered() || !gpio.edgeUnmasked(bit) || gpio.edgePolarity(bit) != 1) return;
  chip_.machine().violate(
      Rule::SignalEdge,
      chip_.pins().pinName(signalPincm_) +
          ": the monitor's active-low signal fell with its GPIO edge interrupt set for the "
          "rising edge only (POLARITY 1): the handler runs when the signal ends, not when it "
          "starts");
}

void Board::checkFaultOutputAsserted() {
  // FAULT-OUT-RELEASED (rules.hpp, the product's contract): by the image's first CAN frame the fault output
  // must have been driven high at least once since the power-up. The first frame comes before any scan could
  // have validated the pack, and an output the image never drove high stays at its reset level (low:
  // released).
  for (const auto& e : faultOutput_) {
    if (e.level) return;
  }
  chip_.machine().violate(
      Rule::FaultOutReleased,
      chip_.pins().pinName(faultPincm_) +
          ": the fault output was never asserted (driven high) between the power-up and the "
          "image's first CAN frame: the pack path behind it may close on a pack not yet "
          "measured");
}

void Board::unrouted(const char* function, int pincm, uint8_t byte, bool transmitted) {
  // PIN-UNROUTED (rules.hpp): the UART works, the pin is muxed to something else (PINCM.PF), so the byte
  // goes nowhere on silicon.
  char buf[200];
  const uint32_t cm = chip_.pins().pincm(pincm);
  std::snprintf(buf, sizeof buf,
                "%s: byte 0x%02X %s %s, whose PINCM 0x%08X (PC %u, PF %u) does not select %s (PF 2): it goes "
                "nowhere",
                function, byte, transmitted ? "sent with its pin" : "arrived at its pin",
                chip_.pins().pinName(pincm).c_str(), cm, (cm >> 7) & 1U, cm & 0x3FU, function);
  chip_.machine().violate(Rule::PinUnrouted, buf);
}

std::vector<std::string> Board::warnings() const {
  // The silicon rules that only warn (rules.hpp: where the part would degrade, not fail), then the board's.
  std::vector<std::string> out = chip_.machine().ruleWarnings();
  for (const std::string& unserved : chip_.unservedInterrupts())
    out.push_back(unserved);
  for (const std::string& pin : chip_.pins().floatingReads())
    out.push_back(pin + " read while floating (no drive, no pull)");
  if (const Mcan* mcan = chip_.mcan()) {
    for (const std::string& n : mcan->notes())
      out.push_back("CANFD0: " + n);
    for (int line = 0; line < 2; ++line) {
      const uint64_t waiting = mcan->awaitingEoiCycles(line) / chip_.machine().cyclesPerUs();
      if (waiting > 10000) {
        out.push_back("CANFD0 interrupt line " + std::to_string(line) + " waiting for MCANSS_EOI for " +
                      std::to_string(waiting / 1000) + " ms: its later interrupts are lost");
      }
    }
  }
  return out;
}

bool Board::setI2cStretch(fw::Duration perByte) {
  if (!line_) return false;
  line_->stretch = perByte;
  return true;
}

bool Board::holdScl() {
  if (!line_) return false;
  const uint64_t until = world_.nowUs() + (bq4050_ ? 35000 : 2000000);
  line_->holdUntilUs = until;
  chip_.pins().setExternal(kPa1, Drive::Low);
  world_.schedule(until, [this] {
    chip_.pins().setExternal(kPa1, Drive::None);
    line_->onBusRecovery();  // its timeout reset the device's interface
  });
  return true;
}

bool Board::holdSda() {
  if (!line_) return false;
  sdaHeldClocks_ = kHeldSdaClocks;
  chip_.pins().setExternal(kPa0, Drive::Low);
  return true;
}

bool Board::setUartNoise(uint32_t ppm) {
  if (!chainUart_) return false;
  chainUart_->noise().setPpm(ppm);
  return true;
}

bool Board::injectCanErrorFrames(uint32_t attempts) {
  if (chip_.mcan() == nullptr) return false;
  chip_.mcan()->injectErrorFrames(attempts);
  return true;
}

bool Board::injectBusOff() {
  if (chip_.mcan() == nullptr) return false;
  chip_.mcan()->injectBusOff();
  return true;
}

bool Board::sendCan(const fw::hal::CanFrame& frame) {
  if (chip_.mcan() == nullptr) return false;
  chip_.mcan()->peerSend(frame);
  return true;
}

bool Board::setCanFlood(std::function<std::optional<fw::hal::CanFrame>()> source) {
  if (chip_.mcan() == nullptr) return false;
  chip_.mcan()->setPeerSource(std::move(source));
  return true;
}

// The PC's bytes, back to back at 115 200 Bd 8N1: byte k of a run ends (10 k + 10) bit times after the run
// began. A byte reaches UART0 only if PA9 is muxed to it (PF 2), as on the LaunchPad.
bool Board::sendSerial(std::string_view bytes) {
  if (image_.part != Part::L1306) return false;
  serialOut_.insert(serialOut_.end(), bytes.begin(), bytes.end());
  if (!serialArriving_ && !serialOut_.empty()) {
    serialArriving_ = true;
    serialStartUs_ = world_.nowUs();
    serialBytes_ = 0;
    world_.schedule(serialStartUs_ + 10 * 1000000 / kSlcanBaud, [this] { serialArrive(); });
  }
  return true;
}

void Board::serialArrive() {
  const uint8_t byte = serialOut_.front();
  serialOut_.pop_front();
  ++serialBytes_;
  if (!chip_.pins().routed(kL1306Pa9, kPf2)) {
    if (chip_.uart(0).receiving()) unrouted("UART0 RX", kL1306Pa9, byte, false);
  } else if (chip_.pins().requireInput(kL1306Pa9, "UART0 RX")) {
    chip_.uart(0).receive(byte, false);
  }
  if (serialOut_.empty()) {
    serialArriving_ = false;
    return;
  }
  world_.schedule(serialStartUs_ + (serialBytes_ + 1) * 10 * 1000000 / kSlcanBaud,
                  [this] { serialArrive(); });
}

}  // namespace twin
