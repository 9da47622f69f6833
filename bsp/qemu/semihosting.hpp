// ARM semihosting for tests under QEMU (-semihosting-config enable=on,target=native): print text and exit
// with a status code that becomes QEMU's own exit code. On M-profile a semihosting call is BKPT 0xAB with the
// operation in r0 and its argument in r1. Only for the QEMU test BSP: on real hardware without a debugger
// attached, BKPT would fault.
#pragma once

#include <cstdint>

namespace bsp::qemu {

void print(const char* text);
void printUnsigned(uint32_t value);
void printHex(uint32_t value);
[[noreturn]] void exit(int status);

}  // namespace bsp::qemu
