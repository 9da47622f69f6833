/* Faults on the twin's core (DDI 0419E B1.5.13, A3.2.1, B1.4.2): an unaligned load and an undefined instruction
 * raise HardFault with the faulting instruction as the stacked return address; a BX to an address with bit 0
 * clear branches with EPSR.T = 0 and the instruction at the target faults (INVSTATE): the stacked return
 * address is the target and the stacked xPSR has T clear (QEMU's Cortex-M0 does the same,
 * core_qemu_test.cpp). The handler marks the stacked PC, steps over the instruction and sets T again. */
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
  bx r2                 /* bit 0 clear: INVSTATE at the target, HardFault */
  .global even
  .align 1
even:
  nop                   /* never executes (T = 0); the handler resumes after it */
  movs r0, #0xFF
  str r0, [r7]
  b .

  .thumb_func
hardfault:
  ldr r0, [sp, #24]     /* stacked return address */
  str r0, [r7]
  adds r0, #2           /* every faulting instruction here is 16 bits */
  str r0, [sp, #24]
  ldr r0, [sp, #28]     /* stacked xPSR: EPSR.T on again */
  movs r1, #1
  lsls r1, r1, #24
  orrs r0, r1
  str r0, [sp, #28]
  bx lr

  .thumb_func
nmi:
  b .
