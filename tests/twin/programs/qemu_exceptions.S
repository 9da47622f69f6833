/* Exceptions, NVIC, PRIMASK/CONTROL, BX/BLX and faults, for the twin and QEMU's Cortex-M0 machine (microbit)
 * to run alike (tests/twin/core_qemu_test.cpp): every observation goes to a log in RAM (the LOG macro), which
 * the program writes to QEMU's semihosting console at `done` and the twin's test reads from SRAM. Each step
 * records what ARM DDI 0419E says the core does; the two runs must agree word for word.
 *
 * Memory (the microbit's nRF51 and the twin's test machine alike): flash at 0, 16 KiB RAM at 0x20000000.
 * Log at 0x20000000 (LOGPTR keeps its end), process stack 0x20003000, main stack top 0x20004000. */
  .syntax unified
  .cpu cortex-m0
  .thumb
  .equ LOG, 0x20000000
  .equ LOGPTR, 0x20002F00
  .equ SCRATCH, 0x20002E00
  .equ PSP_TOP, 0x20003000
  .equ NVIC_ISER, 0xE000E100
  .equ NVIC_ICER, 0xE000E180
  .equ NVIC_ISPR, 0xE000E200
  .equ NVIC_IPR0, 0xE000E400
  .equ ICSR, 0xE000ED04
  .equ SHPR2, 0xE000ED1C
  .equ SHPR3, 0xE000ED20
  .equ ICSR_RETTOBASE, 0x800  /* reserved on ARMv6-M (B3.2.4); QEMU sets it as on ARMv7-M: masked out */

/* log r0 (clobbers r1, r2) */
.macro LOG0
  ldr r2, =LOGPTR
  ldr r1, [r2]
  str r0, [r1]
  adds r1, #4
  str r1, [r2]
.endm
/* log a constant marker */
.macro MARK value
  ldr r0, =\value
  LOG0
.endm

  .section .vectors, "a"
  .word 0x20004000
  .word reset
  .word 0          /* NMI */
  .word hardfault
  .rept 7
  .word 0
  .endr
  .word svcall     /* 11 */
  .word 0
  .word 0
  .word pendsv     /* 14 */
  .word systick    /* 15 */
  .word irq0       /* 16 */
  .word irq1       /* 17 */
  .word irq2       /* 18 */

  .text
  .thumb_func
  .global reset
reset:
  ldr r0, =LOGPTR
  ldr r1, =LOG
  str r1, [r0]
  MARK 0x1000

  /* 1: SVC from Thread on MSP: the handler logs IPSR, EXC_RETURN, CONTROL, PRIMASK and the stacked frame
   * (B1.5.6 PushStack: r0-r3, r12, LR, the return address after the SVC, xPSR; EXC_RETURN 0xFFFFFFF9, B1.5.8). */
  movs r0, #0x10
  movs r1, #0x11
  movs r2, #0x12
  movs r3, #0x13
  mov r12, r3
  svc #7
  MARK 0x1001

  /* 2: PendSV pended through ICSR.PENDSVSET (B3.2.4), taken at once (B1.5.2). */
  ldr r0, =ICSR
  movs r1, #1
  lsls r1, r1, #28
  str r1, [r0]
  MARK 0x1002

  /* 2b: SysTick and PendSV pended together through ICSR (PENDSTSET, PENDSVSET; B3.2.4) with PRIMASK set: ICSR
   * shows both pending and VECTPENDING the one to be taken first; CPSIE takes them in priority order, the
   * second when the first returns (B1.5.4: the lower priority value first; at equal values the lower
   * exception number, PendSV 14 before SysTick 15). Priorities: SHPR3 (B3.2.10). First SysTick 0x40 and
   * PendSV 0x80, then both 0x80. */
  ldr r0, =SHPR3
  ldr r1, =0x40800000
  str r1, [r0]
  bl pend_both
  ldr r0, =SHPR3
  ldr r1, =0x80800000
  str r1, [r0]
  bl pend_both
  MARK 0x1102

  /* 3: nesting: IRQ0 at priority 0xC0, IRQ1 0x40, IRQ2 0xC0; IRQ0 pends IRQ1 (preempts, EXC_RETURN
   * 0xFFFFFFF1) and IRQ2 (same priority: waits for IRQ0's return, then is taken before Thread resumes).
   * B1.5.4 preemption by priority; NVIC_IPR/ISER/ISPR B3.4; EXC_RETURN B1.5.8. */
  ldr r0, =NVIC_IPR0
  ldr r1, =0x00C040C0
  str r1, [r0]
  ldr r0, =NVIC_ISER
  movs r1, #7
  str r1, [r0]
  ldr r0, =NVIC_ISPR
  movs r1, #1
  str r1, [r0]
  MARK 0x1003

  /* 4: PRIMASK holds a pended IRQ0 (B1.4.3); ISPR shows it (B3.4.5); WFI returns at once, the pending
   * interrupt would preempt if PRIMASK were 0 (B1.5.19); CPSIE takes it. */
  cpsid i
  ldr r0, =NVIC_ISPR
  movs r1, #1
  str r1, [r0]
  ldr r0, [r0]
  LOG0
  mrs r0, primask
  LOG0
  wfi
  MARK 0x1004
  cpsie i
  MARK 0x1005

  /* 5: Thread on the process stack (CONTROL.SPSEL, B1.4.4): SVC's frame goes to PSP, EXC_RETURN
   * 0xFFFFFFFD (B1.5.8), MSP untouched; the handler runs on MSP (B1.5.6). */
  ldr r0, =PSP_TOP
  msr psp, r0
  movs r0, #2
  msr control, r0
  isb
  mrs r0, control
  LOG0
  mov r0, sp           /* SP is now PSP */
  LOG0
  movs r0, #0x20
  svc #1
  mrs r0, psp
  LOG0
  movs r0, #0
  msr control, r0
  isb
  mrs r0, control
  LOG0

  /* 6: an SP that is 4 mod 8: the frame is aligned down and the stacked xPSR bit 9 says so; SP comes back
   * unchanged (B1.5.7 stack alignment, B1.5.6 PushStack, B1.5.8 PopStack). */
  mov r4, sp
  subs r4, #4
  mov sp, r4
  movs r0, #0x30
  svc #2
  mov r0, sp
  LOG0
  adds r4, #4
  mov sp, r4

  /* 7: BLX to a Thumb function (LR = return | 1), BX back (A6.7 BLX/BX, BXWritePC A2.3.1); BX to an odd
   * address; MOV PC (ALUWritePC: bit 0 ignored). */
  ldr r3, =callee
  blx r3
  LOG0                 /* callee left its LR in r0 */
  adr r3, 1f
  adds r3, #1
  bx r3
  MARK 0xDEAD          /* skipped */
  .align 2
