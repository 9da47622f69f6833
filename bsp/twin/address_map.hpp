// AddressMap: the twin's system bus outside flash and SRAM. Each model (a peripheral, the System Control
// Space) claims an address range; the core's loads and stores and the DMA's transfers go through here.
//
// Contract
// - A Device answers read()/write() with true for the registers it models; false means "no register
//   modelled here", and the access stops the run: the core halts with the PC and the address, and
//   describe() names the device and offset for that message. The same holds for an address in no range.
// - Peripheral registers are 32 bits wide: a device may refuse a narrower access the same way.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "cpu/core.hpp"

namespace twin {

class Device {
 public:
  virtual ~Device() = default;
  virtual const char* name() const = 0;
  // `offset` from the device's base; `bytes` is 1, 2 or 4 and the access is aligned.
  virtual bool read(uint32_t offset, unsigned bytes, uint32_t& value) = 0;
  virtual bool write(uint32_t offset, unsigned bytes, uint32_t value) = 0;
};

class AddressMap final : public CoreBus {
 public:
  void add(uint32_t base, uint32_t size, Device& device);
  bool load(uint32_t address, unsigned bytes, uint32_t& value) override;
  bool store(uint32_t address, unsigned bytes, uint32_t value) override;
  // Called before every store through the map (tests find the instruction that writes a register).
  void onStore(std::function<void(uint32_t address, uint32_t value)> hook) { storeHook_ = std::move(hook); }
  // "I2C0 + 0x1234" for a mapped address, "no model" otherwise.
  std::string describe(uint32_t address) const override;

 private:
  struct Range {
    uint32_t base, size;
    Device* device;
  };
  const Range* find(uint32_t address) const;

  std::vector<Range> ranges_;
  std::function<void(uint32_t, uint32_t)> storeHook_;
  mutable const Range* last_ = nullptr;
};

}  // namespace twin
