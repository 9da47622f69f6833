#include "uart_link.hpp"

#include "gpio.hpp"
#include "hal/irq.hpp"
#include "mmio.hpp"
#include "regs/cpuss.hpp"
#include "regs/gpio.hpp"
#include "regs/uart.hpp"
#include "uart_common.hpp"

namespace bsp::mspm0 {

namespace uart = reg::uart;
using fw::Status;
namespace gpio = reg::gpio;

void UartLink::init() {
  uartConfigure(config_.base, config_.divisor64, true);
  muxPeripheral(config_.tx);
  muxPeripheral(config_.rx, reg::iomux::kInputEnable | reg::iomux::kPullUp);
  // Preset the ping level: while the pin is muxed to the UART the GPIO output has no effect.
  gpio::data(config_.tx.pin.portBase()).doutclr.write(config_.tx.pin.mask());
  timer_.init();
  nvic::enable(config_.irq);
}

void UartLink::drainRx() {
  // The RX FIFO holds at most 4 bytes; stale bytes (line noise before the exchange) must not land in rx.
  uart::Line& line = uart::line(config_.base);
  for (int i = 0; i < 8 && (line.stat.read() & uart::kStatRxfe) == 0; ++i)
    (void)line.rxdata.read();
}

uint32_t UartLink::received() const {
  return static_cast<uint32_t>(exchange_->rx.size()) - config_.rxDma.remaining();
}

Status UartLink::doStart(fw::hal::UartExchange& exchange, fw::hal::Notify done) {
  if ((exchange.tx.empty() && exchange.rx.empty()) || exchange.tx.size() > 0xFFFF ||
      exchange.rx.size() > 0xFFFF)
    return Status::InvalidArgument;
  if (state_ != State::Idle) return Status::Busy;
  uart::Line& line = uart::line(config_.base);
  reg::EventBlock& events = reg::cpuInt(config_.base);
  exchange.status = Status::Aborted;
  exchange.received = 0;
  exchange_ = &exchange;
  done_ = done;
  lastCount_ = 0;
  drainRx();
  events.iclr.write(0xFFFFFFFF);
  uint32_t irqs = uart::kIntErrors;
  if (!exchange.rx.empty()) {
    // Receiver first: a reply that starts while we still transmit is kept.
    config_.rxDma.start(DmaChannel::Direction::FromPeripheral, mmio::address(&line.rxdata),
                        mmio::address(exchange.rx.data()), static_cast<uint32_t>(exchange.rx.size()));
    irqs |= uart::kIntDmaDoneRx;
  }
  if (!exchange.tx.empty()) {
    state_ = State::Transmitting;
    events.imask.write(irqs | uart::kIntEot);
    config_.txDma.start(DmaChannel::Direction::ToPeripheral, mmio::address(exchange.tx.data()),
                        mmio::address(&line.txdata), static_cast<uint32_t>(exchange.tx.size()));
  } else {
    state_ = State::Receiving;
    events.imask.write(irqs);
    timer_.start(exchange.firstByteTimeout.us);
  }
  return Status::Ok;
}

Status UartLink::doPing(fw::Duration low, fw::hal::Notify done) {
  if (low.us == 0) return Status::InvalidArgument;
  if (state_ != State::Idle) return Status::Busy;
  done_ = done;
  state_ = State::Pinging;
  // DOUT is already low (init): enable the driver, then take the pin from the UART.
  const Pin& tx = config_.tx.pin;
  gpio::data(tx.portBase()).doeset.write(tx.mask());
  reg::iomux::pincm(tx.pincm).write(reg::iomux::kPc | reg::iomux::kPfGpio);
  timer_.start(low.us);
  return Status::Ok;
}

void UartLink::restoreTxPin() {
  muxPeripheral(config_.tx);
  gpio::data(config_.tx.pin.portBase()).doeclr.write(config_.tx.pin.mask());
}

void UartLink::onUartInterrupt() {
  reg::EventBlock& events = reg::cpuInt(config_.base);
  const uint32_t pending = events.mis.read();
  events.iclr.write(pending);
  const State state = state_;
  if (state != State::Transmitting && state != State::Receiving) return;
  if (pending & uart::kIntErrors) {
    finish(Status::CommFault);
  } else if (pending & uart::kIntDmaDoneRx) {
    finish(Status::Ok);
  } else if (pending & uart::kIntEot) {
    if (exchange_->rx.empty()) {
      finish(Status::Ok);
    } else {
      state_ = State::Receiving;
      lastCount_ = received();
      timer_.start(exchange_->firstByteTimeout.us);
    }
  }
}

void UartLink::onTimerInterrupt() {
  if (!timer_.onInterrupt()) return;
  if (state_ == State::Pinging) {
    restoreTxPin();
    state_ = State::Idle;
    done_();
    return;
  }
  if (state_ != State::Receiving) return;
  const uint32_t count = received();
  if (count == lastCount_) {
    finish(count == 0 ? Status::NoResponse : Status::Truncated);
  } else {
    lastCount_ = count;
    timer_.start(exchange_->gapTimeout.us);
  }
}

void UartLink::stopAll() {
  reg::cpuInt(config_.base).imask.write(0);
  config_.txDma.stop();
  config_.rxDma.stop();
  timer_.stop();
}

void UartLink::finish(Status status) {
  stopAll();
  exchange_->received = exchange_->rx.empty() ? 0 : received();
  exchange_->status = status;
  state_ = State::Idle;
  done_();
}

void UartLink::doAbort() {
  fw::hal::CriticalSection cs;
  const bool pinging = state_ == State::Pinging;
  stopAll();
  if (pinging) restoreTxPin();
  drainRx();
  reg::cpuInt(config_.base).iclr.write(0xFFFFFFFF);
  state_ = State::Idle;
}

}  // namespace bsp::mspm0
