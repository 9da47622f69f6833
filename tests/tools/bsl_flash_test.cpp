// `bmsctl flash` pieces (bsp/host/tools/bmsctl/flash/): the BSL packets against TI's published bytes, the
// reply decoder, image files, the flash plan and its refusals, the parts, and the bootloader-entry frames.
//
// Published vectors: SLAU887 (MSPM0 Bootloader User's Guide) 4.3.1 Connection, 4.3.2 Get Device Info (request
// and the example reply), 4.3.3 Unlock with the default password, 4.3.8 Mass Erase, 4.3.10 Standalone
// Verification of 0x20000000 + 1 KiB and the invalid-range reply, 4.3.11 Start Application; SLUUDI8 (the same
// protocol on AM13E230) Change Baud Rate ID 3; a real LP-MSPM0G3507's device info reply
// (kalanzun/lenlab_mspm0 tests/firmware/test_bsl.py). SLAU887 publishes no Program Data (0x20) packet: its
// vector is computed with the CRC that reproduces every published packet above.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "flash/bsl_packet.hpp"
#include "flash/chips.hpp"
#include "flash/flash_image.hpp"
#include "flash/invoke_app.hpp"

namespace {

using namespace bmsctl;
using Bytes = std::vector<uint8_t>;

Bytes ff(size_t n) {
  return Bytes(n, 0xFF);
}
Bytes cat(Bytes a, const Bytes& b) {
  a.insert(a.end(), b.begin(), b.end());
  return a;
}

// ---------------------------------------------------------------------------------------------------------
// Packets

TEST(BslPacket, CrcIsCrc32JamcrcCheckValue) {
  const std::string check = "123456789";
  EXPECT_EQ(bsl::crc32({reinterpret_cast<const uint8_t*>(check.data()), check.size()}), 0x340BC6D9U);
}

TEST(BslPacket, CommandsMatchSlau887PublishedBytes) {
  EXPECT_EQ(bsl::connection(), (Bytes{0x80, 0x01, 0x00, 0x12, 0x3A, 0x61, 0x44, 0xDE}));     // 4.3.1
  EXPECT_EQ(bsl::getDeviceInfo(), (Bytes{0x80, 0x01, 0x00, 0x19, 0xB2, 0xB8, 0x96, 0x49}));  // 4.3.2
  std::array<uint8_t, 32> password;
  password.fill(0xFF);
  EXPECT_EQ(bsl::unlock(password),
            cat(cat({0x80, 0x21, 0x00, 0x21}, ff(32)), {0x02, 0xAA, 0xF0, 0x3D}));       // 4.3.3
  EXPECT_EQ(bsl::massErase(), (Bytes{0x80, 0x01, 0x00, 0x15, 0x99, 0xF4, 0x20, 0x40}));  // 4.3.8
  EXPECT_EQ(bsl::standaloneVerification(0x20000000, 0x400),                              // 4.3.10
            (Bytes{0x80, 0x09, 0x00, 0x26, 0x00, 0x00, 0x00, 0x20, 0x00, 0x04, 0x00, 0x00, 0xA0, 0x97, 0xD5,
                   0x2E}));
  EXPECT_EQ(bsl::startApplication(), (Bytes{0x80, 0x01, 0x00, 0x40, 0xE2, 0x51, 0x21, 0x5B}));  // 4.3.11
  EXPECT_EQ(bsl::changeBaudRate(3),
            (Bytes{0x80, 0x02, 0x00, 0x52, 0x03, 0x6C, 0x83, 0xA2, 0xAF}));  // SLUUDI8
}

TEST(BslPacket, ProgramDataAndEraseLayout) {
  // Computed (no published 0x20 example): header, length 13 LE, CMD, address LE, data, CRC LE.
  EXPECT_EQ(bsl::programData(0, Bytes{0, 1, 2, 3, 4, 5, 6, 7}),
            (Bytes{0x80, 0x0D, 0x00, 0x20, 0, 0, 0, 0, 0, 1, 2, 3, 4, 5, 6, 7, 0x7E, 0x45, 0x7D, 0xAE}));
  EXPECT_EQ(bsl::flashRangeErase(0, 0x3FF),
            (Bytes{0x80, 0x09, 0x00, 0x23, 0, 0, 0, 0, 0xFF, 0x03, 0, 0, 0x9F, 0xED, 0xC9, 0x7E}));
  EXPECT_EQ(bsl::changeBaudRate(6), (Bytes{0x80, 0x02, 0x00, 0x52, 0x06, 0xE3, 0x77, 0xC8, 0xDF}));
  const Bytes big = bsl::programData(0x400, Bytes(4096, 0xAB));
  EXPECT_EQ(big.size(), 4096U + 12U);
  EXPECT_EQ(big[1] | big[2] << 8, 4096 + 5);
}

TEST(BslPacket, BaudRateIdsAreSlau887Table) {
  EXPECT_EQ(bsl::baudRateId(4800), 1);
  EXPECT_EQ(bsl::baudRateId(9600), 2);
  EXPECT_EQ(bsl::baudRateId(115200), 6);
  EXPECT_EQ(bsl::baudRateId(3000000), 9);
  EXPECT_FALSE(bsl::baudRateId(230400));
}

TEST(BslReply, DeviceInfoExampleOfSlau887Decodes) {
  const Bytes reply = {0x08, 0x19, 0x00, 0x31, 0x00, 0x01, 0x00, 0x01, 0x00, 0x00, 0x00,
                       0x00, 0x01, 0x00, 0xC0, 0x06, 0x60, 0x01, 0x00, 0x20, 0x01, 0x00,
                       0x00, 0x00, 0x01, 0x00, 0x00, 0x00, 0x49, 0x61, 0x57, 0x8C};
  bsl::Reply r;
  size_t needed = 0;
  ASSERT_EQ(bsl::decodeReply(reply, r, needed), bsl::ReplyStatus::Complete);
  const auto info = bsl::parseDeviceInfo(r);
  ASSERT_TRUE(info);
  EXPECT_EQ(info->commandInterpreterVersion, 0x0100);
  EXPECT_EQ(info->pluginVersion, 0x0001);
  EXPECT_EQ(info->bufferSize, 0x06C0);
  EXPECT_EQ(info->bufferStart, 0x20000160U);
  EXPECT_EQ(info->bslConfigId, 1U);
  EXPECT_TRUE(info->complete);
  EXPECT_EQ(flash::chipFromBslBuffer(info->bufferSize), flash::chipByName("mspm0l1306"));
}

TEST(BslReply, MessagesCrcAndIncompleteReplies) {
  bsl::Reply r;
  size_t needed = 0;
  const Bytes success = {0x08, 0x02, 0x00, 0x3B, 0x00, 0x38, 0x02, 0x94, 0x82};  // SLAU887 4.3.3 / 4.3.8
  ASSERT_EQ(bsl::decodeReply(success, r, needed), bsl::ReplyStatus::Complete);
  EXPECT_EQ(r.rsp, 0x3B);
  EXPECT_EQ(r.data, Bytes{0x00});
  const Bytes range = {0x08, 0x02, 0x00, 0x3B, 0x05, 0xB7, 0xF6, 0xFE, 0xF2};  // SLAU887 4.3.10
  ASSERT_EQ(bsl::decodeReply(range, r, needed), bsl::ReplyStatus::Complete);
  EXPECT_EQ(r.data, Bytes{0x05});
  Bytes broken = success;
  broken[6] ^= 0x01;
  EXPECT_EQ(bsl::decodeReply(broken, r, needed), bsl::ReplyStatus::BadCrc);
  EXPECT_EQ(bsl::decodeReply(Bytes(success.begin(), success.begin() + 5), r, needed),
            bsl::ReplyStatus::Incomplete);
  EXPECT_EQ(needed, 9U);
  EXPECT_EQ(bsl::decodeReply(Bytes{0x51}, r, needed), bsl::ReplyStatus::BadHeader);
  EXPECT_EQ(bsl::messageText(0x0A), "MSG 0x0A (address or length not 8-byte aligned)");
  EXPECT_EQ(bsl::ackText(0x52), "0x52 (packet CRC incorrect)");
}

TEST(BslReply, AShortDeviceInfoStillGivesTheBufferSize) {
  bsl::Reply r{0x31, {0x00, 0x01, 0x00, 0x01, 0, 0, 0, 0, 0x01, 0x00, 0xC0, 0x06}};  // a 13-byte core
  const auto info = bsl::parseDeviceInfo(r);
  ASSERT_TRUE(info);
  EXPECT_EQ(info->bufferSize, 0x06C0);
  EXPECT_EQ(info->bufferStart, 0U);
  EXPECT_FALSE(info->complete);
  r.data.resize(11);
  EXPECT_FALSE(bsl::parseDeviceInfo(r));
}

TEST(BslReply, RealG3507DeviceInfoNamesTheG3507) {
  // lenlab's LP-MSPM0G3507 answer: the same fields with buffer 0x3EC0; its CRC ends 0B 5F 2D D1.
  Bytes core = {0x31, 0x00, 0x01, 0x00, 0x01, 0x00, 0x00, 0x00, 0x00, 0x01, 0x00, 0xC0, 0x3E,
                0x60, 0x01, 0x00, 0x20, 0x01, 0x00, 0x00, 0x00, 0x01, 0x00, 0x00, 0x00};
  Bytes reply = cat({0x08, 0x19, 0x00}, core);
  const uint32_t crc = bsl::crc32(core);
  EXPECT_EQ(crc, 0xD12D5F0BU);
  bsl::Reply r;
  size_t needed = 0;
  ASSERT_EQ(bsl::decodeReply(cat(reply, {0x0B, 0x5F, 0x2D, 0xD1}), r, needed), bsl::ReplyStatus::Complete);
  EXPECT_EQ(flash::chipFromBslBuffer(bsl::parseDeviceInfo(r)->bufferSize), flash::chipByName("mspm0g3507"));
}

// ---------------------------------------------------------------------------------------------------------
// Image files

struct TempFile {
  explicit TempFile(const std::string& name, const Bytes& bytes)
      : path((std::filesystem::temp_directory_path() / ("bsl_flash_test_" + name)).string()) {
    std::ofstream(path, std::ios::binary)
        .write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
  }
  TempFile(const std::string& name, const std::string& text)
      : TempFile(name, Bytes(text.begin(), text.end())) {}
  ~TempFile() { std::filesystem::remove(path); }
  std::string path;
};

// A minimal ELF32 ARM executable: one PT_LOAD of `load` at `paddr`, and optionally the record-store symbols
// and a .record_store section.
Bytes elf(uint32_t paddr, const Bytes& load, bool reservedSymbols, bool reservedSection) {
  Bytes f(52, 0);
  auto put16 = [&](size_t at, uint16_t v) {
    f[at] = static_cast<uint8_t>(v), f[at + 1] = static_cast<uint8_t>(v >> 8);
  };
  auto put32 = [&](size_t at, uint32_t v) {
    for (int i = 0; i < 4; ++i)
      f[at + i] = static_cast<uint8_t>(v >> (8 * i));
  };
  auto grow = [&](size_t n) {
    const size_t at = f.size();
    f.resize(at + n, 0);
    return at;
  };
  f[0] = 0x7F, f[1] = 'E', f[2] = 'L', f[3] = 'F', f[4] = 1, f[5] = 1, f[6] = 1;
  put16(16, 2), put16(18, 40), put32(20, 1);
  const size_t ph = grow(32);
  put32(28, static_cast<uint32_t>(ph)), put16(42, 32), put16(44, 1);
  const size_t data = grow(load.size());
  std::copy(load.begin(), load.end(), f.begin() + static_cast<long>(data));
  put32(ph, 1), put32(ph + 4, static_cast<uint32_t>(data)), put32(ph + 8, paddr), put32(ph + 12, paddr);
  put32(ph + 16, static_cast<uint32_t>(load.size())), put32(ph + 20, static_cast<uint32_t>(load.size()));
  // Sections: null, .shstrtab, .strtab, .symtab, .record_store
  const std::string shstr = std::string("\0.shstrtab\0.strtab\0.symtab\0.record_store\0", 42);
  const std::string str = std::string("\0__record_store_start__\0__record_store_end__\0", 45);
  const size_t shstrAt = grow(shstr.size());
  std::copy(shstr.begin(), shstr.end(), f.begin() + static_cast<long>(shstrAt));
  const size_t strAt = grow(str.size());
  std::copy(str.begin(), str.end(), f.begin() + static_cast<long>(strAt));
  const size_t symAt = grow(16 * 3);
  if (reservedSymbols) {
    put32(symAt + 16, 1), put32(symAt + 20, 0xF000);
    put32(symAt + 32, 24), put32(symAt + 36, 0xF800);
  }
  const uint16_t sections = reservedSection ? 5 : 4;
  const size_t sh = grow(40U * sections);
  put32(32, static_cast<uint32_t>(sh)), put16(46, 40), put16(48, sections), put16(50, 1);
  auto section = [&](int i, uint32_t name, uint32_t type, uint32_t addr, size_t off, size_t size,
                     uint32_t link) {
    const size_t s = sh + 40U * static_cast<size_t>(i);
    put32(s, name), put32(s + 4, type), put32(s + 12, addr), put32(s + 16, static_cast<uint32_t>(off));
    put32(s + 20, static_cast<uint32_t>(size)), put32(s + 24, link);
  };
  section(1, 1, 3, 0, shstrAt, shstr.size(), 0);
  section(2, 11, 3, 0, strAt, str.size(), 0);
  section(3, 19, 2, 0, symAt, 48, 2);
  if (reservedSection) section(4, 27, 8, 0xE000, 0, 0x200, 0);
  return f;
}

TEST(FlashImage, ElfLoadSegmentsAndTheReservedFlashMarks) {
  const Bytes code = {0x00, 0x10, 0x00, 0x20, 0xC1, 0x00, 0x00, 0x00, 0xAA, 0xBB};
  TempFile file("a.elf", elf(0, code, true, true));
  std::string error;
  const auto image = flash::FlashImage::load(file.path, error);
  ASSERT_TRUE(image) << error;
  EXPECT_STREQ(image->format(), "ELF");
  ASSERT_EQ(image->runs().size(), 1U);
  EXPECT_EQ(image->runs()[0].bytes, code);
  EXPECT_EQ(image->word(0), 0x20001000U);
  ASSERT_EQ(image->reserved().size(), 2U);
  EXPECT_EQ(image->reserved()[0].origin, "section .record_store");
  EXPECT_EQ(image->reserved()[0].range.begin, 0xE000U);
  EXPECT_EQ(image->reserved()[1].range.begin, 0xF000U);
  EXPECT_EQ(image->reserved()[1].range.end, 0xF800U);
  EXPECT_EQ(flash::chipFromStack(*image->word(0)), flash::chipByName("mspm0l1306"));
  EXPECT_EQ(flash::checkRange(*image, *flash::chipByName("mspm0l1306")), "");
}

TEST(FlashImage, BytesInReservedFlashOrItsSectorsAreRefused) {
  // Reserved: 0xF000..0xF7FF (symbols) and 0xE000..0xE1FF (section, half a sector).
  TempFile inside("b.elf", elf(0xF000, Bytes(8, 0), true, true));
  TempFile apart("c.elf", elf(0xE400, Bytes(8, 0), true, true));
  TempFile shared("d.elf", elf(0xE300, Bytes(8, 0), true, true));
  std::string error;
  const flash::Chip& l1306 = *flash::chipByName("mspm0l1306");
  EXPECT_EQ(flash::checkRange(*flash::FlashImage::load(inside.path, error), l1306),
            inside.path +
                ": the image has bytes in the reserved flash 0x0000F000..0x0000F7FF (symbols "
                "__record_store_start__/__record_store_end__), which a flasher never writes");
  EXPECT_EQ(flash::checkRange(*flash::FlashImage::load(apart.path, error), l1306), "");
  EXPECT_EQ(flash::checkRange(*flash::FlashImage::load(shared.path, error), l1306),
            shared.path +
                ": the image's sectors 0x0000E000..0x0000E3FF share a sector with the reserved flash "
                "0x0000E000..0x0000E1FF (section .record_store): erasing them would destroy it");
}

TEST(FlashImage, IntelHexWithLinearAddressesAndItsErrors) {
  TempFile hex("a.hex", std::string(":020000040000FA\n:0400000000100020CC\n:0400040000C100C176\n"
                                    ":04000003000000C138\n:00000001FF\n"));
  std::string error;
  auto image = flash::FlashImage::load(hex.path, error);
  ASSERT_TRUE(image) << error;
  EXPECT_STREQ(image->format(), "Intel HEX");
  EXPECT_EQ(image->word(0), 0x20001000U);
  EXPECT_EQ(image->word(4), 0xC100C100U);

  TempFile nonmain("n.hex", std::string(":0200000441C0F9\n:0400000001020304F2\n:00000001FF\n"));
  image = flash::FlashImage::load(nonmain.path, error);
  ASSERT_TRUE(image) << error;
  EXPECT_EQ(flash::checkRange(*image, *flash::chipByName("mspm0g3507")),
            nonmain.path +
                ": 4 bytes at 0x41C00000..0x41C00003 lie in NONMAIN flash (0x41C00000..0x41C003FF, the "
                "boot and BSL configuration), outside MAIN flash of the MSPM0G3507 (0x00000000..0x0001FFFF); "
                "bmsctl writes MAIN flash only");

  TempFile badSum("s.hex", std::string(":020000040000FA\n:0400000000100020CD\n:00000001FF\n"));
  EXPECT_FALSE(flash::FlashImage::load(badSum.path, error));
  EXPECT_EQ(error, badSum.path + ":2:18: checksum mismatch");
  TempFile badDigit("d.hex", std::string(":0400000000100G20CC\n:00000001FF\n"));
  EXPECT_FALSE(flash::FlashImage::load(badDigit.path, error));
  EXPECT_EQ(error, badDigit.path + ":1:15: not a hex digit");
  TempFile cut("c.hex", std::string(":0400000000100020CC\n"));
  EXPECT_FALSE(flash::FlashImage::load(cut.path, error));
  EXPECT_EQ(error, cut.path + ":1:1: no end-of-file record: the file is cut short");
  TempFile twice("t.hex", std::string(":0400000000100020CC\n:0400020000100020CA\n:00000001FF\n"));
  EXPECT_FALSE(flash::FlashImage::load(twice.path, error));
}

TEST(FlashImage, BinaryIsAtZeroAndSramBytesAreRefused) {
  TempFile bin("a.bin", Bytes{0x00, 0x80, 0x20, 0x20, 0xC1, 0, 0, 0});
  std::string error;
  auto image = flash::FlashImage::load(bin.path, error);
  ASSERT_TRUE(image) << error;
  EXPECT_EQ(flash::chipFromStack(*image->word(0)), flash::chipByName("mspm0g3507"));
  const auto sram = flash::FlashImage::fromRuns({{0, Bytes(8, 0)}, {0x20200000, Bytes(4, 0)}}, "x.elf");
  EXPECT_EQ(
      flash::checkRange(sram, *flash::chipByName("mspm0g3507")),
      "x.elf: 4 bytes at 0x20200000..0x20200003 lie in SRAM (0x20000000..; a load segment without a flash "
      "load address?), outside MAIN flash of the MSPM0G3507 (0x00000000..0x0001FFFF); bmsctl writes MAIN "
      "flash only");
  const auto big = flash::FlashImage::fromRuns({{0xFFF8, Bytes(16, 0)}}, "y.bin");
  EXPECT_NE(flash::checkRange(big, *flash::chipByName("mspm0l1306"))
                .find("8 bytes at 0x00010000..0x00010007 lie in "
                      "flash beyond the MSPM0L1306's MAIN flash"),
            std::string::npos);
}

// ---------------------------------------------------------------------------------------------------------
// Plan

TEST(FlashPlan, WordsPaddedResetVectorLastSectorsAndVerifyWindows) {
  Bytes code(9001);
  for (size_t i = 0; i < code.size(); ++i)
    code[i] = static_cast<uint8_t>(i * 7);
  const auto image = flash::FlashImage::fromRuns({{0, code}, {0x4003, Bytes{0x11, 0x22}}});
  const flash::FlashPlan p = flash::plan(image, 4096);
  ASSERT_GE(p.chunks.size(), 4U);
  // The word with the initial SP and the reset vector goes last, alone.
  EXPECT_EQ(p.chunks.back().address, 0U);
  EXPECT_EQ(p.chunks.back().bytes, Bytes(code.begin(), code.begin() + 8));
  EXPECT_EQ(p.chunks.front().address, 8U);
  for (const auto& c : p.chunks) {
    EXPECT_EQ(c.address % 8, 0U);
    EXPECT_EQ(c.bytes.size() % 8, 0U);
    EXPECT_LE(c.bytes.size(), 4096U);
  }
  // 9001 bytes end in a partial word, padded with 0xFF; the two lone bytes at 0x4003 become one word.
  const auto& lone = p.chunks[p.chunks.size() - 2];
  EXPECT_EQ(lone.address, 0x4000U);
  EXPECT_EQ(lone.bytes, (Bytes{0xFF, 0xFF, 0xFF, 0x11, 0x22, 0xFF, 0xFF, 0xFF}));
  EXPECT_EQ(p.programBytes, 9008U + 8U);
  // Sectors: 0..0x23FF (9 sectors) and 0x4000..0x43FF.
  ASSERT_EQ(p.erase.size(), 2U);
  EXPECT_EQ(p.erase[0].begin, 0U);
  EXPECT_EQ(p.erase[0].end, 0x2400U);
  EXPECT_EQ(p.erase[1].begin, 0x4000U);
  EXPECT_EQ(p.erase[1].end, 0x4400U);
  ASSERT_EQ(p.verify.size(), 2U);
  Bytes expected(0x2400, 0xFF);
  std::copy(code.begin(), code.end(), expected.begin());
  EXPECT_EQ(p.verify[0].expectedCrc, bsl::crc32(expected));
  // Smaller packets when the BSL asks: whole words.
  const auto pieces = flash::split(p.chunks[0], 1000);
  EXPECT_EQ(pieces[0].bytes.size(), 1000U);
  EXPECT_EQ(pieces[1].address, p.chunks[0].address + 1000);
}

TEST(FlashPlan, VerifyWindowsAreAtMost64KiB) {
  const auto image = flash::FlashImage::fromRuns({{0, Bytes(100 * 1024, 0x5A)}});
  const auto p = flash::plan(image, 4096);
  ASSERT_EQ(p.verify.size(), 2U);
  EXPECT_EQ(p.verify[0].range.size(), 64U * 1024U);
  EXPECT_EQ(p.verify[1].range.size(), 36U * 1024U);
}

// ---------------------------------------------------------------------------------------------------------
// --invoke app frames (firmware/app/can/bms.yaml "Commands")

TEST(InvokeApp, Crc8J1850CheckValueAndFrames) {
  const std::string check = "123456789";
  EXPECT_EQ(flash::crc8J1850({reinterpret_cast<const uint8_t*>(check.data()), check.size()}), 0x4B);
  const flash::CanLine identify = flash::identifyFrame(1, 5);
  EXPECT_EQ(identify.id, 0x603);
  const Bytes covered = {0x03, 0x06, 0x05, 0x01};
  EXPECT_EQ(identify.data, (Bytes{flash::crc8J1850(covered), 0x05, 0x01}));
  const flash::CanLine enter = flash::enterBootloaderFrame(1, 6, 0x12345678);
  EXPECT_EQ(enter.id, 0x606);
  EXPECT_EQ(Bytes(enter.data.begin() + 1, enter.data.end()),
            (Bytes{0x06, 0x01, 0x78, 0x56, 0x34, 0x12, 0xA5}));
  const std::string line = flash::slcanLine(enter);
  EXPECT_EQ(line.substr(0, 5), "t6068");
  EXPECT_EQ(line.back(), '\r');
  const auto back = flash::parseSlcanLine(line.substr(0, line.size() - 1));
  ASSERT_TRUE(back);
  EXPECT_EQ(back->data, enter.data);
  EXPECT_FALSE(flash::parseSlcanLine("t60681122"));
}

}  // namespace
