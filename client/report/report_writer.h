// A before/after report of one RPC: a self-contained HTML page (docs/report.md). Each RPC has
// a writer (skeletal_report.h, curves_report.h, lip_blink_report.h) that turns its request and
// response into the page's data; RenderReport puts that data into the templates
// (templates/report.html, report.css, report.js and <kind>.js), where the page's script draws
// the figures. The same writer gives the same bytes every time: no clock, no locale, no
// addresses, object keys in sorted order.
#ifndef KOMA_CLIENT_REPORT_REPORT_WRITER_H_
#define KOMA_CLIENT_REPORT_REPORT_WRITER_H_

#include <string>
#include <string_view>

#include "absl/status/status.h"
#include "nlohmann/json.hpp"

namespace koma::client::report {

class ReportWriter {
 public:
  virtual ~ReportWriter() = default;
  // "skeletal", "curves" or "lipblink": selects templates/<kind>.js.
  virtual std::string_view Kind() const = 0;
  // The page title.
  virtual std::string Title() const = 0;
  // Everything the figures show. Its "header" member (Header() below) is drawn by report.js;
  // the rest by <kind>.js.
  virtual nlohmann::json Data() const = 0;
};

// The header every report starts with: the input file and its format (the format table's
// name for it, when the file is there to sniff or its name says), the options used, the
// counts, and koma's version. options and counts are [label, value] pairs in display order.
nlohmann::json Header(std::string_view rpc, std::string_view input_name,
                      const nlohmann::json& options, const nlohmann::json& counts);

// The HTML page of a writer.
std::string RenderReport(const ReportWriter& writer);

// Writes RenderReport(writer) to `path` with the CLI's WriteFile (client/files.h): "-" is
// standard output, a link is followed, a file is written whole or not at all. Errors name
// the path.
absl::Status WriteReport(const std::string& path, const ReportWriter& writer);

}  // namespace koma::client::report

#endif  // KOMA_CLIENT_REPORT_REPORT_WRITER_H_
