#include "client/files.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <climits>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "absl/strings/str_cat.h"
#include "client/command_io.h"

namespace koma::client {
namespace {

constexpr int kMaxLinks = 40;  // as the kernel's own limit for a path (ELOOP)

absl::Status OsError(absl::string_view action, const std::string& path, int error) {
  const std::string name = action == "read" ? InputName(path) : OutputName(path);
  return absl::ErrnoToStatus(error, absl::StrCat("cannot ", action, " ", name));
}

std::string FolderOf(const std::string& path) {
  const size_t slash = path.rfind('/');
  if (slash == std::string::npos) return ".";
  if (slash == 0) return "/";
  return path.substr(0, slash);
}

// write(2) until all of `data` is out; false with errno set on failure.
bool WriteAll(int fd, const std::string& data) {
  size_t done = 0;
  while (done < data.size()) {
    const ssize_t n = ::write(fd, data.data() + done, data.size() - done);
    if (n < 0) {
      if (errno == EINTR) continue;
      return false;
    }
    done += static_cast<size_t>(n);
  }
  return true;
}

absl::Status ReadFd(int fd, const std::string& path, std::string* out) {
  char buffer[1 << 16];
  while (true) {
    const ssize_t n = ::read(fd, buffer, sizeof buffer);
    if (n == 0) return absl::OkStatus();
    if (n < 0) {
      if (errno == EINTR) continue;
      return OsError("read", path, errno);
    }
    out->append(buffer, static_cast<size_t>(n));
  }
}

// Through a temporary file beside `target` and a rename over it.
absl::Status ReplaceRegularFile(const std::string& target, const std::string& contents) {
  const std::string folder = FolderOf(target);
  const size_t slash = target.rfind('/');
  const std::string name = slash == std::string::npos ? target : target.substr(slash + 1);
  std::string temporary = absl::StrCat(folder, "/.", name, ".koma-XXXXXX");
  std::vector<char> pattern(temporary.begin(), temporary.end());
  pattern.push_back('\0');
  const int fd = ::mkstemp(pattern.data());
  if (fd < 0) return OsError("write", target, errno);
  temporary = pattern.data();
  // mkstemp makes 0600; give the file the mode the target has, or a new file's usual mode.
  struct stat existing {};
  mode_t mode;
  if (::stat(target.c_str(), &existing) == 0) {
    mode = existing.st_mode & 07777;
  } else {
    const mode_t mask = ::umask(0);
    ::umask(mask);
    mode = 0666 & ~mask;
  }
  int error = 0;
  if (!WriteAll(fd, contents) || ::fchmod(fd, mode) != 0 || ::fsync(fd) != 0) error = errno;
  if (::close(fd) != 0 && error == 0) error = errno;
  if (error == 0 && std::rename(temporary.c_str(), target.c_str()) != 0) error = errno;
  if (error != 0) {
    std::remove(temporary.c_str());
    return OsError("write", target, error);
  }
  return absl::OkStatus();
}

}  // namespace

bool IsStdio(const std::string& path) { return path == "-"; }

std::string InputName(std::string_view path) {
  return path == "-" ? "standard input" : std::string(path);
}

std::string OutputName(std::string_view path) {
  return path == "-" ? "standard output" : std::string(path);
}

absl::Status CheckOneOnStdout(std::initializer_list<OutputFlag> outputs, bool json) {
  int on_stdout = json ? 1 : 0;
  std::string flags;
  for (const OutputFlag& output : outputs) {
    on_stdout += IsStdio(output.path) ? 1 : 0;
    absl::StrAppend(&flags, output.flag, " -, ");
  }
  if (on_stdout <= 1) return absl::OkStatus();
  if (flags.size() >= 2) flags.resize(flags.size() - 2);
  return absl::InvalidArgumentError(
      absl::StrCat("only one of ", flags, " and --json can use standard output"));
}

absl::StatusOr<std::string> ReadFile(const std::string& path) {
  if (MemoryCommandIo* io = CurrentMemoryCommandIo()) {
    const auto it = io->readable.find(path);
    if (it == io->readable.end()) return OsError("read", path, ENOENT);
    return it->second;
  }
  std::string contents;
  if (IsStdio(path)) {
    if (absl::Status s = ReadFd(STDIN_FILENO, path, &contents); !s.ok()) return s;
    return contents;
  }
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) return OsError("read", path, errno);
  struct stat info {};
  if (::fstat(fd, &info) == 0 && S_ISDIR(info.st_mode)) {
    ::close(fd);
    return OsError("read", path, EISDIR);
  }
  absl::Status s = ReadFd(fd, path, &contents);
  ::close(fd);
  if (!s.ok()) return s;
  return contents;
}

