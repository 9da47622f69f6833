// FactoryRegion: the MSPM0's read-only factory constants at 0x41C40000 (FACTORYREGION_BASE in mspm0l130x.h
// and mspm0g350x.h), as far as the images read them (TI hw_factoryregion.h FACTORYREGION_OPEN_Regs):
//   TRACEID  0x00  "Defined by TI, during ATE, based on wafer": unique per chip. The twin's chip has the
//                  value setTraceId() gives (by default 0x13060001 on the L1306, 0x35070001 on the G3507).
//   DEVICEID 0x04  VERSION 31:28 (0 here), PARTNUM 27:12 (0xBB82 MSPM0L11xx/L13xx, 0xBB88 MSPM0G1x0x/G3x0x:
//                  the values TI's IAR low-power patch scripts compare), MANUFACTURER 11:1 = 0x17 (TI's JEDEC
//                  code 00000010111b), ALWAYS_1 bit 0.
// Every other word, and any write, stops the run (the region is read-only; the rest is trim data the images
// never read).
#pragma once

#include <cstdint>

#include "address_map.hpp"

namespace twin {

class FactoryRegion final : public Device {
 public:
  static constexpr uint32_t kBase = 0x41C40000;
  static constexpr uint32_t kSize = 0x80;

  FactoryRegion(uint32_t traceId, uint16_t partNumber) : traceId_(traceId), partNumber_(partNumber) {}
  void setTraceId(uint32_t id) { traceId_ = id; }
  uint32_t traceId() const { return traceId_; }

  const char* name() const override { return "FACTORYREGION"; }
  bool read(uint32_t offset, unsigned bytes, uint32_t& value) override {
    if (bytes != 4) return false;
    if (offset == 0x0) {
      value = traceId_;
      return true;
    }
    if (offset == 0x4) {
      value = (uint32_t{partNumber_} << 12) | (0x17U << 1) | 1U;
      return true;
    }
    return false;
  }
  bool write(uint32_t, unsigned, uint32_t) override { return false; }

 private:
  uint32_t traceId_;
  uint16_t partNumber_;
};

}  // namespace twin
