/* Exception entry and return on the twin's core (ARMv6-M ARM DDI 0419E B1.5). The probe device at
 * 0x40000000 logs every word written to +0 (MARK), sets NVIC input levels with +4 (LEVEL, one bit per IRQ)
 * and reads the cycle count at +8. Each handler writes a mark; the test compares the marks with the order
 * the architecture prescribes. */
  .syntax unified
  .cpu cortex-m0plus
  .thumb

  .equ PROBE, 0x40000000
  .equ NVIC_ISER, 0xE000E100
  .equ NVIC_IPR0, 0xE000E400

  .section .vectors, "a"
  .word __stack_top__
  .word reset
  .rept 14
  .word fault
  .endr
  .word irq0            /* IRQ 0 */
  .word irq1            /* IRQ 1 */
  .word irq2            /* IRQ 2 */

  .text
  .thumb_func
reset:
  ldr r7, =PROBE
  /* priorities: IRQ0 = 2 (0x80), IRQ1 = 1 (0x40), IRQ2 = 2 (0x80) */
  ldr r0, =NVIC_IPR0
  ldr r1, =0x00804080
  str r1, [r0]
  ldr r0, =NVIC_ISER
  movs r1, #7
  str r1, [r0]

  /* 1: IRQ0 runs at once; inside it IRQ1 (more urgent) preempts, IRQ2 (same priority) waits: 0x10 0x11
   * 0x1F 0x01 0x20. */
  movs r0, #0x10
  str r0, [r7]
  movs r0, #1
  str r0, [r7, #4]      /* raise IRQ0 */
  movs r0, #0x1F
  str r0, [r7]

  /* 2: PRIMASK holds a pending interrupt; WFI wakes without taking it; CPSIE takes it. */
  cpsid i
  movs r0, #4           /* IRQ2 */
  str r0, [r7, #4]
  movs r0, #0x30
  str r0, [r7]
  wfi
  movs r0, #0x31
  str r0, [r7]
  cpsie i
  movs r0, #0x32
  str r0, [r7]

  /* 3: an odd stack pointer (SP[2] = 1) is aligned on entry and restored on return. */
  sub sp, sp, #4
  mov r6, sp
  movs r0, #1
  str r0, [r7, #4]
  mov r0, sp
  subs r0, r0, r6       /* 0 if SP came back */
  adds r0, #0x40
  str r0, [r7]
  add sp, sp, #4

  /* 4: a level still asserted when the handler returns enters it again (irq2 drops it the second time). */
  movs r0, #0
  str r0, [r7, #12]     /* counter for irq2 */
  movs r0, #4
  str r0, [r7, #4]
  movs r0, #0x50
  str r0, [r7]
  movs r0, #0xFF
  str r0, [r7]
  b .

  .thumb_func
irq0:
  push {r4, lr}
  movs r0, #0x11
  str r0, [r7]
  mov r4, sp
  /* EXC_RETURN in LR: returning to Thread mode on the main stack */
  mov r0, lr
  str r0, [r7]
  movs r0, #0x06        /* raise IRQ1 and IRQ2 while IRQ0 is active (IRQ0 stays raised, bit 0) */
  str r0, [r7, #4]
  movs r0, #0           /* drop every level */
  str r0, [r7, #4]
  movs r0, #0x12
  str r0, [r7]
  pop {r4, pc}

  .thumb_func
irq1:
  movs r0, #0x01
  str r0, [r7]
  mov r0, lr            /* nested: EXC_RETURN to Handler mode */
  str r0, [r7]
  movs r0, #0x04        /* drop its own level (and IRQ0's), keep IRQ2 raised */
  str r0, [r7, #4]
  bx lr

  .thumb_func
irq2:
  ldr r1, [r7, #12]
  adds r1, #1
  str r1, [r7, #12]
  movs r0, #0x20
  adds r0, r0, r1
  str r0, [r7]
  cmp r1, #2
  bne 1f
  movs r0, #0
  str r0, [r7, #4]      /* the second entry drops the level */
1:
  bx lr

  .thumb_func
fault:
  movs r0, #0xEE
  str r0, [r7]
  b .
