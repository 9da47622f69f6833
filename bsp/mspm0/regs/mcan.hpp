// MCAN (CANFD0) registers of the MSPM0G3507 (CANFD0_BASE 0x40508000). Source: mspm0g3507.tsv rows "MCAN.*" /
// "MCAN_*" and "mem CANFD0 message RAM" (message RAM at the base, element addresses in bytes); message RAM
// element layouts (T0/T1, R0/R1, data words) from the tsv "MCAN TX element" rows and the Bosch M_CAN user
// manual section 2.4 (MSPM0 TRM SLAU846A section 21).
#pragma once

#include <cstddef>
#include <cstdint>

#include "regs/common.hpp"

namespace bsp::mspm0::reg::mcan {

// Protocol core, 0x7000..0x707F.
struct Core {
  Reg crel;  // 0x7000
  Reg endn;  // 0x7004
  Reg reserved0_[4];
  Reg cccr;  // 0x7018
  Reg nbtp;  // 0x701C
  Reg reserved1_[8];
  Reg ecr;  // 0x7040
  Reg psr;  // 0x7044
  Reg reserved2_[2];
  Reg ir;   // 0x7050
  Reg ie;   // 0x7054
  Reg ils;  // 0x7058
  Reg ile;  // 0x705C
};
inline constexpr uintptr_t kCoreOffset = 0x7000;
static_assert(kCoreOffset + offsetof(Core, cccr) == 0x7018 && kCoreOffset + offsetof(Core, nbtp) == 0x701C);
static_assert(kCoreOffset + offsetof(Core, ecr) == 0x7040 && kCoreOffset + offsetof(Core, psr) == 0x7044);
static_assert(kCoreOffset + offsetof(Core, ir) == 0x7050 && kCoreOffset + offsetof(Core, ie) == 0x7054);
static_assert(kCoreOffset + offsetof(Core, ils) == 0x7058 && kCoreOffset + offsetof(Core, ile) == 0x705C);

// Filters and message RAM configuration, 0x7080..0x70E3.
struct Queues {
  Reg gfc;    // 0x7080
  Reg sidfc;  // 0x7084
  Reg xidfc;  // 0x7088
  Reg reserved0_[5];
  Reg rxf0c;  // 0x70A0
  Reg rxf0s;  // 0x70A4
  Reg rxf0a;  // 0x70A8
  Reg reserved1_[4];
  Reg rxesc;   // 0x70BC
  Reg txbc;    // 0x70C0
  Reg txfqs;   // 0x70C4
  Reg txesc;   // 0x70C8
  Reg txbrp;   // 0x70CC
  Reg txbar;   // 0x70D0
  Reg txbcr;   // 0x70D4
  Reg txbto;   // 0x70D8
  Reg txbcf;   // 0x70DC
  Reg txbtie;  // 0x70E0
};
inline constexpr uintptr_t kQueuesOffset = 0x7080;
static_assert(kQueuesOffset + offsetof(Queues, rxf0c) == 0x70A0 &&
              kQueuesOffset + offsetof(Queues, rxf0a) == 0x70A8);
static_assert(kQueuesOffset + offsetof(Queues, rxesc) == 0x70BC &&
              kQueuesOffset + offsetof(Queues, txbc) == 0x70C0);
static_assert(kQueuesOffset + offsetof(Queues, txfqs) == 0x70C4 &&
              kQueuesOffset + offsetof(Queues, txbar) == 0x70D0);
static_assert(kQueuesOffset + offsetof(Queues, txbto) == 0x70D8 &&
              kQueuesOffset + offsetof(Queues, txbtie) == 0x70E0);

// Subsystem wrapper: GPRCM at 0x6800 (tsv note "GPRCM keys"), MCANSS_STAT 0x7208 (MEM_INIT_DONE bit 1),
// MCANSS_EOI 0x7220 (EOI 7:0: 0x01 ends the line-0 interrupt, 0x02 line 1; TI MSPM0 SDK hw_mcan.h),
// TI_WRAPPER.MSP.CPU_INT at 0x7820 (INTL0 bit 0), MCANSS_CLKEN 0x7900 (CLK_REQEN bit 0) and
// MCANSS_CLKDIV 0x7904 (RATIO 1:0, 0 = /1).
struct SsClock {
  Reg clken;   // 0x7900
  Reg clkdiv;  // 0x7904
};
inline constexpr uintptr_t kGprcmOffset = 0x6800;
inline constexpr uintptr_t kSsStatOffset = 0x7208;
inline constexpr uintptr_t kSsEoiOffset = 0x7220;
inline constexpr uintptr_t kCpuIntOffset = 0x7820;
inline constexpr uintptr_t kSsClockOffset = 0x7900;

inline Core& core(uintptr_t base) {
  return mmio::block<Core>(base + kCoreOffset);
}
inline Queues& queues(uintptr_t base) {
  return mmio::block<Queues>(base + kQueuesOffset);
}
inline Gprcm& gprcm(uintptr_t base) {
  return mmio::block<Gprcm>(base + kGprcmOffset);
}
inline Reg& ssStat(uintptr_t base) {
  return mmio::block<Reg>(base + kSsStatOffset);
}
inline Reg& ssEoi(uintptr_t base) {
  return mmio::block<Reg>(base + kSsEoiOffset);
}
inline EventBlock& cpuInt(uintptr_t base) {
  return mmio::block<EventBlock>(base + kCpuIntOffset);
}
inline SsClock& ssClock(uintptr_t base) {
  return mmio::block<SsClock>(base + kSsClockOffset);
}
// Message RAM word `index` (the RAM starts at the base; element start addresses are byte offsets).
inline Reg* ram(uintptr_t base, uint32_t byteOffset) {
  return &mmio::block<Reg>(base + byteOffset);
}

inline constexpr uint32_t kSsMemInitDone = 1U << 1;
inline constexpr uint32_t kSsEoiLine0 = 0x01;
inline constexpr uint32_t kIntLine0 = 1U << 0;

// CCCR
inline constexpr uint32_t kCccrInit = 1U << 0;
inline constexpr uint32_t kCccrCce = 1U << 1;

// NBTP: NSJW 31:25, NBRP 24:16, NTSEG1 15:8, NTSEG2 6:0 (each field holds its value minus one).
constexpr uint32_t nbtp(uint32_t sjw, uint32_t brp, uint32_t seg1, uint32_t seg2) {
  return ((sjw - 1) << 25) | ((brp - 1) << 16) | ((seg1 - 1) << 8) | (seg2 - 1);
}

// PSR: BO bit 7, EP bit 5.
inline constexpr uint32_t kPsrBusOff = 1U << 7;
inline constexpr uint32_t kPsrErrorPassive = 1U << 5;

// IR / IE bits.
inline constexpr uint32_t kIrRf0n = 1U << 0;  // RX FIFO 0 new message
inline constexpr uint32_t kIrRf0l = 1U << 3;  // RX FIFO 0 message lost (a frame arrived with the FIFO full)
inline constexpr uint32_t kIrTc = 1U << 9;    // transmission completed
inline constexpr uint32_t kIrEp = 1U << 23;   // error passive changed
inline constexpr uint32_t kIrBo = 1U << 25;   // bus-off status changed

// ILE: EINT0 bit 0. GFC: ANFS 5:4 = 0 and ANFE 3:2 = 0 accept non-matching frames into RX FIFO 0; RRFS bit 1
// and RRFE bit 0 reject remote frames.
inline constexpr uint32_t kIleLine0 = 1U << 0;
inline constexpr uint32_t kGfcAcceptAllRejectRemote = (1U << 1) | (1U << 0);
// ANFS = ANFE = 2: reject non-matching frames too: only frames a filter element stores are received.
inline constexpr uint32_t kGfcRejectAll = (2U << 4) | (2U << 2) | kGfcAcceptAllRejectRemote;

// SIDFC: FLSSA 15:2 (the standard filter list's start, a word address in bits 15:2, so the byte address),
// LSS 23:16 (elements) (hw_mcan.h MCAN_SIDFC; M_CAN user manual SIDFC).
constexpr uint32_t sidfc(uint32_t startByte, uint32_t elements) {
  return startByte | (elements << 16);
}
// Standard ID filter element (one word): SFT 31:30, SFEC 29:27, SFID1 26:16, SFID2 10:0 (M_CAN user manual
// 2.4.5, the standard message ID filter element). SFT 1 = dual ID (SFID1 or SFID2), SFEC 1
// = store in RX FIFO 0, as TI's mcan_message_rx example sets its two filters.
constexpr uint32_t stdFilterDual(uint32_t id1, uint32_t id2) {
  return (1U << 30) | (1U << 27) | ((id1 & 0x7FF) << 16) | (id2 & 0x7FF);
}

// TXBC: TBSA 15:2 (byte address), NDTB 21:16, TFQS 29:24, TFQM bit 30 (0 = FIFO).
constexpr uint32_t txbc(uint32_t startByte, uint32_t fifoElements) {
  return startByte | (fifoElements << 24);
}
// RXF0C: F0SA 15:2, F0S 22:16.
constexpr uint32_t rxf0c(uint32_t startByte, uint32_t elements) {
  return startByte | (elements << 16);
}
// TXFQS: TFQPI 20:16 (put index), TFQF bit 21 (full). RXF0S: F0FL 6:0 (fill level), F0GI 13:8 (get index).
inline constexpr uint32_t kTxfqsFull = 1U << 21;
inline constexpr uint32_t kTxfqsPutShift = 16;
inline constexpr uint32_t kTxfqsPutMask = 0x1F;
inline constexpr uint32_t kRxf0sFillMask = 0x7F;
inline constexpr uint32_t kRxf0sGetShift = 8;
inline constexpr uint32_t kRxf0sGetMask = 0x3F;

// Message RAM elements with 8 data bytes are 4 words (TXESC/RXESC = 0).
inline constexpr uint32_t kElementWords = 4;
// Word 0 (T0/R0): standard ID 28:18 or extended ID 28:0, RTR bit 29, XTD bit 30.
inline constexpr uint32_t kElemXtd = 1U << 30;
inline constexpr uint32_t kElemStdIdShift = 18;
// Word 1 (T1/R1): DLC 19:16.
inline constexpr uint32_t kElemDlcShift = 16;

}  // namespace bsp::mspm0::reg::mcan
