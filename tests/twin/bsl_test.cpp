// The ROM bootloader model and the boot code of the twin (bsp/twin/bsl/): every rule of rom_bsl.hpp and
// boot_code.hpp, driven at the chip's BSL UART byte by byte at the line rate, on the twin's timeline.
// Requests use SLAU887's published packets where there is one (4.3.1 Connection, 4.3.2 Get Device Info, 4.3.3
// Unlock with the default password, 4.3.8 Mass Erase, 4.3.11 Start Application); answers are checked against
// SLAU887's published replies (4.3.2 device info, 4.3.3/4.3.8 success, 4.3.10 invalid range).
#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

#include "bsl/rom_bsl.hpp"
#include "mspm0.hpp"

namespace {

using twin::Mspm0;
using twin::Part;
using Bytes = std::vector<uint8_t>;

const Bytes kConnection = {0x80, 0x01, 0x00, 0x12, 0x3A, 0x61, 0x44, 0xDE};
const Bytes kDeviceInfo = {0x80, 0x01, 0x00, 0x19, 0xB2, 0xB8, 0x96, 0x49};
const Bytes kMassErase = {0x80, 0x01, 0x00, 0x15, 0x99, 0xF4, 0x20, 0x40};
const Bytes kStartApplication = {0x80, 0x01, 0x00, 0x40, 0xE2, 0x51, 0x21, 0x5B};
const Bytes kSuccess = {0x00, 0x08, 0x02, 0x00, 0x3B, 0x00, 0x38, 0x02, 0x94, 0x82};  // ACK + MSG 0x00
const Bytes kInvalidRange = {0x00, 0x08, 0x02, 0x00, 0x3B, 0x05, 0xB7, 0xF6, 0xFE, 0xF2};

Bytes packet(uint8_t command, const Bytes& data = {}) {
  Bytes p = {0x80, static_cast<uint8_t>(data.size() + 1), static_cast<uint8_t>((data.size() + 1) >> 8),
             command};
  p.insert(p.end(), data.begin(), data.end());
  const uint32_t crc = twin::bslCrc32(p.data() + 3, data.size() + 1);
  for (int i = 0; i < 4; ++i)
    p.push_back(static_cast<uint8_t>(crc >> (8 * i)));
  return p;
}
Bytes le32(uint32_t a, uint32_t b) {
  Bytes d;
  for (uint32_t v : {a, b})
    for (int i = 0; i < 4; ++i)
      d.push_back(static_cast<uint8_t>(v >> (8 * i)));
  return d;
}
Bytes unlock(uint8_t fill) {
  return packet(0x21, Bytes(32, fill));
}
Bytes program(uint32_t address, const Bytes& bytes) {
  Bytes d = le32(address, 0);
  d.resize(4);
  d.insert(d.end(), bytes.begin(), bytes.end());
  return packet(0x20, d);
}
// ACK + a core message with its CRC.
Bytes message(uint8_t m) {
  Bytes r = {0x00, 0x08, 0x02, 0x00, 0x3B, m};
  const uint32_t crc = twin::bslCrc32(r.data() + 4, 2);
  for (int i = 0; i < 4; ++i)
    r.push_back(static_cast<uint8_t>(crc >> (8 * i)));
  return r;
}

// A chip, blank unless given a vector table, with a host on its BSL UART.
struct Rig {
  explicit Rig(Part part = Part::L1306) : chip(part) {
    chip.bsl().onTransmit([this](uint8_t byte, uint32_t baud) {
      if (baud == hostBaud) heard.push_back(byte);
    });
  }
  twin::Machine& m() { return chip.machine(); }
  // A tiny image: initial SP, reset vector to a `b .` at 0x100.
  void loadSpinImage() {
    auto& f = m().flash();
    const uint8_t vectors[] = {0x00, 0x10, 0x00, 0x20, 0x01, 0x01, 0x00, 0x00};
    std::copy(std::begin(vectors), std::end(vectors), f.begin());
    f[0x100] = 0xFE, f[0x101] = 0xE7;
  }
  void runUs(uint64_t us) { m().run(m().now() + us * m().cyclesPerUs()); }
  // Sends the bytes at the host's rate (10 bit times each), then lets `settleUs` pass; returns what came
  // back.
  Bytes exchange(const Bytes& bytes, uint64_t settleUs = 80000) {
    heard.clear();
    const uint64_t byteCycles = 10ULL * m().clockHz() / hostBaud;
    for (uint8_t b : bytes) {
      m().run(m().now() + byteCycles);
      chip.bsl().receive(b, hostBaud);
    }
    runUs(settleUs);
    return heard;
  }
  void connectAndUnlock() {
    ASSERT_EQ(exchange(kConnection), Bytes{0x00});
    ASSERT_EQ(exchange(unlock(0xFF)), kSuccess);
  }
  Mspm0 chip;
  uint32_t hostBaud = 9600;
  Bytes heard;
};

// ---------------------------------------------------------------------------------------------------------
// Boot code

TEST(BslBoot, BlankFlashStartsTheBslAndHoldsTheCore) {
  Rig r;
  r.m().powerOn();
  EXPECT_TRUE(r.chip.bsl().running());
  EXPECT_TRUE(r.m().coreHeld());
  EXPECT_EQ(r.chip.bootCode().bslReason(), "MAIN flash blank (initial SP and reset vector erased)");
}

TEST(BslBoot, AnImageRunsUnlessTheInvokePinIsHighAtBootrst) {
  Rig r;
  r.loadSpinImage();
  r.m().powerOn();
  EXPECT_FALSE(r.chip.bsl().running());
  EXPECT_FALSE(r.m().coreHeld());
  const int pa18 = r.chip.pincm(0, 18);
  ASSERT_EQ(pa18, 19);
  r.chip.pins().setExternal(pa18, twin::Drive::High);  // S1 held
  r.m().reset(twin::ResetKind::Bootrst, "NRST");
  EXPECT_TRUE(r.chip.bsl().running());
  EXPECT_EQ(r.chip.bootCode().bslReason(), "invoke pin PA18 high at reset");
  // A software SYSRST does not run the boot code: the image starts whatever the pin says.
  r.m().busWrite(0x400B0300, 4, 0);
  r.m().busWrite(0x400B0304, 4, 0xE4000001);
  r.runUs(10);
  EXPECT_FALSE(r.chip.bsl().running());
  EXPECT_FALSE(r.m().coreHeld());
}

TEST(BslBoot, SoftwareInvokeNeedsTheKeyAndStartsTheBsl) {
  Rig r(Part::G3507);
  r.loadSpinImage();
  r.m().powerOn();
  ASSERT_FALSE(r.chip.bsl().running());
  r.m().busWrite(0x400B0300, 4, 2);           // RESETLEVEL = BOOTLOADERENTRY
  r.m().busWrite(0x400B0304, 4, 0xE5000001);  // wrong key: ignored
  r.runUs(10);
  EXPECT_FALSE(r.chip.bsl().running());
  r.m().busWrite(0x400B0304, 4, 0xE4000001);
  r.runUs(10);
  EXPECT_TRUE(r.chip.bsl().running());
  EXPECT_EQ(r.chip.bootCode().bslReason(), "software invoke (RESETLEVEL BOOTLOADERENTRY)");
  EXPECT_NE(r.m().resets().back().find("bootloader entry (RESETCMD, RESETLEVEL 2)"), std::string::npos);
}

#ifdef TWIN_PROGRAMS
TEST(BslBoot, SoftwareInvokeFromCodeOnTheCore) {
  // programs/bsl_invoke.S: the two stores bsp/mspm0 requestBootloaderEntry() makes, executed by the core.
  twin::ElfFile elf;
  ASSERT_TRUE(elf.load(std::string(TWIN_PROGRAMS) + "/bsl_invoke.elf")) << elf.error();
  Rig r;
  ASSERT_TRUE(r.chip.load(elf));
  EXPECT_FALSE(r.chip.bsl().running());
  r.runUs(100);
  EXPECT_TRUE(r.chip.bsl().running());
  EXPECT_TRUE(r.m().coreHeld());
  EXPECT_EQ(r.exchange(kConnection), Bytes{0x00});
}
#endif

TEST(BslBoot, StartApplicationRunsTheImageButABlankOneComesBack) {
  Rig r;
  r.m().powerOn();
  ASSERT_EQ(r.exchange(kConnection), Bytes{0x00});
  EXPECT_EQ(r.exchange(kStartApplication), Bytes{0x00});
  EXPECT_TRUE(r.chip.bsl().running()) << "MAIN is blank: the boot code starts the BSL again";
  r.connectAndUnlock();
  EXPECT_EQ(r.exchange(program(0x100, {0xFE, 0xE7, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF})), kSuccess);
  EXPECT_EQ(r.exchange(program(0, {0x00, 0x10, 0x00, 0x20, 0x01, 0x01, 0x00, 0x00})), kSuccess);
  r.chip.pins().setExternal(r.chip.pincm(0, 18), twin::Drive::High);  // the exit reset ignores the pin
  EXPECT_EQ(r.exchange(kStartApplication), Bytes{0x00});
  EXPECT_FALSE(r.chip.bsl().running());
  EXPECT_FALSE(r.m().coreHeld());
  EXPECT_NE(r.m().resets().back().find("bootloader exit (RESETCMD, RESETLEVEL 4)"), std::string::npos);
}

// ---------------------------------------------------------------------------------------------------------
// Packet layer

TEST(BslPackets, NothingButConnectionIsAnsweredBeforeIt) {
  Rig r;
  r.m().powerOn();
  EXPECT_EQ(r.exchange({0xBB}), Bytes{});
  EXPECT_EQ(r.exchange(kDeviceInfo), Bytes{});
  EXPECT_EQ(r.exchange(unlock(0xFF)), Bytes{});
  EXPECT_EQ(r.exchange(kConnection), Bytes{0x00});
  EXPECT_EQ(r.exchange(kConnection), message(0x06)) << "a second Connection: invalid command";
}

TEST(BslPackets, StandbyWithoutConnectionFor10s) {
  Rig r;
  r.m().powerOn();
  r.runUs(10000100);
  EXPECT_EQ(r.exchange(kConnection), Bytes{});
  EXPECT_EQ(r.exchange(kConnection), Bytes{});
  r.m().reset(twin::ResetKind::Por, "power cycle");
  EXPECT_EQ(r.exchange(kConnection), Bytes{0x00});
}

TEST(BslPackets, AcknowledgementErrors) {
  Rig r;
  r.m().powerOn();
  ASSERT_EQ(r.exchange(kConnection), Bytes{0x00});
  EXPECT_EQ(r.exchange({0xBB}), Bytes{0x51});
  EXPECT_EQ(r.exchange({0x80, 0x00, 0x00}), Bytes{0x53});
  EXPECT_EQ(r.exchange({0x80, 0xBA, 0x06}), Bytes{0x54}) << "0x06BA + 7 > 0x06C0";
  Bytes bad = kDeviceInfo;
  bad[5] ^= 0x10;
  EXPECT_EQ(r.exchange(bad), Bytes{0x52});
  EXPECT_EQ(r.exchange(packet(0x52, {0x0A})), Bytes{0x56});
  // A packet short of a byte waits for it (no receive timeout): the next byte completes it, with a bad CRC.
  EXPECT_EQ(r.exchange(Bytes(kDeviceInfo.begin(), kDeviceInfo.end() - 1), 500000), Bytes{});
  EXPECT_EQ(r.exchange({0x00}), Bytes{0x52});
  EXPECT_EQ(r.exchange(kDeviceInfo).size(), 1U + 32U);
}

TEST(BslPackets, BytesWhileACommandExecutesAreDropped) {
  Rig r;
  r.m().powerOn();
  r.connectAndUnlock();
  // Mass Erase runs 22 ms: a Connection sent right behind it is lost.
  Bytes both = kMassErase;
  both.insert(both.end(), kConnection.begin(), kConnection.end());
  EXPECT_EQ(r.exchange(both, 50000), kSuccess);
}

TEST(BslPackets, DeviceInfoIsSlau887sExampleOnTheL1306AndLenlabsOnTheG3507) {
  Rig l;
  l.m().powerOn();
  ASSERT_EQ(l.exchange(kConnection), Bytes{0x00});
  EXPECT_EQ(l.exchange(kDeviceInfo),
            (Bytes{0x00, 0x08, 0x19, 0x00, 0x31, 0x00, 0x01, 0x00, 0x01, 0x00, 0x00,
                   0x00, 0x00, 0x01, 0x00, 0xC0, 0x06, 0x60, 0x01, 0x00, 0x20, 0x01,
                   0x00, 0x00, 0x00, 0x01, 0x00, 0x00, 0x00, 0x49, 0x61, 0x57, 0x8C}));
  Rig g(Part::G3507);
  g.m().powerOn();
  ASSERT_EQ(g.exchange(kConnection), Bytes{0x00});
  const Bytes info = g.exchange(kDeviceInfo);
  ASSERT_EQ(info.size(), 33U);
  EXPECT_EQ(info[15], 0xC0);
  EXPECT_EQ(info[16], 0x3E);
  EXPECT_EQ(Bytes(info.end() - 4, info.end()), (Bytes{0x0B, 0x5F, 0x2D, 0xD1}));
}

// ---------------------------------------------------------------------------------------------------------
// Lock, password, baud rate

TEST(BslLock, ProtectedCommandsAnswerLockedUntilUnlock) {
  Rig r;
  r.m().powerOn();
  ASSERT_EQ(r.exchange(kConnection), Bytes{0x00});
  EXPECT_EQ(r.exchange(kMassErase), message(0x01));
  EXPECT_EQ(r.exchange(program(0, Bytes(8, 0))), message(0x01));
  EXPECT_EQ(r.exchange(packet(0x23, le32(0, 0x3FF))), message(0x01));
  EXPECT_EQ(r.exchange(packet(0x26, le32(0, 0x400))), message(0x01));
  EXPECT_EQ(r.exchange(packet(0x29, le32(0, 8))), message(0x01));
  EXPECT_EQ(r.exchange(kDeviceInfo).size(), 33U) << "device info needs no password";
  EXPECT_EQ(r.exchange(unlock(0xFF)), kSuccess) << "SLAU887 4.3.3's packet, the factory password";
  EXPECT_EQ(r.exchange(kMassErase), kSuccess);
}

TEST(BslLock, WrongPasswordsCostTwoSecondsAndTheThirdTakesTheAlert) {
  Rig r;
  r.m().powerOn();
  ASSERT_EQ(r.exchange(kConnection), Bytes{0x00});
  EXPECT_EQ(r.exchange(unlock(0x00)), message(0x02));
  EXPECT_EQ(r.exchange(kDeviceInfo, 1000000), Bytes{}) << "deaf for 2 s";
  r.runUs(1000000);
  EXPECT_EQ(r.exchange(kDeviceInfo).size(), 33U);
  EXPECT_EQ(r.exchange(packet(0x21, Bytes(31, 0xFF))), message(0x02)) << "the length field must be 0x21";
  r.runUs(2000000);
  EXPECT_EQ(r.exchange(unlock(0x11)), message(0x03));
  r.runUs(2000000);
  EXPECT_EQ(r.exchange(kMassErase), message(0x01));
}

TEST(BslLock, RelocksTenSecondsAfterTheLastCommand) {
  Rig r;
  r.m().powerOn();
  r.connectAndUnlock();
  r.runUs(9000000);
  EXPECT_EQ(r.exchange(kMassErase), kSuccess);
  r.runUs(10000100);
  EXPECT_EQ(r.exchange(kMassErase), message(0x01));
}

TEST(BslBaud, NewRateAfterTheAckAndBackTo9600AfterAWrongPassword) {
  Rig r;
  r.m().powerOn();
  ASSERT_EQ(r.exchange(kConnection), Bytes{0x00});
  EXPECT_EQ(r.exchange(packet(0x52, {0x06})), Bytes{0x00}) << "the ACK still at 9600 Bd";
  EXPECT_EQ(r.exchange(kDeviceInfo), Bytes{}) << "9600 Bd is gone";
  EXPECT_EQ(r.chip.bsl().bytesLost(), kDeviceInfo.size());
  r.hostBaud = 115200;
  EXPECT_EQ(r.exchange(kDeviceInfo).size(), 33U);
  EXPECT_EQ(r.exchange(unlock(0x00)), message(0x02));
  r.runUs(2100000);
  EXPECT_EQ(r.exchange(kDeviceInfo), Bytes{});
  r.hostBaud = 9600;
  EXPECT_EQ(r.exchange(kDeviceInfo).size(), 33U);
}

// ---------------------------------------------------------------------------------------------------------
// Flash

TEST(BslFlash, ProgramNeedsAlignmentRangeAndErasedWords) {
  Rig r;
  r.m().powerOn();
  r.connectAndUnlock();
  const Bytes word = {1, 2, 3, 4, 5, 6, 7, 8};
  EXPECT_EQ(r.exchange(program(4, word)), message(0x0A));
  EXPECT_EQ(r.exchange(program(8, Bytes(4, 0))), message(0x0A));
  EXPECT_EQ(r.exchange(program(0x10000, word)), message(0x05)) << "64 KiB of MAIN on the L1306";
  EXPECT_EQ(r.exchange(program(0x8, word)), kSuccess);
  EXPECT_TRUE(std::equal(word.begin(), word.end(), r.m().flash().begin() + 8));
  EXPECT_EQ(r.exchange(program(0x8, word)), message(0xF1)) << "a programmed word is not erased";
  EXPECT_EQ(r.exchange(program(0x20000100, word)), kSuccess) << "SRAM may be written";
  EXPECT_EQ(r.m().readSram32(0x20000100), 0x04030201U);
}

TEST(BslFlash, EraseVerifyAndReadBack) {
  Rig r;
  r.m().powerOn();
  r.connectAndUnlock();
  std::fill(r.m().flash().begin(), r.m().flash().begin() + 0x1000, 0x00);
  EXPECT_EQ(r.exchange(packet(0x23, le32(0x400, 0x800))), kSuccess);  // sectors 0x400..0xBFF
  EXPECT_EQ(r.m().flash()[0x3FF], 0x00);
  EXPECT_EQ(r.m().flash()[0x400], 0xFF);
  EXPECT_EQ(r.m().flash()[0xBFF], 0xFF);
  EXPECT_EQ(r.m().flash()[0xC00], 0x00);
  EXPECT_EQ(r.exchange(packet(0x23, le32(0x800, 0x400))), kInvalidRange);
  EXPECT_EQ(r.exchange(packet(0x23, le32(0, 0x10000))), kInvalidRange);
  // Standalone Verification: 1 KiB of 0xFF has CRC 0x47C5000B (bsl.md's computed check).
  EXPECT_EQ(r.exchange(packet(0x26, le32(0x400, 0x400))),
            (Bytes{0x00, 0x08, 0x05, 0x00, 0x32, 0x0B, 0x00, 0xC5, 0x47, 0x3D, 0x93, 0x08, 0x6B}));
  EXPECT_EQ(r.exchange(packet(0x26, le32(0x400, 0x3FF))), message(0x0B));
  EXPECT_EQ(r.exchange(packet(0x26, le32(0xFC00, 0x800))), kInvalidRange);
  EXPECT_EQ(r.exchange(packet(0x29, le32(0, 8))), message(0x09)) << "read-out disabled";
  EXPECT_EQ(r.exchange(kMassErase), kSuccess);
  EXPECT_TRUE(std::all_of(r.m().flash().begin(), r.m().flash().end(), [](uint8_t b) { return b == 0xFF; }));
  EXPECT_EQ(r.exchange(packet(0x77)), message(0x04));
}

TEST(BslFlash, TimingFollowsTheLineAndTheFlash) {
  Rig r;
  r.m().powerOn();
  r.connectAndUnlock();
  // 4 sectors: the answer comes 16 ms after the ACK (4 ms a sector).
  uint64_t ackAt = 0, answerAt = 0;
  r.chip.bsl().onTransmit([&](uint8_t, uint32_t) {
    if (ackAt == 0) {
      ackAt = r.m().now();
    } else {
      answerAt = r.m().now();
    }
  });
  r.exchange(packet(0x23, le32(0, 0xFFF)));
  const uint64_t byte = 10ULL * r.m().clockHz() / 9600;
  EXPECT_EQ(answerAt - ackAt, 16000 * r.m().cyclesPerUs() + 9 * byte);
}

TEST(BslFlash, NonmainWritesAndFactoryResetStopTheTwin) {
  Rig r;
  r.m().powerOn();
  r.connectAndUnlock();
  r.exchange(program(0x41C00000, Bytes(8, 0)));
  EXPECT_TRUE(r.m().stopped());
  EXPECT_NE(r.m().stopReason().find("NONMAIN"), std::string::npos);
  Rig f;
  f.m().powerOn();
  f.connectAndUnlock();
  f.exchange(packet(0x30, Bytes(16, 0xFF)));
  EXPECT_TRUE(f.m().stopped());
  EXPECT_NE(f.m().stopReason().find("Factory Reset"), std::string::npos);
}

}  // namespace