absl::StatusOr<std::string> ResolveOutputPath(const std::string& path) {
  if (CurrentMemoryCommandIo() != nullptr) return path;  // no links in memory
  // An existing file: the kernel's resolution (realpath), which also handles links that
  // readlink cannot express as a path (/dev/stdout -> /proc/self/fd/1 -> "pipe:[...]"; such
  // targets are not regular files and WriteFile opens `path` itself for them).
  struct stat info {};
  if (::stat(path.c_str(), &info) == 0 && S_ISREG(info.st_mode)) {
    char* real = ::realpath(path.c_str(), nullptr);
    if (real != nullptr) {
      std::string resolved(real);
      std::free(real);
      return resolved;
    }
  }
  // A new file, perhaps through a dangling link: follow the links by hand.
  std::string current = path;
  for (int links = 0; links <= kMaxLinks; ++links) {
    if (::lstat(current.c_str(), &info) != 0 || !S_ISLNK(info.st_mode)) return current;
    std::vector<char> buffer(PATH_MAX + 1);
    const ssize_t n = ::readlink(current.c_str(), buffer.data(), buffer.size() - 1);
    if (n < 0) return OsError("follow the link", current, errno);
    const std::string target(buffer.data(), static_cast<size_t>(n));
    current = (!target.empty() && target[0] == '/') ? target
                                                    : absl::StrCat(FolderOf(current), "/", target);
  }
  return absl::FailedPreconditionError(
      absl::StrCat("cannot write ", path, ": more than ", kMaxLinks, " symbolic links"));
}

absl::Status WriteFile(const std::string& path, const std::string& contents) {
  if (MemoryCommandIo* io = CurrentMemoryCommandIo()) {
    if (IsStdio(path)) {
      io->stdout_text += contents;
    } else {
      io->written[path] = contents;
    }
    return absl::OkStatus();
  }
  if (IsStdio(path)) {
    if (!WriteAll(STDOUT_FILENO, contents)) return OsError("write", path, errno);
    return absl::OkStatus();
  }
  struct stat info {};
  if (::stat(path.c_str(), &info) == 0 && !S_ISREG(info.st_mode)) {
    if (S_ISDIR(info.st_mode)) return OsError("write", path, EISDIR);
    // A device or a pipe (perhaps through links): there is nothing to replace, and a rename
    // would replace the node or the link. The kernel follows the links on open.
    const int fd = ::open(path.c_str(), O_WRONLY | O_CLOEXEC);
    if (fd < 0) return OsError("write", path, errno);
    int error = WriteAll(fd, contents) ? 0 : errno;
    if (::close(fd) != 0 && error == 0) error = errno;
    if (error != 0) return OsError("write", path, error);
    return absl::OkStatus();
  }
  absl::StatusOr<std::string> target = ResolveOutputPath(path);
  if (!target.ok()) return target.status();
  absl::Status s = ReplaceRegularFile(*target, contents);
  if (!s.ok() && *target != path) {
    return absl::Status(s.code(),
                        absl::StrCat(s.message(), " (the target of the link ", path, ")"));
  }
  return s;
}

absl::Status CheckWritable(std::initializer_list<std::string> paths) {
  if (CurrentMemoryCommandIo() != nullptr) return absl::OkStatus();  // memory takes any name
  for (const std::string& path : paths) {
    if (path.empty() || IsStdio(path)) continue;
    struct stat info {};
    if (::stat(path.c_str(), &info) == 0) {
      if (S_ISDIR(info.st_mode)) return OsError("write", path, EISDIR);
      if (!S_ISREG(info.st_mode)) {
        if (::access(path.c_str(), W_OK) != 0) return OsError("write", path, errno);
        continue;
      }
    }
    absl::StatusOr<std::string> target = ResolveOutputPath(path);
    if (!target.ok()) return target.status();
    // Write and search permission on the folder: what creating the temporary file and
    // renaming it over the target need.
    if (::access(FolderOf(*target).c_str(), W_OK | X_OK) != 0) return OsError("write", path, errno);
  }
  return absl::OkStatus();
}

}  // namespace koma::client
