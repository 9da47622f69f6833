// The bytes of one fuzz input, taken from the front as the target needs them. Past the end every read is 0,
// so a short input is a valid input too.
#pragma once

#include <cstddef>
#include <cstdint>

namespace bms_fuzz {

class Input {
 public:
  Input(const uint8_t* data, size_t size) : data_(data), size_(size) {}
  uint8_t byte() { return pos_ < size_ ? data_[pos_++] : 0; }
  uint16_t word() { return static_cast<uint16_t>(byte() | (byte() << 8)); }
  bool flag() { return (byte() & 1) != 0; }
  bool empty() const { return pos_ >= size_; }
  const uint8_t* rest() const { return data_ + (pos_ < size_ ? pos_ : size_); }
  size_t restSize() const { return pos_ < size_ ? size_ - pos_ : 0; }

 private:
  const uint8_t* data_;
  size_t size_;
  size_t pos_ = 0;
};

}  // namespace bms_fuzz
