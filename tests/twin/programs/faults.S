/* Faults on the twin's core (DDI 0419E B1.5.13, A3.2.1, B1.4.2): an unaligned load, an undefined instruction
 * and a BX to an address with bit 0 clear each raise HardFault with the faulting instruction as the stacked
 * return address. The handler marks the stacked PC and steps over the instruction. */
  .syntax unified
  .cpu cortex-m0plus
  .thumb
  .equ PROBE, 0x40000000

  .section .vectors, "a"
  .word __stack_top__
  .word reset
  .word nmi
  .word hardfault

  .text
  .thumb_func
reset:
  ldr r7, =PROBE
  ldr r1, =0x20000001
  .global unaligned
unaligned:
  ldr r0, [r1]          /* unaligned word load: HardFault */
  .global undefined
undefined:
  udf #7                /* permanently undefined: HardFault */
  ldr r2, =even
  .global branch
branch:
  bx r2                 /* bit 0 clear: INVSTATE, HardFault */
even:
  movs r0, #0xFF
  str r0, [r7]
  b .

  .thumb_func
hardfault:
  ldr r0, [sp, #24]     /* stacked return address */
  str r0, [r7]
  adds r0, #2           /* every faulting instruction here is 16 bits */
  str r0, [sp, #24]
  bx lr

  .thumb_func
nmi:
  b .
