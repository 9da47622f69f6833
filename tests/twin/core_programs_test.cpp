// The twin's core running small assembled programs (tests/twin/programs/*.S, built with arm-none-eabi-gcc):
// exception entry and return, nesting by priority, PRIMASK and WFI, level re-entry, stack alignment, faults
// and cycle counts, each against the architecture's or the timing table's own statement (cited in the .S).
// The programs talk to a probe device at 0x40000000: +0 logs marks, +4 sets NVIC input levels (bit n = IRQ
// n), +8 reads the cycle count, +12 is a scratch word.
#include <chrono>
#include <cstdio>
#include <sstream>
#include <string>
#include <vector>

#include "gtest/gtest.h"
#include "machine.hpp"
#include "profiler.hpp"

namespace {

class Probe final : public twin::Device {
 public:
  explicit Probe(twin::Machine& m) : m_(m) {}
  const char* name() const override { return "probe"; }
  bool read(uint32_t offset, unsigned, uint32_t& value) override {
    if (offset == 8) value = static_cast<uint32_t>(m_.now());
    if (offset == 12) value = scratch_;
    return offset == 8 || offset == 12;
  }
  bool write(uint32_t offset, unsigned, uint32_t value) override {
    if (offset == 0) marks.push_back(value);
    if (offset == 4) {
      for (int irq = 0; irq < 32; ++irq)
        m_.setIrq(irq, (value >> irq) & 1U);
    }
    if (offset == 12) scratch_ = value;
    return offset == 0 || offset == 4 || offset == 12;
  }
  std::vector<uint32_t> marks;

 private:
  twin::Machine& m_;
  uint32_t scratch_ = 0;
};

struct Run {
  twin::ElfFile elf;
  std::unique_ptr<twin::Machine> machine;
  std::unique_ptr<Probe> probe;
};

std::unique_ptr<Run> run(const std::string& name, uint64_t cycles = 100000,
                         twin::Profiler* profiler = nullptr) {
  auto r = std::make_unique<Run>();
  const std::string path = std::string(TWIN_PROGRAMS) + "/" + name + ".elf";
  EXPECT_TRUE(r->elf.load(path)) << r->elf.error();
  r->machine = std::make_unique<twin::Machine>(twin::MemoryLayout{0x10000, 0x20000000, 0x1000, 32000000});
  r->probe = std::make_unique<Probe>(*r->machine);
  r->machine->map().add(0x40000000, 0x100, *r->probe);
  r->machine->loadFlash(r->elf.flashImage());
  r->machine->setProfiler(profiler);
  r->machine->powerOn();
  r->machine->run(cycles);
  EXPECT_FALSE(r->machine->stopped()) << r->machine->stopReason();
  return r;
}

uint32_t address(const Run& r, const char* symbol) {
  const auto s = r.elf.symbol(symbol);
  EXPECT_TRUE(s.has_value()) << symbol;
  return s ? s->value & ~1U : 0;
}

TEST(CorePrograms, ExceptionsNestByPriorityAndReturnAsTheArchitectureSays) {
  const auto r = run("exceptions");
  // exceptions.S: (1) IRQ0 entered at once with EXC_RETURN 0xFFFFFFF9, IRQ1 (more urgent) preempts it with
  // 0xFFFFFFF1, IRQ2 (same priority) waits for IRQ0's return; (2) PRIMASK holds IRQ2 through WFI until
  // CPSIE; (3) an SP with bit 2 set comes back unchanged; (4) a level still asserted re-enters its handler.
  const std::vector<uint32_t> expected = {
      0x10, 0x11,       0xFFFFFFF9, 0x01,       0xFFFFFFF1, 0x12, 0x21, 0x1F, 0x30, 0x31, 0x22, 0x32,
      0x11, 0xFFFFFFF9, 0x01,       0xFFFFFFF1, 0x12,       0x23, 0x40, 0x21, 0x22, 0x50, 0xFF};
  EXPECT_EQ(r->probe->marks, expected);
}

TEST(CorePrograms, SleepOnExitSleepsOnTheReturnToThreadModeOnly) {
  const auto r = run("sleep_on_exit");
  // sleep_on_exit.S: with SCR.SLEEPONEXIT set, IRQ0's return to Thread mode sleeps (0x11 comes only after
  // SysTick cleared the bit, 0x30); a return to Handler mode (IRQ1 preempting IRQ0) does not (0x41 at once).
  const std::vector<uint32_t> expected = {0x10, 0x20, 0x30, 0x11, 0x12, 0x40, 0x41, 0x31, 0x13, 0xFF};
  EXPECT_EQ(r->probe->marks, expected);
}

TEST(CorePrograms, AWakeUpFromSleepIsCountedLikeAnyOtherStep) {
  // The step that wakes the core takes the exception at once (sleep-on-exit leaves PRIMASK clear): its entry
  // is busy time and a profiler entry like any other (it was dropped: the L1306 image's profile showed 1 314
  // I2C handler entries of 4 288).
  twin::ElfFile elf;
  ASSERT_TRUE(elf.load(std::string(TWIN_PROGRAMS) + "/sleep_on_exit.elf")) << elf.error();
  twin::Profiler profiler(elf);
  const auto r = run("sleep_on_exit", 100000, &profiler);
  std::ostringstream out;
  profiler.write(out, "sleep_on_exit", 32000000, r->machine->now(), r->machine->busyCycles());
  std::istringstream in(out.str());
  uint64_t systickEntries = 0, exceptionCycles = 0;
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("exception\t", 0) != 0) continue;
    std::istringstream row(line);
    std::string kind, name;
    int number = 0;
    uint64_t entries = 0, cycles = 0;
    row >> kind >> number;
    row.ignore(1);
    std::getline(row, name, '\t');
    row >> entries >> cycles;
    exceptionCycles += cycles;
    if (number == 15) systickEntries = entries;
  }
  EXPECT_EQ(r->machine->interrupts()[15].entries, 2u);
  EXPECT_EQ(systickEntries, 2u) << "both SysTick entries came from sleep";
  EXPECT_EQ(exceptionCycles, r->machine->busyCycles());
}

