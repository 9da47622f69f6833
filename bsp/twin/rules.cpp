#include "rules.hpp"

#include <array>

namespace twin {

namespace {

constexpr std::array<RuleInfo, 42> kRules = {{
    {"WIRE-UART-BAUD", "SLUSE81E UART RX baud rate error; SLAU846B/SLAU847D UART baud-rate generation", true},
    {"WIRE-I2C-SCL", "SLUSE13B 14 I2C up to 400 kHz; SLUSC67A SMBus 10..100 kHz", true},
    {"WIRE-I2C-TPR", "hw_i2c.h MTPR.TPR 1..127; SLAU846B 20.1 / SLAU847D 21.1 up to 1 Mbps", true},
    {"WIRE-CAN-BITRATE", "ISO 11898-1 bit timing, oscillator tolerance of the image's NBTP", true},
    {"WIRE-CAN-SAMPLE", "CiA 301 sample point 87.5 %; TI bq79616_uart_to_can NBTP", false},
    {"WIRE-HFXT-RANGE", "hw_sysctl HFCLKCLKCFG.HFXTRSEL; SLAU846B 2 SYSCTL HFXT", true},
    {"PIN-INENA", "hw_iomux.h PINCM.INENA; SLAU846B/SLAU847D IOMUX input enable", true},
    {"IDLE-WFI", "firmware/hal/irq.hpp idle rule; DDI 0419E B1.5.19", true},
    {"RACE-ISR-RMW", "DDI 0419E B1.5 exception preemption between a load and its store", true},
    {"I2C-CLKSTRETCH", "hw_i2c.h MCR.CLKSTRETCH", true},
    {"I2C-FLUSH", "hw_i2c.h MFIFOCTL.TXFLUSH/RXFLUSH; DL_I2C_flushControllerTXFIFO", true},
    {"WIRE-UART-FRAME",
     "hw_uart.h LCRH WLEN/PEN; SLUSE81E DEV_CONF (8 data bits, no parity); TI BQ79616 example 8N1", true},
    {"I2C-READ-NACK", "UM10204 3.1.6; SLUSE13B I2C read: NACK, then Stop; hw_i2c.h MCTR.ACK", true},
    {"KEY-WRITE",
     "hw_*.h KEY fields (PWREN 0x26, RSTCTL 0xB1, SYSOSCFCLCTL 0x2A, RESETCMD 0xE4, WWDT 0xC9/0xBE)", false},
    {"WWDT-STOPPED", "SLAU846B/SLAU847D WWDT: off after reset until a keyed WWDTCTL0 write; hw_wwdt.h",
     false},
    {"MCAN-INIT-SYNC", "hw_mcan.h CCCR.INIT read-back delay and CCCR.CCE; DL_MCAN_getOpMode poll", true},
    {"PIN-UNROUTED", "hw_iomux.h PINCM.PF; the data sheets' pin function tables", true},
    {"DMA-TRIGGER", "hw_dma.h DMATCTL.DMATSEL; the data sheets' DMA trigger tables", true},
    {"UART-DMA-LEVEL", "hw_uart.h IFLS level 7 'esp. required for DMA Trigger'; DL_UART_setTXFIFOThreshold",
     false},
    {"IRQ-UNSERVED", "DDI 0419E B3.4 NVIC ISER; TI examples' NVIC_EnableIRQ", false},
    {"CLOCK-OFF", "hw_sysctl GENCLKCFG.CANCLKSRC, HSCLKEN.HFXTEN/SYSPLLEN; SLAU846B 2 clock tree", true},
    {"IRQ-STORM", "DDI 0419E B1.5 a level still asserted at return pends again; hw_*.h CPU_INT ICLR", false},
    {"MCAN-TC-UNARMED", "hw_mcan.h TXBTIE and IE.TCE; TI examples' DL_MCAN_TXBufTransIntrEnable", false},
    {"DMA-NO-INCREMENT", "hw_dma.h DMACTL.DMADSTINCR; TI UART RX DMA examples", false},
    {"I2C-NO-STOP", "UM10204 3.1.4; hw_i2c.h MCTR.STOP; SLAU846B 20.2 / SLAU847D 21.2 clock low timeout",
     false},
    {"SIGNAL-EDGE", "hw_gpio.h POLARITY; the monitor's ALERT / NFAULT active low (SLUSE13B, SLUSE81E)",
     false},
    {"BSS-UNINIT",
     "ISO C++ [basic.start.static] zero-initialisation; the start-up zero fill of .bss (TI SDK "
     "Reset_Handler)",
     true},
    {"I2C-RX-UNREAD", "hw_i2c.h MFIFOCTL.RXFLUSH, MFIFOSR.RXFIFOCNT; SLAU846B 20.2 / SLAU847D 21.2 RX FIFO",
     true},
    {"UART-TX-END-UNSEEN",
     "SLAU846B/SLAU847D UART interrupts (an event reaches the CPU through IMASK); hw_uart.h CPU_INT EOT, "
     "DMA_DONE_TX",
     false},
    {"MCAN-BUS-OFF-STUCK",
     "Bosch M_CAN user's manual 3.1.1 (INIT set on bus-off, recovery once the CPU clears it); hw_mcan.h "
     "PSR.BO, CCCR.INIT",
     false},
    {"TIMER-TICK",
     "SLAU846B/SLAU847D TIMx clock prescaler (hw_gptimer.h CPS.PCNT); the firmware's 1 us time base "
     "(bsp/mspm0/README.md TimgClock)",
     true},
    {"I2C-NO-TIMEOUT", "hw_i2c.h TIMEOUT_CTL.TCLKAEN; SLAU846B 20.2 / SLAU847D 21.2 clock low timeout",
     false},
    {"SLEEP-EVENT-LOST",
     "SLAU847D/SLAU846B 2 PMCU operating modes (clocks per mode); hw_sysctl PMODECFG.DSLEEP; "
     "DDI 0419E B3.2.7 SCR.SLEEPDEEP",
     true},
    {"FLASH-PROTECTED",
     "SLAU846A/SLAU847 FLASHCTL write/erase protection; hw_flashctl.h CMDWEPROTA, STATCMD.FAILWEPROT", true},
    {"FLASH-UNERASED", "SLAU846A FLASHCTL program (ECC over the 64-bit word); fw::hal::FlashStorage contract",
     true},
    {"FLASH-REGION",
     "bsp/mspm0/flashctl.hpp data region; SLAU887 4.3.9 NONMAIN lockout; hw_flashctl.h CMDWEPROTNM", true},
    {"FAULT-OUT-RELEASED",
     "the product's contract, not TI's: README Protection, board_g3507_can.cpp (asserted until the pack is "
     "measured)",
     true},
    {"MCAN-FILTER-OPEN",
     "hw_mcan.h GFC.ANFS; Bosch M_CAN user's manual 3.4.1 acceptance filtering (SLAU846 MCAN)", false},
    {"HFXT-WAIT-UNBOUNDED",
     "SLAU846A 2 HFXT startup monitor (HFCLKOFF: dead at startup); SLASEX6B HFXT start-up time 0.5 ms", true},
    {"TIMER-COMPARE-UNSEEN",
     "hw_gptimer.h CPU_INT IMASK CCU0/CCU1; SLAU846B/SLAU847D TIMx interrupts (an event reaches the CPU only "
     "through IMASK)",
     false},
    {"TIMER-COMPARE-PASSED",
     "SLAU847D 23 TIMx shadow compare table 23-16 (compare event when CTR equals CC; SLAU846B TIMx the "
     "same); hw_gptimer.h CPU_INT CCU0, ICLR, ISET",
     true},
    {"PREFETCH-SLEEP",
     "CPU_ERR_03 (SLAZ741D/E MSPM0L130x, SLAZ742E MSPM0G350x; text in SLAZ763 6.3); hw_cpuss.h CTL.PREFETCH",
     true},
}};

static_assert(kRules.size() == static_cast<size_t>(Rule::PrefetchSleep) + 1,
              "one entry per Rule, in its order");

}  // namespace

const RuleInfo& ruleInfo(Rule rule) {
  return kRules[static_cast<size_t>(rule)];
}

std::string ruleText(Rule rule, const std::string& detail) {
  const RuleInfo& r = ruleInfo(rule);
  return std::string("[") + r.id + "] " + detail + " (" + r.source + ")";
}

}  // namespace twin
