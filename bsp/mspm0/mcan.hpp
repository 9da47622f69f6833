// McanBus: fw::hal::CanBus on the MSPM0G3507's MCAN (CANFD0), classic CAN only.
//
// Message RAM (at the peripheral base, byte addresses): an 8-element TX FIFO at 0x000, an 8-element RX FIFO
// 0 at 0x080, 16 bytes per element (8 data bytes), and the standard ID filter list at 0x100: one dual-ID
// element (SFT 1, SFEC 1: store in RX FIFO 0) per two identifiers of Config::accept (the last one repeats its
// identifier when the count is odd). The global filter rejects every frame no element matches and every
// remote frame (GFC ANFS = ANFE = 2, RRFS = RRFE = 1), so only the accepted identifiers ever raise RF0N. This
// is the set-up of TI's mcan_message_rx example (two standard dual-ID filter elements, M_CAN user manual
// 2.4.5, storing to FIFO 0; there the non-matching frames go to FIFO 1). The TX FIFO (TXBC.TFQM = 0) sends
// frames in the order they were queued, which is what the contract asks of frames of equal priority.
//
// Bit timing (TI's bq79616_uart_to_can example, MSPM0 SDK 2.09, ti_msp_dl_config.c): CANCLK = HFXT 40 MHz,
// prescaler 1, 1 + 69 + 10 = 80 tq of 25 ns = 500 kbit/s, sample point 70/80 = 87.5 %, SJW 10 tq. kNbtp500k
// below is that word. Documented alternative without the crystal: SYSPLLCLK1 as CANCLK (GENCLKCFG.CANCLKSRC =
// 1) at 40 MHz gives the same NBTP; from a 32 MHz clock, 1 + 55 + 8 = 64 tq gives 500 kbit/s at 87.5 % as
// well.
//
// Contract (see hal/can_bus.hpp)
// - init(): thread mode; Ok, NotReady when the message RAM or an INIT handshake (entering configuration,
//   then leaving it for normal operation) did not complete in time (bounded polls), or InvalidArgument when
//   Config::accept names more identifiers than the filter list holds. Until init() succeeds (or when it was
//   never called: a board without its crystal skips it) send() and recover() return NotReady, state()
//   BusOff (off the bus) and receive() false, without touching the peripheral, whose power may be off.
// - send(): Ok, Overflow (TX FIFO full, counted), BusOff, InvalidArgument (dlc > 8, id out of range),
//   NotReady. Task context (a short critical section guards the put index).
// - receive(): task context; pops RX FIFO 0 in arrival order. Reception is built unless BSP_MCAN_RX is 0
//   (mspm0/config.hpp): then the global filter rejects every frame and receive() always returns false (no
//   frame). A frame that arrives with the FIFO full is lost (RF0L, counted in counters().rxLost).
// - Bus-off: the MCAN sets CCCR.INIT itself and stops (ISO 11898-1). recover() clears INIT, after which
//   the controller waits for 129 x 11 recessive bits and returns to error active; the BO interrupt fires on
//   entering and on leaving bus-off and the registered Notify is called both times.
// - onInterrupt(): body of CANFD0_IRQHandler: reads the wrapper MIS and clears it, reads the MCAN IR and
//   clears exactly those bits (IR is write-1-to-clear), ends the interrupt at the subsystem (MCANSS_EOI),
//   updates counters, calls the receive Notify on RF0N and the other one on TC/EP/BO, returns (TI's
//   mcan_message_rx ISR order: the line's status, the interrupt flags cleared (IR, then EOI), then the FIFO
//   is read, here by the task the Notify wakes).
#pragma once

#include <cstdint>
#include <span>

#include "hal/can_bus.hpp"
#include "mspm0/config.hpp"
#include "pin.hpp"
#include "regs/mcan.hpp"

namespace bsp::mspm0 {

inline constexpr bool kMcanRx = BSP_MCAN_RX != 0;

class McanBus final : public fw::hal::CanBus {
 public:
  static constexpr uint32_t kNbtp500k = reg::mcan::nbtp(10, 1, 69, 10);
  static_assert(kNbtp500k == 0x12004409, "the NBTP word of TI's bq79616_uart_to_can configuration");

  struct Config {
    uintptr_t base = 0;
    uint8_t irq = 0;
    PinFunction tx{};
    PinFunction rx{};
    uint32_t nbtp = kNbtp500k;
    std::span<const uint32_t> accept{};  // the standard identifiers received (at most 2 x kFilterElements)
  };

  static constexpr uint32_t kTxFifoStart = 0x000;  // byte address in the message RAM
  static constexpr uint32_t kRxFifoStart = 0x080;
  static constexpr uint32_t kFifoElements = 8;
  static constexpr uint32_t kFilterStart = 0x100;
  static constexpr uint32_t kFilterElements = 8;

  constexpr explicit McanBus(const Config& config) : config_(config) {}
  fw::Status init();
  void onInterrupt();

 private:
  fw::Status doSend(const fw::hal::CanFrame& frame) override;
  bool doReceive(fw::hal::CanFrame& frame) override;
  void doOnEvent(const fw::hal::Notify& notify) override { notify_ = notify; }
  void doOnReceive(const fw::hal::Notify& notify) override { rxNotify_ = notify; }
  fw::hal::CanState doState() const override;
  fw::Status doRecover() override;
  fw::hal::CanCounters doCounters() const override;

  Config config_;
  fw::hal::Notify notify_{};
  fw::hal::Notify rxNotify_{};
  volatile uint32_t inFlight_ = 0;  // TX FIFO elements requested and not yet seen transmitted
  volatile uint32_t txFrames_ = 0;
  uint32_t rxFrames_ = 0;
  volatile uint32_t txOverflows_ = 0;
  volatile uint32_t busOffEvents_ = 0;
  volatile uint32_t rxLost_ = 0;
  bool ready_ = false;
};

}  // namespace bsp::mspm0
