// Tests for the HID report-descriptor parser and the pen finder, on real descriptors and built ones.
#include <gtest/gtest.h>

#include <fstream>
#include <iterator>

#include "input/hid_descriptor.h"
#include "test_support.h"

namespace emboss {
namespace {

namespace fs = std::filesystem;

std::vector<uint8_t> readBytes(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return std::vector<uint8_t>((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

void expectLoc(const std::optional<HidValueLoc>& loc, uint32_t bit, uint32_t size, int32_t max, const char* what) {
  ASSERT_TRUE(loc) << what << " missing";
  EXPECT_EQ(loc->bit, bit) << what;
  EXPECT_EQ(loc->size, size) << what;
  EXPECT_EQ(loc->max, max) << what;
}

TEST(HidDescriptor, EveryFixtureParsesAndEmptyOnesFailClearly) {
  EMBOSS_REQUIRE_FIXTURES(dir);
  size_t parsed = 0;
  size_t empty = 0;
  for (const auto& e : fs::recursive_directory_iterator(dir / "hid")) {
    const std::string name = e.path().filename().string();
    if (name.size() < 8 || name.substr(name.size() - 8) != ".hid.bin") continue;
    const auto bytes = readBytes(e.path());
    const auto d = parseHidDescriptor(bytes);
    if (bytes.empty()) {
      ASSERT_FALSE(d) << name;
      EXPECT_NE(d.error().find("empty"), std::string::npos) << d.error();
      ++empty;
      continue;
    }
    ASSERT_TRUE(d) << name << ": " << d.error();
    EXPECT_FALSE(d->fields.empty()) << name;
    EXPECT_TRUE(d->warnings.empty()) << name << ": " << d->warnings.front();
    ++parsed;
  }
  // 12 .hid.bin files in hid/ (find hid -name "*.hid.bin" | wc -l): the XP-Pen .0008/.0009 are 0 bytes.
  EXPECT_EQ(parsed, 10u);
  EXPECT_EQ(empty, 2u);
}

// Figures read off the decoded .hid.txt listings: bits after the report-ID byte are the sum of
// Report Size x Report Count of the Input items before the value in the same report.
struct PenFigures {
  const char* file;
  uint8_t reportId;
  uint32_t xBit, xSize;
  int32_t xMax;
  uint32_t yBit, ySize;
  int32_t yMax;
  uint32_t pBit, pSize;
  int32_t pMax;
  uint32_t tipBit, inRangeBit;
};

class HidPens : public ::testing::TestWithParam<PenFigures> {};

TEST_P(HidPens, FoundWhereTheListingSays) {
  EMBOSS_REQUIRE_FIXTURES(dir);
  const auto& f = GetParam();
  const auto d = parseHidDescriptor(readBytes(dir / "hid" / f.file));
  ASSERT_TRUE(d) << d.error();
  const auto pens = findPens(*d);
  ASSERT_EQ(pens.size(), 1u) << f.file;
  const auto& p = pens[0];
  EXPECT_EQ(p.reportId, f.reportId);
  expectLoc(p.x, f.xBit, f.xSize, f.xMax, "x");
  expectLoc(p.y, f.yBit, f.ySize, f.yMax, "y");
  expectLoc(p.pressure, f.pBit, f.pSize, f.pMax, "pressure");
  expectLoc(p.tip, f.tipBit, 1, 1, "tip");
  expectLoc(p.inRange, f.inRangeBit, 1, 1, "in range");
  ASSERT_TRUE(p.barrel1);
  EXPECT_EQ(p.barrel1->bit, 1u);
}

INSTANTIATE_TEST_SUITE_P(
    Fixtures, HidPens,
    ::testing::Values(
        // Huion H640P under hid-uclogic: report 8; 3 buttons, 3 pad, in range, 1 pad; Push; X, Y 24 bits; Pop; pressure 16.
        PenFigures{"Huion_H640P/0003:256C:006D.0005.hid.bin", 8, 8, 24, 32000, 32, 24, 20000, 56, 16, 8191, 0, 6},
        PenFigures{"Huion_H640P/0003:256C:006D.000C.hid.bin", 8, 8, 24, 32000, 32, 24, 20000, 56, 16, 8191, 0, 6},
        // Huion H640P native: report 10; 6 switch bits, in range, pad; X, Y, pressure 16 bits each.
        PenFigures{"Huion_H640P/0003:256C:006D.0006.hid.bin", 10, 8, 16, 32767, 24, 16, 32767, 40, 16, 8191, 0, 6},
        // Goodix screen pen: report 8; 4 switches, pad, in range, 2 pad, contact id 8 bits; X, Y, pressure 16.
        PenFigures{"Huion_H640P/0018:27C6:0113.0004.hid.bin", 8, 16, 16, 6400, 32, 16, 10240, 48, 16, 4095, 0, 5},
        // Wacom Intuos S on the vendor page 0xFF0D: report 16; X 0x0130, Y 0x0131 24 bits, pressure 0x30 16 bits.
        PenFigures{"Wacom_Intuos_S_3rd-gen/0003:056A:0374.0005.hid.bin", 16, 8, 24, 15200, 32, 24, 9500, 56, 16, 4095, 0, 5},
        // XP-Pen Deco L: report 2; pressure is 13 bits.
        PenFigures{"XP-Pen_Deco_L/0003:28BD:0935.000A.hid.bin", 2, 8, 16, 50800, 24, 16, 30480, 40, 13, 8191, 0, 5}));

TEST(HidDescriptor, NoPenWhereThereIsNone) {
  EMBOSS_REQUIRE_FIXTURES(dir);
  // Elan touch screen (fingers only) and the PenPartner (vendor page report 2).
  for (const char* f : {"Wacom_Intuos_S_3rd-gen/0003:04F3:003D.0001.hid.bin", "Wacom_PenPartner/0003:056A:0061.0022.hid.bin"}) {
    const auto d = parseHidDescriptor(readBytes(dir / "hid" / f));
    ASSERT_TRUE(d) << f << ": " << d.error();
    EXPECT_TRUE(findPens(*d).empty()) << f;
  }
}

TEST(HidDescriptor, PenPartnerFields) {
  EMBOSS_REQUIRE_FIXTURES(dir);
  const auto d = parseHidDescriptor(readBytes(dir / "hid" / "Wacom_PenPartner" / "0003:056A:0061.0022.hid.bin"));
  ASSERT_TRUE(d) << d.error();
  EXPECT_TRUE(d->usesReportIds);
  // Report 1 (mouse): 3 buttons + 5 pad + X, Y, wheel 8 bits + 3 constant bytes = 56 bits.
  EXPECT_EQ(d->reportBits(HidReportType::kInput, 1), 56u);
  // Report 2: 7 vendor bytes; report 99: 7 bytes; features 2 and 3: 1 byte each.
  EXPECT_EQ(d->reportBits(HidReportType::kInput, 2), 56u);
  EXPECT_EQ(d->reportBits(HidReportType::kInput, 99), 56u);
  EXPECT_EQ(d->reportBits(HidReportType::kFeature, 3), 8u);
  ASSERT_FALSE(d->fields.empty());
  EXPECT_EQ(d->fields[0].usageAt(0), hidUsage(0x09, 1));  // Usage Minimum/Maximum 1..3 on the Button page
  EXPECT_EQ(d->fields[0].usageAt(2), hidUsage(0x09, 3));
  EXPECT_EQ(d->fields[0].usageAt(7), hidUsage(0x09, 3));  // past the range the last usage repeats
}

// A hand-built pen descriptor exercising the less common items.
const std::vector<uint8_t> kBuilt = {
    0x05, 0x0d,                    // Usage Page (Digitizer)
    0x09, 0x02,                    // Usage (Pen)
    0xa1, 0x01,                    // Collection (Application)
    0x85, 0x05,                    //   Report ID (5)
    0x0b, 0x20, 0x00, 0x0d, 0x00,  //   Usage (0x000D0020 Stylus), extended 32-bit
    0xa0,                          //   Collection (Physical), no data bytes
    0x14,                          //     Logical Minimum (0), no data bytes
    0x25, 0x01,                    //     Logical Maximum (1)
    0x75, 0x01, 0x95, 0x02,        //     Report Size 1, Count 2
    0x09, 0x42, 0x09, 0x32,        //     Usage (Tip Switch), Usage (In Range)
    0x81, 0x02,                    //     Input (Variable)
    0xfe, 0x02, 0x10, 0xaa, 0xbb,  //     a long item, skipped
    0x95, 0x06, 0x81, 0x03,        //     6 bits of padding
    0xa4,                          //     Push
    0x09, 0x30, 0x09, 0x31,        //     Usage (0x30), Usage (0x31) before their page ...
    0x05, 0x01,                    //     ... Usage Page (Desktop): they become X and Y
    0x75, 0x10, 0x95, 0x02,        //     Report Size 16, Count 2
    0x26, 0xff, 0x7f,              //     Logical Maximum (32767)
    0x81, 0x02,                    //     Input (Variable)
    0xb4,                          //     Pop: back to Digitizer, 1 bit, max 1
    0x09, 0x30,                    //     Usage (Tip Pressure)
    0x75, 0x0c, 0x95, 0x01,        //     Report Size 12, Count 1
    0x26, 0xff, 0x0f,              //     Logical Maximum (4095)
    0x81, 0x02,                    //     Input (Variable)
    0x15, 0x81, 0x25, 0x7f,        //     Logical Minimum (-127), Maximum (127)
    0x75, 0x08, 0x09, 0x3d,        //     Report Size 8, Usage (X Tilt)
    0x81, 0x02,                    //     Input (Variable)
    0xc0,                          //   End Collection
    0xc0,                          // End Collection
};

TEST(HidDescriptor, BuiltDescriptorWithPushPopLongItemsAndLatePage) {
  const auto d = parseHidDescriptor(kBuilt);
  ASSERT_TRUE(d) << d.error();
  EXPECT_TRUE(d->warnings.empty());
  ASSERT_EQ(d->collections.size(), 2u);
  EXPECT_EQ(d->collections[1].usage, hidusage::kStylus);
  EXPECT_EQ(d->collections[1].type, 0);
  EXPECT_EQ(d->reportBits(HidReportType::kInput, 5), 2u + 6u + 32u + 12u + 8u);
  const auto pens = findPens(*d);
  ASSERT_EQ(pens.size(), 1u);
  const auto& p = pens[0];
  EXPECT_EQ(p.reportId, 5);
  EXPECT_EQ(p.application, hidusage::kPen);
  expectLoc(p.tip, 0, 1, 1, "tip");
  expectLoc(p.inRange, 1, 1, 1, "in range");
  expectLoc(p.x, 8, 16, 32767, "x");
  expectLoc(p.y, 24, 16, 32767, "y");
  expectLoc(p.pressure, 40, 12, 4095, "pressure");
}

TEST(HidDescriptor, MalformedInputFailsWithTheOffset) {
  const std::vector<uint8_t> truncated = {0x05, 0x0d, 0x26, 0xff};  // Logical Maximum missing a byte
  auto d = parseHidDescriptor(truncated);
  ASSERT_FALSE(d);
  EXPECT_NE(d.error().find("byte 2"), std::string::npos) << d.error();
  d = parseHidDescriptor(std::vector<uint8_t>{0xb4});
  ASSERT_FALSE(d);
  EXPECT_NE(d.error().find("Pop"), std::string::npos);
  d = parseHidDescriptor(std::vector<uint8_t>{0xc0});
  ASSERT_FALSE(d);
  EXPECT_NE(d.error().find("End Collection"), std::string::npos);
  d = parseHidDescriptor(std::vector<uint8_t>{0x85, 0x00});
  ASSERT_FALSE(d);
  EXPECT_NE(d.error().find("Report ID 0"), std::string::npos);
  d = parseHidDescriptor(std::vector<uint8_t>{0x75, 0x08, 0x96, 0xff, 0xff, 0x81, 0x02});
  ASSERT_FALSE(d);
  EXPECT_NE(d.error().find("Report Count"), std::string::npos);
  d = parseHidDescriptor(std::vector<uint8_t>{0xfe, 0x05, 0x00, 0x01});
  EXPECT_FALSE(d);
  d = parseHidDescriptor(std::vector<uint8_t>{});
  ASSERT_FALSE(d);
  EXPECT_NE(d.error().find("empty"), std::string::npos);
}

TEST(HidDescriptor, LargeFieldsStayFast) {
  // 12288 one-bit values with 6000 declared usages: the pen finder must not go quadratic.
  std::vector<uint8_t> d = {0x05, 0x0d, 0x09, 0x20, 0xa1, 0x01, 0x75, 0x01, 0x96, 0x00, 0x30};
  for (int i = 0; i < 6000; ++i) {
    d.push_back(0x09);
    d.push_back(static_cast<uint8_t>(0x40 + i % 8));
  }
  for (uint8_t b : {0x81, 0x02, 0x05, 0x01, 0x09, 0x30, 0x09, 0x31, 0x75, 0x10, 0x95, 0x02, 0x81, 0x02, 0xc0}) d.push_back(b);
  const auto parsed = parseHidDescriptor(d);
  ASSERT_TRUE(parsed) << parsed.error();
  const auto pens = findPens(*parsed);
  ASSERT_EQ(pens.size(), 1u);
  expectLoc(pens[0].x, 12288, 16, 0, "x");
  expectLoc(pens[0].tip, 2, 1, 0, "tip");
}

TEST(HidDescriptor, WacomVendorPageIsEquivalent) {
  EXPECT_EQ(hidEquivalentUsage(0xff0d0130), hidusage::kX);
  EXPECT_EQ(hidEquivalentUsage(0xff0d0042), hidusage::kTipSwitch);
  EXPECT_EQ(hidEquivalentUsage(0xff0d1013), 0xff0d1013u);
  EXPECT_EQ(hidEquivalentUsage(hidusage::kY), hidusage::kY);
}

TEST(HidDescriptor, ExtractBits) {
  const std::vector<uint8_t> data = {0xb4, 0x5a, 0xff, 0x01};
  EXPECT_EQ(hidExtractBits(data, 0, 8), 0xb4u);
  EXPECT_EQ(hidExtractBits(data, 4, 8), 0xabu);
  EXPECT_EQ(hidExtractBits(data, 8, 16), 0xff5au);
  EXPECT_EQ(hidExtractBits(data, 31, 1), 0u);
  EXPECT_EQ(hidExtractBits(data, 24, 1), 1u);
  EXPECT_FALSE(hidExtractBits(data, 30, 8));
  EXPECT_FALSE(hidExtractBits(data, 0, 33));
  EXPECT_EQ(hidExtractValue(data, HidValueLoc{16, 8, -127, 127}), -1);
  EXPECT_EQ(hidExtractValue(data, HidValueLoc{16, 8, 0, 255}), 255);
}

}  // namespace
}  // namespace emboss
