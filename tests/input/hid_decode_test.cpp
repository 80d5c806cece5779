// Tests for HID report decoding: descriptor layouts, Wacom and UC-Logic protocols, hid-recorder captures.
#include <gtest/gtest.h>

#include <fstream>
#include <iterator>

#include "input/evemu.h"
#include "input/hid_decode.h"
#include "input/hidrecord.h"
#include "test_support.h"

namespace emboss {
namespace {

namespace fs = std::filesystem;

std::vector<uint8_t> readBytes(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return std::vector<uint8_t>((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

TEST(HidRecord, ParsesTheCapture) {
  EMBOSS_REQUIRE_FIXTURES(dir);
  const auto rec = loadHidRecord(dir / "hid" / "Wacom_PenPartner" / "hidrecord.txt");
  ASSERT_TRUE(rec) << rec.error();
  EXPECT_EQ(rec->name, "WACOM FT-0203-UV1.4-2");
  EXPECT_EQ(rec->bus, 3);
  EXPECT_EQ(rec->vendorId, 0x056a);
  EXPECT_EQ(rec->productId, 0x0061);
  EXPECT_EQ(rec->descriptor.size(), 110u);  // "R: 110 ..."
  EXPECT_EQ(rec->descriptor, readBytes(dir / "hid" / "Wacom_PenPartner" / "0003:056A:0061.0022.hid.bin"));
  ASSERT_EQ(rec->reports.size(), 874u);  // grep -c '^E:' hidrecord.txt
  EXPECT_EQ(rec->reports.front().bytes.size(), 8u);
  EXPECT_DOUBLE_EQ(rec->reports.back().time_s, 12.687850);
}

TEST(HidRecord, MalformedLinesNameTheLine) {
  auto r = parseHidRecord("D: 0\nR: 2 05 01\nI: 3 056a 0061\nE: 0.5 3 02 00\n");
  ASSERT_FALSE(r);
  EXPECT_NE(r.error().find("line 4"), std::string::npos) << r.error();
  r = parseHidRecord("I: 3 056a 0061\nE: 0.5 1 02\n");
  ASSERT_FALSE(r);
  EXPECT_NE(r.error().find("R:"), std::string::npos) << r.error();
  r = parseHidRecord("R: 1 zz\n");
  EXPECT_FALSE(r);
}

// The capture is a Wacom 056a:0061 ("PenStation2" in the kernel's table: graphire protocol,
// 3250 x 2320, pressure 255). Counted by hand with
//   grep '^E:' hidrecord.txt | awk '$4=="02"{print $5}' | uniq -c
// which gives the status-byte runs 50x90 17x91 60x90 5x91 10x90 6x10 1x00 88x90 20x94 361x90
// 37x94 16x95 48x94 34x90 3x10 1x00: tip (bit 0) in three runs of 17, 5 and 16 reports; 746
// reports in proximity (bit 7) plus one out-of-proximity sample at each of the two exits = 748.
// Pressure (byte 6) peaks at 99, 96 and 194 in the three strokes.
TEST(HidRecord, PenPartnerCaptureDecodesIntoThreeStrokes) {
  EMBOSS_REQUIRE_FIXTURES(dir);
  const auto rec = loadHidRecord(dir / "hid" / "Wacom_PenPartner" / "hidrecord.txt");
  ASSERT_TRUE(rec) << rec.error();
  auto decoder = makePenDecoder(rec->vendorId, rec->productId, rec->descriptor);
  ASSERT_TRUE(decoder) << decoder.error();
  EXPECT_NE((*decoder)->name().find("graphire"), std::string::npos) << (*decoder)->name();
  const auto samples = decodeHidRecording(*rec);
  ASSERT_TRUE(samples) << samples.error();
  EXPECT_EQ(samples->size(), 748u);
  size_t outOfRange = 0;
  for (const auto& s : *samples) {
    ASSERT_GE(s.x, 0.0);
    ASSERT_LE(s.x, 1.0);
    ASSERT_GE(s.y, 0.0);
    ASSERT_LE(s.y, 1.0);
    ASSERT_GE(s.pressure, 0.0);
    ASSERT_LE(s.pressure, 1.0);
    outOfRange += !s.inRange;
  }
  EXPECT_EQ(outOfRange, 2u);
  const auto strokes = splitStrokes(*samples);
  ASSERT_EQ(strokes.size(), 3u);
  const size_t lengths[] = {17, 5, 16};
  const int peaks[] = {99, 96, 194};
  for (size_t i = 0; i < 3; ++i) {
    const auto& st = strokes[i];
    EXPECT_EQ(st.size(), lengths[i]) << "stroke " << i;
    double peak = 0.0;
    for (const auto& s : st) peak = std::max(peak, s.pressure);
    EXPECT_NEAR(peak, peaks[i] / 255.0, 1e-9) << "stroke " << i;
    EXPECT_LT(st.front().pressure, peak) << "pressure rises in stroke " << i;
    EXPECT_LT(st.back().pressure, peak) << "pressure falls in stroke " << i;
    EXPECT_GT(st.back().time_s, st.front().time_s);
  }
  // The second stroke was drawn with the side button (0x94/0x95): barrel2 (byte 1 bit 2).
  EXPECT_TRUE(strokes[2].front().barrel2);
  EXPECT_FALSE(strokes[0].front().barrel2);
}

TEST(HidDecode, DescriptorLayoutDecodesAHuionReport) {
  EMBOSS_REQUIRE_FIXTURES(dir);
  const auto desc = readBytes(dir / "hid" / "Huion_H640P" / "0003:256C:006D.0005.hid.bin");
  auto decoder = makePenDecoder(0x256c, 0x006d, desc);
  ASSERT_TRUE(decoder) << decoder.error();
  // Report 8: tip + in range (0x41), X = 16000 (of 32000), Y = 5000 (of 20000), pressure 8191.
  const std::vector<uint8_t> report = {0x08, 0x41, 0x80, 0x3e, 0x00, 0x88, 0x13, 0x00, 0xff, 0x1f, 0x00, 0x00};
  const auto s = (*decoder)->decode(report, 1.5);
  ASSERT_TRUE(s);
  EXPECT_DOUBLE_EQ(s->time_s, 1.5);
  EXPECT_DOUBLE_EQ(s->x, 0.5);
  EXPECT_DOUBLE_EQ(s->y, 0.25);
  EXPECT_DOUBLE_EQ(s->pressure, 1.0);
  EXPECT_TRUE(s->tip);
  EXPECT_TRUE(s->inRange);
  EXPECT_FALSE((*decoder)->decode(std::vector<uint8_t>{0x09, 0x41}, 0));  // another report
  EXPECT_FALSE((*decoder)->decode(std::vector<uint8_t>{0x08, 0x41, 0x00}, 0));  // too short
}

TEST(HidDecode, PenWithoutInRangeLeavesAfterSilence) {
  PenLayout l;
  l.reportId = 3;
  l.x = HidValueLoc{0, 8, 0, 200};
  l.y = HidValueLoc{8, 8, 0, 200};
  l.tip = HidValueLoc{16, 1, 0, 1};
  DescriptorPenDecoder d({l}, true);
  const auto s = d.decode(std::vector<uint8_t>{0x03, 100, 50, 0x01}, 1.0);
  ASSERT_TRUE(s);
  EXPECT_TRUE(s->inRange);
  EXPECT_TRUE(s->tip);
  EXPECT_DOUBLE_EQ(s->pressure, 1.0);  // no pressure usage: full pressure while touching
  EXPECT_FALSE(d.idle(1.05));
  const auto out = d.idle(1.2);
  ASSERT_TRUE(out);
  EXPECT_FALSE(out->inRange);
  EXPECT_DOUBLE_EQ(out->x, 0.5);
  EXPECT_FALSE(d.idle(1.5));
}

TEST(HidDecode, NoDecoderForADescriptorWithoutPen) {
  EMBOSS_REQUIRE_FIXTURES(dir);
  const auto desc = readBytes(dir / "hid" / "Wacom_Intuos_S_3rd-gen" / "0003:04F3:003D.0001.hid.bin");
  const auto decoder = makePenDecoder(0x04f3, 0x003d, desc);
  ASSERT_FALSE(decoder);
  EXPECT_NE(decoder.error().find("no pen"), std::string::npos) << decoder.error();
  const auto empty = makePenDecoder(0x28bd, 0x0935, std::vector<uint8_t>{});
  ASSERT_FALSE(empty);
  EXPECT_NE(empty.error().find("empty"), std::string::npos) << empty.error();
  EXPECT_NE(empty.error().find("UC-Logic"), std::string::npos) << empty.error();
}

// hid-uclogic-params.c reads string descriptor 200 with 18 bytes: bLength, bDescriptorType (3),
// then X max (le24 at 2), Y max (le24 at 5), pressure max (le16 at 8), resolution (le16 at 10).
std::vector<uint8_t> v2String(uint32_t x, uint32_t y, uint16_t p, uint16_t res) {
  std::vector<uint8_t> b(18, 0);
  b[0] = 18;
  b[1] = 0x03;
  b[2] = x & 0xff;
  b[3] = (x >> 8) & 0xff;
  b[4] = (x >> 16) & 0xff;
  b[5] = y & 0xff;
  b[6] = (y >> 8) & 0xff;
  b[7] = (y >> 16) & 0xff;
  b[8] = p & 0xff;
  b[9] = p >> 8;
  b[10] = res & 0xff;
  b[11] = res >> 8;
  b[13] = 0x08;  // number of frame buttons on real tablets; not read here
  return b;
}

TEST(Uclogic, ParsesTheV2HandshakeString) {
  const auto p = parseUclogicPenString(200, v2String(100000, 65000, 8191, 5080));
  ASSERT_TRUE(p) << p.error();
  EXPECT_EQ(p->version, 2);
  EXPECT_EQ(p->xMax, 100000);  // needs the third byte: above 16 bits
  EXPECT_EQ(p->yMax, 65000);
  EXPECT_EQ(p->pressureMax, 8191);
  EXPECT_EQ(p->resolution, 5080);
  EXPECT_EQ(p->reportId(), 8);
}

TEST(Uclogic, ParsesTheV1HandshakeString) {
  // String 100 (0x64), 12 bytes: X max le16 at 2, Y max le16 at 4, pressure max le16 at 8, resolution at 10.
  const std::vector<uint8_t> b = {12, 0x03, 0x50, 0xc3, 0x30, 0x75, 0x00, 0x00, 0xff, 0x07, 0xd0, 0x07};
  const auto p = parseUclogicPenString(100, b);
  ASSERT_TRUE(p) << p.error();
  EXPECT_EQ(p->version, 1);
  EXPECT_EQ(p->xMax, 50000);
  EXPECT_EQ(p->yMax, 30000);
  EXPECT_EQ(p->pressureMax, 2047);
  EXPECT_EQ(p->resolution, 2000);
  EXPECT_EQ(p->reportId(), 7);
}

TEST(Uclogic, RejectsWhatIsNotParameters) {
  // The model name in UTF-16LE, as some tablets answer every unknown index.
  std::vector<uint8_t> text = {18, 0x03};
  for (char c : std::string("HUION T")) {
    text.push_back(static_cast<uint8_t>(c));
    text.push_back(0);
  }
  text.resize(18, 0x20);
  text[17] = 0;
  auto p = parseUclogicPenString(200, text);
  ASSERT_FALSE(p);
  EXPECT_NE(p.error().find("text"), std::string::npos) << p.error();
  p = parseUclogicPenString(200, std::vector<uint8_t>{12, 0x03, 1, 2, 3});
  ASSERT_FALSE(p);
  EXPECT_NE(p.error().find("expected 18"), std::string::npos) << p.error();
  auto wrongType = v2String(1000, 1000, 1023, 0);
  wrongType[1] = 0x02;
  EXPECT_FALSE(parseUclogicPenString(200, wrongType));
  EXPECT_FALSE(parseUclogicPenString(200, v2String(0, 1000, 1023, 0)));
  EXPECT_FALSE(parseUclogicPenString(7, v2String(1000, 1000, 1023, 0)));
}

TEST(Uclogic, DecodesFragmentedHighResolutionReports) {
  UclogicPenParams params;
  params.version = 2;
  params.xMax = 0x20000;
  params.yMax = 0x10000;
  params.pressureMax = 8191;
  UclogicPenDecoder d(params);
  // Raw v2 pen report: ID 8, status 0x81 (pen, tip), X low 16 @2, Y low 16 @4, pressure @6,
  // X high byte @8, Y high byte @9, tilt @10, @11. X = 0x010000, Y = 0x008000.
  const std::vector<uint8_t> r = {0x08, 0x81, 0x00, 0x00, 0x00, 0x80, 0xff, 0x0f, 0x01, 0x00, 0x00, 0x00};
  const auto s = d.decode(r, 10.0);
  ASSERT_TRUE(s);
  EXPECT_DOUBLE_EQ(s->x, 0.5);
  EXPECT_DOUBLE_EQ(s->y, 0.5);
  EXPECT_NEAR(s->pressure, 4095.0 / 8191.0, 1e-12);
  EXPECT_TRUE(s->tip);
  EXPECT_TRUE(s->inRange);
  // Frame-button sub-reports (0xe0) carry no pen sample.
  EXPECT_FALSE(d.decode(std::vector<uint8_t>{0x08, 0xe0, 0x01, 0x01, 0, 0, 0, 0, 0, 0, 0, 0}, 10.01));
  // No report for 100 ms: the pen left; reported once.
  EXPECT_FALSE(d.idle(10.05));
  const auto out = d.idle(10.2);
  ASSERT_TRUE(out);
  EXPECT_FALSE(out->inRange);
  EXPECT_FALSE(out->tip);
  EXPECT_DOUBLE_EQ(out->x, 0.5);
  EXPECT_FALSE(d.idle(10.3));
}

TEST(Uclogic, V1InRangeIsInverted) {
  UclogicPenParams params;
  params.version = 1;
  params.xMax = 40000;
  params.yMax = 25000;
  params.pressureMax = 1023;
  UclogicPenDecoder d(params);
  const auto near = d.decode(std::vector<uint8_t>{0x07, 0x80, 0x20, 0x4e, 0xa8, 0x61, 0x00, 0x00}, 0);
  ASSERT_TRUE(near);
  EXPECT_TRUE(near->inRange);
  EXPECT_DOUBLE_EQ(near->x, 0.5);
  EXPECT_DOUBLE_EQ(near->y, 1.0);
  const auto away = d.decode(std::vector<uint8_t>{0x07, 0xc0, 0, 0, 0, 0, 0, 0}, 0);
  ASSERT_TRUE(away);
  EXPECT_FALSE(away->inRange);
}

TEST(Uclogic, ChosenOnlyWhenTheDescriptorDoesNotDescribeTheReport) {
  EMBOSS_REQUIRE_FIXTURES(dir);
  UclogicPenParams params;
  params.xMax = 50800;
  params.yMax = 30480;
  params.pressureMax = 8191;
  // Native descriptor (report 10 only): the raw report 8 needs the UC-Logic decoder.
  auto native = makePenDecoder(0x256c, 0x006d, readBytes(dir / "hid" / "Huion_H640P" / "0003:256C:006D.0006.hid.bin"), params);
  ASSERT_TRUE(native) << native.error();
  EXPECT_NE((*native)->name().find("uc-logic"), std::string::npos) << (*native)->name();
  // Descriptor already rewritten by the kernel's hid-uclogic: the descriptor decodes report 8.
  auto rewritten = makePenDecoder(0x256c, 0x006d, readBytes(dir / "hid" / "Huion_H640P" / "0003:256C:006D.0005.hid.bin"), params);
  ASSERT_TRUE(rewritten) << rewritten.error();
  EXPECT_EQ((*rewritten)->name().find("uc-logic"), std::string::npos) << (*rewritten)->name();
}

TEST(Wacom, Intuos4PacketsAsTheKernelReadsThem) {
  const WacomModel* m = findWacomModel(0x056a, 0x00b9);
  ASSERT_NE(m, nullptr);
  EXPECT_EQ(m->xMax, 44704);
  WacomPenDecoder d(*m);
  // Enter proximity: tool id 0x802 (Intuos4 general pen) from bytes 2, 3, 7, 8.
  EXPECT_FALSE(d.decode(std::vector<uint8_t>{0x02, 0xc2, 0x80, 0x20, 0, 0, 0, 0, 0, 0}, 0));
  // General pen packet (0xe0 | tip 0x01): X = (d2 << 9) | (d3 << 1) | bit 1 of d9 = 22353;
  // pressure = ((d6 << 2) | (d7 >> 6)) << 1 | (d1 & 1) = 2047.
  const std::vector<uint8_t> pkt = {0x02, 0xe1, 0x2b, 0xa8, 0x1b, 0x48, 0xff, 0xc0, 0x00, 0x02};
  const auto s = d.decode(pkt, 1.0);
  ASSERT_TRUE(s);
  EXPECT_NEAR(s->x, 22353.0 / 44704.0, 1e-12);
  EXPECT_NEAR(s->y, ((0x1b << 9) | (0x48 << 1)) / 27940.0, 1e-12);
  EXPECT_DOUBLE_EQ(s->pressure, 1.0);
  EXPECT_TRUE(s->tip);
  // Exit proximity.
  const auto out = d.decode(std::vector<uint8_t>{0x02, 0x80, 0, 0, 0, 0, 0, 0, 0, 0}, 2.0);
  ASSERT_TRUE(out);
  EXPECT_FALSE(out->inRange);
  EXPECT_DOUBLE_EQ(out->x, s->x);
  // A mouse entering is not a pen.
  EXPECT_FALSE(d.decode(std::vector<uint8_t>{0x02, 0xc2, 0x80, 0x60, 0, 0, 0, 0, 0, 0}, 3.0));
  EXPECT_FALSE(d.decode(pkt, 3.1));
}

TEST(Wacom, NewerModelsUseTheirDescriptor) {
  EXPECT_EQ(findWacomModel(0x056a, 0x0374), nullptr);
  EXPECT_EQ(findWacomModel(0x256c, 0x0061), nullptr);
  ASSERT_NE(findWacomModel(0x056a, 0x0061), nullptr);
  EXPECT_EQ(findWacomModel(0x056a, 0x0061)->pressureMax, 255);
}

}  // namespace
}  // namespace emboss
