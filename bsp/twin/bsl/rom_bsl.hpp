// RomBsl: the MSPM0 ROM bootstrap loader (BSL) as its UART pins show it: the packets it takes, what it
// answers and when, and what it does to MAIN flash. The twin runs it instead of the image while the boot code
// (boot_code.hpp) has started it; the core is held meanwhile (Machine::holdCore). Its code is not TI's (the
// ROM is not available); every rule below is the documented behaviour, with its source.
//
// Line (SLAU887 4.2.2.1): UART0, 8N1, 9600 Bd after start. A byte sent by the host at another rate is lost
// (receive() gets the host's rate; a real UART sees framing errors and garbage). Bytes leave back to back,
// 10 bit times each.
//
// Packet layer (SLAU887 4.1, 4.2.1; mspm0-sdk secondary_bsl_uart/bsl_uart.c, TI's code for the same
// protocol in flash, for the order of the checks):
// - 0x80 | length LE | CMD | data | CRC32 LE, the CRC (reflected 0xEDB88320, seed 0xFFFFFFFF, no final XOR)
//   over CMD and data. A first byte other than 0x80 is answered 0x51; length 0 with 0x53 and length + 7 >
//   the buffer size with 0x54 as soon as the length is in; a CRC mismatch with 0x52. After any of these the
//   next byte starts a new packet. A good packet is acknowledged 0x00. There is no receive timeout: a packet
//   short of bytes waits for them.
// - While a command executes and until its answer has left, received bytes are dropped (bsl_uart.c: the
//   RX state is BLOCKED; "packet is dropped").
// - Before a valid Connection the BSL "does not react to anything but the connect command" (observed on an
//   LP-MSPM0G3507, kalanzun/lenlab_mspm0 notes/protocol.md): other packets and errors get no answer. No
//   Connection within 10 s of the start: STANDBY, silent until the next reset (SLAU887 3.1.1).
//
// Commands (SLAU887 4.3; codes as mspm0-sdk secondary_bsl_uart/bsl_ci.h):
// - Connection 0x12: ACK; a second one: ACK + MSG 0x06 (lenlab observation; SLAU887 says nothing).
// - Get Device Info 0x19: 0x31 + 24 bytes (SLAU887 4.4.4): interpreter version 0x0100, build 0x0100,
//   application version 0, plug-in 0x0001, buffer size (0x06C0 on a 4 KiB-SRAM part as SLAU887 4.3.2's
//   example, 0x3EC0 on the G3507 as lenlab's board answers), buffer start 0x20000160, BCR and BSL
//   configuration IDs 1.
// - Unlock 0x21: the length field must be 0x21 and the 32 bytes the configured password (all 0xFF on a fresh
//   part, SLAU887 4.3.3), else MSG 0x02; the BSL then ignores the line for 2 s, and a wrong password reverts
//   the rate to 9600 Bd after its answer (SLAU887 4.3.3, 4.3.12). The third wrong password of a session
//   answers MSG 0x03 and takes the configured security alert (factory default "ignore": nothing more;
//   mspm0-sdk boot_config.c BSL_CFG_SECURITY_IGNORE). Not unlocked, the protected commands (0x20, 0x24,
//   0x29, 0x23, 0x15, 0x30, 0x26) answer MSG 0x01 (SLAU846A "BSL password": only Get Identity and Start
//   Application are allowed without it). 10 s without a command after the Connection lock it again
//   (SLAU887 4.4.1 MSG 0x01 "timeout occurred in the command-reception phase"; the secondary BSL's timer
//   restarts at every command: secondary_bsl.c BSL_TEN_SECOND_TIMEOUT).
// - Program Data 0x20 / Program Data Fast 0x24: start address and length multiples of 8, else MSG 0x0A; the
//   range inside MAIN flash, else MSG 0x05; SRAM may be written too (SLAU887 4.3.4). Each 64-bit word must be
//   erased (all 0xFF) before it is programmed: a word that is not fails the command with 0xF1, the secondary
//   BSL's "flash program failed" (the ROM's code for it is not documented). 50 us per word (MSPM0L110x data
//   sheet SLASEX5C 7.7 tPROG(WORD,64) typical; the L130x/G350x tables were not read). 0x24 gives no answer
//   and does not block the line.
// - Flash Range Erase 0x23: first <= last, both in MAIN, else MSG 0x05; erases every 1 KiB sector from the
// one
//   holding `first` to the one holding `last` (SLAU887 4.3.7; bsl_ci.c). 4 ms a sector (SLASEX5C 7.7
//   tERASE(SEC) typical, under 2k cycles).
// - Mass Erase 0x15: all of MAIN (SLAU887 4.3.8); 22 ms (a bank erase: MSPM0C110x data sheet SLASF90B 7.7
//   typical, the only bank figure read).
// - Memory Read Back 0x29: MSG 0x09, read-out disabled as on a fresh part (boot_config.c memoryRead).
// - Standalone Verification 0x26: length < 1 KiB: MSG 0x0B; the range must lie in MAIN flash, NONMAIN or
//   SRAM, else MSG 0x05; the answer is 0x32 + the CRC32 of the range (SLAU887 4.3.10, 4.4.5). 8 cycles a
//   byte (an estimate: a byte-wise feed of the CRC peripheral, bsl_ci.c BSL_CI_calculateCRC).
// - Start Application 0x40: ACK, then the software reset with bootloader exit (bsl_ci.c:
//   DL_SYSCTL_resetDevice(DL_SYSCTL_RESET_BOOTLOADER_EXIT), i.e. RESETLEVEL 4 through SYSCTL).
// - Change Baud Rate 0x52: IDs 1..9 (4800 .. 3 000 000): ACK at the old rate, the new one after it (SLAU887
//   4.3.12); any other ID is answered 0x56 instead of the ACK.
// - Any other command: MSG 0x04. Factory Reset 0x30 and any write to NONMAIN stop the run: they reprogram
//   the boot configuration, and a flasher must never send them.
#pragma once

