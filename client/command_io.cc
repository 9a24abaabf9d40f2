#include "client/command_io.h"

#include <cstdio>

namespace koma::client {
namespace {

thread_local MemoryCommandIo* current_io = nullptr;

void Print(std::FILE* stream, std::string* captured, std::string_view text) {
  if (captured != nullptr) {
    captured->append(text);
    return;
  }
  std::fwrite(text.data(), 1, text.size(), stream);
  std::fflush(stream);
}

}  // namespace

ScopedMemoryCommandIo::ScopedMemoryCommandIo(MemoryCommandIo* io) : previous_(current_io) {
  current_io = io;
}

ScopedMemoryCommandIo::~ScopedMemoryCommandIo() { current_io = previous_; }

MemoryCommandIo* CurrentMemoryCommandIo() { return current_io; }

void PrintStdout(std::string_view text) {
  Print(stdout, current_io ? &current_io->stdout_text : nullptr, text);
}

void PrintStderr(std::string_view text) {
  Print(stderr, current_io ? &current_io->stderr_text : nullptr, text);
}

}  // namespace koma::client
