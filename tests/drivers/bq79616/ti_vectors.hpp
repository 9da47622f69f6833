// The BQ79616 command frames byte for byte as TI prints them (SLUUC56B, SLUAA17A;
// CRCs computed there with an independent CRC-16/MODBUS implementation). Used by the codec tests and by the
// bmsctl test, which feeds `args` to the built tool and compares its TX line with `bytes`.
#pragma once

#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include "drivers/bq79616/frame.hpp"

namespace test {

struct TiVector {
  const char* what;
  fw::drivers::bq79616::RequestType type;
  uint8_t device;
  uint16_t reg;
  std::vector<uint8_t> data;  // write data, or {count} for a read
  std::vector<uint8_t> bytes;
  std::string args;  // the bmsctl trace bq79616 operation that sends this frame
};

inline const std::vector<TiVector>& tiVectors() {
  using T = fw::drivers::bq79616::RequestType;
  static const std::vector<TiVector> v = {
      {"single W dev0 CONTROL1=0x20 (SEND_WAKE)",
       T::SingleWrite,
       0,
       0x309,
       {0x20},
       {0x90, 0x00, 0x03, 0x09, 0x20, 0x13, 0x95},
       "write single 0 0x309 20"},
      {"broadcast W OTP_ECC_DATAIN1=0x00",
       T::BroadcastWrite,
       0,
       0x343,
       {0x00},
       {0xD0, 0x03, 0x43, 0x00, 0xF9, 0xD4},
       "write broadcast 0x343 00"},
      {"broadcast W CONTROL1=0x01 (auto-address)",
       T::BroadcastWrite,
       0,
       0x309,
       {0x01},
       {0xD0, 0x03, 0x09, 0x01, 0x0F, 0x74},
       "write broadcast Control1 01"},
      {"broadcast W DIR0_ADDR=0x00",
       T::BroadcastWrite,
       0,
       0x306,
       {0x00},
       {0xD0, 0x03, 0x06, 0x00, 0xCB, 0x44},
       "write broadcast 0x306 00"},
      {"broadcast W DIR0_ADDR=0x01",
       T::BroadcastWrite,
       0,
       0x306,
       {0x01},
       {0xD0, 0x03, 0x06, 0x01, 0x0A, 0x84},
       "write broadcast DIR0_ADDR 01"},
      {"broadcast W COMM_CTRL=0x02",
       T::BroadcastWrite,
       0,
       0x308,
       {0x02},
       {0xD0, 0x03, 0x08, 0x02, 0x4E, 0xE5},
       "write broadcast 0x308 02"},
      {"single W dev0 COMM_CTRL=0x00",
       T::SingleWrite,
       0,
       0x308,
       {0x00},
       {0x90, 0x00, 0x03, 0x08, 0x00, 0x13, 0xDD},
       "write single 0 0x308 00"},
      {"single W dev1 COMM_CTRL=0x03",
       T::SingleWrite,
       1,
       0x308,
       {0x03},
       {0x90, 0x01, 0x03, 0x08, 0x03, 0x52, 0x20},
       "write single 1 CommCtrl 03"},
      {"broadcast R OTP_ECC_DATAIN1, 1 byte",
       T::BroadcastRead,
       0,
       0x343,
       {1},
       {0xC0, 0x03, 0x43, 0x00, 0xFD, 0x14},
       "read broadcast 0x343 1"},
      {"broadcast W FAULT_RST2=0x03",
       T::BroadcastWrite,
       0,
       0x332,
       {0x03},
       {0xD0, 0x03, 0x32, 0x03, 0x9D, 0x85},
       "write broadcast 0x332 03"},
      {"broadcast W FAULT_MSK2=0x40",
       T::BroadcastWrite,
       0,
       0x017,
       {0x40},
       {0xD0, 0x00, 0x17, 0x40, 0x36, 0xE4},
       "write broadcast 0x017 40"},
      {"broadcast R CUST_CRC_RSLT_HI, 2 bytes",
       T::BroadcastRead,
       0,
       0x50C,
       {2},
       {0xC0, 0x05, 0x0C, 0x01, 0xE8, 0xE5},
       "read broadcast CUST_CRC_RSLT_HI 2"},
      {"broadcast W FAULT_RST1=FF FF",
       T::BroadcastWrite,
       0,
       0x331,
       {0xFF, 0xFF},
       {0xD1, 0x03, 0x31, 0xFF, 0xFF, 0x88, 0x29},
       "write broadcast 0x331 FF FF"},
      {"broadcast W ACTIVE_CELL=0x0A",
       T::BroadcastWrite,
       0,
       0x003,
       {0x0A},
       {0xD0, 0x00, 0x03, 0x0A, 0xB8, 0x13},
       "write broadcast 0x003 0A"},
      {"broadcast W ADC_CONF1=0x02",
       T::BroadcastWrite,
       0,
       0x007,
       {0x02},
       {0xD0, 0x00, 0x07, 0x02, 0xBB, 0x15},
       "write broadcast AdcConf1 02"},
      {"broadcast W ADC_CTRL1=0x0E",
       T::BroadcastWrite,
       0,
       0x30D,
       {0x0E},
       {0xD0, 0x03, 0x0D, 0x0E, 0x4D, 0xB0},
       "write broadcast 0x30D 0E"},
      {"broadcast R VCELL16_HI, 32 bytes",
       T::BroadcastRead,
       0,
       0x568,
       {32},
       {0xC0, 0x05, 0x68, 0x1F, 0x42, 0x2D},
       "read broadcast 0x568 32"},
      {"single R dev1 DIR0_ADDR, 1 byte",
       T::SingleRead,
       1,
       0x306,
       {1},
       {0x80, 0x01, 0x03, 0x06, 0x00, 0xD7, 0x82},
       "read single 1 0x306 1"},
      {"stack W CONTROL1=0x20",
       T::StackWrite,
       0,
       0x309,
       {0x20},
       {0xB0, 0x03, 0x09, 0x20, 0xD1, 0x6C},
       "write stack 0x309 20"},
  };
  return v;
}

inline std::string hexLine(const char* prefix, const std::vector<uint8_t>& bytes) {
  std::string s = prefix;
  char buf[4];
  for (uint8_t b : bytes) {
    std::snprintf(buf, sizeof buf, " %02X", b);
    s += buf;
  }
  return s;
}

}  // namespace test
