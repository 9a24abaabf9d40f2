// The report's HTML, CSS and JavaScript: the files of client/report/templates/, embedded in
// the binary at build time (embed_templates.cmake), so `koma` writes a report with no files
// beside it.
#ifndef KOMA_CLIENT_REPORT_TEMPLATES_H_
#define KOMA_CLIENT_REPORT_TEMPLATES_H_

#include <string_view>

namespace koma::client::report {

// The text of templates/<name> ("report.html", "skeletal.js", ...); empty if there is none.
std::string_view Template(std::string_view name);

}  // namespace koma::client::report

#endif  // KOMA_CLIENT_REPORT_TEMPLATES_H_
