// A pseudo-terminal for the twin's serial ports (the ROM bootloader's UART, an image's command link): the
// master side the twin reads and writes without blocking, and the twin's own hold on the slave side, raw at
// `speed`, so a program (bmsctl) may open and close the path any number of times.
#pragma once

#include <string>

#include <termios.h>

namespace twin {

// Opens both sides into `master` and `slave` and names the slave's `path`; false with `error` set otherwise
// (the caller closes whichever descriptor is not -1).
bool openRawPty(speed_t speed, int& master, int& slave, std::string& path, std::string& error);

}  // namespace twin
