// UartLink: fw::hal::Uart on an MSPM0 UART for the BQ79616 daisy-chain base link (1 Mbaud, 8N1), with DMA
// transmit and receive, hardware-timed receive timeouts and pings.
//
// How an exchange runs: the RX DMA channel is armed first (so a reply that starts while we still transmit
// is kept), then the TX DMA channel feeds the TX FIFO. At EOT (last stop bit sent) a TIMG one-shot starts
// the first-byte timeout; each time it expires the ISR compares the RX DMA count with the previous check:
// progress re-arms the timer with the gap timeout, no progress ends the exchange (NoResponse with nothing
// received, Truncated otherwise). A full buffer ends it at once (DMA_DONE_RX, Ok). A framing, parity, break
// or overrun error ends it with CommFault. A gap is therefore detected between gapTimeout and 2 x
// gapTimeout after the last byte; the UART's own RX timeout (IFLS.RXTOSEL) tops out at 15 bit times and
// cannot express 100 us at 1 Mbaud.
//
// A ping mutes the UART by muxing the TX pin to GPIO driven low, starts the one-shot for the ping length,
// and in the timer ISR gives the pin back to the UART (line idle high again) and calls `done`: the pulse is
// the requested length plus interrupt latency (a few microseconds at 32 MHz), with no busy loop.
//
// Contract: see hal/uart.hpp. Statuses from start(): Ok, Busy, InvalidArgument (both spans empty, or a
// span longer than 65535). ping(): Ok, Busy, InvalidArgument (zero). onUartInterrupt() and
// onTimerInterrupt() are the bodies of the UART's and the timer's IRQ handlers (MIS -> ICLR -> act).
#pragma once

#include <cstdint>

#include "dma.hpp"
#include "hal/uart.hpp"
#include "pin.hpp"
#include "timg_one_shot.hpp"

namespace bsp::mspm0 {

class UartLink final : public fw::hal::Uart {
 public:
  struct Config {
    uintptr_t base = 0;
    uint8_t irq = 0;
    uint16_t divisor64 = 0;  // reg::uart::baudDivisor64(bus clock, baud)
    uint32_t baud = 1000000;
    PinFunction tx{};
    PinFunction rx{};
    DmaChannel rxDma{};
    DmaChannel txDma{};
    TimgOneShot::Config timer{};
  };

  constexpr explicit UartLink(const Config& config) : config_(config), timer_(config.timer) {}
  void init();
  void onUartInterrupt();
  void onTimerInterrupt();

 private:
  enum class State : uint8_t { Idle, Transmitting, Receiving, Pinging };

  fw::Status doStart(fw::hal::UartExchange& exchange, fw::hal::Notify done) override;
  fw::Status doPing(fw::Duration low, fw::hal::Notify done) override;
  void doAbort() override;
  uint32_t doBaudRate() const override { return config_.baud; }

  uint32_t received() const;
  void drainRx();
  void restoreTxPin();
  void stopAll();
  void finish(fw::Status status);

  Config config_;
  TimgOneShot timer_;
  fw::hal::UartExchange* exchange_ = nullptr;
  fw::hal::Notify done_{};
  uint32_t lastCount_ = 0;
  volatile State state_ = State::Idle;
};

}  // namespace bsp::mspm0
