// Dma: the MSPM0 DMA (DMA_BASE 0x4042A000; 3 channels on the L1306, 7 on the G3507: tsv "DMA channels"),
// registers from mspm0-sdk hw_dma.h: DMATRIG[n].DMATCTL at 0x1110 + 4n (DMATSEL 5:0, DMATINT bit 7),
// DMACHAN[n] at 0x1200 + 0x10n: DMACTL (DMAREQ 0, DMAEN 1, DMASRCWDTH 10:8, DMADSTWDTH 14:12, DMASRCINCR
// 19:16, DMADSTINCR 23:20, DMAEM 25:24, DMATM 29:28), DMASA, DMADA, DMASZ (15:0); CPU_INT bit n = channel n
// "Size counter reached zero (DMASZ=0)". The DMA has no GPRCM: it is always powered (tsv note "DMA").
//
// Transfers (hw_dma.h DMATM descriptions):
// - Single transfer mode: "Each transfer requires a new trigger. When the DMASZ counts down to zero an event
//   can be generated and the DMAEN is cleared." A trigger is a peripheral's DMA request (its DMA_TRIGx MIS,
//   peripherals connect with DmaRequester); each transfer acknowledges the request, which the peripheral
//   raises again when its condition still holds. At DMASZ = 0 the channel's CPU_INT flag is set and the
//   triggering peripheral is told (its DMA_DONE_TX/RX interrupt).
// - Block mode: one trigger moves DMASZ transfers. Repeat modes, extended modes (gather/fill/table),
//   strides and widths above a word stop the run (not modelled; the images use none).
// - A transfer takes kTransferCycles after its trigger (read + write on the bus; an estimate, README).
// - A channel enabled to move to a peripheral's TX data register or from its RX data register must select
//   that peripheral's trigger for that direction (rules.hpp DMA-TRIGGER: the run stops), and the peripheral
//   may say what else keeps its trigger from firing (DmaRequester::dmaTriggerProblem, rules.hpp
//   UART-DMA-LEVEL).
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "address_map.hpp"
#include "machine.hpp"
#include "periph/peripheral.hpp"
#include "timeline.hpp"

namespace twin {

class DmaRequester {
 public:
  virtual bool dmaRequested(int trigger) const = 0;
  virtual void dmaAcknowledge(int trigger) = 0;
  virtual void dmaDone(int trigger) = 0;
  // Why `trigger` cannot pace a DMA channel with the current settings ("" when it can); `rule` the rule.
  virtual std::string dmaTriggerProblem(int /*trigger*/, Rule& /*rule*/) const { return ""; }

 protected:
  ~DmaRequester() = default;
};

class Dma final : public Device {
 public:
  static constexpr uint32_t kBase = 0x4042A000;
  static constexpr uint32_t kSize = 0x2000;
  static constexpr uint64_t kTransferCycles = 4;

  Dma(Machine& machine, int channels);
  const char* name() const override { return "DMA"; }
  bool read(uint32_t offset, unsigned bytes, uint32_t& value) override;
  bool write(uint32_t offset, unsigned bytes, uint32_t value) override;

  void connect(int trigger, DmaRequester& requester) {
    requesters_[static_cast<size_t>(trigger)] = &requester;
  }
  // The data register a trigger paces: `name` (e.g. "UART0 TX"), its address, and whether the channel writes
  // to it (TX) or reads from it (RX). DMA-TRIGGER checks every channel enabled on it.
  void describeTrigger(int trigger, std::string name, uint32_t dataRegister, bool toPeripheral) {
    triggers_.push_back({trigger, std::move(name), dataRegister, toPeripheral});
  }
  // A requester's request for `trigger` was raised.
  void requestRaised(int trigger);
  void connectInterrupt(std::function<void(bool)> line) { line_ = std::move(line); }
  InterruptSources interruptSources() const {  // race_watch.hpp
    return {cpuInt_.imask | cpuInt_.mis(), cpuInt_.mis()};
  }

 private:
  struct Channel {
    uint32_t ctl = 0, sa = 0, da = 0, sz = 0, tctl = 0;
  };
  struct TriggerInfo {
    int trigger;
    std::string name;
    uint32_t dataRegister;
    bool toPeripheral;
  };
  void checkTrigger(int n, const Channel& ch);
  void service();
  bool transfer(Channel& ch);
  void reset();
  void updateInterrupt();

  Machine& machine_;
  int channels_;
  std::array<Channel, 16> ch_{};
  std::array<DmaRequester*, 64> requesters_{};
  EventRegs cpuInt_;
  std::function<void(bool)> line_;
  bool lineLevel_ = false;
  TimedEvent serviceEvent_;
  uint32_t prio_ = 0;
  std::vector<TriggerInfo> triggers_;
};

}  // namespace twin
