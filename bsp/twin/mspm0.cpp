#include "mspm0.hpp"

#include <array>

#include "power.hpp"

namespace twin {

namespace {

// Package pins (port, DIO, PINCM): mspm0g350x.h IOMUX_PINCMn_PF_GPIOx_DIOyy for the G3507 (64-pin); on the
// L1306 PINCMn is PA(n-1) for n = 1..28 (mspm0l130x.h IOMUX_PINCMn_PF_GPIOA_DIO(n-1)).
constexpr PinId kG3507Pins[] = {
    {0, 0, 1},   {0, 1, 2},   {0, 28, 3},  {0, 29, 4},  {0, 30, 5},  {0, 31, 6},  {0, 2, 7},   {0, 3, 8},
    {0, 4, 9},   {0, 5, 10},  {0, 6, 11},  {1, 0, 12},  {1, 1, 13},  {0, 7, 14},  {1, 2, 15},  {1, 3, 16},
    {1, 4, 17},  {1, 5, 18},  {0, 8, 19},  {0, 9, 20},  {0, 10, 21}, {0, 11, 22}, {1, 6, 23},  {1, 7, 24},
    {1, 8, 25},  {1, 9, 26},  {1, 10, 27}, {1, 11, 28}, {1, 12, 29}, {1, 13, 30}, {1, 14, 31}, {1, 15, 32},
    {1, 16, 33}, {0, 12, 34}, {0, 13, 35}, {0, 14, 36}, {0, 15, 37}, {0, 16, 38}, {0, 17, 39}, {0, 18, 40},
    {0, 19, 41}, {0, 20, 42}, {1, 17, 43}, {1, 18, 44}, {1, 19, 45}, {0, 21, 46}, {0, 22, 47}, {1, 20, 48},
    {1, 21, 49}, {1, 22, 50}, {1, 23, 51}, {1, 24, 52}, {0, 23, 53}, {0, 24, 54}, {0, 25, 55}, {1, 25, 56},
    {1, 26, 57}, {1, 27, 58}, {0, 26, 59}, {0, 27, 60},
};

std::array<PinId, 28> l1306Pins() {
  std::array<PinId, 28> pins{};
  for (uint8_t n = 1; n <= 28; ++n)
    pins[n - 1] = {0, static_cast<uint8_t>(n - 1), n};
  return pins;
}
const std::array<PinId, 28> kL1306Pins = l1306Pins();

// Memories (tsv "mem" rows) and the peripheral bases, IRQs and DMA triggers (tsv base/irq/dmatrig rows).
constexpr uint32_t kPeripheralSpan = 0x2000;
constexpr uint32_t kGpioa = 0x400A0000, kGpiob = 0x400A2000, kTimg0 = 0x40084000, kWwdt0 = 0x40080000;
constexpr uint32_t kI2c0 = 0x400F0000, kI2c1 = 0x400F2000, kUart0 = 0x40108000, kUart1 = 0x40100000;
constexpr uint32_t kCanfd0 = 0x40508000, kCanfdSpan = 0x8000;

// The timers and UARTs each part has: base, IRQ, name and (UARTs) the DMA trigger of RX and TX.
struct Slot {
  uint32_t base;
  int irq;
  const char* name;
  int dmaRx = 0, dmaTx = 0;
};
struct TimerSlot {
  Slot slot;
  StandbyClock standby;  // periph/timg.hpp
};
// Deep-mode clocks: L1306 TIMG0/1 through STANDBY1, TIMG2/4 through STANDBY0 (MSPM0L130x data sheet
// SLASEX0D table 8-1). G3507: TIMG0 through STANDBY1 (SLAU846A 2 "LFCLK": RTC, TIMG0 and TIMG1 are the only
// clocked peripherals in STANDBY1); TIMG8 is PD0 but its STANDBY1 clock was not confirmed by a second TI
// source, so the twin takes the safe side (STANDBY0 only); TIMG6/TIMG7 are taken as PD1 (no deep-mode
// clock, SLAU846A TIMx low-power modes), also the safe side until the G3507 table is read.
constexpr TimerSlot kG3507Timers[] = {{{kTimg0, 16, "TIMG0"}, StandbyClock::AllModes},
                                      {{0x40868000, 17, "TIMG6"}, StandbyClock::RunSleepOnly},
                                      {{0x4086A000, 20, "TIMG7"}, StandbyClock::RunSleepOnly},
                                      {{0x40090000, 2, "TIMG8"}, StandbyClock::UpToStandby0}};
constexpr TimerSlot kL1306Timers[] = {{{kTimg0, 16, "TIMG0"}, StandbyClock::AllModes},
                                      {{0x40086000, 2, "TIMG1"}, StandbyClock::AllModes},
                                      {{0x40088000, 18, "TIMG2"}, StandbyClock::UpToStandby0},
                                      {{0x4008C000, 20, "TIMG4"}, StandbyClock::UpToStandby0}};
constexpr Slot kG3507Uarts[] = {{kUart0, 15, "UART0", 17, 18},
                                {kUart1, 13, "UART1", 19, 20},
                                {0x40102000, 14, "UART2", 21, 22},
                                {0x40500000, 3, "UART3", 15, 16}};
constexpr Slot kL1306Uarts[] = {{kUart0, 15, "UART0", 10, 11}, {kUart1, 13, "UART1", 12, 13}};

}  // namespace

template <class Model, class... Args>
Model* Mspm0::add(uint32_t base, uint32_t size, int irq, Args&&... args) {
  auto* model = new Model(*machine_, std::forward<Args>(args)...);
  machine_->map().add(base, size, *model);
  if (irq >= 0) {
    irqNames_[static_cast<size_t>(irq)] = model->name();
    model->connectInterrupt([this, irq](bool level) { machine_->setIrq(irq, level); });
    machine_->setIrqSources(irq, [model] { return model->interruptSources(); });
  }
  machine_->onReset([model](ResetKind) { model->systemReset(); });
  return model;
}

Mspm0::Mspm0(Part part) : part_(part) {
  const bool g = part == Part::G3507;
  machine_ = std::make_unique<Machine>(
      MemoryLayout{g ? 0x20000U : 0x10000U, g ? 0x20200000U : 0x20000000U, g ? 0x8000U : 0x1000U, 32000000});
  Machine& m = *machine_;
  sysctl_ = std::make_unique<Sysctl>(m, g);
  m.map().add(Sysctl::kBase, Sysctl::kSize, *sysctl_);
  cpuss_ = std::make_unique<Cpuss>(m);
  m.map().add(Cpuss::kBase, Cpuss::kSize, *cpuss_);
  factory_ = g ? std::make_unique<FactoryRegion>(0x35070001, 0xBB88)
               : std::make_unique<FactoryRegion>(0x13060001, 0xBB82);
  m.map().add(FactoryRegion::kBase, FactoryRegion::kSize, *factory_);
  flashctl_ = std::make_unique<Flashctl>(m, g);  // ECC on the G3507 only (reference section 3)
  m.map().add(Flashctl::kBase, Flashctl::kSize, *flashctl_);
  m.onReset([this](ResetKind) { flashctl_->systemReset(); });
  if (g) {
    pins_ = std::make_unique<Pins>(m, std::span<const PinId>(kG3507Pins));
  } else {
    pins_ = std::make_unique<Pins>(m, std::span<const PinId>(kL1306Pins));
  }
  m.map().add(Pins::kBase, Pins::kSize, *pins_);
  dma_ = std::make_unique<Dma>(m, g ? 7 : 3);
  m.map().add(Dma::kBase, Dma::kSize, *dma_);
  dma_->connectInterrupt([&m](bool level) { m.setIrq(31, level); });
  m.setIrqSources(31, [this] { return dma_->interruptSources(); });
  irqNames_[31] = "DMA";
  irqNames_[1] = g ? "INT_GROUP1 (GPIOA, GPIOB)" : "INT_GROUP1 (GPIOA)";

  // GPIO ports feed INT_GROUP1: GPIOA is member 1, GPIOB member 2 (tsv group_iidx rows).
  gpioA_.reset(add<Gpio>(kGpioa, kPeripheralSpan, -1, "GPIOA", 0, *pins_));
  gpioA_->connectInterrupt([this](bool level) { cpuss_->setMember(1, 1, level); });
  cpuss_->setMembers(1, g ? 0x3F : 0x5);  // G3507: GPIOA, GPIOB, COMP0-2, TRNG; L1306: GPIOA, COMP0 (IIDX 3)
  if (g) {
    gpioB_.reset(add<Gpio>(kGpiob, kPeripheralSpan, -1, "GPIOB", 1, *pins_));
    gpioB_->connectInterrupt([this](bool level) { cpuss_->setMember(1, 2, level); });
  }
  // The group's sources are its members (bit 1 GPIOA, bit 2 GPIOB), as the handler tells them apart by IIDX.
  m.setIrqSources(1, [this] {
    auto member = [](const Gpio* port, uint32_t bit) {
      if (port == nullptr) return InterruptSources{};
      const InterruptSources s = port->interruptSources();
      return InterruptSources{s.possible != 0 ? bit : 0, s.pending != 0 ? bit : 0};
    };
    const InterruptSources a = member(gpioA_.get(), 1U << 1), b = member(gpioB_.get(), 1U << 2);
    return InterruptSources{a.possible | b.possible, a.pending | b.pending};
  });
  wwdt0_.reset(add<Wwdt>(kWwdt0, kPeripheralSpan, -1, "WWDT0"));
  i2c0_.reset(add<I2c>(kI2c0, kPeripheralSpan, 24, "I2C0", *pins_));
  i2c1_.reset(add<I2c>(kI2c1, kPeripheralSpan, 25, "I2C1", *pins_));
  // I2C0 on PA0 (SDA, PINCM1) / PA1 (SCL, PINCM2), PF 3 on both parts (device headers).
  i2c0_->setPins(1, 3, 2, 3);
  const std::span<const TimerSlot> timers(g ? std::span<const TimerSlot>(kG3507Timers) : kL1306Timers);
  for (size_t i = 0; i < timers.size(); ++i) {
    const Slot& t = timers[i].slot;
    timg_[i].reset(add<Timg>(t.base, kPeripheralSpan, t.irq, t.name, timers[i].standby));
  }
  const std::span<const Slot> uarts(g ? std::span<const Slot>(kG3507Uarts) : kL1306Uarts);
  for (size_t i = 0; i < uarts.size(); ++i) {
    const Slot& u = uarts[i];
    uart_[i].reset(add<Uart>(u.base, kPeripheralSpan, u.irq, u.name, *dma_, u.dmaRx, u.dmaTx));
    dma_->describeTrigger(u.dmaRx, std::string(u.name) + " RX", u.base + Uart::kRxdataOffset, false);
    dma_->describeTrigger(u.dmaTx, std::string(u.name) + " TX", u.base + Uart::kTxdataOffset, true);
  }
  addSleepChecks();
  machine().setWakeCycles(wakeCycles(part, machine().clockHz()));
  if (g) {
    mcan_.reset(add<Mcan>(kCanfd0, kCanfdSpan, 6, *pins_, *sysctl_));
    mcan_->setPins(34, 5, 35, 6);  // PA12 CANFD0_CANTX (PF 5), PA13 CANFD0_CANRX (PF 6)
    // SLEEP-EVENT-LOST: the MCAN is in PD1, disabled in STOP and STANDBY ("the CPU, SRAM, and PD1 peripherals
    // are disabled and in retention (if applicable)", SLAU846A 2 STOP), and "some MSPM0G peripherals residing
    // in PD1 do not retain register contents when entering STOP or STANDBY" (SLAAET4 2.4, MCAN app note):
    // a powered MCAN neither receives nor keeps its configuration there.
    Mcan* can = mcan_.get();
    machine().addSleepCheck([can](PowerMode) {
      return can->powered() ? std::string("CANFD0 is powered: PD1, no clock and no retention in STOP/STANDBY")
                            : std::string();
    });
    // Output functions idle high: UART0 TX on PA10 (PINCM21), UART1 TX on PA8 (PINCM19), CAN TX.
    pins_->setFunctionDrive(21, 2, Drive::High);
    pins_->setFunctionDrive(19, 2, Drive::High);
    pins_->setFunctionDrive(34, 5, Drive::High);
  } else {
    // UART0 TX idles high on PA8 (PINCM9, PF 2) and PA23 (PINCM24, PF 2).
    pins_->setFunctionDrive(9, 2, Drive::High);
    pins_->setFunctionDrive(24, 2, Drive::High);
  }
  // The ROM bootloader, and the boot code as the last reset hook. Its invoke pin is PA18 on both parts
  // (mspm0-sdk boot_config.h DEFAULT_BSL_PIN_INVOCATION_DATA0: PINCM 0x28 on the G3507, 0x13 on the L1306).
  bsl_ = std::make_unique<RomBsl>(m, RomBsl::factoryConfig(g));
  boot_ = std::make_unique<BootCode>(m, *sysctl_, *pins_, *bsl_, g ? 40 : 19);
}

Mspm0::~Mspm0() = default;

std::vector<std::string> Mspm0::unservedInterrupts() const {
  std::vector<std::string> out;
  const uint64_t tenMs = 10000 * machine_->cyclesPerUs();
  for (const auto& [irq, held] : machine_->unservedIrqs(tenMs)) {
    const std::string who =
        irqNames_[static_cast<size_t>(irq)].empty() ? "a peripheral" : irqNames_[static_cast<size_t>(irq)];
    out.push_back(ruleText(Rule::IrqUnserved,
                           who + " interrupt request (IRQ " + std::to_string(irq) + ") pending for " +
                               std::to_string(held / machine_->cyclesPerUs() / 1000) +
                               " ms with its NVIC line never enabled (ISER) since the reset: no "
                               "handler ever runs for it"));
  }
  return out;
}

void Mspm0::cutPower() {
  flashctl_->cutPower();
  machine_->reset(ResetKind::Por, "power cut", rstcause::kPorSupply);
}

int Mspm0::pincm(int port, int bit) const {
  const PinId* p = pins_->find(port, bit);
  return p == nullptr ? 0 : p->pincm;
}

bool Mspm0::load(const ElfFile& elf) {
  elf_ = &elf;
  if (!machine_->loadFlash(elf.flashImage())) {
    error_ = elf.path() + ": the image (" + std::to_string(elf.flashImage().size()) +
             " B) does not fit the part's flash (" + std::to_string(machine_->layout().flashSize) + " B)";
    return false;
  }
  machine_->setSymbolizer([this](uint32_t address) { return elf_->symbolAt(address); });
  flashctl_->setImageEnd(static_cast<uint32_t>(elf.flashImage().size()));
  // The data-race rule, IDLE-WFI and BSS-UNINIT (rules.hpp); the stack reservation starts at __stack_limit__,
  // .bss spans [__bss_start__, __bss_end__) (bsp/mspm0/linker).
  const auto limit = elf.symbol("__stack_limit__");
  const auto bssStart = elf.symbol("__bss_start__");
  const auto bssEnd = elf.symbol("__bss_end__");
  machine_->enableImageRules(limit ? limit->value : machine_->layout().sramBase,
                             bssStart ? bssStart->value : 0, bssEnd ? bssEnd->value : 0);
  // WWDT-STOPPED (rules.hpp): bring-up ends at the first Thread-mode WFI; the watchdog must be running then.
  machine_->onFirstIdle([this] {
    if (!wwdt0_->running())
      machine_->violate(
          Rule::WatchdogStopped,
          "bring-up ended (the first WFI of Thread mode) with WWDT0 never started: a firmware that "
          "hangs from now on stays hung");
  });
  machine_->powerOn();
  return true;
}

// SLEEP-EVENT-LOST (rules.hpp): in every STOP and STANDBY mode the 32 MHz BUSCLK these models run from is
// gone (STOP0/1: ULPCLK at most 4 MHz; STOP2 and STANDBY: LFCLK; STANDBY1: only TIMG0/TIMG1 clocked at all;
// SLAU847D/SLAU846B 2 PMCU operating modes, the data sheets' STOP/STANDBY test conditions), so a transfer
// in flight or a timer deadline counted from it does not arrive as configured; a timer on LFCLK keeps
// counting where its instance keeps LFCLK (periph/timg.hpp StandbyClock). A GPIO edge (ALERT, nFAULT)
// wakes from every mode and is not checked; an idle UART or I2C target waiting for an external start wakes
// by an asynchronous fast-clock request (dl_sysctl_mspm0l11xx_l13xx.h STANDBY1 comment).
void Mspm0::addSleepChecks() {
  Machine& m = machine();
  // PREFETCH-SLEEP (rules.hpp, CPU_ERR_03): every sleep with the flash prefetcher off.
  m.onSleep([this, &m] {
    if (m.imageRules() && cpuss_->prefetchOn())
      m.violate(Rule::PrefetchSleep,
                "the core sleeps with CPUSS CTL.PREFETCH set: CPU_ERR_03, the prefetcher can fetch zeros "
                "entering the sleep and the code after the wake-up run corrupted; turn it off across the "
                "WFI");
  });
  for (auto& i2c : {i2c0_.get(), i2c1_.get()}) {
    m.addSleepCheck([i2c](PowerMode) {
      return i2c->transferInFlight()
                 ? std::string(i2c->name()) +
                       " has a transfer in flight, timed from the 32 MHz BUSCLK this mode stops"
                 : std::string();
    });
  }
  for (auto& uart : uart_) {
    if (!uart) continue;
    Uart* u = uart.get();
    m.addSleepCheck([u](PowerMode) {
      return u->transmitting() ? std::string(u->name()) +
                                     " is transmitting, its baud from the 32 MHz BUSCLK this mode stops"
                               : std::string();
    });
  }
  for (auto& timer : timg_) {
    if (!timer) continue;
    Timg* t = timer.get();
    m.addSleepCheck([t](PowerMode mode) { return t->deadlineLostIn(mode); });
    m.onSleep([t] { t->checkArmedCompares(); });
  }
}

}  // namespace twin
