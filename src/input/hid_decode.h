// HID input reports to PenSamples: via a descriptor's pen layout or the Wacom/UC-Logic vendor protocols.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "devices/pen.h"
#include "input/hid_descriptor.h"
#include "util/result.h"

namespace emboss {

// Turns one device's input reports into pen samples. Stateful (proximity, last position); one per device.
class PenReportDecoder {
 public:
  virtual ~PenReportDecoder() = default;
  // Which decoding this is, for logs ("descriptor report 8", "wacom graphire: Wacom PenStation2").
  virtual std::string name() const = 0;
  // report: as hidraw delivers it, the report-ID byte first when the device numbers its reports.
  // Returns nullopt for reports that carry no pen sample (other report IDs, pads, mice, short data).
  virtual std::optional<PenSample> decode(std::span<const uint8_t> report, double time_s) = 0;
  // Called when no report came for a while: protocols that never report leaving proximity
  // (UC-Logic v2) return an out-of-range sample once, 100 ms after the last report.
  virtual std::optional<PenSample> idle(double now_s) { return std::nullopt; }
};

// One report through a descriptor pen layout. x, y and pressure are (v - logical min) / (logical
// max - logical min), clamped to 0..1; without a pressure usage pressure is 1 while the tip touches;
// without a tip switch the tip is pressure above its minimum; without in-range the pen is in range
// whenever it reports; the eraser touching counts as the tip.
std::optional<PenSample> decodePenReport(const PenLayout& layout, bool usesReportIds, std::span<const uint8_t> report,
                                         double time_s);

class DescriptorPenDecoder final : public PenReportDecoder {
 public:
  DescriptorPenDecoder(std::vector<PenLayout> pens, bool usesReportIds);
  std::string name() const override;
  std::optional<PenSample> decode(std::span<const uint8_t> report, double time_s) override;
  // A pen without an in-range usage only reports while near: 100 ms of silence means it left.
  std::optional<PenSample> idle(double now_s) override;

 private:
  std::vector<PenLayout> pens_;
  bool usesReportIds_ = false;
  std::optional<PenSample> last_;
  bool lastHasInRange_ = true;
};

// ---- Wacom: the fixed-packet protocols of the kernel's wacom_wac.c, selected by product ID.
enum class WacomProtocol : uint8_t { kPenPartner, kGraphire, kIntuos, kIntuos3, kIntuos4 };

struct WacomModel {
  uint16_t productId = 0;
  const char* name = "";
  WacomProtocol protocol = WacomProtocol::kGraphire;
  int32_t xMax = 0;
  int32_t yMax = 0;
  int32_t pressureMax = 0;
};

inline constexpr uint16_t kWacomVendorId = 0x056a;
// The model table entry, or nullptr when the device is not one of the fixed-packet models (newer
// Wacoms describe their pen in the descriptor, on the vendor page 0xFF0D).
const WacomModel* findWacomModel(uint16_t vendorId, uint16_t productId);

class WacomPenDecoder final : public PenReportDecoder {
 public:
  explicit WacomPenDecoder(const WacomModel& model);
  std::string name() const override;
  std::optional<PenSample> decode(std::span<const uint8_t> report, double time_s) override;

 private:
  std::optional<PenSample> penPartner(std::span<const uint8_t> d, double t);
  std::optional<PenSample> graphire(std::span<const uint8_t> d, double t);
  std::optional<PenSample> intuos(std::span<const uint8_t> d, double t);
  PenSample make(double t, int32_t x, int32_t y, int32_t pressure, bool tip, bool inRange, bool b1, bool b2) const;
  PenSample outOfRange(double t) const;

  WacomModel model_;
  bool inProx_ = false;
  bool penTool_ = true;
  PenSample last_;
};

// ---- UC-Logic (Huion, Gaomon, XP-Pen, Ugee): the full-resolution mode of the kernel's hid-uclogic.
inline constexpr uint8_t kUclogicV1StringIndex = 100;  // 0x64: 12-byte pen parameters, report ID 7
inline constexpr uint8_t kUclogicV2StringIndex = 200;  // 0xC8: 18-byte pen parameters, report ID 8
bool isUclogicVendor(uint16_t vendorId);  // 0x256c Huion, 0x28bd XP-Pen, 0x5543 UC-Logic

struct UclogicPenParams {
  int version = 2;          // 1: string 100, 16-bit reports; 2: string 200, 24-bit reports
  int32_t xMax = 0;
  int32_t yMax = 0;
  int32_t pressureMax = 0;
  uint16_t resolution = 0;  // lines per inch, 0 when unknown
  uint8_t reportId() const { return version == 1 ? 7 : 8; }
};

// Parses the raw string descriptor (bLength, bDescriptorType 3, then the parameters) the tablet
// returns for index 100 or 200, as hid-uclogic-params.c reads it:
//   v1 (index 100, 12 bytes): x max le16 @2, y max le16 @4, pressure max le16 @8, resolution le16 @10;
//   v2 (index 200, 18 bytes): x max le24 @2, y max le24 @5, pressure max le16 @8, resolution le16 @10.
// Fails when the bytes are too short, not a string descriptor, or (v2) just a UTF-16 text such as
// the model name that some tablets return for every unknown index.
Result<UclogicPenParams> parseUclogicPenString(uint8_t index, std::span<const uint8_t> descriptor);

class UclogicPenDecoder final : public PenReportDecoder {
 public:
  explicit UclogicPenDecoder(const UclogicPenParams& params);
  std::string name() const override;
  std::optional<PenSample> decode(std::span<const uint8_t> report, double time_s) override;
  std::optional<PenSample> idle(double now_s) override;

 private:
  UclogicPenParams params_;
  PenSample last_;
  bool inRange_ = false;
};

// Tries several decoders in turn; the first to give a sample wins.
class ChainPenDecoder final : public PenReportDecoder {
 public:
  explicit ChainPenDecoder(std::vector<std::unique_ptr<PenReportDecoder>> decoders);
  std::string name() const override;
  std::optional<PenSample> decode(std::span<const uint8_t> report, double time_s) override;
  std::optional<PenSample> idle(double now_s) override;

 private:
  std::vector<std::unique_ptr<PenReportDecoder>> decoders_;
};

// Picks the decoding for a device: a Wacom fixed-packet model by product ID; else, for a UC-Logic
// vendor whose handshake gave parameters (and whose descriptor does not already describe that
// report, as it does when the kernel's hid-uclogic rewrote it), the UC-Logic decoder; else the
// pens in the descriptor. Fails with the reason when none applies.
Result<std::unique_ptr<PenReportDecoder>> makePenDecoder(uint16_t vendorId, uint16_t productId,
                                                         std::span<const uint8_t> descriptor,
                                                         const std::optional<UclogicPenParams>& uclogic = std::nullopt);

}  // namespace emboss