1:
  MARK 0x1007
  adr r3, 2f
  mov pc, r3
  MARK 0xDEAD
  .align 2
2:
  MARK 0x1008

  /* 8: faults (B1.5.13; HardFault only on ARMv6-M): an unaligned LDR (A3.2.1), UDF (UNDEFINED), a BX to an
   * even address (EPSR.T = 0: the target faults, B1.4.2), BKPT without a debugger (C1.7), an SVC with
   * PRIMASK set (escalation, B1.5.6). The HardFault handler logs the stacked PC and xPSR and moves the PC
   * past the faulting instruction (2 bytes; for INVSTATE to the instruction after the BX). */
  ldr r0, =SCRATCH + 1
unaligned:
  ldr r1, [r0]
  MARK 0x1009
undefined:
  udf #0x42
  MARK 0x100A
  ldr r3, =thumbless
branch:
  bx r3                /* bit 0 clear: INVSTATE at the target */
  MARK 0x100B
breakpoint:
  bkpt 0x12
  MARK 0x100C
  cpsid i
svc_masked:
  svc #3               /* SVC cannot be taken with PRIMASK set: escalates to HardFault (B1.5.6) */
svc_after:
  cpsie i              /* the escalated SVC returns here, after the SVC (see hardfault) */
  mrs r0, primask
  LOG0
  MARK 0x100D

  /* 9: priorities read back with the implemented bits only (2 on Cortex-M0: B3.2.9 SHPR2, B3.4.7 IPR);
   * ICER clears the enables ISER shows (B3.4.3, B3.4.4). */
  ldr r0, =SHPR2
  ldr r1, =0xFFFFFFFF
  str r1, [r0]
  ldr r0, [r0]
  LOG0
  ldr r0, =NVIC_IPR0
  ldr r0, [r0]
  LOG0
  ldr r0, =NVIC_ISER
  ldr r0, [r0]
  LOG0
  ldr r0, =NVIC_ICER
  movs r1, #7
  str r1, [r0]
  ldr r0, =NVIC_ISER
  ldr r0, [r0]
  LOG0
  /* 10: the registers at the exit: APSR (flags of the last CMP: r0 = 0 vs 1 gives N), PRIMASK, CONTROL, MSP,
   * PSP, LR, and r8-r12, which no handler touches (B1.5.6/B1.5.8: the frame restores r0-r3, r12, LR, PC and
   * xPSR only, the rest are callee-saved). */
  movs r0, #0
  cmp r0, #1
  mrs r0, apsr
  LOG0
  mrs r0, primask
  LOG0
  mrs r0, control
  LOG0
  mrs r0, msp
  LOG0
  mrs r0, psp
  LOG0
  mov r0, lr
  LOG0
  mov r0, r8
  LOG0
  mov r0, r9
  LOG0
  mov r0, r10
  LOG0
  mov r0, r11
  LOG0
  mov r0, r12
  LOG0
  MARK 0x10FF
  .global done
