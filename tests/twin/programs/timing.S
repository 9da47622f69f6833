/* Cycle counts on the twin's core against ARM DDI 0484C Table 3-1 (Cortex-M0+) and the 15-cycle interrupt
 * latency. The probe's +8 reads the cycle count at the start of the reading instruction; each mark below is
 * the difference between two such reads. */
  .syntax unified
  .cpu cortex-m0plus
  .thumb
  .equ PROBE, 0x40000000
  .equ NVIC_ISER, 0xE000E100

  .section .vectors, "a"
  .word __stack_top__
  .word reset
  .rept 14
  .word 0
  .endr
  .word irq0

  .text
  .thumb_func
reset:
  ldr r7, =PROBE
  ldr r0, =NVIC_ISER
  movs r1, #1
  str r1, [r0]
  /* A: LDR (2) + 3 x NOP (3) + ADDS (1) + MULS (1) + B (2) = 9 */
  ldr r5, [r7, #8]
  nop
  nop
  nop
  adds r1, r1, #1
  muls r1, r1, r1
  b 1f
1:
  ldr r6, [r7, #8]
  subs r0, r6, r5
  str r0, [r7]
  /* B: LDR (2) + PUSH {r4-r6, lr} (1 + 4) + POP {r4-r6} (1 + 3) + MOVS (1) + BEQ not taken (1) + BNE taken (2) = 15 */
  ldr r5, [r7, #8]
  push {r4, r5, r6, lr}
  pop {r4, r5, r6}
  movs r0, #1
  beq 2f
  bne 2f
2:
  ldr r6, [r7, #8]
  subs r0, r6, r5
  str r0, [r7]
  add sp, #4
  /* C: LDR (2) + BL (3) + [in f: BX LR (2)] = 7 */
  ldr r5, [r7, #8]
  bl f
  ldr r6, [r7, #8]
  subs r0, r6, r5
  str r0, [r7]
  /* D: interrupt latency: the STR that raises IRQ0 (2) + entry (15) = 17 from its start to the handler's first
   * instruction. */
  ldr r5, [r7, #8]
  movs r0, #1
  str r0, [r7, #4]
  /* E: the handler's return: from its BX LR to the next Thread instruction, BX (2) + frame pop (11) = 13 */
  ldr r6, [r7, #8]
  ldr r1, [r7, #12]     /* the handler left its BX LR time here */
  subs r0, r6, r1
  str r0, [r7]
  movs r0, #0xFF
  str r0, [r7]
  b .

  .thumb_func
f:
  bx lr

  .thumb_func
irq0:
  ldr r6, [r7, #8]      /* first instruction of the handler */
  subs r0, r6, r5
  subs r0, #3           /* the LDR and MOVS before the STR */
  str r0, [r7]
  movs r0, #0
  str r0, [r7, #4]
  ldr r0, [r7, #8]
  adds r0, #2           /* the BX LR below starts after this LDR (2), */
  adds r0, #4           /* these two ADDS (1 + 1) and the STR (2) */
  str r0, [r7, #12]
  bx lr