#include <array>
#include <cstdint>
#include <deque>
#include <functional>
#include <string>
#include <vector>

#include "machine.hpp"
#include "timeline.hpp"

namespace twin {

class RomBsl {
 public:
  struct Config {
    uint32_t mainFlashSize = 0;
    uint32_t sramBase = 0, sramSize = 0;
    uint16_t bufferSize = 0;
    std::array<uint8_t, 32> password{};  // all 0xFF unless a test sets one
  };
  // The part's configuration as TI ships it (Config comment above).
  static Config factoryConfig(bool g3507);

  RomBsl(Machine& machine, const Config& config);
  // A part whose NONMAIN holds another password (tests).
  void setPassword(const std::array<uint8_t, 32>& password) { config_.password = password; }

  // The boot code starts it (the reset put every register back) or leaves it off.
  void start(const std::string& reason);
  void stop();
  bool running() const { return running_; }
  // A byte whose stop bit just reached the BSL's RX pin, sent at `hostBaud`.
  void receive(uint8_t byte, uint32_t hostBaud);
  // Each byte as its stop bit leaves the TX pin, with the rate it was sent at.
  void onTransmit(std::function<void(uint8_t byte, uint32_t baud)> sink) { sink_ = std::move(sink); }
  uint32_t baud() const { return baud_; }
  // Something to send or a command executing (a host that waits for it needs no wall-clock pacing).
  bool busy() const { return !tx_.empty() || execute_.armed(); }

  // What it did, for tests and the runner.
  struct Record {
    uint64_t cycle;    // the answer's last byte left (or the command was taken, without an answer)
    uint8_t command;   // 0 for a packet-layer answer
    int result;        // the core message, the acknowledgement error, or -1 for a data reply / ACK only
    std::string text;  // e.g. "Program Data 0x00000400 4096 B: MSG 0x00"
  };
  const std::vector<Record>& records() const { return records_; }
  uint64_t connectedAt() const { return connectedAt_; }  // the first Connection acknowledged (0 = none)
  uint64_t bytesLost() const { return lost_; }           // sent at a rate the BSL was not at
  void onCommand(std::function<void(const Record&)> observer) { observer_ = std::move(observer); }

  // Fault injection (tests): the `nth` core answer from now on (1 = the next) leaves with a wrong CRC.
  void corruptAnswerCrc(unsigned nth) { corruptAnswer_ = nth; }

 private:
  enum class Rx : uint8_t { Idle, Header, Body, Blocked };

  void send(std::vector<uint8_t> bytes, std::function<void()> then = nullptr);
  void sendNext();
  void packetError(uint8_t ack);
  void packetDone();
  void interpret(uint8_t command, const std::vector<uint8_t>& data, uint16_t length);
  void answer(uint8_t rsp, const std::vector<uint8_t>& data, uint64_t executionCycles, std::string text);
  void message(uint8_t msg, uint64_t executionCycles, std::string text) {
    answer(0x3B, {msg}, executionCycles, text);
  }
  void note(uint8_t command, int result, std::string text);
  uint8_t program(uint32_t address, const std::vector<uint8_t>& bytes, uint64_t& cycles);
  uint64_t byteCycles() const;
  uint64_t micros(uint64_t us) const { return us * machine_.cyclesPerUs(); }

  Machine& machine_;
  Config config_;
  bool running_ = false, connected_ = false, unlocked_ = false, standby_ = false;
  uint32_t baud_ = 9600;
  unsigned wrongPasswords_ = 0;
  uint64_t startedAt_ = 0, lastCommandAt_ = 0, deafUntil_ = 0, connectedAt_ = 0, lost_ = 0;
  Rx rx_ = Rx::Idle;
  std::vector<uint8_t> packet_;
  size_t expected_ = 0;
  std::deque<std::pair<uint8_t, std::function<void()>>> tx_;
  TimedEvent txDone_;
  TimedEvent execute_;
  std::function<void()> executeAction_;
  std::function<void(uint8_t, uint32_t)> sink_;
  std::function<void(const Record&)> observer_;
  std::vector<Record> records_;
  unsigned corruptAnswer_ = 0;
};

// CRC-32 as the BSL computes it (SLAU887 4.2.2.3): reflected 0xEDB88320, seed 0xFFFFFFFF, no final XOR.
uint32_t bslCrc32(const uint8_t* data, size_t size);

}  // namespace twin
