// CommandPty: the running image's command link on a pseudo-terminal, so `bmsctl flash --invoke app
// --invoke-port /dev/pts/N` (or bmsctl send, python-can's slcan interface) can ask the image on the twin to
// restart into its ROM bootloader, as on a board:
// - L1306 boards: the LaunchPad's back-channel UART0 (PA9 RX, PA8 TX, 115 200 Bd 8N1). What the program
//   writes reaches PA9 byte after byte at 115 200 Bd (Board::sendSerial); the image's SLCAN text comes back
//   line by line as it leaves PA8 (Board::slcanLines). The BSL is on other pins (PA22/PA23, BslPty).
// - G3507 boards: an SLCAN (Lawicel CAN232) adapter on the board's CAN bus at 500 kbit/s. O, C, S0..S8,
//   F, V, N are answered with CR (V and N with a version and serial number first); `tiiildd..` goes on the
//   bus as another node's frame (Board::sendCan, through the MCAN's filters) and is answered "z\r"; any other
//   line with BEL. While the channel is open (O), every frame the image sends comes back as a `t` line.
// Simulated time is the twin's: the caller runs the board and calls service() between runs.
#pragma once

#include <cstddef>
#include <string>

#include "board/board.hpp"

namespace twin {

class CommandPty {
 public:
  explicit CommandPty(Board& board) : board_(board) {}
  ~CommandPty();
  CommandPty(const CommandPty&) = delete;
  CommandPty& operator=(const CommandPty&) = delete;

  bool open(std::string& error);
  const std::string& path() const { return path_; }
  int fd() const { return master_; }  // for poll()
  // Takes what the program wrote onto the link, and hands it what the image sent since the last call.
  void service();
  // Bytes still travelling to the image (L1306).
  bool inFlight() const { return board_.serialBacklog() != 0; }

 private:
  void adapterLine(const std::string& line);  // G3507: one Lawicel command
  void toHost(const std::string& text);

  Board& board_;
  int master_ = -1, slave_ = -1;
  std::string path_;
  std::string line_;   // G3507: the command being received
  bool open_ = false;  // G3507: the adapter's channel
  size_t linesSent_ = 0, framesSent_ = 0;
  std::string out_;
};

}  // namespace twin