TEST(CorePrograms, FaultsRaiseHardFaultWithTheFaultingInstructionStacked) {
  const auto r = run("faults");
  const std::vector<uint32_t> expected = {address(*r, "unaligned"), address(*r, "undefined"),
                                          address(*r, "even"), 0xFF};
  EXPECT_EQ(r->probe->marks, expected);
  EXPECT_EQ(r->machine->hardFaults().size(), 3U);
}

TEST(CorePrograms, CyclesFollowTheCortexM0PlusTable) {
  const auto r = run("timing");
  // timing.S: 9, 15 and 7 cycles for the sequences (DDI 0484C Table 3-1), 17 from the start of the store
  // that raises IRQ0 to its handler's first instruction (2 + the 15-cycle latency), 13 for BX LR + return.
  const std::vector<uint32_t> expected = {9, 15, 7, 17, 13, 0xFF};
  EXPECT_EQ(r->probe->marks, expected);
}

TEST(CorePrograms, SpinLoopReportsTheInterpreterSpeed) {
  // A figure, not a timed assertion: the loop must finish (mark 0xFF) within its cycle count.
  // spin.S: 5 000 000 ALU and branch instructions, 6 000 000 cycles at 32 MHz (0.19 s of chip time).
  const auto start = std::chrono::steady_clock::now();
  const auto r = run("spin", 7000000);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  ASSERT_EQ(r->probe->marks, std::vector<uint32_t>{0xFF});
  const double mips = static_cast<double>(r->machine->core().instructions()) / seconds / 1e6;
  std::printf(
      "REPORT twin core: %.0f MIPS on this host (%llu instructions in %.3f s; the chip runs 32 MHz)\n", mips,
      static_cast<unsigned long long>(r->machine->core().instructions()), seconds);
  EXPECT_GE(r->machine->core().instructions(), 5000000u + 4u);
}

}  // namespace
