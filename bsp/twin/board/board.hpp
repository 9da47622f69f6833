// Board: one of the five LaunchPad set-ups around a twin MSPM0, wired to the device emulators the host tools
// use (bsp/host/emul), on the emulators' SimClock. The wiring is the README's "Connections" table
// (bsp/mspm0/README.md) and the README's image table, not the firmware's choices: if an image muxes a
// signal to another pin, nothing arrives where the board expects it.
//
//   L1306 + BQ76952 / BQ76907 EVM: I2C0 PA0 SDA / PA1 SCL (pull-ups on the board), the monitor's ALERT
//       to PA15 (open drain, low when asserted), the XDS110 back-channel's receive line on PA8 (UART0 TX,
//       PF 2): SLCAN, and its transmit line on PA9 (UART0 RX, PF 2): what the PC sends, at 115 200 Bd.
//   G3507 + BQ76952 or BQ4050: I2C0 PA0 / PA1 (pull-ups), BQ76952 ALERT to PB0; CAN on PA12 TX / PA13 RX to
//       a bus with one listener that acknowledges every frame (the candump log) and sends what sendCan() and
//       setCanFlood() give it; the fault output PB26.
//   G3507 + BQ79616 chain (seed 001): UART0 PA10 TX / PA11 RX at the chain's base device, nFAULT to PB0, CAN
//       and PB26 as above. A ping is the TX line held low (the firmware muxes it to GPIO): its length goes to
//       the chain as the emulator's onPing().
//
// Times in the observations are CPU cycles of the twin (32 per microsecond).
#pragma once

#include <cstdint>
#include <deque>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "bq4050/gauge_emulator.hpp"
#include "bq769x2/emulator.hpp"
#include "bq79616/chain_emulator.hpp"
#include "mspm0.hpp"
#include "sim/peripherals.hpp"
#include "sim/uart.hpp"

namespace twin {

enum class Family : uint8_t { Bq76952, Bq76907, Bq79616, Bq4050 };

struct ImageId {
  Part part;
  Family family;
  std::string preset;
};

// An image is named lp-<chip>-<device> (bsp/mspm0/images/images.cmake checks it): imageByPreset() reads the
// part and the monitor from the name, for any image whose part and monitor the twin's board can wire up;
// identify() reads the name from the ELF's `.bms_image` section (ElfFile::imageName()).
std::optional<ImageId> imageByPreset(const std::string& preset);
std::optional<ImageId> identify(const ElfFile& elf, std::string& error);

struct PinEdge {
  uint64_t cycle;
  bool level;
};

// A command frame the MCU sent the BQ79616 chain (INIT byte and register; SLUSE81E §9.3.6.1.1 frame layout).
struct ChainCommand {
  uint64_t cycle;
  uint8_t init;
  uint16_t reg;
  uint64_t rxBytesBefore;  // bytes the MCU had received from the chain when this command was complete
};

struct SlcanLine {
  uint64_t cycle;  // the line's last byte left the UART
  std::string text;
};

class Board {
 public:
  // `devices`: BQ79616 chain length (the other monitors are single devices).
  Board(const ImageId& image, bsp::host::SimClock& world, int devices);
  ~Board();
  Board(const Board&) = delete;
  Board& operator=(const Board&) = delete;

  // Loads the image and powers the board on. False with error() set when the ELF does not fit.
  bool load(const ElfFile& elf);
  const std::string& error() const { return chip_.error(); }
  const ImageId& image() const { return image_; }
  Mspm0& chip() { return chip_; }
  Machine& machine() { return chip_.machine(); }
  const Machine& machine() const { return chip_.machine(); }
  // Runs the MCU and the devices up to `us` of world time.
  void runUntilUs(uint64_t us);

  // The devices (the one this image has; the others are null).
  bsp::host::Bq769xEmulator* bq769x() { return bq769x_.get(); }
  const bsp::host::Bq769xEmulator* bq769x() const { return bq769x_.get(); }
  const bsp::host::Bq79616ChainEmulator* chain() const { return chain_.get(); }
  bsp::host::Bq4050Emulator* bq4050() { return bq4050_.get(); }
  bsp::host::Bq79616ChainEmulator* chain() { return chain_.get(); }
  // An I2C monitor leaves the bus (every transaction NACKed) or comes back.
  void setMonitorPresent(bool present);
  // Called at every watchdog restart, with the world clock at that moment.
  void onWatchdogFeed(std::function<void()> hook) { feedHook_ = std::move(hook); }
  // Drives the monitor's ALERT (BQ769x2/BQ7690x) or nFAULT (BQ79616) line: low = asserted.
  void driveMonitorSignal(bool level);
  // The CAN controller goes bus-off; false on a board without CAN.
  bool injectBusOff();
  // The other node on CAN sends `frame`, or (a source) always has one waiting; false on a board without CAN.
  bool sendCan(const fw::hal::CanFrame& frame);
  bool setCanFlood(std::function<std::optional<fw::hal::CanFrame>()> source);
  // The PC sends `bytes` on the L1306's back-channel (they arrive on PA9 one after another, after what it
  // sent before); false on a board without it. serialBacklog(): bytes sent and not arrived yet.
  bool sendSerial(std::string_view bytes);
  size_t serialBacklog() const { return serialOut_.size(); }

