// Mcan: the MSPM0G3507's CAN-FD controller CANFD0 (0x40508000) as a classic-CAN transmitter, with the TI
// subsystem wrapper (MCANSS) around the Bosch M_CAN core. Offsets from mspm0-sdk hw_mcan.h and the tsv
// "MCAN.*" rows: message RAM at the base (1 KiB here, README open questions), GPRCM at 0x6800, M_CAN core
// 0x7000..0x70FC, MCANSS registers 0x7200.. (STAT 0x7208 MEM_INIT_DONE bit 1, EOI 0x7220), the MSP wrapper's
// CPU_INT at 0x7820 (INTL0 bit 0, INTL1 bit 1), MCANSS_CLKEN 0x7900 (CLK_REQEN), MCANSS_CLKDIV 0x7904 (RATIO
// 1:0).
//
// What is modelled, each from the document named:
// - CCCR.INIT crosses clock domains: "there may be a delay until the value written to INIT can be read back.
//   Therefore the programmer has to assure that the previous value written to INIT has been accepted by
//   reading INIT before setting INIT to a new value" (hw_mcan.h CCCR.INIT). A new INIT value written before
//   the previous one reads back stops the run. The delay is kInitSyncCycles (an estimate). CCE written
//   together with INIT, or before INIT reads back 1, is refused and stops the run (rules.hpp
//   MCAN-INIT-SYNC): TI's set-up polls DL_MCAN_getOpMode for SW_INIT before it configures. After a reset
//   INIT is already 1 (CCCR reset value), so a set-up that writes INIT again and goes on at once is fine.
// - Protected registers (NBTP, DBTP, TEST, GFC, SIDFC, XIDFC, XIDAM, RXF0C, RXF1C, RXBC, RXESC, TXBC, TXESC,
//   TXEFC, TSCC, TOCC, TDCR) take a write only "with CCCR.CCE='1' and CCCR.INIT='1'" (hw_mcan.h CCCR.CCE);
//   otherwise the write is ignored, as the M_CAN ignores it, and noted in notes().
// - MCANSS_CLKDIV written before MCANSS_CLKEN.CLK_REQEN stops the run: CLK_REQEN "requests the functional
//   and register clocks" (hw_mcan.h MCAN_CLKEN) and TI's set-up enables the module clock first.
// - CLK_REQEN with CANCLK's source off (rules.hpp CLOCK-OFF: the HFXT never started, or the SYSPLL off)
//   stops the run: the message RAM would never initialise.
// - MEM_INIT_DONE: the message RAM is ready kMemInitCycles after the module clock is requested (CLK_REQEN)
//   with CANCLK running (SYSCTL HFXT good, CANCLKSRC = HFCLK).
// - TX FIFO (TXBC.TFQS elements from TXBC.TBSA, TXESC = 0: 8 data bytes, 16-byte elements; element T0/T1
//   layout from the tsv "MCAN TX element" rows and the M_CAN user manual 2.4.3): TXFQS free level, get and
//   put indices, full flag; a TXBAR bit for the put index queues that element; frames leave in FIFO order,
//   each taking its real length (bsp::host::canFrameBits: stuff bits, ACK, EOF, intermission) at the NBTP bit
//   time of CANCLK / MCANSS_CLKDIV. Leaving INIT, the controller first waits for 11 recessive bits (bus
//   integration). A frame done: TXBRP bit cleared, TXBTO bit set, IR.TC if the element's TXBTIE bit is set.
//   A transmission needs CAN TX and RX pins routed (PA12 PF 5, PA13 PF 6 on the LaunchPad): otherwise no
//   frame reaches the bus and each attempt counts as a transmit error (TEC + 8; error passive at 128, bus-off
//   above 255, ISO 11898-1 12.1.4).
// - Bus-off (injected by the board, or from TEC): PSR.BO, CCCR.INIT set by the controller, IR.BO; pending
//   requests stay pending. Clearing INIT starts the recovery: 129 x 11 recessive bits, then PSR.BO and ECR
//   clear and IR.BO is set again. Still bus-off with INIT at 1 kBusOffStuckMs after the bus-off began, no
//   CPU write having cleared INIT, warns (rules.hpp MCAN-BUS-OFF-STUCK): the node would never rejoin.
// - Interrupts: IR & IE, each bit to line 0 or 1 by ILS, lines enabled by ILE. The MCANSS holds a line's
//   interrupt until it is acknowledged: "MCANSS_EOI ... A write to this register will clear the associated
//   interrupt ... 0x01 MCAN(0) interrupt is cleared, 0x02 MCAN(1) interrupt is cleared" (hw_mcan.h MCAN_EOI).
//   The wrapper's RIS.INTLn is set when line n asserts; a line asserted and not yet acknowledged by EOI
//   gives no further interrupt, however many IR events follow. An EOI with IR events still pending on the
//   line asserts it again (TI's ISRs: DL_MCAN_clearIntrStatus writes IR, then EOI).
// - Wire agreement (rules.hpp), checked when the controller leaves INIT to join the bus: the nominal bit
//   rate, CANCLK / MCANSS_CLKDIV / (NBRP + 1) / (1 + (NTSEG1 + 1) + (NTSEG2 + 1)), equals the bus's (setBus)
//   within the oscillator tolerance the image's own bit timing allows (ISO 11898-1 bit timing: df <=
//   min(PS2 / (2 (13 NBT - PS2)), SJW / (20 NBT)) in time quanta; TSEG1's split into propagation and phase
//   segment is not known, so PS2 stands for min(PS1, PS2)): WIRE-CAN-BITRATE stops; a sample point
//   (1 + NTSEG1 + 1) / NBT more than 5 points from 87.5 % (CiA 301; TI's bq79616_uart_to_can NBTP) warns
//   (WIRE-CAN-SAMPLE). The CAN RX pin needs INENA (PIN-INENA): the M_CAN reads its own bits back.
// - Error frames from the bus (injectErrorFrames, bms-sim's can-error-frames): each of the next n attempts
//   is destroyed by an error frame: TEC + 8 (ISO 11898-1 12.1.4 rule 3), error passive at 128 (IR.EP),
//   bus-off above 255; the M_CAN retransmits unless CCCR.DAR. The error frame's own 17 bits are not counted.
// - The bus: other nodes' frames (peerSend, or a peer source that always has one waiting: a flood)
//   compete with the TX FIFO at every bus idle; the lowest identifier wins arbitration (ISO 11898-1: a
//   dominant 0 bit wins; a standard identifier against an extended one is compared on its 11 base bits, the
//   standard frame winning a tie), and the frame takes the wire for its real length.
// - Reception (hw_mcan.h GFC, SIDFC, RXF0C/RXF0S/RXF0A; the acceptance filtering of the M_CAN user manual
//   3.4.1, as SLAU846 chapter "MCAN" describes it): a peer frame that has left the wire while the controller
//   takes part in the bus (INIT clear, not bus-off, its RX pin routed) goes through the standard filter list
//   (LSS elements from FLSSA, element 0 first, the first match decides: SFT 0 range SFID1..SFID2, 1 dual ID,
//   2 classic SFID1 with mask SFID2, 3 disabled; SFEC 0 disabled, 1 store in RX FIFO 0, 3 reject; FIFO 1,
//   priority and RX buffer storage stop the run). A frame no element matches is handled as GFC.ANFS (ANFE for
//   extended frames, whose filter list is not modelled: XIDFC.LSE must be 0) says: 0 RX FIFO 0, 2/3 reject,
//   1 (FIFO 1) stops the run. A rejected frame leaves no trace: no IR bit, no interrupt.
//   RX FIFO 0 (F0SA, F0S elements, RXESC.F0DS = 0: 16-byte elements, R0 identifier and XTD as T0, R1 DLC
//   19:16): a stored frame advances the put index and the fill level and sets IR.RF0N, and IR.RF0F when the
//   FIFO is then full; a frame that finds it full is lost in blocking mode (F0OM 0: RXF0S.RF0L, IR.RF0L;
//   overwrite mode stops the run). RXF0S reads fill level 6:0, get index 13:8, put index 21:16, full bit 24,
//   RF0L bit 25; writing RXF0A = n (the last element read) sets the get index to n + 1 and lowers the fill
//   level by the elements acknowledged.
// FD, dedicated TX buffers, the TX event FIFO, RX FIFO 1, RX buffers and test modes are not modelled:
// anything that would act on them stops the run.
#pragma once

