#include "client/files.h"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <sstream>

#include "absl/strings/str_cat.h"

namespace koma::client {
namespace {

absl::Status OsError(absl::string_view action, const std::string& path, int error) {
  return absl::ErrnoToStatus(error, absl::StrCat("cannot ", action, " ", path));
}

}  // namespace

absl::StatusOr<std::string> ReadFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return OsError("read", path, errno);
  std::ostringstream contents;
  contents << in.rdbuf();
  if (in.bad()) return OsError("read", path, errno);
  return std::move(contents).str();
}

absl::Status WriteFile(const std::string& path, const std::string& contents) {
  const std::string temporary = path + ".tmp";
  {
    std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
    if (!out) return OsError("write", temporary, errno);
    out << contents;
    out.flush();
    if (!out) return OsError("write", temporary, errno);
  }
  if (std::rename(temporary.c_str(), path.c_str()) != 0) {
    const int error = errno;
    std::remove(temporary.c_str());
    return OsError("rename to", path, error);
  }
  return absl::OkStatus();
}

}  // namespace koma::client
