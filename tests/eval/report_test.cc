// Text table and JSON rendering of evaluation results.

#include "eval/report.h"

#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "eval/number_format.h"
#include "eval_test_util.h"

namespace mvtrack::eval {
namespace {

using testing::Add;
using testing::At;

// The one-switch case of tracking_metrics_test.cc: MOTA = 5/6, IDF1 = 2/3.
TrackingEvaluation OneSwitch() {
  EvalSequence gt;
  EvalSequence pred;
  for (FrameIndex f = 0; f < 6; ++f) {
    const double x = 0.2 * static_cast<double>(f);
    Add(&gt, f, At(1, x, 0.0));
    Add(&pred, f, At(f < 4 ? 7 : 8, x, 0.0));
  }
  return EvaluateTracking(gt, pred, TrackingOptions{});
}

// Checks that brackets and braces outside strings balance and strings are terminated.
bool Balanced(const std::string& json) {
  std::vector<char> stack;
  bool in_string = false;
  for (std::size_t i = 0; i < json.size(); ++i) {
    const char c = json[i];
    if (in_string) {
      if (c == '\\') {
        ++i;
      } else if (c == '"') {
        in_string = false;
      }
      continue;
    }
    if (c == '"') in_string = true;
    if (c == '{' || c == '[') stack.push_back(c);
    if (c == '}' || c == ']') {
      if (stack.empty() || stack.back() != (c == '}' ? '{' : '[')) return false;
      stack.pop_back();
    }
  }
  return stack.empty() && !in_string;
}

TEST_CASE("FormatFixed is locale-free, fixed precision and never prints -0", "[unit]") {
  CHECK(internal::FormatFixed(0.5, 3) == "0.500");
  CHECK(internal::FormatFixed(5.0 / 6.0, 6) == "0.833333");
  CHECK(internal::FormatFixed(2.0 / 3.0, 2) == "0.67");
  CHECK(internal::FormatFixed(-1e-9, 4) == "0.0000");
  CHECK(internal::FormatFixed(-0.0, 2) == "0.00");
  CHECK(internal::FormatFixed(-0.004, 2) == "0.00");
  CHECK(internal::FormatFixed(-0.006, 2) == "-0.01");
  CHECK(internal::FormatFixed(1234.56, 1) == "1234.6");
  CHECK(internal::FormatFixed(std::nan(""), 3) == "nan");
  CHECK(internal::FormatFixed(-std::numeric_limits<double>::infinity(), 3) == "-inf");
}

TEST_CASE("JSON: sorted keys, fixed precision, null for undefined values", "[unit]") {
  EvaluationReport report;
  report.tracking = OneSwitch();
  REQUIRE(report.tracking->valid);
  const std::string json = ReportToJson(report, 6);
  CHECK(Balanced(json));
  CHECK(json.back() == '\n');
  CHECK(json.find("\"schema\": \"mvtrack.eval/1\"") != std::string::npos);
  CHECK(json.find("\"mota\": 0.833333") != std::string::npos);
  CHECK(json.find("\"idf1\": 0.666667") != std::string::npos);
  CHECK(json.find("\"num_switches\": 1,") != std::string::npos);
  CHECK(json.find("\"threshold_m\": 0.500000") != std::string::npos);
  // No joints: MPJPE is undefined and written as null.
  CHECK(json.find("\"mpjpe_m\": null") != std::string::npos);
  // Keys are sorted: within clear_mot, "mostly_lost" < "mota" < "motp_m" < "num_false_positives".
  const auto pos = [&json](const char* key) { return json.find(std::string("\"") + key + "\""); };
  CHECK(pos("mostly_lost") < pos("mota"));
  CHECK(pos("mota") < pos("motp_m"));
  CHECK(pos("motp_m") < pos("num_false_positives"));
  CHECK(pos("schema") < pos("tracking"));
  // The switch event is listed.
  CHECK(json.find("\"previous_prediction_id\": 7") != std::string::npos);
  // Precision is honoured and the output is a pure function of the input.
  CHECK(ReportToJson(report, 2).find("\"mota\": 0.83,") != std::string::npos);
  CHECK(ReportToJson(report, 6) == json);
}

TEST_CASE("JSON escapes strings and reports invalid results", "[unit]") {
  EvaluationReport report;
  PcpProtocol protocol;
  protocol.name = "quote\"back\\slash\ttab";
  protocol.bones = {PcpBone::Between("b", 0, 1)};
  EvalObject g = At(0, 0, 0);
  g.joints = {Vec3(0, 0, 0), Vec3(1, 0, 0)};
  const EvalSequence gt = testing::Sequence({{0, {g}}});
  report.pcp = EvaluatePcp(gt, gt, protocol, PcpOptions{});
  REQUIRE(report.pcp->valid);
  const std::string json = ReportToJson(report);
  CHECK(Balanced(json));
  CHECK(json.find("quote\\\"back\\\\slash\\ttab") != std::string::npos);
  CHECK(json.find("\"average_pcp\": 1.000000") != std::string::npos);
  CHECK(json.find("\"tracking\"") == std::string::npos);

  TrackingOptions bad;
  bad.mean_joint_threshold_m = -1.0;
  report.tracking = EvaluateTracking(gt, gt, bad);
  REQUIRE_FALSE(report.tracking->valid);
  const std::string with_error = ReportToJson(report);
  CHECK(Balanced(with_error));
  CHECK(with_error.find("\"valid\": false") != std::string::npos);
  CHECK(with_error.find("mean_joint_threshold_m") != std::string::npos);
  CHECK(with_error.find("\"clear_mot\"") == std::string::npos);
}

TEST_CASE("Text table shows percentages, metres and n/a", "[unit]") {
  EvaluationReport report;
  report.tracking = OneSwitch();
  const std::string table = FormatReportTable(report);
  CHECK(table.find("MOTA%") != std::string::npos);
  CHECK(table.find("83.33") != std::string::npos);   // MOTA 5/6
  CHECK(table.find("66.67") != std::string::npos);   // IDF1 2/3
  CHECK(table.find("0.0000") != std::string::npos);  // MOTP: exact positions
  CHECK(table.find("MPJPE n/a") != std::string::npos);
  CHECK(table.find("Protocol: CLEAR MOT") != std::string::npos);
  CHECK(table.back() == '\n');
  CHECK(FormatReportTable(EvaluationReport{}) == "No evaluation results.\n");
}

}  // namespace
}  // namespace mvtrack::eval
