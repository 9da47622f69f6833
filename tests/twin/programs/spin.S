/* A busy loop for the interpreter's speed: 5 instructions x 1 000 000 iterations, then mark 0xFF. */
  .syntax unified
  .cpu cortex-m0plus
  .thumb
  .equ PROBE, 0x40000000

  .section .vectors, "a"
  .word __stack_top__
  .word reset

  .text
  .thumb_func
reset:
  ldr r7, =PROBE
  ldr r1, =1000000
loop:
  adds r2, r2, #1
  eors r3, r2
  lsls r4, r3, #3
  subs r1, #1
  bne loop
  movs r0, #0xFF
  str r0, [r7]
  b .
