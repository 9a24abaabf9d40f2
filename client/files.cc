#include "client/files.h"

#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
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

absl::Status CheckWritable(std::initializer_list<std::string> paths) {
  for (const std::string& path : paths) {
    if (path.empty()) continue;
    std::error_code ignored;
    if (std::filesystem::is_directory(path, ignored)) return OsError("write", path, EISDIR);
    std::string folder = std::filesystem::path(path).parent_path().string();
    if (folder.empty()) folder = ".";
    // Write and search permission on the folder: what creating "<path>.tmp" and renaming it
    // over `path` need.
    if (access(folder.c_str(), W_OK | X_OK) != 0) return OsError("write", path, errno);
  }
  return absl::OkStatus();
}

}  // namespace koma::client
