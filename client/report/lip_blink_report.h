// The LipBlink report: mouth and eye values before and after, speech intervals and blinks
// marked, the sequence of mouth shapes.
#ifndef KOMA_CLIENT_REPORT_LIP_BLINK_REPORT_H_
#define KOMA_CLIENT_REPORT_LIP_BLINK_REPORT_H_

#include <string>

#include "absl/status/status.h"
#include "client/report/report_writer.h"
#include "koma/v1/retime.pb.h"

namespace koma::client::report {

class LipBlinkReportWriter : public ReportWriter {
 public:
  // Keeps references: request and response must outlive the writer.
  LipBlinkReportWriter(const v1::LipBlinkRequest& request, const v1::LipBlinkResponse& response,
                       std::string input_name)
      : request_(request), response_(response), input_name_(std::move(input_name)) {}

  std::string_view Kind() const override { return "lipblink"; }
  std::string Title() const override;
  nlohmann::json Data() const override;

 private:
  const v1::LipBlinkRequest& request_;
  const v1::LipBlinkResponse& response_;
  std::string input_name_;
};

// `koma lipblink --report PATH`: writes the report of this call to `path`.
absl::Status WriteLipBlinkReport(const std::string& path, const v1::LipBlinkRequest& request,
                                 const v1::LipBlinkResponse& response,
                                 const std::string& input_name);

}  // namespace koma::client::report

#endif  // KOMA_CLIENT_REPORT_LIP_BLINK_REPORT_H_
