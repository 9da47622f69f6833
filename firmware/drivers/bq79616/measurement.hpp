// BQ79616 measurement records and link statistics: what a scan of the daisy chain produces.
//
// Units (integers only; the conversion helpers are constexpr and exact to the rounding noted):
//   cells        raw two's-complement ADC codes, 1 LSB = 190.73 uV (SLUSE81E §9.5.4.4, VCELLn_HI/LO);
//                cellMicrovolts() converts, rounded to the nearest microvolt. 0x8000 (regs::kNotReady)
//                means "no conversion yet" and is never converted: the record marks the device NotReady.
//   die temp     tenths of a kelvin (DIETEMPn: 1 LSB = 0.025 degC, converted and rounded to 0.1 K)
//   GPIO         raw codes, 1 LSB = 152.59 uV (thermistor inputs; the application owns the curve);
//                0x8000 = not converted (GPIO not configured as an ADC input)
//   faults       FAULT_SUMMARY as read (bit 4 FAULT_COMM, bit 5 FAULT_OTP, ...)
#pragma once

#include <cstdint>

#include "core/status.hpp"
#include "core/time.hpp"

namespace fw::drivers::bq79616 {

inline constexpr uint8_t kMaxDevices = 64;  // addresses 0..63
inline constexpr uint8_t kCellsPerDevice = 16;
inline constexpr uint8_t kGpiosPerDevice = 8;
inline constexpr uint8_t kNoDevice = 0xFF;  // "no device" in a FaultReport

// Which parts of a DeviceRecord hold values validated in the last scan (DeviceRecord::valid).
enum ValidBits : uint8_t {
  kValidCells = 0x01,
  kValidDieTemp = 0x02,
  kValidGpio = 0x04,
  kValidFaults = 0x08,
};

// One device of the chain, as of its last scan. A part is meaningful only when its ValidBits bit is set;
// values of parts that did not validate are zero, never left over from an earlier scan.
struct DeviceRecord {
  Instant takenAt{};                   // end of the bus exchange that delivered this device's cells
  int16_t cellRaw[kCellsPerDevice]{};  // index 0 = cell 1 (VCELL1) ... 15 = cell 16
  int16_t dieTemp[2]{};                // DIETEMP1, DIETEMP2 in 0.1 K
  int16_t gpioRaw[kGpiosPerDevice]{};  // index 0 = GPIO1
  uint8_t faultSummary = 0;
  uint8_t valid = 0;           // ValidBits
  Status status = Status::Ok;  // Ok, or the first error that hit this device in the last scan
};

// Which device an error names, and what the error is.
struct FaultReport {
  Status status = Status::Ok;
  uint8_t device = kNoDevice;
};

struct ScanSummary {
  Instant started{};
  Instant finished{};
  uint8_t devices = 0;         // devices in the chain (discovered at bring-up)
  uint8_t validDevices = 0;    // devices whose every requested part validated
  uint8_t faultedDevices = 0;  // devices with a non-zero FAULT_SUMMARY
  FaultReport firstError;      // the first device that failed, and how
};

// Link statistics since construction (never reset by the driver).
struct LinkStats {
  uint32_t commandFrames = 0;          // command frames sent
  uint32_t responseFrames = 0;         // response frames that validated
  uint32_t errors[kStatusCount] = {};  // failed exchanges and frames, per Status (Crc, NoResponse, ...)
  uint32_t retries = 0;                // whole-transaction retries
  uint32_t localisations = 0;          // chain reads that fell back to per-device reads
  uint32_t recoveryAttempts = 0;       // startRecovery() calls
  uint32_t recoveries[4] = {};         // recoveries that succeeded, per ladder level (RecoveryLevel)
  uint32_t faultClears = 0;            // fault-reset operations
  uint32_t faultLineEdges = 0;         // nFAULT falling edges seen

  uint32_t crcErrors() const { return errors[static_cast<uint8_t>(Status::Crc)]; }
  uint32_t timeouts() const {
    return errors[static_cast<uint8_t>(Status::NoResponse)] +
           errors[static_cast<uint8_t>(Status::Truncated)] + errors[static_cast<uint8_t>(Status::Timeout)];
  }
};

// Microvolts of a raw cell code, rounded to nearest (190.73 uV = 19073 / 100 uV; |raw| <= 32768 keeps the
// product inside 32 bits).
constexpr int32_t cellMicrovolts(int16_t raw) {
  const int32_t n = static_cast<int32_t>(raw) * 19073;
  return (n >= 0 ? n + 50 : n - 50) / 100;
}

// Tenths of a kelvin of a raw DIETEMP code, rounded half up: 1 LSB = 0.025 degC = a quarter of 0.1 K, and
// 0 degC = 273.15 K = 10926 quarters of 0.1 K. floor((quarters + 2) / 4) is rounding half up for either sign,
// and C++20 defines >> of a negative value as that floor (no signed division on Cortex-M0+).
constexpr int16_t dieTempDeciKelvin(int16_t raw) {
  const int32_t quarters = static_cast<int32_t>(raw) + 10926;
  return static_cast<int16_t>((quarters + 2) >> 2);
}

}  // namespace fw::drivers::bq79616
