#include "flash/chips.hpp"

namespace bmsctl::flash {

namespace {

// Invoke procedures: the BSL invoke pin is PA18, active high, S1 on both LaunchPads (mspm0-sdk boot_config.h
// DEFAULT_BSL_PIN_INVOCATION_DATA0; the LaunchPad example READMEs "PA18 invokes BSL by default when high
// during reset"); the BSL then waits 10 s for a Connection (SLAU887 3.1.1). Its UART: PA22 RX / PA23 TX on
// the MSPM0L1306, PA11 RX / PA10 TX on the MSPM0G3507 (boot_config.h DEF_UART_RXD_PAD / DEF_UART_TXD_PAD);
// the jumpers are bsp/mspm0/README.md "Flashing".
constexpr Chip kChips[] = {
    {"mspm0l1306", "MSPM0L1306", "LP-MSPM0L1306", 64 * 1024, 0x20000000, 4 * 1024, 0, 0x06C0,
     "hold S1 (PA18), press and release the reset button NRST, release S1 at least 100 ms later; the BSL "
     "then "
     "listens for 10 s on PA22 (RX) / PA23 (TX), which are not the back-channel pins: J101 TXD/RXD jumpers "
     "off, "
     "the XDS110 side of TXD wired to PA22 and of RXD to PA23 (bsp/mspm0/README.md, Flashing)"},
    {"mspm0g3507", "MSPM0G3507", "LP-MSPM0G3507", 128 * 1024, 0x20200000, 32 * 1024, 0x20000000, 0x3EC0,
     "hold S1 (PA18), press and release the reset button NRST, release S1 at least 100 ms later; the BSL "
     "then "
     "listens for 10 s on PA11 (RX) / PA10 (TX), the back-channel with J21/J22 at 1:2 and the J101 TXD/RXD "
     "jumpers on (the default lp-mspm0g3507-bq79616 wiring moves J21/J22 to the BQ79616: put them back to "
     "flash)"},
};

bool within(uint32_t sp, uint32_t base, uint32_t size) {
  return base != 0 && sp > base && sp - base <= size;
}

}  // namespace

std::span<const Chip> chips() {
  return kChips;
}

const Chip* chipByName(const std::string& name) {
  for (const Chip& c : kChips) {
    if (name == c.name) return &c;
  }
  return nullptr;
}

const Chip* chipFromStack(uint32_t initialStackPointer) {
  for (const Chip& c : kChips) {
    if (within(initialStackPointer, c.sramBase, c.sramSize)) return &c;
  }
  // The G3507's other SRAM window starts where the L1306's SRAM does: only above the L1306's top is it
  // unambiguous.
  for (const Chip& c : kChips) {
    if (within(initialStackPointer, c.sramAliasBase, c.sramSize)) return &c;
  }
  return nullptr;
}

const Chip* chipFromBslBuffer(uint16_t bufferSize) {
  for (const Chip& c : kChips) {
    if (c.bslBufferSize == bufferSize) return &c;
  }
  return nullptr;
}

}  // namespace bmsctl::flash
