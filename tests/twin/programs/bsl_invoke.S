/* The software invoke of the ROM bootloader as bsp/mspm0 requestBootloaderEntry() makes it: SYSCTL
   RESETLEVEL (0x400B0300) = 2 (BOOTLOADERENTRY), then RESETCMD (0x400B0304) = KEY 0xE4 | GO. */
  .syntax unified
  .cpu cortex-m0plus
  .thumb

  .section .vectors, "a"
  .word __stack_top__
  .word reset

  .text
  .thumb_func
reset:
  ldr r0, =0x400B0300
  movs r1, #2
  str r1, [r0]
  ldr r1, =0xE4000001
  str r1, [r0, #4]
  b .
