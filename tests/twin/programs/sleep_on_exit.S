/* Sleep-on-exit on the twin's core (ARMv6-M ARM DDI 0419E B3.2.7, SCR.SLEEPONEXIT: "on an exit from an ISR
 * that returns to the base level of execution priority, the processor enters a sleep state"; TI's MSPM0 SDK
 * sets the same bit with DL_SYSCTL_enableSleepOnExit in its low-power examples). The probe at 0x40000000
 * logs marks (+0) and sets NVIC input levels (+4). SysTick is the wake-up that clears the bit.
 * Expected marks: 0x10 0x20 | 0x30 0x11 | 0x12 0x40 0x41 | 0x31 0x13 0xFF (| the Thread's sleeps)
 *   - IRQ0 returns to Thread with the bit set: the Thread sleeps (0x11 only after SysTick cleared it);
 *   - IRQ1 preempting IRQ0 returns to Handler mode: no sleep there (0x41 at once), IRQ0's return sleeps. */
  .syntax unified
  .cpu cortex-m0plus
  .thumb

  .equ PROBE, 0x40000000
  .equ NVIC_ISER, 0xE000E100
  .equ NVIC_IPR0, 0xE000E400
  .equ SCR, 0xE000ED10
  .equ SYST_CSR, 0xE000E010
  .equ SYST_RVR, 0xE000E014
  .equ SYST_CVR, 0xE000E018

  .section .vectors, "a"
  .word __stack_top__
  .word reset
  .rept 13
  .word fault
  .endr
  .word systick         /* 15: SysTick */
  .word irq0            /* IRQ 0 */
  .word irq1            /* IRQ 1 */

  .text
  .thumb_func
reset:
  ldr r7, =PROBE
  ldr r6, =SCR
  ldr r0, =NVIC_IPR0    /* IRQ0 priority 2 (0x80), IRQ1 priority 1 (0x40) */
  ldr r1, =0x00004080
  str r1, [r0]
  ldr r0, =NVIC_ISER
  movs r1, #3
  str r1, [r0]

  /* 1: IRQ0 returns to Thread mode with SLEEPONEXIT: the Thread sleeps until SysTick clears the bit. */
  movs r0, #0x10
  str r0, [r7]
  movs r0, #2
  str r0, [r6]          /* SCR.SLEEPONEXIT */
  bl start_systick
  movs r0, #1
  str r0, [r7, #4]      /* raise IRQ0 */
  movs r0, #0x11
  str r0, [r7]

  /* 2: a return to Handler mode does not sleep; the return to Thread does. */
  movs r0, #0x12
  str r0, [r7]
  movs r0, #2
  str r0, [r6]
  bl start_systick
  movs r0, #1
  str r0, [r7, #4]      /* raise IRQ0; it raises IRQ1 */
  movs r0, #0x13
  str r0, [r7]
  movs r0, #0xFF
  str r0, [r7]
  b .

  .thumb_func
start_systick:
  ldr r1, =SYST_RVR
  ldr r0, =2000
  str r0, [r1]
  ldr r1, =SYST_CVR
  str r0, [r1]          /* any write clears the counter */
  ldr r1, =SYST_CSR
  movs r0, #7           /* CLKSOURCE processor clock, TICKINT, ENABLE */
  str r0, [r1]
  bx lr

  .thumb_func
irq0:
  ldr r1, [r7, #12]     /* scratch: 0 in part 1, 1 in part 2 */
  cmp r1, #0
  bne 1f
  movs r0, #0x20
  str r0, [r7]
  movs r0, #0
  str r0, [r7, #4]      /* drop the level */
  movs r0, #1
  str r0, [r7, #12]
  bx lr
1:
  movs r0, #0
  str r0, [r7, #4]
  movs r0, #2
  str r0, [r7, #4]      /* raise IRQ1: it preempts */
  movs r0, #0x41
  str r0, [r7]
  bx lr

  .thumb_func
irq1:
  movs r0, #0x40
  str r0, [r7]
  movs r0, #0
  str r0, [r7, #4]
  bx lr

  .thumb_func
systick:
  ldr r1, [r7, #12]
  movs r0, #0x30
  adds r0, r0, r1
  subs r0, r0, #1       /* 0x30 the first time, 0x31 the second */
  str r0, [r7]
  adds r1, #1
  str r1, [r7, #12]
  movs r0, #0
  str r0, [r6]          /* SCR = 0: the Thread resumes at this return */
  ldr r1, =SYST_CSR
  str r0, [r1]
  bx lr

  .thumb_func
fault:
  movs r0, #0xEE
  str r0, [r7]
  b .
