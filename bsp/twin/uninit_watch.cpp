#include "uninit_watch.hpp"

#include <algorithm>

namespace twin {

UninitWatch::UninitWatch(uint32_t low, uint32_t high, SramWatch* next,
                         std::function<void(uint32_t address)> report)
    : low_(low),
      high_(std::max(low, high)),
      next_(next),
      report_(std::move(report)),
      written_(high_ - low_) {}

void UninitWatch::reset() {
  std::fill(written_.begin(), written_.end(), false);
  reported_ = false;
}

void UninitWatch::onSramLoad(uint32_t address, unsigned bytes) {
  for (uint32_t a = address; a < address + bytes && !reported_; ++a) {
    if (a >= low_ && a < high_ && !written_[a - low_]) {
      reported_ = true;
      report_(a);
    }
  }
  if (next_ != nullptr) next_->onSramLoad(address, bytes);
}

void UninitWatch::onSramStore(uint32_t address, unsigned bytes) {
  for (uint32_t a = address; a < address + bytes; ++a)
    if (a >= low_ && a < high_) written_[a - low_] = true;
  if (next_ != nullptr) next_->onSramStore(address, bytes);
}

}  // namespace twin
