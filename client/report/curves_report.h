// The RetimeCurves report: each curve before (smooth) and after (stepped) with the key poses
// marked, the drawing sheet, the hold histogram.
#ifndef KOMA_CLIENT_REPORT_CURVES_REPORT_H_
#define KOMA_CLIENT_REPORT_CURVES_REPORT_H_

#include <string>

#include "absl/status/status.h"
#include "client/report/report_writer.h"
#include "koma/v1/retime.pb.h"

namespace koma::client::report {

class CurvesReportWriter : public ReportWriter {
 public:
  // Keeps references: request and response must outlive the writer.
  CurvesReportWriter(const v1::RetimeCurvesRequest& request,
                     const v1::RetimeCurvesResponse& response, std::string input_name)
      : request_(request), response_(response), input_name_(std::move(input_name)) {}

  std::string_view Kind() const override { return "curves"; }
  std::string Title() const override;
  nlohmann::json Data() const override;

 private:
  const v1::RetimeCurvesRequest& request_;
  const v1::RetimeCurvesResponse& response_;
  std::string input_name_;
};

// `koma curves --report PATH`: writes the report of this call to `path`.
absl::Status WriteCurvesReport(const std::string& path, const v1::RetimeCurvesRequest& request,
                               const v1::RetimeCurvesResponse& response,
                               const std::string& input_name);

}  // namespace koma::client::report

#endif  // KOMA_CLIENT_REPORT_CURVES_REPORT_H_
