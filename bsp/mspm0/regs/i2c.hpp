// I2C controller registers. Source: mspm0l1306.tsv / mspm0g3507.tsv rows "I2C.*" (offsets) and "I2C_*"
// (fields), MSPM0 TRM I2C chapter (SLAU846A section 19).
#pragma once

#include <cstddef>
#include <cstdint>

#include "regs/common.hpp"

namespace bsp::mspm0::reg::i2c {

struct Clock {
  Reg clkdiv;  // 0x1000: RATIO 2:0, divide by RATIO + 1
  Reg clksel;  // 0x1004: BUSCLK_SEL bit 3
};
inline constexpr uintptr_t kClockOffset = 0x1000;

struct Controller {
  Reg gfctl;       // 0x1200
  Reg timeoutCtl;  // 0x1204
  Reg timeoutCnt;  // 0x1208
  Reg reserved0_;
  Reg msa;      // 0x1210
  Reg mctr;     // 0x1214
  Reg msr;      // 0x1218
  Reg mrxdata;  // 0x121C
  Reg mtxdata;  // 0x1220
  Reg mtpr;     // 0x1224
  Reg mcr;      // 0x1228
  Reg reserved1_[2];
  Reg mbmon;     // 0x1234
  Reg mfifoctl;  // 0x1238
  Reg mfifosr;   // 0x123C
  Reg pecctl;    // 0x1240: CONTROLLER_I2CPECCTL
  Reg pecsr;     // 0x1244: CONTROLLER_PECSR
};
inline constexpr uintptr_t kControllerOffset = 0x1200;
constexpr uintptr_t at(size_t member) {
  return kControllerOffset + member;
}
static_assert(at(offsetof(Controller, timeoutCtl)) == 0x1204 && at(offsetof(Controller, msa)) == 0x1210);
static_assert(at(offsetof(Controller, mctr)) == 0x1214 && at(offsetof(Controller, msr)) == 0x1218);
static_assert(at(offsetof(Controller, mrxdata)) == 0x121C && at(offsetof(Controller, mtxdata)) == 0x1220);
static_assert(at(offsetof(Controller, mtpr)) == 0x1224 && at(offsetof(Controller, mcr)) == 0x1228);
static_assert(at(offsetof(Controller, mbmon)) == 0x1234 && at(offsetof(Controller, mfifoctl)) == 0x1238);
static_assert(at(offsetof(Controller, mfifosr)) == 0x123C && at(offsetof(Controller, pecctl)) == 0x1240);
static_assert(at(offsetof(Controller, pecsr)) == 0x1244);

inline Clock& clock(uintptr_t base) {
  return mmio::block<Clock>(base + kClockOffset);
}
inline Controller& controller(uintptr_t base) {
  return mmio::block<Controller>(base + kControllerOffset);
}

inline constexpr uint32_t kClkselBusclk = 1U << 3;

// TIMEOUT_CTL: TCNTLA 7:0 (SCL-low timeout count, the upper 8 bits of a 12-bit counter: i2c_timing.hpp),
// TCNTAEN bit 15.
inline constexpr uint32_t kTimeoutAEnable = 1U << 15;

// MSA: SADDR 10:1, DIR bit 0 (1 = receive).
inline constexpr uint32_t kMsaRead = 1U << 0;

// MCTR
inline constexpr uint32_t kMctrBurstRun = 1U << 0;
inline constexpr uint32_t kMctrStart = 1U << 1;
inline constexpr uint32_t kMctrStop = 1U << 2;
inline constexpr uint32_t kMctrAck = 1U << 3;
inline constexpr uint32_t kMctrLenShift = 16;  // MBLEN 27:16
inline constexpr uint32_t kMctrLenMax = 0xFFF;

// MSR
inline constexpr uint32_t kMsrBusy = 1U << 0;
inline constexpr uint32_t kMsrErr = 1U << 1;
inline constexpr uint32_t kMsrAdrAck = 1U << 2;  // set: the address was not acknowledged
inline constexpr uint32_t kMsrDatAck = 1U << 3;  // set: a data byte was not acknowledged
inline constexpr uint32_t kMsrArbLost = 1U << 4;
inline constexpr uint32_t kMsrIdle = 1U << 5;
inline constexpr uint32_t kMsrBusBusy = 1U << 6;

// MCR
inline constexpr uint32_t kMcrActive = 1U << 0;
inline constexpr uint32_t kMcrClkStretch = 1U << 2;

// MBMON
inline constexpr uint32_t kMbmonScl = 1U << 0;
inline constexpr uint32_t kMbmonSda = 1U << 1;

// MFIFOCTL: TXTRIG 2:0, TXFLUSH 7, RXTRIG 10:8, RXFLUSH 15. TX level 4 = 0x4; RX level 7 = 0x600 (RXTRIG
// LEVEL_n = (n - 1) << 8: "trigger when RX FIFO contains at least n bytes", hw_i2c.h MFIFOCTL.RXTRIG and
// dl_i2c.h DL_I2C_RX_FIFO_LEVEL_BYTES_7).
inline constexpr uint32_t kFifoTxTrigLevel4 = 0x4;
inline constexpr uint32_t kFifoRxTrigLevel7 = 0x600;
inline constexpr uint32_t kFifoTxFlush = 1U << 7;
inline constexpr uint32_t kFifoRxFlush = 1U << 15;

// MFIFOSR: RXFIFOCNT 3:0 (bytes to read), TXFIFOCNT 11:8 (bytes that can still be written; 8 = empty).
// FIFO depth: param I2C_SYS_FENTRIES = 8; SLAAE56A (MSPM0 vs STM32G0, I2C table, which lists the
// L130x): "TX: 8 byte, RX: 8 byte" for MSPM0L and MSPM0G. E2E threads report 4 entries on the newer
// MSPM0L111x and C110x: other parts; i2c.cpp's RX trigger at 7 relies on the L130x/G350x's 8.
inline constexpr uint32_t kFifoRxCountMask = 0xF;
inline constexpr uint32_t kFifoTxFreeShift = 8;
inline constexpr uint32_t kFifoTxFreeMask = 0xF00;
inline constexpr uint32_t kFifoDepth = 8;

// CONTROLLER_I2CPECCTL: PECCNT 8:0, PECEN bit 12. CONTROLLER_PECSR: PECSTS_ERROR bit 17.
inline constexpr uint32_t kPecEnable = 1U << 12;
inline constexpr uint32_t kPecsrError = 1U << 17;

// CPU_INT bits (I2C_CPU_INT_IMASK_*).
inline constexpr uint32_t kIntRxDone = 1U << 0;
inline constexpr uint32_t kIntTxDone = 1U << 1;
inline constexpr uint32_t kIntRxFifoTrig = 1U << 2;
inline constexpr uint32_t kIntTxFifoTrig = 1U << 3;
inline constexpr uint32_t kIntNack = 1U << 7;
inline constexpr uint32_t kIntStart = 1U << 8;
inline constexpr uint32_t kIntStop = 1U << 9;
inline constexpr uint32_t kIntArbLost = 1U << 10;
inline constexpr uint32_t kIntPecRxErr = 1U << 13;
inline constexpr uint32_t kIntTimeoutA = 1U << 14;

}  // namespace bsp::mspm0::reg::i2c
