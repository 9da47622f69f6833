// Register-level tests of GPIO outputs, edge inputs and the INT_GROUP1 dispatch (bsp/mspm0/gpio.*) on the
// twin's IOMUX, GPIO ports and CPUSS groups (bsp/twin/periph/pins.hpp, gpio.hpp, cpuss.hpp): a test drives a
// pin from outside the chip and the edge reaches the handler only if the driver set the pin up as TI
// describes. Addresses: GPIOA 0x400A0000, GPIOB 0x400A2000 + GPIO.* offsets; IOMUX PINCMn at 0x40428000 +
// 4n; CPUSS INT_GROUP[1].IIDX at 0x40401130 (mspm0g3507.tsv rows and group_iidx: GPIOA 1, GPIOB 2); pins: the
// G3507 PINCM numbers (mspm0g350x.h).
#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <utility>
#include <vector>

#include "fixture.hpp"
#include "gpio.hpp"

namespace bsp::mspm0::test {
namespace {

constexpr uintptr_t kGpioa = 0x400A0000;
constexpr uintptr_t kGpiob = 0x400A2000;
constexpr uintptr_t kImask = 0x1028;
constexpr uintptr_t kRis = 0x1030;
constexpr uintptr_t kIclr = 0x1048;
constexpr uintptr_t kDoutSet = 0x1290;
constexpr uintptr_t kDoutClr = 0x12A0;
constexpr uintptr_t kDoeSet = 0x12D0;
constexpr uintptr_t kDin = 0x1380;
constexpr uintptr_t kPolarity15_0 = 0x1390;
constexpr uintptr_t kPolarity31_16 = 0x13A0;
constexpr uintptr_t kGroup1Iidx = 0x40401130;
constexpr uintptr_t pincm(int n) {
  return 0x40428000 + 4 * n;
}

class GpioTest : public RegisterTest {
 protected:
  void SetUp() override {
    RegisterTest::SetUp();
    powerGpioPort(kGpioa);
    powerGpioPort(kGpiob);
  }
  // The board drives a pin (an active-low signal asserted: Low; released: None).
  void drive(int pincm, twin::Drive level) { chip().pins().setExternal(pincm, level); }

