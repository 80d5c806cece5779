// The staff protocol: requests parse and round-trip, bad ones are refused with a reason, names are safe.
#include "staff/staff_protocol.h"

#include <gtest/gtest.h>

namespace emboss {
namespace {

TEST(StaffProtocol, RequestsRoundTrip) {
  StaffRequest r;
  r.command = StaffRequest::Command::Export;
  r.dest = "/media/emboss-export";
  r.sinceUnix = 1.7e9;
  const auto back = parseStaffRequest(staffRequestLine(r));
  ASSERT_TRUE(back) << back.error();
  EXPECT_EQ(back->command, StaffRequest::Command::Export);
  EXPECT_EQ(back->dest, r.dest);
  EXPECT_EQ(back->sinceUnix, r.sinceUnix);
  EXPECT_FALSE(back->allowAnyDir);
  EXPECT_FALSE(back->progress);
  r.progress = true;
  EXPECT_TRUE(parseStaffRequest(staffRequestLine(r))->progress);
}

TEST(StaffProtocol, ProgressLinesRoundTripAndAreNotAnswers) {
  const StaffProgress p{3, 12, 1234567};
  const auto back = parseStaffProgress(staffProgressLine(p));
  ASSERT_TRUE(back);
  EXPECT_EQ(back->sessionsDone, 3u);
  EXPECT_EQ(back->sessions, 12u);
  EXPECT_EQ(back->bytes, 1234567u);
  EXPECT_EQ(staffProgressText(p), "3/12 sessions, 1.2 MB");
  // The answer that ends an export is never taken for progress, nor is anything malformed.
  EXPECT_FALSE(parseStaffProgress(R"({"ok":true,"folder":"/media/x","files":2,"bytes":10})"));
  EXPECT_FALSE(parseStaffProgress(R"({"ok":false,"progress":{"sessions_done":1,"sessions":2,"bytes":3}})"));
  EXPECT_FALSE(parseStaffProgress(R"({"progress":{"sessions_done":-1,"sessions":2,"bytes":3}})"));
  EXPECT_FALSE(parseStaffProgress(R"({"progress":{"sessions":2,"bytes":3}})"));
  EXPECT_FALSE(parseStaffProgress("not json"));
}

TEST(StaffProtocol, BadRequestsSayWhy) {
  EXPECT_NE(parseStaffRequest("nonsense").error().find("JSON"), std::string::npos);
  EXPECT_NE(parseStaffRequest(R"({"cmd":"format"})").error().find("unknown command"), std::string::npos);
  EXPECT_NE(parseStaffRequest(R"({"cmd":"export"})").error().find("dest"), std::string::npos);
  EXPECT_NE(parseStaffRequest(R"({"cmd":"export","dest":"relative/dir"})").error().find("absolute"), std::string::npos);
  EXPECT_NE(parseStaffRequest(R"({"cmd":"wipe","older_than_days":-1})").error().find("older_than_days"), std::string::npos);
  EXPECT_FALSE(parseStaffRequest(R"({"cmd":"wipe","older_than_days":1e308})"));
  EXPECT_NE(parseStaffRequest(R"({"cmd":"export","dest":"/media/x","progress":"yes"})").error().find("progress"), std::string::npos);
}

TEST(StaffProtocol, ExportDestinationMustBeAFolderOffTheRootFileSystem) {
  EXPECT_FALSE(checkExportDestination("/no/such/folder", false));
  EXPECT_FALSE(checkExportDestination("/no/such/folder", true));
  // The test's temporary folder is on the root file system here or on a tmpfs; either way, allowed
  // with allowAnyDir.
  EXPECT_TRUE(checkExportDestination(::testing::TempDir(), true));
}

TEST(StaffProtocol, SinceTakesDatesAndDays) {
  EXPECT_DOUBLE_EQ(*parseSince("7d", 1e9), 1e9 - 7 * 86400.0);
  EXPECT_TRUE(parseSince("2026-11-01", 1e9));
  EXPECT_FALSE(parseSince("yesterday", 1e9));
  EXPECT_FALSE(parseSince("2026-13-45x", 1e9));
}

TEST(StaffProtocol, SanitizedNamesStayInTheirFolder) {
  EXPECT_EQ(sanitizeName("../../etc/passwd"), ".._.._etc_passwd");
  EXPECT_EQ(sanitizeName(".."), "_..");
  EXPECT_EQ(sanitizeName(""), "_");
  EXPECT_EQ(sanitizeName("session-20261125-101010"), "session-20261125-101010");
}

}  // namespace
}  // namespace emboss
