// SystemControl: what the application needs of the MCU itself: who it is, why it last reset, and the restart
// into the ROM bootloader for flashing.
//
// Contract
// - identity(): read once at start-up by the BSP (the reset cause register clears when read) and constant
//   afterwards; any context.
// - enterBootloader(): thread mode; the MCU resets into its ROM bootloader and this never returns on a target
//   (the MSPM0 software-invoke reset). A host implementation records the call and returns. The caller is
//   responsible for having put the outputs in a safe state first: nothing runs after it.
#pragma once

#include <cstdint>

namespace fw::hal {

struct ChipIdentity {
  uint32_t traceId = 0;     // unique per chip (MSPM0: FACTORYREGION TRACEID)
  uint16_t partNumber = 0;  // the part (MSPM0: FACTORYREGION DEVICEID PARTNUM)
  uint8_t resetCause = 0;   // why the MCU last reset (MSPM0: SYSCTL RSTCAUSE ID, 0 = none recorded)
};

class SystemControl {
 public:
  ChipIdentity identity() const { return doIdentity(); }
  void enterBootloader() { doEnterBootloader(); }

 protected:
  ~SystemControl() = default;

 private:
  virtual ChipIdentity doIdentity() const = 0;
  virtual void doEnterBootloader() = 0;
};

}  // namespace fw::hal
