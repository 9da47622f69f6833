#include "address_map.hpp"

#include <cstdio>

namespace twin {

void AddressMap::add(uint32_t base, uint32_t size, Device& device) {
  ranges_.push_back({base, size, &device});
  last_ = nullptr;
}

const AddressMap::Range* AddressMap::find(uint32_t address) const {
  if (last_ != nullptr && address - last_->base < last_->size) return last_;
  for (const Range& r : ranges_) {
    if (address - r.base < r.size) return last_ = &r;
  }
  return nullptr;
}

bool AddressMap::load(uint32_t address, unsigned bytes, uint32_t& value) {
  const Range* r = find(address);
  return r != nullptr && r->device->read(address - r->base, bytes, value);
}

bool AddressMap::store(uint32_t address, unsigned bytes, uint32_t value) {
  if (storeHook_) storeHook_(address, value);
  const Range* r = find(address);
  return r != nullptr && r->device->write(address - r->base, bytes, value);
}

std::string AddressMap::describe(uint32_t address) const {
  const Range* r = find(address);
  if (r == nullptr) return "no model";
  char buf[96];
  std::snprintf(buf, sizeof buf, "%s + 0x%X: no register modelled there", r->device->name(),
                address - r->base);
  return buf;
}

}  // namespace twin
