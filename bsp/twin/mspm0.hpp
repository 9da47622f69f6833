// Mspm0: one MSPM0L1306 or MSPM0G3507 as the twin builds it: the machine (core, memories, SCS) and every
// peripheral model at its base address, interrupt line and DMA triggers. Every number comes from the rows of
// TI's MSPM0 device headers (mspm0-sdk hw_*.h: bases, IRQ numbers, DMA triggers, memories, INT_GROUP IIDX),
// the data sheets' memory maps and, for the pins, the device headers' IOMUX_PINCMn_PF_* definitions
// (mspm0-sdk mspm0g350x.h / mspm0l130x.h).
//
// Instances the images use are modelled; every other peripheral address is left unmapped, so an image that
// touches one stops with the PC and the address.
#pragma once

#include <array>
#include <memory>
#include <string>
#include <vector>

#include "bsl/boot_code.hpp"
#include "bsl/rom_bsl.hpp"
#include "elf_file.hpp"
#include "machine.hpp"
#include "periph/cpuss.hpp"
#include "periph/dma.hpp"
#include "periph/factory.hpp"
#include "periph/flashctl.hpp"
#include "periph/gpio.hpp"
#include "periph/i2c.hpp"
#include "periph/mcan.hpp"
#include "periph/pins.hpp"
#include "periph/sysctl.hpp"
#include "periph/timg.hpp"
#include "periph/uart.hpp"
#include "periph/wwdt.hpp"

namespace twin {

enum class Part : uint8_t { L1306, G3507 };

class Mspm0 {
 public:
  explicit Mspm0(Part part);
  ~Mspm0();

  Part part() const { return part_; }
  // Loads the image's flash bytes and its symbols (for messages), then powers the chip on. False with
  // error() set if the image does not fit.
  bool load(const ElfFile& elf);
  const std::string& error() const { return error_; }

  Machine& machine() { return *machine_; }
  const Machine& machine() const { return *machine_; }
  Pins& pins() { return *pins_; }
  Sysctl& sysctl() { return *sysctl_; }
  Gpio& gpio(int port) { return port == 0 ? *gpioA_ : *gpioB_; }
  Wwdt& wwdt0() { return *wwdt0_; }
  I2c& i2c0() { return *i2c0_; }
  Uart& uart(int n) { return *uart_[n]; }  // 0..3 on the G3507, 0..1 on the L1306
  Mcan* mcan() { return mcan_.get(); }     // G3507 only
  FactoryRegion& factory() { return *factory_; }
  Flashctl& flashctl() { return *flashctl_; }
  // Power fails now and comes back: a flash operation in progress is left half done (Flashctl::cutPower),
  // then a power-on reset; the flash keeps its content, SRAM does not. To cut after a given instruction:
  // machine().run(machine().now() + 1) executes exactly one (every instruction takes at least one cycle);
  // during a given operation: run until flashctl().commandsStarted() counts it and busy() is set.
  void cutPower();
  const Mcan* mcan() const { return mcan_.get(); }
  const Pins& pins() const { return *pins_; }
  // The ROM bootloader and the boot code that starts it (bsl/).
  RomBsl& bsl() { return *bsl_; }
  const BootCode& bootCode() const { return *boot_; }
  // PINCM index of port/bit (0 if the part has no such pin).
  int pincm(int port, int bit) const;
  // What drives IRQ n ("UART0", "INT_GROUP1 (GPIOA/GPIOB)", "DMA"; "" if nothing modelled).
  std::string irqName(int irq) const {
    return irq >= 0 && irq < 32 ? irqNames_[static_cast<size_t>(irq)] : "";
  }
  // IRQ-UNSERVED (rules.hpp): a line pending 10 ms or more, its NVIC enable never set since the reset. The
  // texts, in the rules' form ("[IRQ-UNSERVED] ...").
  std::vector<std::string> unservedInterrupts() const;

 private:
  void addSleepChecks();  // SLEEP-EVENT-LOST: what each model needs awake (rules.hpp)
  template <class Model, class... Args>
  Model* add(uint32_t base, uint32_t size, int irq, Args&&... args);

  Part part_;
  std::string error_;
  std::unique_ptr<Machine> machine_;
  std::unique_ptr<Sysctl> sysctl_;
  std::unique_ptr<Cpuss> cpuss_;
  std::unique_ptr<FactoryRegion> factory_;
  std::unique_ptr<Flashctl> flashctl_;
  std::unique_ptr<Pins> pins_;
  std::unique_ptr<Dma> dma_;
  std::unique_ptr<Gpio> gpioA_, gpioB_;
  std::unique_ptr<Timg> timg_[4];
  std::unique_ptr<Wwdt> wwdt0_;
  std::unique_ptr<I2c> i2c0_, i2c1_;
  std::unique_ptr<Uart> uart_[4];
  std::unique_ptr<Mcan> mcan_;
  std::unique_ptr<RomBsl> bsl_;
  std::unique_ptr<BootCode> boot_;
  const ElfFile* elf_ = nullptr;
  std::array<std::string, 32> irqNames_{};
};

}  // namespace twin
