// `bmsctl flash --invoke app`: ask the running image to restart into the ROM bootloader, with the command
// frames of the CAN catalogue (firmware/app/can/bms.yaml, "Commands") carried as SLCAN text lines
// ("t<id:3 hex><dlc><data hex>\r", Lawicel CAN232 format, as the images' SLCAN output writes them).
//
// The exchange, node N (--node, the image's FW_COMMAND_NODE, 1 by default):
//   1. Identify      0x603 [Crc, Counter, Target N]
//        answers     IdentifyVersion 0x581 [Node, Major, Minor, Patch, BuildId:24, Image]
//                    IdentifyChip    0x582 [Node, ResetCause, TraceId:32, PartNumber:16]
//   2. EnterBootloader 0x606 [Crc, Counter, Target N, TraceId:32 (from IdentifyChip), Key 0xA5]
//        answer      CommandAck 0x580 [Node, Command:16, Counter, Result, Rejected:16]; Result 0 = accepted:
//                    the image has opened every path its protection controls and makes TI's software-invoke
//                    reset (SYSCTL RESETLEVEL = BOOTLOADERENTRY, bsp/mspm0/bootloader_entry.hpp).
// Every signal is little endian from the bit given in bms.yaml. Crc is CRC-8 SAE J1850 (polynomial 0x1D,
// initial 0xFF, final XOR 0xFF; check value 0x4B over "123456789") over the identifier's low byte, its high
// byte, then payload bytes 1 .. DLC-1; Counter (low nibble of byte 1) advances by one per frame of a message.
//
// The request goes on the flash port itself (the L1306 images' SLCAN link is the back-channel UART at
// 115 200 Bd) or, with --invoke-port, on an SLCAN CAN adapter on the G3507's CAN bus (opened with "S6" =
// 500 kbit/s and "O" first, closed with "C").
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "flash/serial_port.hpp"

namespace bmsctl::flash {

uint8_t crc8J1850(std::span<const uint8_t> bytes);

struct CanLine {
  uint16_t id = 0;
  std::vector<uint8_t> data;
};
std::string slcanLine(const CanLine& frame);  // "t6068...\r"
std::optional<CanLine> parseSlcanLine(
    const std::string& line);  // one line without its '\r'; standard ids only

// The command frames, Crc filled in.
CanLine identifyFrame(uint8_t node, uint8_t counter);
CanLine enterBootloaderFrame(uint8_t node, uint8_t counter, uint32_t traceId);

struct InvokeResult {
  enum class Kind : uint8_t { Entered, NoAnswer, Refused, WrongImage };
  Kind kind = Kind::NoAnswer;
  std::string text;       // for the message
  int runningImage = -1;  // IdentifyVersion.Image (1..5), -1 if unknown
};

// Runs the exchange on `port` (already open; `adapter` opens the SLCAN channel first). `imageChipIsG3507`:
// the image being flashed is for a G3507 (images 3..5) rather than an L1306 (1, 2); a running image of the
// other part is refused before the reset (WrongImage).
InvokeResult invokeApplication(SerialPort& port, bool adapter, uint8_t node,
                               std::optional<bool> imageChipIsG3507);

}  // namespace bmsctl::flash
