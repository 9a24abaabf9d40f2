// Where a `koma` command's files and messages go. By default the file system, standard
// output and standard error. Within a ScopedMemoryCommandIo (on this thread) they go to
// memory instead: a read finds only the files the scope holds (nothing on disk, no standard
// input), every write lands in the scope, and what would be printed is kept as text. The page
// that koma_server serves (server/page_jobs.h) runs the CLI's own commands this way, so its
// outputs are the CLI's bytes by construction (client/file_job.h).
#ifndef KOMA_CLIENT_COMMAND_IO_H_
#define KOMA_CLIENT_COMMAND_IO_H_

#include <map>
#include <string>
#include <string_view>

namespace koma::client {

struct MemoryCommandIo {
  std::map<std::string, std::string> readable;  // path -> bytes: the only files a read finds
  std::map<std::string, std::string> written;   // path -> bytes of each write (the last one)
  std::string stdout_text;                      // what the command printed to standard output
  std::string stderr_text;                      // ... and to standard error
};

// Routes this thread's command I/O to `io` until destroyed (then to what it was before).
class ScopedMemoryCommandIo {
 public:
  explicit ScopedMemoryCommandIo(MemoryCommandIo* io);
  ~ScopedMemoryCommandIo();
  ScopedMemoryCommandIo(const ScopedMemoryCommandIo&) = delete;
  ScopedMemoryCommandIo& operator=(const ScopedMemoryCommandIo&) = delete;

 private:
  MemoryCommandIo* previous_;
};

// The scope's I/O on this thread; null: the real file system and streams.
MemoryCommandIo* CurrentMemoryCommandIo();

// To standard output / standard error, or the scope's text; flushed.
void PrintStdout(std::string_view text);
void PrintStderr(std::string_view text);

}  // namespace koma::client

#endif  // KOMA_CLIENT_COMMAND_IO_H_
