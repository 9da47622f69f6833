// Rules: what the twin checks that silicon would get wrong without a word, each with its TI source (or the
// standard's), so a violation names the rule, the document and the place in the image.
//
// A rule either stops the run (the part would fail: the device or the bus partner misreads the wire, an input
// reads 0, an update is lost) or warns (the part would only degrade: a CAN sample point away from the bus's
// recommendation). The message of a stop is "[<id>] <peripheral>: <what> (<source>) (PC 0x... in <function>)"
// like every other reason the twin stops (Machine::stop); a warning has the same form and is kept in
// Machine::ruleWarnings() (bms-sim --json twin_warnings).
//
// The table (bsp/twin/README.md "Rules" lists the same):
//   WIRE-UART-FRAME   UART LCRH frame (WLEN, PEN) against the link partner's (8N1 for the BQ79616: SLUSE81E
//                     DEV_CONF, one stop bit unless TWO_STOP_EN; TI's BQ79616 example ti_msp_dl_config.c
//                     configures 8 data bits, no parity, one stop bit;
//                     8N1 for the XDS110 back-channel the PC opens): a frame of another length or with a
//                     parity bit is misread by the partner and the partner's by the MSPM0 (hw_uart.h LCRH)
//   WIRE-UART-BAUD    UART baud (BUSCLK / CLKDIV / (oversampling x (IBRD + FBRD/64))) against the link
//                     partner's rate within the tolerance the receiver allows (BQ79616: SLUSE81E "UART RX
//                     baud rate error" +-1 %; XDS110 back-channel: half the 16x sampling margin, computed)
//   WIRE-I2C-SCL      SCL = f_func / ((1 + TPR) x 10) inside the addressed device's range (BQ76952 / BQ7690x
//                     SLUSE13B 14: up to 400 kHz; BQ4050 SMBus 10..100 kHz, SLUSC67A)
//   WIRE-I2C-TPR      the controller's own limits: MTPR.TPR 1..127 (hw_i2c.h MTPR) and SCL <= 1 MHz
//                     (Fast-mode Plus, SLAU846B 20.1 / SLAU847D 21.1)
//   WIRE-CAN-BITRATE  MCAN nominal bit rate (CANCLK / MCANSS_CLKDIV / (NBRP + 1) / (3 + NTSEG1 +
//                     NTSEG2)) equal to the bus's within the oscillator tolerance its own bit timing allows
//                     (ISO 11898-1 bit timing; df = min(PS1, PS2) / (2 (13 NBT - PS2)), SJW / (20 NBT))
//   WIRE-CAN-SAMPLE   (warns) sample point within 5 points of 87.5 % (CiA 301 / the TI example's 87.5 %)
//   WIRE-HFXT-RANGE   HFCLKCLKCFG.HFXTRSEL selects the crystal's range when HFXTEN starts it (hw_sysctl
//                     HFXTRSEL: 32..48 MHz = 3 for the LaunchPad's 40 MHz)
//   PIN-INENA         every input function's pin has IOMUX PINCM.INENA (hw_iomux.h "Input Enable Control";
//                     SLAU846B / SLAU847D IOMUX: without it the input reads 0): UART RX, CAN RX, I2C SDA and
//                     SCL, GPIO edge inputs
//   IDLE-WFI          WFI in Thread mode only with PRIMASK set (the idle rule of firmware/hal/irq.hpp: an
//                     interrupt between the last ready check and WFI is otherwise slept through; DDI 0419E
//                     B1.5.19: WFI wakes on a pending interrupt with PRIMASK set)
//   RACE-ISR-RMW      a Thread-mode read-modify-write of RAM that a handler also writes, outside a critical
//                     section (PRIMASK), while that handler can run for the sources that led it to write
//                     (DDI 0419E B1.5: an exception can preempt between the load and the store)
//   I2C-CLKSTRETCH    a target stretches SCL on any byte with MCR.CLKSTRETCH clear (hw_i2c.h MCR.CLKSTRETCH:
//                     the controller then does not detect the stretch); and a device documented to stretch
//                     (I2c::TargetRange::stretchSource: BQ76952 SLUUBY2B 9 and TI's bq769x2_control_i2c
//                     example, BQ4050 SMBus tLOW:SEXT) addressed with CLKSTRETCH clear, stretch or not
//   I2C-FLUSH         MFIFOCTL.TXFLUSH/RXFLUSH held as TI describes: while set the FIFO is flushed (a byte
//                     written or a burst started then is lost), and cleared only after MFIFOSR showed the
//                     flush complete (hw_i2c.h MFIFOCTL "Before clearing this bit to stop Flush the TXFIFOCNT
//                     should be checked to be 8"; DL_I2C_flushControllerTXFIFO waits the same way)
//   I2C-READ-NACK     a controller read burst that ends with STOP has MCTR.ACK clear: the last byte is NACKed
//                     (UM10204 3.1.6: the controller-receiver signals the end of the transfer with a NACK
//                     before STOP; SLUSE13B I2C read figure: the last data byte, NACK, Stop; hw_i2c.h
//                     MCTR.ACK); an ACKed last byte leaves the target driving SDA for the next one, and the
//                     STOP can fail
//   KEY-WRITE         (warns) a keyed register written without its key: the part ignores the write
//                     (GPRCM.PWREN 0x26, GPRCM.RSTCTL 0xB1 in every hw_*.h; SYSCTL SYSOSCFCLCTL 0x2A and
//                     RESETCMD 0xE4 in hw_sysctl; WWDTCTL0 0xC9 / WWDTCTL1 0xBE in hw_wwdt.h; TI's driverlib
//                     writes each key with its register: DL_*_enablePower, DL_SYSCTL_enableSYSOSCFCL)
//   WWDT-STOPPED      (warns) bring-up ends (the first WFI in Thread mode: the scheduler has nothing to
//                     do) with WWDT0 not running: a firmware that hangs later stays hung. WWDT0 is off after
//                     a reset and starts only with a keyed WWDTCTL0 write (SLAU846B / SLAU847D WWDT;
//                     hw_wwdt.h); the product relies on it (firmware/README.md, bsp/mspm0/README.md watchdog)
//   MCAN-INIT-SYNC    CCCR.CCE written while CCCR.INIT does not read back 1 yet (refused: the protected
//                     writes after it are then ignored): "there may be a delay until the value written to
//                     INIT can be read back" (hw_mcan.h CCCR.INIT, the M_CAN user manual it follows); CCE and
//                     the protected registers are written only with INIT = 1 (hw_mcan.h CCCR.CCE); TI's
//                     set-up polls DL_MCAN_getOpMode until it reads SW_INIT before it configures
// The rules below name the usual cause of "nothing ever happens": a block enabled whose pin, DMA trigger or
// interrupt can never work. Each looks at what the firmware set, not at the result, so it names the cause:
//   PIN-UNROUTED      a UART byte leaves while its TX pin is muxed to another function, or one arrives at its
//                     RX pin while the receiver is enabled and the pin is muxed elsewhere: the byte goes
//                     nowhere (hw_iomux.h PINCM.PF/PC: the pin function selects who drives and reads the pin;
//                     the data sheets' pin function tables, bsp/mspm0/README.md "Connections")
//   DMA-TRIGGER       a DMA channel enabled to move to a peripheral's TX data register (or from its RX data
//                     register) on another trigger than that peripheral's for that direction: its transfers
//                     are never paced by the peripheral (hw_dma.h DMATCTL.DMATSEL; the data sheets' DMA
//                     trigger tables, e.g. UART0 RX 17 / TX 18 on the G3507)
//   UART-DMA-LEVEL    (warns) a DMA channel enabled on a UART trigger whose IFLS level is not 7: "TX FIFO
//                     >= 1 entry free / RX FIFO >= 1 entry available ... esp. required for DMA Trigger"
//                     (hw_uart.h IFLS); the other levels trigger on a transition through the level (driverlib
//                     DL_UART_setTXFIFOThreshold), which an idle FIFO never makes
//   CLOCK-OFF         the MCAN's clock requested (MCANSS_CLKEN.CLK_REQEN) from a source that is not running:
//                     GENCLKCFG.CANCLKSRC selects HFCLK with the HFXT never started (HSCLKEN.HFXTEN), or
//                     SYSPLLCLK1 with the SYSPLL off (HSCLKEN.SYSPLLEN) (hw_sysctl_mspm0g1x0x_g3x0x.h;
//                     SLAU846B 2 clock tree: CANCLK from HFCLK or SYSPLLCLK1): the message RAM never
//                     initialises
//   MCAN-TC-UNARMED   (warns) the MCAN joins the bus with IE.TCE set and no TX buffer's TXBTIE bit: IR.TC is
//                     raised only for buffers whose TXBTIE bit is set ("Each Tx Buffer has its own
//                     Transmission Interrupt Enable bit", hw_mcan.h TXBTIE; TI's MCAN examples set it with
//                     DL_MCAN_TXBufTransIntrEnable), so the enabled interrupt never comes
//   DMA-NO-INCREMENT  (warns) a channel moves DMASZ > 1 items from a peripheral's RX data register into SRAM
//                     without incrementing the destination (DMACTL.DMADSTINCR unchanged): each byte
//                     overwrites the last (hw_dma.h DMADSTINCR; TI's UART RX DMA examples increment the
//                     destination)
//   I2C-NO-STOP       (warns) the clock-low timeout expires while the controller itself holds SCL after
//                     a burst that ended without STOP and was never continued: the firmware left the
//                     transaction open (UM10204 3.1.4: a transaction ends with STOP; hw_i2c.h MCTR.STOP
//                     "generate STOP condition at the end of the burst"; SLAU846B 20.2 / SLAU847D 21.2 clock
//                     low timeout)
//   SIGNAL-EDGE       (warns) the monitor's active-low signal (BQ769x2/BQ7690x ALERT as the board's device
//                     drives it, open drain; BQ79616 NFAULT, SLUSE81E) falls on a GPIO input whose edge
//                     interrupt is unmasked but set for the rising edge only (hw_gpio.h POLARITY 1): the
//                     interrupt comes when the alert ends, not when it starts
//   IRQ-STORM         (warns) a handler returns 1000 times in a row with the source it was entered for still
//                     pending (the same MIS bit at its return and at its next entry): it never clears its
//                     flag (ICLR), so the line re-enters it at once and Thread code no longer runs (DDI 0419E
//                     B1.5: a level still asserted at exception return pends the interrupt again; hw_*.h
//                     CPU_INT ICLR clears the RIS bit)
//   BSS-UNINIT        a load from .bss ([__bss_start__, __bss_end__)) of a byte no instruction stored since
//                     the reset: no reset initialises SRAM (the twin fills it with a pattern at power-up and
//                     BOOTRST, Machine::reset; a SYSRST keeps the last run's values), and a static object
//                     without initialiser must read 0 (ISO C++ [basic.start.static] zero-initialisation),
//                     which only the start-up's zero fill before main gives (bsp/mspm0/startup.cpp, as the
//                     Reset_Handler of TI's SDK start-up files does). A read of one is start-up garbage
//                     (uninit_watch.hpp)
//   I2C-RX-UNREAD     MFIFOCTL.RXFLUSH empties bytes of a read burst that ended with STOP, no NACK and no
//                     error, none of them read from MRXDATA: the transfer's data are thrown away (hw_i2c.h
//                     MFIFOCTL.RXFLUSH flushes the RX FIFO, MFIFOSR.RXFIFOCNT counts the bytes still to read;
//                     SLAU846B 20.2 / SLAU847D 21.2 controller RX FIFO: the CPU or DMA reads each received
//                     byte from MRXDATA). A flush after a NACK or an error is the drivers' clean-up, not this
//   IRQ-UNSERVED      (warns) at the end of the run a peripheral's interrupt request has been pending 10 ms
//                     or more and its NVIC line was never enabled since the reset: no handler will ever run
//                     (DDI 0419E B3.4 NVIC, ISER: a disabled interrupt stays pending and is not taken; TI's
//                     examples enable the line, NVIC_EnableIRQ, after the peripheral's IMASK)
//   UART-TX-END-UNSEEN (warns) the last byte a TX DMA transfer moved leaves the serializer while the driver
//                     keeps interrupts of that UART unmasked (an exchange is open) but none of EOT,
//                     DMA_DONE_TX or TXINT: an event reaches the CPU only through its IMASK bit (SLAU846B /
//                     SLAU847D UART chapter, interrupts: RIS, IMASK, MIS; hw_uart.h CPU_INT IMASK EOT "End of
//                     Transmission", DMA_DONE_TX), so nothing tells the CPU the transmission ended and what
//                     it starts then (a response timeout) never starts
//   MCAN-BUS-OFF-STUCK (warns) the MCAN stays bus-off (PSR.BO) with CCCR.INIT at 1 for 1 s and no CPU write
//                     has cleared INIT since the bus-off began: the M_CAN sets INIT itself on bus-off and
//                     starts the recovery (129 x 11 recessive bits) only once the CPU clears it (Bosch M_CAN
//                     user's manual 3.1.1, the same text as periph/mcan.cpp's bus-off model; hw_mcan.h
//                     PSR.BO, CCCR.INIT): the node never rejoins the bus. The bound (1 s) is ours, far above
//                     any recovery policy's delay (the product recovers within a few ms, twin.bus-off)
//   TIMER-TICK        a TIMG counter enabled (CTRCTL.EN) in an image with a counter clock other than 1 MHz:
//                     BUSCLK / (CLKDIV.RATIO + 1) / (CPS.PCNT + 1) (SLAU846B / SLAU847D TIMx clock
//                     prescaler; hw_gptimer.h CPS.PCNT) against the product's time base, microseconds
//                     (fw::Duration; TimgClock and TimgOneShot count at 1 MHz, bsp/mspm0/README.md): every
//                     period and timeout of the firmware would be off by the ratio. A project rule, like
//                     IDLE-WFI
//   I2C-NO-TIMEOUT    (warns) a device documented to stretch or hold SCL (I2c::TargetRange::stretchSource)
//                     addressed while the controller's clock-low timeout A is off (TIMEOUT_CTL.TCLKAEN clear,
//                     or a count of 0..1): with CLKSTRETCH the controller waits on a held SCL as long as the
//                     device holds it, and only timeout A ends that wait (SLAU846B 20.2 / SLAU847D 21.2 clock
//                     low timeout; hw_i2c.h TIMEOUT_CTL.TCLKAEN). The board works until a device hangs with
//                     SCL low (a reset or brown-out mid-byte); then the transaction never ends and the
//                     monitor is never read again: a degradation, hence a warning
//   SLEEP-EVENT-LOST  the core sleeps (WFI or sleep-on-exit) in STOP or STANDBY (SCR.SLEEPDEEP, SYSCTL
//                     PMODECFG) while an event it waits for needs a clock that mode stops or slows: an
//                     I2C or UART transfer in flight (its bit timing runs from the 32 MHz BUSCLK/ULPCLK; in
//                     STOP0/1 ULPCLK is at most 4 MHz, in STOP2 and STANDBY it is LFCLK, and in STANDBY1
//                     only TIMG0/TIMG1 keep a clock: SLAU847D/SLAU846B 2 PMCU operating modes, mspm0-sdk
//                     dl_sysctl_mspm0l11xx_l13xx.h DL_SYSCTL_setPowerPolicySTANDBY1 comment), or a TIMG
//                     deadline counted from that BUSCLK, or from LFCLK on an instance the mode leaves
//                     unclocked (periph/timg.hpp StandbyClock), or a powered MCAN (G3507, PD1: SLAU846A 2
//                     STOP, SLAAET4 2.4): the transfer stalls or runs at another rate, the deadline comes
//                     late or never
//   FLASH-PROTECTED   a FLASHCTL command on a sector still protected: the controller protects every sector
//                     after each command, so each command needs its own unprotect (SLAU846A/SLAU847 FLASHCTL
//                     write/erase protection; hw_flashctl.h CMDWEPROTA, STATCMD.FAILWEPROT)
//   FLASH-UNERASED    a program into a flash word that is not erased (SLAU846A program section: ECC over the
//                     whole 64-bit word on the G3507; the safe side on the L1306; hal/flash.hpp)
//   FLASH-REGION      a FLASHCTL command to NONMAIN or to the image's sectors, or CMDWEPROTNM cleared: the
//                     firmware writes only its data region (bsp/mspm0/flashctl.hpp; bsl.md NONMAIN lockout)
//   FAULT-OUT-RELEASED the G3507 images' fault output (PB26) was never driven asserted (high) between the
//                     power-up and the image's first CAN frame: the product's contract (README "Protection",
//                     board_g3507_can.cpp) asserts it from reset until the application has measured the pack,
//                     so a pack path behind it never closes on a pack nobody measured. Not a TI rule.
//   MCAN-FILTER-OPEN  (warns) a frame that no element of the standard ID filter list matched is stored in RX
//                     FIFO 0 by GFC.ANFS 0 while the list has an enabled element storing into RX FIFO 0:
//                     the list selects the firmware's identifiers and the global filter lets every other
//                     frame in as well, so the bus's whole traffic takes FIFO room and CPU time meant for the
//                     commands (hw_mcan.h GFC.ANFS 0: non-matching standard frames go to RX FIFO 0; Bosch
//                     M_CAN user's manual 3.4.1 acceptance filtering, as SLAU846 MCAN describes it). TI does
//                     not call the combination wrong: the safe side, as a warning (bsp/twin/README.md)
//   HFXT-WAIT-UNBOUNDED the CPU still polls CLKSTATUS 20 ms after the HFXT start-up monitor declared the
//                     crystal dead (HFCLKOFF): "If the HFXT did not start within the specified startup time,
//                     the HFCLKOFF bit is set, indicating that the HFXT was dead at startup" (SLAU846A 2 HFXT
//                     startup monitor), and HFCLKGOOD never comes after that verdict, so a wait for it with
//                     no bound hangs the part (before the watchdog starts, for good). The data sheet's
//                     start-up time is 0.5 ms typical (SLASEX6B HFXT tstart, HFXTRSEL=11): 20 ms after the
//                     verdict is our bound, 40 times that and more than HFXTTIME's longest (255 x 64 us); a
//                     poll is reads of CLKSTATUS no more than 1 ms apart. Only a board without a crystal
//                     (Sysctl::removeCrystal, bms-sim --no-crystal) can reach it
//   TIMER-COMPARE-UNSEEN (warns) a TIMG compare register the firmware wrote (CC0/CC1) reaches its value 3
//                     times on a counter whose CPU interrupt serves other events (IMASK not 0) without its
//                     own CCUn/CCDn bit ever set in IMASK at those times: the event the firmware set up
//                     reaches nothing (the twin models no event route or CCP output for it), so code waiting
//                     for it (a half-period count, an alarm) never runs (hw_gptimer.h CPU_INT IMASK
//                     CCU0/CCU1; SLAU846B / SLAU847D TIMx interrupts: an event reaches the CPU only through
//                     its IMASK bit). A compare written and never used is not wrong by TI's text: the safe
//                     side, a warning
//   TIMER-COMPARE-PASSED a TIMG compare written (CCn) while its counter runs is armed (its CCUn/CCDn bit set
//   in
//                     IMASK) and the core sleeps without the firmware having read CTR since the write and the
//                     last ICLR of that bit, or pended the event itself (ISET), and without the event already
//                     pending: the compare event comes only when the counter becomes CCn ("TIMx.CTR value
//                     equals TIMx.CC", SLAU847D chapter 23 TIMx, shadow compare table 23-16; the same TIMx
//                     text in SLAU846B; hw_gptimer.h CPU_INT CCU0 "capture or compare up event"), not when it
//                     is already past it, and ICLR wipes a match that came before the clear. A counter that
//                     passes CCn between the firmware's read and the arming (a deadline that close, or
//                     already due) therefore wakes the core only after a whole wrap (65.5 ms at 1 MHz). The
//                     twin's run is deterministic and never arms that close, so the rule checks what makes
//                     the race harmless, a read of the counter after the arming (the re-check), not the race
//                     itself, as IDLE-WFI does for its race. A firmware that instead never arms closer than
//                     its arming window (and pends near deadlines itself) would be named too: none of ours
//                     does
//   PREFETCH-SLEEP    the core goes to sleep (WFI, or back to sleep at a handler's return) while CPUSS
//                     CTL.PREFETCH is set: CPU_ERR_03 (MSPM0L130x SLAZ741D/E, MSPM0G350x SLAZ742E; the
//                     advisory's text in SLAZ763 6.3): entering a low-power mode with a prefetch pending the
//                     prefetcher can fetch all zeros, and code run after the wake-up before a handler has
//                     refilled it can be corrupted; SLEEP0 is one of those modes. The twin does not model the
//                     corruption, so it checks the workaround: the prefetcher off across every sleep
#pragma once

