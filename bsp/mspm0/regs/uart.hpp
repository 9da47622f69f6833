// UART registers. Source: mspm0*.tsv rows "UART.*" and "UART_*" (MSPM0 TRM UART chapter, SLAU846A 20).
#pragma once

#include <cstddef>
#include <cstdint>

#include "regs/common.hpp"

namespace bsp::mspm0::reg::uart {

struct Clock {
  Reg clkdiv;  // 0x1000
  Reg reserved_;
  Reg clksel;  // 0x1008: BUSCLK_SEL bit 3
};
inline constexpr uintptr_t kClockOffset = 0x1000;
// DMA_TRIG_RX (IMASK RXINT bit 10 routes "RX FIFO at level" to the DMA) and DMA_TRIG_TX (TXINT bit 11).
inline constexpr uintptr_t kDmaTrigRxOffset = 0x1050;
inline constexpr uintptr_t kDmaTrigTxOffset = 0x1080;

struct Line {
  Reg ctl0;   // 0x1100
  Reg lcrh;   // 0x1104
  Reg stat;   // 0x1108
  Reg ifls;   // 0x110C
  Reg ibrd;   // 0x1110
  Reg fbrd;   // 0x1114
  Reg gfctl;  // 0x1118
  Reg reserved_;
  Reg txdata;  // 0x1120
  Reg rxdata;  // 0x1124
};
inline constexpr uintptr_t kLineOffset = 0x1100;
constexpr uintptr_t at(size_t member) {
  return kLineOffset + member;
}
static_assert(at(offsetof(Line, lcrh)) == 0x1104 && at(offsetof(Line, stat)) == 0x1108);
static_assert(at(offsetof(Line, ifls)) == 0x110C && at(offsetof(Line, ibrd)) == 0x1110);
static_assert(at(offsetof(Line, fbrd)) == 0x1114 && at(offsetof(Line, txdata)) == 0x1120);
static_assert(at(offsetof(Line, rxdata)) == 0x1124 && kClockOffset + offsetof(Clock, clksel) == 0x1008);

inline Clock& clock(uintptr_t base) {
  return mmio::block<Clock>(base + kClockOffset);
}
inline Line& line(uintptr_t base) {
  return mmio::block<Line>(base + kLineOffset);
}
inline EventBlock& dmaTrigRx(uintptr_t base) {
  return mmio::block<EventBlock>(base + kDmaTrigRxOffset);
}
inline EventBlock& dmaTrigTx(uintptr_t base) {
  return mmio::block<EventBlock>(base + kDmaTrigTxOffset);
}

inline constexpr uint32_t kClkselBusclk = 1U << 3;

// CTL0: ENABLE 0, RXE 3, TXE 4, FEN 17; HSE 16:15 = 0 (16x oversampling).
inline constexpr uint32_t kCtl0Enable = 1U << 0;
inline constexpr uint32_t kCtl0Rxe = 1U << 3;
inline constexpr uint32_t kCtl0Txe = 1U << 4;
inline constexpr uint32_t kCtl0Fen = 1U << 17;

// LCRH: WLEN 5:4 = 8 data bits (0x30); no parity, one stop bit.
inline constexpr uint32_t kLcrh8N1 = 0x30;

// STAT
inline constexpr uint32_t kStatBusy = 1U << 0;
inline constexpr uint32_t kStatRxfe = 1U << 2;

// IFLS: TXIFLSEL 2:0 = 7, "TX FIFO has at least one entry free", and RXIFLSEL 6:4 = 7 (0x70), "at least one
// entry received": the levels the DMA triggers need (TI MSPM0 SDK hw_uart.h UART_IFLS_TXIFLSEL_LVL_1 and
// dl_uart.h DL_UART_RX_FIFO_LEVEL_ONE_ENTRY notes; every TI UART DMA example of both LaunchPads selects
// them).
inline constexpr uint32_t kIflsTxOneFree = 0x7;
inline constexpr uint32_t kIflsRxOne = 0x70;

// CPU_INT bits (UART_CPU_INT_IMASK_*).
inline constexpr uint32_t kIntRtout = 1U << 0;
inline constexpr uint32_t kIntFrmErr = 1U << 1;
inline constexpr uint32_t kIntParErr = 1U << 2;
inline constexpr uint32_t kIntBrkErr = 1U << 3;
inline constexpr uint32_t kIntOvrErr = 1U << 4;
inline constexpr uint32_t kIntRx = 1U << 10;
inline constexpr uint32_t kIntTx = 1U << 11;
inline constexpr uint32_t kIntEot = 1U << 12;
inline constexpr uint32_t kIntDmaDoneRx = 1U << 15;
inline constexpr uint32_t kIntDmaDoneTx = 1U << 16;
inline constexpr uint32_t kIntErrors = kIntFrmErr | kIntParErr | kIntBrkErr | kIntOvrErr;

// Baud divisor for 16x oversampling: IBRD + FBRD/64 = clock / (16 * baud), FBRD rounded to the nearest
// 1/64 (TRM UART "Baud-rate generation"). Returns IBRD << 6 | FBRD.
constexpr uint32_t baudDivisor64(uint32_t clockHz, uint32_t baud) {
  return (clockHz * 8U / baud + 1U) / 2U;  // round(clock * 64 / (16 * baud)) = round(clock * 4 / baud)
}
static_assert(baudDivisor64(32000000, 1000000) == (2U << 6), "1 Mbaud from 32 MHz: IBRD=2 FBRD=0 (tsv)");

}  // namespace bsp::mspm0::reg::uart
