// SlcanAdapter: the PC's side of the L1306 board's back-channel UART, read as a LAWICEL (SLCAN) serial CAN
// adapter, so python-can's `slcan` interface and slcand can send frames to the board as well as read them.
//
// Lines end with CR (a LF is ignored). Each line gets one answer: CR for OK, BEL for an error, as the LAWICEL
// CAN232/CANUSB ASCII protocol gives them (EasySYNC USB2-F-7x01 user guide, ES_000005, 4.1):
//   ""          (an empty line)      CR
//   O           open the channel     CR; BEL if it is open
//   C           close the channel    CR; BEL if it is closed
//   S0 .. S8    set the bit rate     CR (only while closed; the board's SLCAN has no bit rate of its own, so
//                                    it is recorded and nothing else); BEL while open
//   V           version              "Vhhss" CR: hardware 01, software the firmware's major and minor digits
//                                    (identity.hpp kVersion)
//   N           serial number        "Nxxxx" CR: the low 16 bits of the chip's TraceId, hex
//   F           status flags         "Fxx" CR (only while open): bit 3 data overrun (received bytes lost
//   since
//                                    the last F), cleared by reading; BEL while closed
//   tiiildd..   standard frame       "z" CR (only while open); the frame goes to the command handler
//   Tiiiiiiiildd.. extended frame    "Z" CR (only while open); no command is extended: it is filtered out
// Anything else (another command, a malformed frame: a digit that is not hex, a DLC above 8, data shorter or
// longer than the DLC, an identifier out of range, a line longer than any command) gets BEL and changes
// nothing. python-can reads CR, BEL, "z", V and N answers between frames and ignores what is not a frame;
// slcand ignores every line that is not a frame.
// The board is a CAN node, not an adapter: it publishes whether or not the channel is open; open and closed
// decide only whether the PC may send frames.
// Pure logic (no I/O); thread mode (the command task).
#pragma once

#include <cstdint>

#include "app/command/identity.hpp"
#include "hal/can_bus.hpp"

namespace fw::app::command {

class SlcanAdapter {
 public:
  static constexpr uint8_t kMaxLine = 1 + 8 + 1 + 16;  // the longest valid line: an extended 8-byte frame
  static constexpr uint8_t kMaxAnswer = 6;             // "Vhhss\r"

  struct Line {
    uint8_t answer[kMaxAnswer];
    uint8_t answerLength;
    bool hasFrame;  // a t/T line that parsed: `frame` holds it
    hal::CanFrame frame;
  };
  struct Info {
    uint16_t serial;        // N's four hex digits
    bool overrunSinceLast;  // for F: received bytes were lost since the last F
  };

  // Takes one received byte; true when it ended a line: then answer() handles that line.
  bool take(uint8_t byte);
  // The answer to the line take() just ended (and its frame).
  void answer(const Info& info, Line& out);
  bool open() const { return state_.open; }
  uint8_t bitrateCode() const { return state_.bitrate; }  // the last S<n> taken (0 until one was)

 private:
  bool execute(const Info& info, Line& out);

  struct State {             // all-zero: closed, no line
    uint8_t line[kMaxLine];  // as received (execute() turns the hex digits after the letter into values)
    uint8_t length;
    bool overlong;  // more than kMaxLine bytes before the CR: the line is refused
    bool open;
    uint8_t bitrate;
  };
  State state_{};
};

}  // namespace fw::app::command