#include <cstdint>
#include <string>

namespace twin {

enum class Rule : uint8_t {
  UartBaud,
  I2cScl,
  I2cTpr,
  CanBitRate,
  CanSamplePoint,
  HfxtRange,
  InputEnable,
  IdleWfi,
  IsrRace,
  I2cClockStretch,
  I2cFlush,
  UartFrame,
  I2cReadNack,
  KeyWrite,
  WatchdogStopped,
  McanInitSync,
  PinUnrouted,
  DmaTrigger,
  UartDmaLevel,
  IrqUnserved,
  ClockOff,
  IrqStorm,
  McanTcUnarmed,
  DmaNoIncrement,
  I2cNoStop,
  SignalEdge,
  BssUninit,
  I2cRxUnread,
  UartTxEndUnseen,
  McanBusOffStuck,
  TimerTick,
  I2cNoTimeout,
  SleepEventLost,
  FlashProtected,
  FlashUnerased,
  FlashRegion,
  FaultOutReleased,
  McanFilterOpen,
  HfxtWaitUnbounded,
  TimerCompareUnseen,
  TimerComparePassed,
  PrefetchSleep,
};

struct RuleInfo {
  const char* id;
  const char* source;
  bool stops;  // false: a warning (the part would degrade, not fail)
};

const RuleInfo& ruleInfo(Rule rule);
// "[<id>] <detail> (<source>)"
std::string ruleText(Rule rule, const std::string& detail);

}  // namespace twin