  // Device faults (bms-sim's scenario steps stretch, stuck-scl, stuck-sda, uart-noise, can-error-frames);
  // each is false on a board without that link.
  // The I2C device stretches SCL by `perByte` on every byte: after the address and each written byte's ACK
  // and before each byte it sends, the places a BQ76952 or BQ4050 extends the clock (SLUSE13B 14 "clock low
  // responder extend"; SLUSC67A tLOW:SEXT). 0 stops it.
  bool setI2cStretch(fw::Duration perByte);
  // The I2C device holds SCL low from now until its own bus timeout resets its interface: 2 s on the
  // BQ76952 / BQ7690x (SLUSE13B 14: "a long-term timeout if the SCL pin is detected low for more than 2
  // seconds"), 35 ms on the BQ4050 (the end of SMBus tTIMEOUT 25..35 ms, SLUSC67A).
  bool holdScl();
  // The I2C device holds SDA low (a read byte cut by a reset: it drives a 0 bit) until the controller has
  // clocked SCL 8 times (the I2C bus clear, UM10204 3.1.16: at most 9 clocks).
  bool holdSda();
  // Bit errors on the BQ79616 UART link, both directions (bsp/host/sim/bit_noise.hpp), in ppm; 0 stops.
  bool setUartNoise(uint32_t ppm);
  // Another node destroys the next `attempts` CAN transmissions with error frames (Mcan::injectErrorFrames).
  bool injectCanErrorFrames(uint32_t attempts);
  static constexpr uint32_t kHeldSdaClocks = 8;

  // What the board did.
  const std::vector<CanWireFrame>& canFrames() const { return canFrames_; }
  const std::vector<SlcanLine>& slcanLines() const { return slcanLines_; }
  const std::vector<PinEdge>& faultOutput() const { return faultOutput_; }      // PB26 (G3507)
  const std::vector<PinEdge>& monitorSignal() const { return monitorSignal_; }  // ALERT / nFAULT pin
  const std::vector<PinEdge>& fetsOn() const { return fetsOn_; }                // BQ769x: CHG and DSG both on
  const std::vector<uint64_t>& watchdogFeeds() const { return watchdogFeeds_; }
  const std::vector<I2cWireLog>& i2cLog() const { return i2cLog_; }
  const std::vector<ChainCommand>& chainCommands() const { return chainCommands_; }
  const std::vector<uint64_t>& chainPings() const { return chainPings_; }  // cycle each ping on TX ended
  // What the twin noticed that the part would do silently: floating inputs read, protected MCAN writes
  // ignored, an MCAN interrupt line waiting for its EOI longer than 10 ms. Empty for a healthy image.
  std::vector<std::string> warnings() const;
  uint64_t uartBytes() const { return uartBytes_; }
  uint64_t uartRxBytes() const { return uartRxBytes_; }
  uint64_t unroutedBytes() const { return unroutedBytes_; }  // UART bytes that left on no connected pin

 private:
  void wireI2cMonitor();
  void wireChain(int devices);
  void wireCan();
  void samplePins();
  void serialArrive();
  void noteChainByte(uint8_t byte);
  class DeviceLine;

  ImageId image_;
  bsp::host::SimClock& world_;
  Mspm0 chip_;
  std::unique_ptr<bsp::host::Bq769xEmulator> bq769x_;
  std::unique_ptr<bsp::host::Bq4050Emulator> bq4050_;
  std::unique_ptr<bsp::host::SimUart> chainUart_;
  std::unique_ptr<bsp::host::Bq79616ChainEmulator> chain_;
  std::unique_ptr<bsp::host::SimEdgeInput> nfault_;
  std::unique_ptr<DeviceLine> line_;  // the I2C device as the bus sees it (its faults on top)
  uint32_t sdaHeldClocks_ = 0;
  int signalPincm_ = 0;  // ALERT or nFAULT input
  int faultPincm_ = 0;   // fault output
  uint8_t i2cAddress_ = 0;
  std::vector<CanWireFrame> canFrames_;
  std::vector<SlcanLine> slcanLines_;
  std::string slcanPending_;
  std::vector<PinEdge> faultOutput_, monitorSignal_, fetsOn_;
  std::vector<uint64_t> watchdogFeeds_;
  std::function<void()> feedHook_;
  std::vector<I2cWireLog> i2cLog_;
  std::vector<ChainCommand> chainCommands_;
  std::vector<uint64_t> chainPings_;
  std::vector<uint8_t> chainFrame_;
  void unrouted(const char* function, int pincm, uint8_t byte, bool transmitted);
  void checkSignalEdge();
  void checkFaultOutputAsserted();
  uint64_t uartBytes_ = 0, uartRxBytes_ = 0, unroutedBytes_ = 0;
  uint64_t pingStart_ = 0;
  bool fets_ = false;
  std::deque<uint8_t> serialOut_;                 // the PC's bytes not arrived yet
  uint64_t serialStartUs_ = 0, serialBytes_ = 0;  // timing of the bytes in flight (115 200 Bd, 10 bits each)
  bool serialArriving_ = false;
};

}  // namespace twin
