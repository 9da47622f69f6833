// The SLCAN side of the L1306 board (firmware/app/command/slcan_adapter.hpp): every line python-can's slcan
// interface and slcand send, answered as the LAWICEL protocol answers (CR OK, BEL error, z for a frame), and
// malformed lines refused with BEL without changing anything.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "app/command/slcan_adapter.hpp"

namespace {

using fw::app::command::SlcanAdapter;

struct Rig {
  SlcanAdapter adapter;
  SlcanAdapter::Info info{0x1306, false};
  std::vector<fw::hal::CanFrame> frames;
  // Feeds `text`; returns the answers, one per line ended.
  std::string feed(const std::string& text) {
    std::string out;
    for (char c : text) {
      SlcanAdapter::Line line;
      if (!adapter.take(static_cast<uint8_t>(c))) continue;
      adapter.answer(info, line);
      out.append(reinterpret_cast<const char*>(line.answer), line.answerLength);
      if (line.hasFrame) frames.push_back(line.frame);
    }
    return out;
  }
};

TEST(SlcanAdapter, PythonCanOpensAtFiveHundredKilobitsAndSendsAFrame) {
  Rig r;
  // python-can 4.1 slcanBus(bitrate=500000): C, S6, O (can/interfaces/slcan.py set_bitrate, open).
  EXPECT_EQ(r.feed("C\r"), "\a");  // closing a closed channel is an error (nothing else happens)
  EXPECT_EQ(r.feed("S6\r"), "\r");
  EXPECT_EQ(r.adapter.bitrateCode(), 6);
  EXPECT_FALSE(r.adapter.open());
  EXPECT_EQ(r.feed("O\r"), "\r");
  EXPECT_TRUE(r.adapter.open());
  // send(): "t%03X%d" + "%02X" per byte, then CR.
  EXPECT_EQ(r.feed("t6003950301\r"), "z\r");
  ASSERT_EQ(r.frames.size(), 1U);
  EXPECT_EQ(r.frames[0].id, 0x600U);
  EXPECT_FALSE(r.frames[0].extended);
  EXPECT_EQ(r.frames[0].dlc, 3);
  EXPECT_EQ(r.frames[0].data[0], 0x95);
  EXPECT_EQ(r.frames[0].data[2], 0x01);
  // shutdown(): C.
  EXPECT_EQ(r.feed("C\r"), "\r");
  EXPECT_FALSE(r.adapter.open());
}

TEST(SlcanAdapter, VersionSerialNumberAndStatusFlags) {
  Rig r;
  // get_version(): "V" + 4 digits (hardware 01, software major*10+minor), 6 characters with the CR.
  EXPECT_EQ(r.feed("V\r"), "V0101\r");
  // get_serial_number(): "N" + 4 characters.
  EXPECT_EQ(r.feed("N\r"), "N1306\r");
  EXPECT_EQ(r.feed("F\r"), "\a");  // only while open
  r.feed("O\r");
  EXPECT_EQ(r.feed("F\r"), "F00\r");
  r.info.overrunSinceLast = true;
  EXPECT_EQ(r.feed("F\r"), "F08\r");  // bit 3: data overrun
}

TEST(SlcanAdapter, ExtendedFramesAndLowerCaseHexAreTaken) {
  Rig r;
  r.feed("O\r");
  EXPECT_EQ(r.feed("T18FF50E52abcd\r"), "Z\r");
  ASSERT_EQ(r.frames.size(), 1U);
  EXPECT_TRUE(r.frames[0].extended);
  EXPECT_EQ(r.frames[0].id, 0x18FF50E5U);
  EXPECT_EQ(r.frames[0].data[0], 0xAB);
  EXPECT_EQ(r.feed("t1230\r"), "z\r");  // no data
  EXPECT_EQ(r.frames.back().dlc, 0);
  EXPECT_EQ(r.feed("\n\r"), "\r");  // a LF is ignored; an empty line is OK
}

TEST(SlcanAdapter, AMalformedLineGetsBelAndChangesNothing) {
  Rig r;
  EXPECT_EQ(r.feed("t6003950301\r"), "\a");  // a frame while closed
  r.feed("O\r");
  const std::vector<std::string> bad = {
      "t60039503\r",                      // data shorter than the DLC
      "t600395030101\r",                  // longer
      "t6009\r",                          // DLC 9
      "t8000\r",                          // identifier above 0x7FF
      "t6G03950301\r",                    // not hex
      "T2000000010\r",                    // extended identifier above 0x1FFFFFFF
      "t60\r",                            // too short
      "S6\r",                             // bit rate while open
      "S9\r",                             // no such bit rate
      "O\r",                              // open while open
      "r6003\r",                          // remote frames are not taken
      "X\r",                              // unknown command
      "V1\r",                             // V takes nothing
      "t6003950301000000000000000000\r",  // longer than any valid line
      std::string("t600\0"
                  "3\r",
                  7),  // a NUL byte
  };
  for (const std::string& line : bad) {
    EXPECT_EQ(r.feed(line), "\a") << line;
    EXPECT_TRUE(r.adapter.open()) << line;
    EXPECT_EQ(r.adapter.bitrateCode(), 0) << line;
  }
  EXPECT_TRUE(r.frames.empty());
  // The next good line is read as if nothing had happened.
  EXPECT_EQ(r.feed("t6003950301\r"), "z\r");
  EXPECT_EQ(r.frames.size(), 1U);
}

}  // namespace