done:
  /* semihosting: SYS_OPEN(":tt", "wb"), SYS_WRITE the log, SYS_EXIT */
  movs r0, #1
  adr r1, openblock
  bkpt 0xab
  ldr r2, =0x20003F00
  str r0, [r2]
  ldr r1, =LOG
  str r1, [r2, #4]
  ldr r1, =0x800
  str r1, [r2, #8]
  movs r0, #5
  mov r1, r2
  bkpt 0xab
  movs r0, #0x18
  ldr r1, =0x20026
  bkpt 0xab
  b .
  .ltorg
  .align 2
openblock:
  .word tty
  .word 5
  .word 3
tty:
  .asciz ":tt"
  .align 1

  .thumb_func
callee:
  mov r0, lr
  bx lr

  .thumb_func
pend_both:              /* pends SysTick and PendSV with PRIMASK set, logs ICSR, then lets them run */
  push {lr}
  cpsid i
  ldr r0, =ICSR
  ldr r1, =0x14000000  /* PENDSVSET | PENDSTSET */
  str r1, [r0]
  ldr r0, [r0]
  ldr r1, =ICSR_RETTOBASE
  bics r0, r1
  LOG0
  cpsie i
  MARK 0x1200
  pop {pc}

  .align 2
thumbless:
  nop                  /* reached with EPSR.T = 0: never executes */
  nop

/* --- handlers --------------------------------------------------------------------------------------------- */
/* Log IPSR, EXC_RETURN, CONTROL, PRIMASK, the SP the frame is on, and the eight frame words. */
  .thumb_func
frame_log:              /* r4 = EXC_RETURN, r5 = frame address */
  push {lr}
  mrs r0, ipsr
  LOG0
  mov r0, r4
  LOG0
  mrs r0, control
  LOG0
  mrs r0, primask
  LOG0
  mov r0, r5
  LOG0
  movs r6, #0
3:
  ldr r0, [r5, r6]
  LOG0
  adds r6, #4
  cmp r6, #32
  bne 3b
  pop {pc}

  .thumb_func
svcall:                 /* r4-r6 are the Thread's: saved, and the return is a POP of EXC_RETURN into PC */
  push {r4, r5, r6, lr}
  mov r4, lr
  mrs r5, msp
  adds r5, #16
  movs r0, #4
  tst r4, r0
  beq 4f
  mrs r5, psp
4:
  bl frame_log
  pop {r4, r5, r6, pc}

  .thumb_func
pendsv:
  push {r4, r5, r6, lr}
  mov r4, lr
  mrs r5, msp
  adds r5, #16
  bl frame_log
  pop {r4, r5, r6, pc}

  .thumb_func
systick:
  push {r4, lr}
  mov r4, lr
  MARK 0x2400
  mrs r0, ipsr
  LOG0
  mov r0, r4
  LOG0
  pop {r4, pc}

  .thumb_func
irq0:
  push {r4, lr}
  mov r4, lr
  MARK 0x2000
  mov r0, r4
  LOG0
  ldr r0, =NVIC_ISPR
  movs r1, #6          /* IRQ1 preempts, IRQ2 waits */
  str r1, [r0]
  MARK 0x2001
  ldr r0, =ICSR        /* VECTACTIVE 16, IRQ2 pending: VECTPENDING 18, ISRPENDING (B3.2.4) */
  ldr r0, [r0]
  ldr r1, =ICSR_RETTOBASE
  bics r0, r1
  LOG0
  pop {r4, pc}

  .thumb_func
irq1:                   /* returns with BX LR */
  mov r3, lr
  MARK 0x2100
  mov r0, r3
  LOG0
  mrs r0, ipsr
  LOG0
  bx r3

  .thumb_func
irq2:
  push {r4, lr}
  mov r4, lr
  MARK 0x2200
  mov r0, r4
  LOG0
  pop {r4, pc}

  .thumb_func
hardfault:
  push {r4, r5, r6, lr}
  mov r4, lr
  mrs r5, msp
  adds r5, #16
  MARK 0x3000
  ldr r0, [r5, #24]    /* stacked PC */
  LOG0
  ldr r0, [r5, #28]    /* stacked xPSR */
  LOG0
  mrs r0, ipsr
  LOG0
  mov r0, r4
  LOG0
  ldr r0, [r5, #24]
  ldr r1, =svc_after   /* an escalated SVC already returns after itself */
  cmp r0, r1
  beq 6f
  ldr r1, =thumbless
  cmp r0, r1
  bne 5f
  ldr r0, =branch      /* INVSTATE: go on after the BX */
5:
  adds r0, #2
  str r0, [r5, #24]
6:
  ldr r0, [r5, #28]    /* EPSR.T back on (an INVSTATE frame has it clear) */
  movs r1, #1
  lsls r1, r1, #24
  orrs r0, r1
  str r0, [r5, #28]
  pop {r4, r5, r6, pc}
