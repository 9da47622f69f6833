// Cortex-M0+ cycle counts: ARM DDI 0484C (Cortex-M0+ Technical Reference Manual), Table 3-1 "Cortex-M0+
// instruction summary", for a system with zero wait states. The twin charges exactly these per executed
// instruction; the MSPM0 flash at 32 MHz is taken as zero-wait-state (bsp/twin/README.md, open questions).
#pragma once

#include <cstdint>

namespace twin::cycles {

inline constexpr uint32_t kAlu = 1;       // MOV, ADD, SUB, logic, shifts, compare, extend, reverse
inline constexpr uint32_t kWritePc = 2;   // MOV PC,Rm / ADD PC,PC,Rm
inline constexpr uint32_t kMultiply = 1;  // MULS with the single-cycle multiplier (the 32-cycle option: open)
inline constexpr uint32_t kLoadStore = 2;     // LDR*/STR* every addressing mode
inline constexpr uint32_t kMultipleBase = 1;  // LDM/STM/PUSH/POP: 1 + N
inline constexpr uint32_t kPopPcExtra = 2;    // POP with PC: 3 + N
inline constexpr uint32_t kBranchTaken = 2;   // B<cc> taken, B
inline constexpr uint32_t kBranchNotTaken = 1;
inline constexpr uint32_t kBranchLink = 3;      // BL
inline constexpr uint32_t kBranchExchange = 2;  // BX, BLX
inline constexpr uint32_t kCps = 1;
inline constexpr uint32_t kSpecialRegister = 3;  // MRS, MSR
inline constexpr uint32_t kBarrier = 3;          // DSB, DMB, ISB
inline constexpr uint32_t kHint = 1;             // NOP, YIELD, SEV
inline constexpr uint32_t kWait = 2;             // WFI, WFE
// Exception entry: "the worst case interrupt latency ... in a zero wait-state system ... is 15 cycles"
// (DDI 0484C 5.3; TI SWCU193 "Cortex-M0+ ... interrupt latency"). Return has no table entry: the instruction
// that returns (BX LR, POP {..., PC}) is charged its own cycles plus the pop of the eight-word frame with PC
// (3 + 8), an estimate (README, open questions).
inline constexpr uint32_t kExceptionEntry = 15;
inline constexpr uint32_t kExceptionReturn = 11;

}  // namespace twin::cycles
