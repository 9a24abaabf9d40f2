#include "client/report/report_writer.h"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <string>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_replace.h"
#include "client/report/templates.h"
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

}  // namespace

nlohmann::json Header(std::string_view rpc, std::string_view input_name,
                      const nlohmann::json& options, const nlohmann::json& counts) {
  nlohmann::json header;
  header["rpc"] = rpc;
  // "-" is how the CLI names standard input.
  header["input"] = input_name == "-" ? std::string_view("standard input") : input_name;
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
  const std::string page = RenderReport(writer);
  if (path == "-") {  // the CLI's name for standard output (its summary then goes to stderr)
    if (std::fwrite(page.data(), 1, page.size(), stdout) != page.size() ||
        std::fflush(stdout) != 0) {
      return absl::InternalError(
          absl::StrCat("--report -: cannot write standard output: ", std::strerror(errno)));
    }
    return absl::OkStatus();
  }
  const std::string temporary = path + ".tmp";
  std::FILE* file = std::fopen(temporary.c_str(), "wb");
  if (file == nullptr) {
    return absl::PermissionDeniedError(
        absl::StrCat("--report ", path, ": cannot write: ", std::strerror(errno)));
  }
  const bool written = std::fwrite(page.data(), 1, page.size(), file) == page.size();
  const bool closed = std::fclose(file) == 0;
  if (!written || !closed || std::rename(temporary.c_str(), path.c_str()) != 0) {
    const std::string reason = std::strerror(errno);
    std::remove(temporary.c_str());
    return absl::InternalError(absl::StrCat("--report ", path, ": cannot write: ", reason));
  }
  return absl::OkStatus();
}

}  // namespace koma::client::report
