// McanModel: the MSPM0 MCAN subsystem (CANFD0) in the register model, with the rules a driver must follow.
// Register offsets from the peripheral base: mspm0g3507.tsv "MCAN.*" rows; MCANSS_EOI at 0x7220 and the
// fields below from TI's MSPM0 SDK hw_mcan.h.
//
// Rules (TI source next to each)
// - Clock first: a write to MCANSS_CLKDIV before MCANSS_CLKEN.CLK_REQEN is set is flagged. CLK_REQEN
//   requests the module's functional and register clocks (hw_mcan.h MCAN_CLKEN), and TI's generated MCAN
//   set-up (SYSCFG_DL_MCAN0_init) calls DL_MCAN_enableModuleClock before DL_MCAN_setClockConfig.
//   MCANSS_STAT.MEM_INIT_DONE reads 1 once the clock is requested (unless noMessageRam()).
// - CCCR.INIT crosses clock domains: a written INIT value reads back only from the second CCCR read on, and
//   writing INIT again with another value before the previous one has read back is flagged (hw_mcan.h
//   MCAN_CCCR INIT note: read INIT back before setting it to a new value; TI's example polls
//   DL_MCAN_getOpMode after every DL_MCAN_setOpMode). Reset value INIT = 1 (M_CAN user manual, CCCR).
// - IR is write-1-to-clear; interrupt line 0 is driven by IR & IE & ~ILS while ILE.EINT0 is set.
// - The wrapper keeps its line-0 interrupt asserted from the first line-0 event until MCANSS_EOI is written
//   with 0x01 (0x02 is line 1, 0x00 the external timestamp, other values are ignored); after the EOI a
//   source that is still pending asserts it again (hw_mcan.h MCAN_EOI description; TI's
//   DL_MCAN_clearIntrStatus writes IR, then EOI, in every TI MCAN ISR). While it is asserted the MSP
//   wrapper's CPU_INT RIS.INTL0 reads 1: ICLR clears only the latched edge, not a held line.
#pragma once

#include <cstdint>

namespace bsp::mspm0::test {

class McanModel {
 public:
  explicit McanModel(uintptr_t base) : base_(base) {}
  // Hooks the registers into model(); call after the fixture reset the model.
  void attach();

  // The controller sets IR bits (an event happened).
  void raise(uint32_t irBits);
  // The controller went bus-off: PSR.BO, CCCR.INIT set by the controller itself, IR.BO.
  void busOff();
  // The controller left bus-off (after recovery): PSR.BO clear, IR.BO.
  void leaveBusOff();
  // Faults: the message RAM never finishes its initialisation; INIT never reads back 0.
  void noMessageRam() { noMessageRam_ = true; }
  void stayInInit() { stayInInit_ = true; }

  bool lineHeld() const { return held_; }
  // CPU_INT.MIS as the NVIC line sees it (no register access logged).
  bool interruptPending() const;
  // CCCR.INIT as it reads now, and whether the driver has read back the last value it wrote.
  bool initVisible() const { return initVisible_; }
  bool initReadBack() const { return !initPending_ && initReadAfterWrite_; }
  uint32_t ir() const { return ir_; }

 private:
  void resetState();
  void onCccrWrite(uint32_t value);
  uint32_t onCccrRead();
  void updateLine();

  uintptr_t base_;
  uint32_t ir_ = 0;
  bool held_ = false;   // line 0 asserted, waiting for its EOI
  bool latch_ = false;  // CPU_INT RIS.INTL0 edge latch
  bool clockOn_ = false;
  bool initVisible_ = true;
  bool initPending_ = false;
  bool initTarget_ = false;
  uint32_t initSyncReads_ = 0;
  bool initReadAfterWrite_ = true;
  bool noMessageRam_ = false;
  bool stayInInit_ = false;
};

}  // namespace bsp::mspm0::test
