// A deterministic sequence of record writes of the four firmware record types, shared by the store tests.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "app/store/records.hpp"

namespace store_test {

using Bytes = std::vector<uint8_t>;

struct Item {
  uint8_t type;
  Bytes payload;
};

// Write i: its type cycles with a skew (so the types are not written in lock step) and its payload depends
// on i, so every write of a type differs from the one before.
inline Item scriptItem(uint32_t i) {
  using namespace fw::app::store;
  const uint32_t pick = (i * 7 + i / 5) % 4;
  switch (pick) {
    case 0: {
      SettingsRecord r;
      for (uint32_t k = 0; k < r.value.size(); ++k)
        r.value[k] = static_cast<int32_t>(i * 100 + k) - 800;
      std::array<uint8_t, SettingsRecord::kBytes> b{};
      encode(r, b);
      return {static_cast<uint8_t>(RecordType::Settings), Bytes(b.begin(), b.end())};
    }
    case 1: {
      ProtectionLogRecord r;
      r.count = static_cast<uint8_t>(i % 5);
      for (uint32_t k = 0; k < r.count; ++k)
        r.entry[k] = {static_cast<uint8_t>(k + i % 13), i * 60 + k, -static_cast<int32_t>(i * 3 + k)};
      std::array<uint8_t, ProtectionLogRecord::kBytes> b{};
      encode(r, b);
      return {static_cast<uint8_t>(RecordType::ProtectionLog), Bytes(b.begin(), b.end())};
    }
    case 2: {
      FaultRecord r{static_cast<uint8_t>(i % 30), static_cast<uint16_t>(i), 0x2000'0000U + i, i * 11};
      std::array<uint8_t, FaultRecord::kBytes> b{};
      encode(r, b);
      return {static_cast<uint8_t>(RecordType::Fault), Bytes(b.begin(), b.end())};
    }
    default: {
      SocRecord r{static_cast<uint16_t>(i % 1001), 5000 + i};
      std::array<uint8_t, SocRecord::kBytes> b{};
      encode(r, b);
      return {static_cast<uint8_t>(RecordType::StateOfCharge), Bytes(b.begin(), b.end())};
    }
  }
}

}  // namespace store_test