#include <array>
#include <cstdint>
#include <deque>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "hal/can_bus.hpp"
#include "periph/peripheral.hpp"
#include "periph/pins.hpp"
#include "periph/sysctl.hpp"
#include "timeline.hpp"

namespace twin {

struct CanWireFrame {
  uint64_t endCycle = 0;
  fw::hal::CanFrame frame{};
};

class Mcan final : public Peripheral {
 public:
  static constexpr uint32_t kRamBytes = 0x400;
  static constexpr uint64_t kInitSyncCycles = 8;
  static constexpr uint64_t kMemInitCycles = 32;
  static constexpr uint32_t kCanClockHz = 40000000;  // HFXT on the LP-MSPM0G3507 (tsv "HFXT" example row)
  // MCAN-BUS-OFF-STUCK's bound: the project's choice, no TI figure (bsp/twin/README.md rules table).
  static constexpr uint64_t kBusOffStuckMs = 1000;

  Mcan(Machine& machine, Pins& pins, Sysctl& sysctl);
  void setPins(int txPincm, uint32_t txPf, int rxPincm, uint32_t rxPf) {
    txPincm_ = txPincm, txPf_ = txPf, rxPincm_ = rxPincm, rxPf_ = rxPf;
  }
  void onFrame(std::function<void(const CanWireFrame&)> sink) { sink_ = std::move(sink); }
  void injectBusOff();
  void setBus(uint32_t bitRate) { busBitRate_ = bitRate; }
  void injectErrorFrames(uint32_t attempts) { errorFramesLeft_ += attempts; }
  uint32_t errorFrames() const { return errorFrames_; }  // attempts destroyed so far
  // Another node sends `frame` (it competes for the bus from now); while a source is set, another node always
  // has a frame waiting: the source gives the next one each time the last has left (nullopt: none this time).
  void peerSend(const fw::hal::CanFrame& frame);
  void setPeerSource(std::function<std::optional<fw::hal::CanFrame>()> source);
  uint64_t peerFrames() const { return peerFrames_; }        // peer frames that went over the wire
  uint64_t framesReceived() const { return received_; }      // stored in RX FIFO 0
  uint64_t framesRejected() const { return rejected_; }      // filtered out: no trace, no interrupt
  uint64_t newMessageEvents() const { return rf0nEvents_; }  // IR.RF0N raised (one per stored frame)
  const std::vector<std::string>& notes() const { return notes_; }
  // How long line n has been waiting for its EOI (0 if it is not asserted): an ISR that never writes
  // MCANSS_EOI leaves it waiting for ever, and every later interrupt of the line is lost.
  uint64_t awaitingEoiCycles(int line) const;
  bool busOff() const { return busOff_; }
  // A fault for the tests of a driver's bounded wait: from now on CCCR.INIT reads 1 whatever is written.
  void holdInit() { initHeld_ = true; }
  // Each bus-off: the cycle it began and the cycle the recovery ended (0: not yet), for reports.
  struct BusOffSpan {
    uint64_t startCycle = 0, recoveredCycle = 0;
  };
  const std::vector<BusOffSpan>& busOffLog() const { return busOffLog_; }

