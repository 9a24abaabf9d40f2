#include "client/report/report_writer.h"

#include <algorithm>
#include <fstream>
#include <string>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_replace.h"
#include "client/files.h"
#include "client/report/templates.h"
#include "formats/format_table.h"
#include "koma/version.h"

namespace koma::client::report {
namespace {

// JSON inside <script type="application/json">: "<" only occurs inside JSON strings, where
// \u003c means the same character and cannot close the script element or open a comment.
std::string JsonForScript(const nlohmann::json& data) {
  return absl::StrReplaceAll(data.dump(), {{"<", "\\u003c"}});
}

// Text for an HTML element's content: the title.
std::string EscapeHtml(const std::string& text) {
  return absl::StrReplaceAll(text, {{"&", "&amp;"}, {"<", "&lt;"}, {">", "&gt;"}});
}

// The input's format as `koma` reads it (formats/format_table.h): sniffed from the file's
// first bytes (a Spine skeleton and a motion3.json are both .json), else by its name (a voice
// recording, which libsndfile tells apart); "" for standard input and what no row claims.
std::string InputFormat(std::string_view input_name) {
  formats::FormatId format = formats::FormatId::kUnknown;
  if (!input_name.empty() && input_name != "-") {
    std::ifstream in{std::string(input_name), std::ios::binary};
    std::string head(64 * 1024, '\0');
    in.read(head.data(), static_cast<std::streamsize>(head.size()));
    head.resize(static_cast<size_t>(std::max<std::streamsize>(in.gcount(), 0)));
    format = formats::SniffFormat(head);
    if (format == formats::FormatId::kUnknown) format = formats::FormatFromName(input_name);
  }
  return format == formats::FormatId::kUnknown ? ""
                                                : std::string(formats::FormatOf(format).name);
}

}  // namespace

nlohmann::json Header(std::string_view rpc, std::string_view input_name,
                      const nlohmann::json& options, const nlohmann::json& counts) {
  nlohmann::json header;
  header["rpc"] = rpc;
  header["input"] = InputName(input_name);
  if (const std::string format = InputFormat(input_name); !format.empty()) {
    header["format"] = format;
  }
  header["options"] = options;
  header["counts"] = counts;
  header["version"] = kVersion;
  return header;
}

std::string RenderReport(const ReportWriter& writer) {
  const std::string kind(writer.Kind());
  const std::string title = EscapeHtml(writer.Title());
  const std::string data = JsonForScript(writer.Data());
  auto view = [](std::string_view text) { return absl::string_view(text.data(), text.size()); };
  // One pass over the page template: text put in is never scanned for markers again.
  return absl::StrReplaceAll(view(Template("report.html")),
                             {{"{{TITLE}}", title},
                              {"{{KIND}}", kind},
                              {"{{STYLE}}", view(Template("report.css"))},
                              {"{{DATA}}", data},
                              {"{{COMMON_SCRIPT}}", view(Template("report.js"))},
                              {"{{KIND_SCRIPT}}", view(Template(kind + ".js"))}});
}

absl::Status WriteReport(const std::string& path, const ReportWriter& writer) {
  // The CLI's own writer: "-" is standard output, links are followed, a device or pipe is
  // written straight, a file through "<path>.tmp" and a rename.
  if (absl::Status s = WriteFile(path, RenderReport(writer)); !s.ok()) {
    return absl::Status(s.code(), absl::StrCat("--report: ", s.message()));
  }
  return absl::OkStatus();
}

}  // namespace koma::client::report
