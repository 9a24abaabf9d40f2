// The page's requests (server/page_routes.h) as a file job: POST /page/run?command=skeletal
// &name=pitch.bvh&preset=twos&... with the file's bytes as the body. Only the options below
// are taken, each turned into the `koma` flag of the same meaning with its value checked for
// its form here (a number, a listed word) and for its range by the CLI's own parse, so the
// page offers no flag that names a file or a server.
#ifndef KOMA_SERVER_PAGE_OPTIONS_H_
#define KOMA_SERVER_PAGE_OPTIONS_H_

#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "absl/status/statusor.h"
#include "client/file_job.h"

namespace koma::server {

// The decoded name=value pairs of a URL query, in order. INVALID_ARGUMENT for more than 32
// pairs or a name given twice.
absl::StatusOr<std::vector<std::pair<std::string, std::string>>> SplitQuery(
    std::string_view query);

// One page option: its query name, the flag it becomes, the commands that take it, and its
// form ("int" a whole number >= 0, "number" a decimal, or the words it may be, "|"-joined).
struct PageOption {
  const char* name;
  const char* flag;
  std::vector<std::string> commands;
  const char* form;
};
const std::vector<PageOption>& PageOptions();

// The job the query asks for on `body` (the file). The query must have command and name; the
// others are PageOptions(), and timing, xdts and report ("0" leaves that output out).
// INVALID_ARGUMENT naming the parameter and value: an unknown parameter, an option the command
// does not take, a value not of the option's form.
absl::StatusOr<client::FileJob> PageJobFromQuery(std::string_view query, std::string body);

}  // namespace koma::server

#endif  // KOMA_SERVER_PAGE_OPTIONS_H_