  GpioEdgeInput button{Pin{1, 21, 49}, Edge::Falling, Pull::Up};   // PB21 = S2 (PINCM49)
  GpioEdgeInput nfault{Pin{1, 0, 12}, Edge::Falling, Pull::None};  // PB0 (PINCM12)
  GpioEdgeInput alert{Pin{0, 15, 37}, Edge::Falling, Pull::Up};    // PA15 (PINCM37; the L1306 ALERT pin)
  std::array<uintptr_t, 2> ports{kGpioa, kGpiob};
  std::array<GpioEdgeInput*, 3> inputs{&button, &nfault, &alert};
  GpioInterrupts dispatcher{0x40400000, ports, inputs};
  int buttonCalls = 0;
  int nfaultCalls = 0;
  int alertCalls = 0;
};

TEST_F(GpioTest, EdgeInputMuxesAnInputAndSelectsItsEdge) {
  button.init();
  // PINCM49 = PC (bit 7) | PF 1 (GPIO) | INENA (bit 18) | PIPU (bit 17).
  EXPECT_EQ(regs().lastWrite(pincm(49)), 0x80U | 1U | (1U << 18) | (1U << 17));
  // POLARITY31_16 holds DIO16..31 two bits each: DIO21 is bits 11:10, FALL = 2.
  EXPECT_EQ(regs().lastWrite(kGpiob + kPolarity31_16), 2U << 10);
  alert.init();
  EXPECT_EQ(regs().lastWrite(kGpioa + kPolarity15_0), 2U << 30);  // DIO15 bits 31:30, FALL = 2
  GpioEdgeInput both{Pin{0, 3, 8}, Edge::Both, Pull::None};
  both.init();
  EXPECT_EQ(regs().lastWrite(kGpioa + kPolarity15_0), (2U << 30) | (3U << 6));  // DIO3 RISE_FALL = 3
  EXPECT_EQ(regs().lastWrite(pincm(8)), 0x80U | 1U | (1U << 18));               // no pull
  EXPECT_FALSE(regs().lastWrite(kGpiob + kImask).has_value());                  // masked until enable()
}

TEST_F(GpioTest, EnableClearsAStaleEdgeThenUnmasks) {
  button.init();
  regs().clearLog();
  button.enable(counter(buttonCalls));
  EXPECT_TRUE(regs().wroteInOrder({{kGpiob + kIclr, 1U << 21}, {kGpiob + kImask, 1U << 21}}));
  nfault.enable(counter(nfaultCalls));
  EXPECT_EQ(regs().lastWrite(kGpiob + kImask), (1U << 21) | 1U);  // read-modify-write keeps the other pin
  button.disable();
  EXPECT_EQ(regs().lastWrite(kGpiob + kImask), 1U);
}

TEST_F(GpioTest, Group1DispatchFindsThePortClearsExactlyItsBitsAndNotifies) {
  for (GpioEdgeInput* input : inputs)
    input->init();
  drive(12, twin::Drive::High);  // nFAULT is driven by its device (no pull): high while no fault
  button.enable(counter(buttonCalls));
  nfault.enable(counter(nfaultCalls));
  alert.enable(counter(alertCalls));
  regs().clearLog();
  drive(12, twin::Drive::Low);  // PB0 falls: GPIOB pending (group_iidx GROUP1.GPIOB = 2)
  EXPECT_EQ(regs().peek(kGroup1Iidx), 2U);
  dispatcher.onInterrupt();
  EXPECT_EQ(nfaultCalls, 1);
  EXPECT_EQ(buttonCalls, 0);
  EXPECT_EQ(alertCalls, 0);
  EXPECT_EQ(regs().writes(kGpiob + kIclr), (std::vector<uint32_t>{1U}));
  EXPECT_TRUE(regs().writes(kGpioa + kIclr).empty());

  drive(37, twin::Drive::Low);  // PA15 falls: GPIOA
  dispatcher.onInterrupt();
  EXPECT_EQ(alertCalls, 1);
  EXPECT_EQ(regs().lastWrite(kGpioa + kIclr), 1U << 15);

  regs().queueRead(kGroup1Iidx, 3);  // COMP0 (the twin has no comparator): not ours, nothing touched
  regs().clearLog();
  dispatcher.onInterrupt();
  EXPECT_EQ(regs().log().size(), 1U);
}

TEST_F(GpioTest, SinglePortDispatchNeedsIidxOneClearsExactlyItsBitsAndNotifies) {
  // A part with GPIOA alone (the L1306): the same contract as the dispatcher, with the port fixed.
  alert.init();
  alert.enable(counter(alertCalls));
  int otherCalls = 0;
  GpioEdgeInput other{Pin{0, 3, 8}, Edge::Falling, Pull::Up};  // PA3, an edge input of nobody's list
  other.init();
  other.enable(counter(otherCalls));
  GpioEdgeInput* const portA[] = {&alert};
  drive(37, twin::Drive::Low);
  drive(8, twin::Drive::Low);
  regs().clearLog();
  onPortInterrupt(0x40400000, kGpioa, portA);
  EXPECT_EQ(alertCalls, 1);
  EXPECT_EQ(regs().writes(kGpioa + kIclr), (std::vector<uint32_t>{(1U << 15) | (1U << 3)}));

  drive(8, twin::Drive::None);  // another pin of the port: cleared, nobody notified
  drive(8, twin::Drive::Low);
  onPortInterrupt(0x40400000, kGpioa, portA);
  EXPECT_EQ(alertCalls, 1);
  EXPECT_EQ(otherCalls, 0);

  regs().clearLog();  // nothing pending in the group: nothing touched
  onPortInterrupt(0x40400000, kGpioa, portA);
  EXPECT_EQ(regs().log().size(), 1U);
  EXPECT_EQ(alertCalls, 1);
}

TEST_F(GpioTest, InitOfAConstexprCopyWritesWhatTheInputsOwnInitWrites) {
  // The boards run init() on a constexpr copy of each input, so that its writes fold to constants.
  static constexpr GpioEdgeInput kCopy{Pin{1, 21, 49}, Edge::Falling, Pull::Up};
  regs().clearLog();
  const auto writes = [this] {
    std::vector<std::pair<uintptr_t, uint32_t>> w;
    for (const auto& a : regs().log())
      if (a.kind == Access::Kind::Write) w.emplace_back(a.address, a.value);
    return w;
  };
  kCopy.init();
  const auto fromCopy = writes();
  regs().clearLog();
  button.init();
  EXPECT_EQ(writes(), fromCopy);
  EXPECT_FALSE(fromCopy.empty());
}

TEST_F(GpioTest, AnOpenDrainAlertIsAFallingEdgeInputWithThePullUp) {
  // The BQ769x2-family images set the BQ76952 ALERT pin active-low, open-drain: the MCU input needs the
  // internal pull-up (PINCM.PIPU, bit 17) to read high while the device lets go, and the falling edge.
  alert.init();
  alert.enable(counter(alertCalls));
  EXPECT_EQ(regs().lastWrite(pincm(37)), 0x80U | 1U | (1U << 18) | (1U << 17));
  EXPECT_TRUE(alert.level()) << "released: the pull-up holds it high";
  drive(37, twin::Drive::Low);
  EXPECT_NE(regs().peek(kGpioa + kRis) & (1U << 15), 0U);
  EXPECT_FALSE(alert.level());
  EXPECT_TRUE(chip().pins().floatingReads().empty());
}

TEST_F(GpioTest, AnInputWithoutPullUpFloatsAndOneOnTheRisingEdgeMissesTheAlert) {
  // What the twin makes of the wrong set-ups (pins.hpp, gpio.hpp): without a pull the released open-drain
  // line floats (the twin records the read), and the rising edge flags the end of the alert, not its start.
  GpioEdgeInput floating{Pin{0, 15, 37}, Edge::Falling, Pull::None};
  floating.init();
  (void)floating.level();
  EXPECT_EQ(chip().pins().floatingReads().size(), 1U);
  GpioEdgeInput rising{Pin{0, 15, 37}, Edge::Rising, Pull::Up};
  rising.init();
  rising.enable(counter(alertCalls));
  drive(37, twin::Drive::Low);
  EXPECT_EQ(regs().peek(kGpioa + kRis) & (1U << 15), 0U);
  drive(37, twin::Drive::None);
  EXPECT_NE(regs().peek(kGpioa + kRis) & (1U << 15), 0U);
}

TEST_F(GpioTest, LevelReadsDin) {
  button.init();
  nfault.init();
  drive(12, twin::Drive::Low);  // nFAULT asserted; S2 released, pulled up
  EXPECT_TRUE(button.level());
  EXPECT_FALSE(nfault.level());
}

TEST_F(GpioTest, OutputPresetsLevelBeforeDrivingAndUsesSetClear) {
  GpioOut led{Pin{1, 22, 50}};  // PB22
  led.init(false);
  EXPECT_TRUE(
      regs().wroteInOrder({{kGpiob + kDoutClr, 1U << 22}, {kGpiob + kDoeSet, 1U << 22}, {pincm(50), 0x81U}}));
  led.set(true);
  EXPECT_EQ(regs().lastWrite(kGpiob + kDoutSet), 1U << 22);
  EXPECT_TRUE(led.level());
  led.set(false);
  EXPECT_EQ(regs().lastWrite(kGpiob + kDoutClr), 1U << 22);
}

}  // namespace
}  // namespace bsp::mspm0::test