 private:
  bool readRegister(uint32_t offset, uint32_t& value) override;
  bool writeRegister(uint32_t offset, uint32_t value) override;
  void resetRegisters() override;

  bool initReadBack() const;
  bool configurable() const { return initReadBack() && (cccr_ & 2U) != 0; }
  uint64_t bitCycles() const;
  bool memReady() const;
  void setIr(uint32_t bits);
  void updateLines();
  void tryTransmit();
  void transmitDone();
  void peerDone();
  void receive(const fw::hal::CanFrame& frame);
  bool busIdle() const { return !transmitting_ && !peerOnWire_; }
  void enterBusOff();
  void note(const std::string& text);
  void checkWire();

  Pins& pins_;
  Sysctl& sysctl_;
  TimedEvent txDone_, integrated_, recovered_, peerDone_, busOffStuck_;
  std::function<void(const CanWireFrame&)> sink_;
  int txPincm_ = 0, rxPincm_ = 0;
  uint32_t txPf_ = 0, rxPf_ = 0;
  std::vector<uint32_t> ram_;
  std::vector<std::string> notes_;
  std::vector<BusOffSpan> busOffLog_;

  // Core registers
  uint32_t cccr_ = 1, nbtp_ = 0x06000A03, dbtp_ = 0, test_ = 0, ir_ = 0, ie_ = 0, ils_ = 0, ile_ = 0;
  uint32_t gfc_ = 0, sidfc_ = 0, xidfc_ = 0, xidam_ = 0x1FFFFFFF, rxf0c_ = 0, rxf1c_ = 0, rxbc_ = 0,
           rxesc_ = 0;
  uint32_t txbc_ = 0, txesc_ = 0, txefc_ = 0, txbrp_ = 0, txbto_ = 0, txbtie_ = 0, txbcie_ = 0, tscc_ = 0;
  uint32_t tocc_ = 0, tdcr_ = 0;
  uint32_t tec_ = 0;
  uint32_t busBitRate_ = 0, errorFramesLeft_ = 0, errorFrames_ = 0;
  bool initValue_ = true;  // INIT as the core sees it once synchronised
  bool initHeld_ = false;
  uint64_t initSyncAt_ = 0;
  bool busOff_ = false, errorPassive_ = false, integrating_ = false;
  // TX FIFO
  uint32_t get_ = 0, queued_ = 0;
  // The other nodes and RX FIFO 0
  std::deque<fw::hal::CanFrame> peerQueue_;
  std::function<std::optional<fw::hal::CanFrame>()> peerSource_;
  bool peerOnWire_ = false;
  fw::hal::CanFrame peerFrame_{};
  uint32_t rxGet_ = 0, rxFill_ = 0;
  bool rxLost_ = false;
  uint64_t peerFrames_ = 0, received_ = 0, rejected_ = 0, rf0nEvents_ = 0;
  bool transmitting_ = false;
  fw::hal::CanFrame current_{};
  // Wrapper
  uint32_t clken_ = 0, clkdiv_ = 0;
  uint64_t clockRequestedAt_ = UINT64_MAX;
  std::array<bool, 2> lineHeld_{};  // asserted, waiting for EOI
  std::array<uint64_t, 2> heldSince_{};
};

}  // namespace twin
