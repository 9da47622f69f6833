// `bmsctl flash`: program a LaunchPad through the MSPM0 ROM bootloader (BSL) over its USB serial port.
//
//   bmsctl flash IMAGE --port DEV [--chip mspm0l1306|mspm0g3507|auto] [--baud 9600|19200|...|115200|1000000]
//                [--password FILE] [--invoke button|app|none] [--invoke-port DEV] [--node N] [--wait S]
//                [--verify-only]
//
// IMAGE is the build's .elf, .hex or .bin (flash_image.hpp). What it does, in order: refuses an image with a
// byte outside MAIN flash (it never writes NONMAIN and never sends Factory Reset); invokes the BSL as asked;
// Connection; Get Device Info (the part, from its buffer size: chips.hpp; the packet size); Change Baud Rate
// to --baud; Unlock (32-byte password, all 0xFF unless --password: a file of 32 raw bytes or 64 hex digits);
// Flash Range Erase of the image's sectors only; Program Data in packets of at most min(4096, buffer - 12)
// bytes, the word with the reset vector last; Standalone Verification of every erased sector against the CRC
// the image gives; Start Application. --verify-only does the verification alone.
//
// Output: progress (bytes, percentage, rate) on stderr when it is a terminal; one summary line on stdout at
// the end; "bmsctl: warning: ..." for a recovered fault; every failure one "bmsctl: error: ..." line on
// stderr and its own exit status:
namespace bmsctl::flash {

enum class FlashExit : int {
  Ok = 0,
  Failed = 1,           // an error none of the below covers (e.g. writing to the port failed)
  Usage = 2,            // bad arguments
  ImageUnreadable = 3,  // the file cannot be read or parsed (file:line:col for HEX)
  OutOfRange = 4,       // a byte outside MAIN flash or in reserved flash; or the BSL said MSG 0x05
  WrongChip = 5,        // the image, --chip and the device do not name the same part
  PortMissing = 6,      // the port does not exist or is not a serial port
  PortBusy = 7,         // another program has the port
  NoAnswer = 8,         // the BSL never acknowledged Connection (the message gives the invoke procedure)
  WrongPassword = 9,    // MSG 0x02; never retried
  Locked = 10,          // MSG 0x01 (or 0x03: the security alert after the third wrong password)
  CrcMismatch = 11,     // a verification window's CRC differs from the image's (the message names it)
  TransferError = 12,   // the line lost packets or replies beyond what retrying recovers
  FlashFailed = 13,     // the BSL reported an erase or program failure
  InvokeFailed = 14,    // --invoke app: the image did not take the bootloader-entry command
  PortPermission = 15,  // the port may not be opened (not in its group, usually dialout)
};

// argv after "flash"; returns the process exit status.
int runFlash(int argc, char** argv);

}  // namespace bmsctl::flash
