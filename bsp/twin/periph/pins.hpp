// Pins: the IOMUX (PINCM registers) and the level of every package pin, resolved from what drives it.
//
// IOMUX: IOMUX_BASE 0x40428000 on both parts; PINCMn (1-based) at IOMUX_BASE + 4n (tsv note "PINCM index",
// hw_iomux.h SECCFG.PINCM[n-1]); fields PF 5:0, PC bit 7 (connected), PIPD 16, PIPU 17, INENA 18, HIZ1 25
// (hw_iomux.h IOMUX_PINCM_*). PF 1 is the GPIO function on every pin; the peripheral function values per
// pin are the device header's IOMUX_PINCMn_PF_* (mspm0g350x.h, mspm0l130x.h).
//
// A pin's level, each time anything that drives it changes:
// - the MCU drives it when PC = 1 and PF selects GPIO with DOE set: DOUT, except that a 1 with HIZ1 is
//   released (open drain). Peripheral functions (UART, I2C, CAN) are exchanged at byte level by their
//   models, which only ask routed(): is the pin connected to that function?
// - the board drives it (an emulated device's ALERT or nFAULT, setExternal), or holds a pull-up (the I2C
//   pull-ups on the EVMs);
// - otherwise the MCU's own pull (PIPU / PIPD). An input nobody drives or pulls floats: the twin reads it
//   as 0 and records the pin in floatingReads() (a real pin reads anything).
// A pin muxed to GPIO reads into DIN only with INENA (hw_iomux.h "Input Enable Control").
#pragma once

#include <cstdint>
#include <functional>
#include <set>
#include <span>
#include <string>
#include <vector>

#include "address_map.hpp"
#include "machine.hpp"

namespace twin {

struct PinId {
  uint8_t port;   // 0 = A, 1 = B
  uint8_t bit;    // DIO number
  uint8_t pincm;  // 1-based IOMUX index
};

enum class Drive : uint8_t { None, Low, High };

class Gpio;

class Pins final : public Device {
 public:
  static constexpr uint32_t kBase = 0x40428000;
  static constexpr uint32_t kSize = 0x400;
  static constexpr uint32_t kPfGpio = 1;
  static constexpr uint32_t kPc = 1U << 7, kPullDown = 1U << 16, kPullUp = 1U << 17, kInputEnable = 1U << 18;
  static constexpr uint32_t kHiZ1 = 1U << 25;

  Pins(Machine& machine, std::span<const PinId> pins);
  void attachPort(int port, Gpio& gpio) { ports_[static_cast<size_t>(port)] = &gpio; }

  const char* name() const override { return "IOMUX"; }
  bool read(uint32_t offset, unsigned bytes, uint32_t& value) override;
  bool write(uint32_t offset, unsigned bytes, uint32_t value) override;

  const PinId* find(int port, int bit) const;
  uint32_t pincm(int index) const { return pincm_[static_cast<size_t>(index)]; }
  // The pin is connected (PC) to peripheral function `pf`.
  bool routed(int index, uint32_t pf) const { return (pincm(index) & (kPc | 0x3FU)) == (kPc | pf); }
  bool level(int index) const { return level_[static_cast<size_t>(index)]; }
  // IOMUX PINCM.INENA: the pin's input buffer is on. Without it an input function reads 0 on silicon
  // (hw_iomux.h "Input Enable Control"); rules.hpp PIN-INENA.
  bool inputEnabled(int index) const { return (pincm(index) & kInputEnable) != 0; }
  // Stops the run (PIN-INENA) when `function` (e.g. "UART0 RX") is to read the pin and INENA is clear.
  // True when the input is enabled.
  bool requireInput(int index, const std::string& function);
  std::string pinName(int index) const;  // "PA11 (PINCM22)"
  // What the MCU does to the pin now (GPIO output), for the board's observers.
  Drive mcuDrive(int index) const;

  // A peripheral output function that drives the pin when it is selected (UART TX and CAN TX idle high;
  // their data travels at byte level through the models).
  void setFunctionDrive(int index, uint32_t pf, Drive drive);

  // Board side.
  void setExternal(int index, Drive drive);
  void setBoardPullUp(int index, bool on);
  // Called with the pin's new level whenever it changes.
  void onChange(int index, std::function<void(bool)> observer);
  // GPIO side: DOUT/DOE of this pin's port changed.
  void refresh(int index);
  void refreshPort(int port);

  // No driver and no pull on the pin: a read of it is recorded (floatingReads()).
  bool floating(int index) const;
  void noteFloatingRead(const PinId& pin);
  const std::set<std::string>& floatingReads() const { return floating_; }

 private:
  void reset();

  Machine& machine_;
  std::vector<PinId> pins_;
  std::vector<uint32_t> pincm_;
  std::vector<bool> level_;
  std::vector<Drive> external_;
  std::vector<bool> boardPullUp_;
  std::vector<std::pair<uint32_t, Drive>> functionDrive_;  // per pin: (PF, drive), PF 0 = none
  std::vector<std::vector<std::function<void(bool)>>> observers_;
  Gpio* ports_[2] = {nullptr, nullptr};
  std::set<std::string> floating_;
};

}  // namespace twin
