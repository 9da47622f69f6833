// The BQ79616 registers this driver touches, taken from the generated register map (regmap/bq79616.hpp,
// generated from regmaps/bq79616/*.yaml). No address is written down here: each constant is the address of a
// generated descriptor, and the static_asserts check the layout facts the driver relies on (consecutive
// blocks read or written in one frame), so a wrong table fails the build instead of the bus.
//
// Also here: the few register *values* the driver writes, each with the datasheet field it sets.
#pragma once

#include <cstdint>

#include "regmap/bq79616.hpp"

namespace fw::drivers::bq79616::regs {

namespace r = ::fw::regmap::bq79616::reg;

using ::fw::regmap::code16;  // BQ79616 register addresses are 16-bit

// Addressing and communication (SLUSE81E §9.5.4.3).
inline constexpr uint16_t kDir0Addr = code16(r::Dir0Addr);
inline constexpr uint16_t kCommCtrl = code16(r::CommCtrl);
inline constexpr uint16_t kControl1 = code16(r::Control1);
inline constexpr uint16_t kControl2 = code16(r::Control2);
inline constexpr uint16_t kOtpEccDatain1 = code16(r::OtpEccDatain1);  // DLL synchronisation dummies 1..8
// Configuration (NVM shadow registers, covered by the customer CRC).
inline constexpr uint16_t kActiveCell = code16(r::ActiveCell);
inline constexpr uint16_t kAdcConf1 = code16(r::AdcConf1);
inline constexpr uint16_t kCustCrcHi = code16(r::CustCrcHi);
inline constexpr uint16_t kCustCrcRsltHi = code16(r::CustCrcRsltHi);
inline constexpr uint16_t kAdcCtrl1 = code16(r::AdcCtrl1);
inline constexpr uint16_t kDevStat = code16(r::DevStat);
// Faults.
inline constexpr uint16_t kFaultMsk2 = code16(r::FaultMsk2);
inline constexpr uint16_t kFaultRst1 = code16(r::FaultRst1);
inline constexpr uint16_t kFaultRst2 = code16(r::FaultRst2);
inline constexpr uint16_t kFaultSummary = code16(r::FaultSummary);
// The VC open-wire diagnostic (open_wire.hpp).
inline constexpr uint16_t kDiagCompCtrl2 = code16(r::DiagCompCtrl2);
inline constexpr uint16_t kDiagCompCtrl3 = code16(r::DiagCompCtrl3);
inline constexpr uint16_t kAdcStat2 = code16(r::AdcStat2);
inline constexpr uint16_t kBalCtrl2 = code16(r::BalCtrl2);
inline constexpr uint16_t kFaultCompVcow1 = code16(r::FaultCompVcow1);
// Measurements.
inline constexpr uint16_t kVcell16Hi = code16(r::Vcell16Hi);
inline constexpr uint16_t kGpio1Hi = code16(r::Gpio1Hi);
inline constexpr uint16_t kDietemp1Hi = code16(r::Dietemp1Hi);

// Blocks the driver moves in one frame must be contiguous in the map.
static_assert(code16(r::OtpEccDatain8) == kOtpEccDatain1 + 7, "OTP_ECC_DATAIN1..8 are consecutive");
static_assert(code16(r::CustCrcLo) == kCustCrcHi + 1, "CUST_CRC_HI/LO are one 2-byte write");
static_assert(code16(r::CustCrcRsltLo) == kCustCrcRsltHi + 1, "CUST_CRC_RSLT_HI/LO are one 2-byte read");
static_assert(kFaultRst2 == kFaultRst1 + 1, "FAULT_RST1/2 are one 2-byte write");
static_assert(code16(r::Vcell1Lo) == kVcell16Hi + 31, "VCELL16_HI..VCELL1_LO are one 32-byte read");
static_assert(code16(r::Gpio8Lo) == kGpio1Hi + 15, "GPIO1_HI..GPIO8_LO are one 16-byte read");
static_assert(code16(r::FaultCompVcow2) == kFaultCompVcow1 + 1, "FAULT_COMP_VCOW1/2 are one 2-byte read");
static_assert(code16(r::Dietemp2Lo) == kDietemp1Hi + 3, "DIETEMP1_HI..DIETEMP2_LO are one 4-byte read");

namespace b = ::fw::regmap::bq79616::bits;
namespace e = ::fw::regmap::bq79616::enums;

// CONTROL1 (SLUSE81E §9.5.4.3.11): self-clearing command bits.
inline constexpr uint8_t kControl1AddrWr = b::Control1{}.with_addr_wr(true).raw();      // swallow next frame
inline constexpr uint8_t kControl1SendWake = b::Control1{}.with_send_wake(true).raw();  // WAKE tone up
// CONTROL2: SEND_HW_RESET sends the HW_RESET tone up the stack.
inline constexpr uint8_t kControl2SendHwReset = b::Control2{}.with_send_hw_reset(true).raw();
// COMM_CTRL: STACK_DEV, TOP_STACK.
inline constexpr uint8_t kCommBase = b::CommCtrl{}.raw();                        // base of 2+
inline constexpr uint8_t kCommStack = b::CommCtrl{}.with_stack_dev(true).raw();  // below the top
inline constexpr uint8_t kCommTop = b::CommCtrl{}.with_stack_dev(true).with_top_stack(true).raw();
inline constexpr uint8_t kCommStandalone = b::CommCtrl{}.with_top_stack(true).raw();  // a chain of one
// FAULT_RST2: TI's auto-addressing step clears COMM1 and COMM2 (0x03); recovery clears every comm group.
inline constexpr uint8_t kFaultRst2StartupComm =
    b::FaultRst2{}.with_rst_comm1(true).with_rst_comm2(true).raw();
inline constexpr uint8_t kFaultRst2AllComm = b::FaultRst2{}
                                                 .with_rst_comm1(true)
                                                 .with_rst_comm2(true)
                                                 .with_rst_comm3_hb(true)
                                                 .with_rst_comm3_ftone(true)
                                                 .with_rst_comm3_fcomm(true)
                                                 .raw();
inline constexpr uint8_t kSummaryFaultComm = b::FaultSummary::fault_comm_mask;
// ADC_CTRL1 (SLUSF21): the cell LPF on (its corner is ADC_CONF1[LPF_VCELL]), continuous run, MAIN_GO. TI's
// bring-up writes the same byte, 0x0E ("continuous run, LPF enabled, MAIN_GO").
inline constexpr uint8_t kAdcCtrl1Continuous =
    b::AdcCtrl1{}.with_lpf_vcell_en(true).with_main_go(true).with_main_mode(e::MainAdcMode::Continuous).raw();
static_assert(kAdcCtrl1Continuous == 0x0E, "TI's bq79616 example writes ADC_CTRL1 = 0x0E");
// FAULT_MSK2[MSK_OTP_CRC]: keeps the customer CRC fault out of FAULT_SUMMARY and NFAULT while the CRC is
// refreshed. TI's bq79616 example writes the same byte, 0x40, "to mask CUST_CRC".
inline constexpr uint8_t kFaultMsk2CustCrc = b::FaultMsk2{}.with_msk_otp_crc(true).raw();
static_assert(kFaultMsk2CustCrc == 0x40, "TI's bq79616 example masks the CRC fault with FAULT_MSK2 = 0x40");
// DEV_STAT (SLUSF21): CUST_CRC_DONE (cleared on read), MAIN_RUN.
inline constexpr uint8_t kDevStatCustCrcDone = b::DevStat::cust_crc_done_mask;
inline constexpr uint8_t kDevStatMainRun = b::DevStat::main_run_mask;
// ACTIVE_CELL NUM_CELL: 0x0 = 6 cells ... 0xA = 16 cells.
inline constexpr uint8_t kActiveCellMin = 6;
static_assert(static_cast<uint8_t>(e::ActiveCells::Cells16) == 16 - kActiveCellMin);

// DIAG_COMP_CTRL3 (SLUSF21; the layout as TI's BQ79616 register header gives it, no fieldset in the map yet):
// COMP_ADC_GO bit 0 (starts the comparison COMP_ADC_SEL names), COMP_ADC_SEL bits 3:1 (010 = VC open wire),
// OW_SNK bits 5:4 (01 = the VC pins' sinks and VC0's source on). Both drivers that quote TI's procedure write
// 0x10 (sinks on), then 0x15 (sinks on, VC open wire, go), then 0x00.
inline constexpr uint8_t kDiagOwSinksVc = 0x01 << 4;
inline constexpr uint8_t kDiagSelVcOw = 0x02 << 1;
inline constexpr uint8_t kDiagCompGo = 0x01;
static_assert(kDiagOwSinksVc == 0x10 && (kDiagOwSinksVc | kDiagSelVcOw | kDiagCompGo) == 0x15);
// ADC_STAT2[DRDY_VCOW] bit 3: the VC open-wire comparison has ended (0x08 in both drivers;
// regmaps/README.md).
inline constexpr uint8_t kAdcStat2DrdyVcow = 0x08;
// BAL_CTRL2 around the check: CB_PAUSE with FLTSTOP_EN (what the Balancer's BAL_GO wrote), then FLTSTOP_EN
// alone; without BAL_GO only CB_PAUSE acts (SLUSE81E BAL_CTRL2).
inline constexpr uint8_t kBalCtrl2Resume = b::BalCtrl2{}.with_fltstop_en(true).raw();
inline constexpr uint8_t kBalCtrl2Pause = b::BalCtrl2{}.with_fltstop_en(true).with_cb_pause(true).raw();
static_assert(kBalCtrl2Pause == 0x60 && kBalCtrl2Resume == 0x20);
// FAULT_RST1[RST_COMP]: clears every FAULT_COMP_* register.
inline constexpr uint8_t kFaultRst1Comp = b::FaultRst1{}.with_rst_comp(true).raw();
static_assert(kFaultRst1Comp == 0x04);

// Values the device returns for a measurement that is not available (not converted yet, channel off).
inline constexpr int16_t kNotReady = static_cast<int16_t>(-32768);  // 0x8000

}  // namespace fw::drivers::bq79616::regs
