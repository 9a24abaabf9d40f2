// The RetimeSkeletal report: the stick figure before and after, playing at the clip's rate;
// the input's SSD curve with the omitted and hidden frames marked; the X-sheet.
#ifndef KOMA_CLIENT_REPORT_SKELETAL_REPORT_H_
#define KOMA_CLIENT_REPORT_SKELETAL_REPORT_H_

#include <string>

#include "absl/status/status.h"
#include "client/report/report_writer.h"
#include "koma/v1/retime.pb.h"

namespace koma::client::report {

class SkeletalReportWriter : public ReportWriter {
 public:
  // Keeps references: request and response must outlive the writer.
  SkeletalReportWriter(const v1::RetimeSkeletalRequest& request,
                       const v1::RetimeSkeletalResponse& response, std::string input_name)
      : request_(request), response_(response), input_name_(std::move(input_name)) {}

  std::string_view Kind() const override { return "skeletal"; }
  std::string Title() const override;
  // The joint positions of the input's frames come from forward kinematics of its channels
  // (or are the positions it sent), projected through the request's camera when it has one.
  nlohmann::json Data() const override;

 private:
  const v1::RetimeSkeletalRequest& request_;
  const v1::RetimeSkeletalResponse& response_;
  std::string input_name_;
};

// `koma skeletal --report PATH`: writes the report of this call to `path`.
absl::Status WriteSkeletalReport(const std::string& path, const v1::RetimeSkeletalRequest& request,
                                 const v1::RetimeSkeletalResponse& response,
                                 const std::string& input_name);

}  // namespace koma::client::report

#endif  // KOMA_CLIENT_REPORT_SKELETAL_REPORT_H_
