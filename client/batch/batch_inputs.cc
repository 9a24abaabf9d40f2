#include "client/batch/batch_inputs.h"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <string_view>
#include <system_error>

#include "absl/status/status.h"
#include "absl/strings/ascii.h"
#include "absl/strings/match.h"
#include "absl/strings/str_cat.h"
#include "absl/strings/strip.h"
#include "client/batch/batch_audio_beside.h"
#include "formats/format_table.h"
#include "formats/text_encoding.h"

namespace koma::client::batch {
namespace fs = std::filesystem;
namespace {

bool HasExtension(const std::string& name, const std::vector<std::string>& extensions) {
  return std::any_of(extensions.begin(), extensions.end(), [&](const std::string& extension) {
    return absl::EndsWithIgnoreCase(name, extension);
  });
}

// Collects items in order; remembers canonical inputs to take each once.
class Collector {
 public:
  Collector(const std::vector<std::string>& extensions, const std::string& out_dir)
      : extensions_(extensions), out_dir_(out_dir) {
    std::error_code error;
    const fs::path canonical = fs::weakly_canonical(out_dir, error);
    out_dir_canonical_ = error ? fs::path(out_dir) : canonical;
  }

  // `where`: how the path was named, for messages ("argument", "list.txt:3").
  absl::Status Add(const std::string& path, const std::string& where) {
    std::error_code error;
    const fs::file_status status = fs::status(path, error);
    if (error || !fs::exists(status)) {
      return absl::InvalidArgumentError(
          absl::StrCat(where, ": ", path, ": no such file or folder"));
    }
    if (fs::is_directory(status)) return AddFolder(path, where);
    AddFile(path, fs::path(path).filename().string());
    return absl::OkStatus();
  }

  std::vector<BatchItem> Take() { return std::move(items_); }

 private:
  absl::Status AddFolder(const std::string& folder, const std::string& where) {
    std::vector<std::pair<std::string, std::string>> found;  // path, relative
    std::error_code error;
    fs::recursive_directory_iterator it(folder, fs::directory_options::follow_directory_symlink,
                                        error);
    for (; !error && it != fs::recursive_directory_iterator(); it.increment(error)) {
      std::error_code ignored;
      if (it->is_directory(ignored)) {
        // Outputs must never become inputs of the same (or the next) run.
        if (fs::equivalent(it->path(), out_dir_canonical_, ignored)) it.disable_recursion_pending();
        continue;
      }
      if (!it->is_regular_file(ignored) || !HasExtension(it->path().filename().string(), extensions_)) {
        continue;
      }
      found.emplace_back(it->path().string(),
                         it->path().lexically_relative(folder).lexically_normal().string());
    }
    if (error) {
      return absl::InvalidArgumentError(
          absl::StrCat(where, ": ", folder, ": cannot list: ", error.message()));
    }
    std::sort(found.begin(), found.end(),
              [](const auto& a, const auto& b) { return a.second < b.second; });
    for (const auto& [path, relative] : found) AddFile(path, relative);
    return absl::OkStatus();
  }

  void AddFile(const std::string& path, const std::string& relative) {
    std::error_code error;
    fs::path canonical = fs::canonical(path, error);
    if (!seen_.insert(error ? path : canonical.string()).second) return;
    BatchItem item;
    item.input = path;
    item.relative = relative;
    item.output = (fs::path(out_dir_) / relative).string();
    // A recording's output is the motion written from it.
    if (IsAudioPath(relative)) item.output = BesidePath(item.output, AudioExtensions(), ".motion3.json");
    items_.push_back(std::move(item));
  }

  const std::vector<std::string>& extensions_;
  std::string out_dir_;
  fs::path out_dir_canonical_;
  std::set<std::string> seen_;
  std::vector<BatchItem> items_;
};

absl::Status AddList(const std::string& list_path, Collector& collector) {
  std::ifstream in(list_path);
  if (!in) {
    return absl::InvalidArgumentError(absl::StrCat("@", list_path, ": cannot read the list"));
  }
  std::string line;
  for (int number = 1; std::getline(in, line); ++number) {
    if (number == 1) {
      // A UTF-8 byte order mark (Notepad writes one) is skipped; UTF-16 is refused by name.
      absl::StatusOr<std::string_view> text = formats::SkipUtf8Bom(line);
      if (!text.ok()) {
        return absl::InvalidArgumentError(absl::StrCat("@", list_path, ": ", text.status().message()));
      }
      line = std::string(*text);
    }
    const std::string path(absl::StripAsciiWhitespace(line));
    if (path.empty() || path[0] == '#') continue;
    if (absl::Status s = collector.Add(path, absl::StrCat(list_path, ":", number)); !s.ok()) {
      return s;
    }
  }
  if (in.bad()) {
    return absl::InvalidArgumentError(absl::StrCat("@", list_path, ": cannot read the list"));
  }
  return absl::OkStatus();
}

}  // namespace

const std::vector<std::string>& AudioExtensions() {
  static const std::vector<std::string>* const extensions = [] {
    const formats::FormatRow& audio = formats::FormatOf(formats::FormatId::kAudio);
    return new std::vector<std::string>(audio.folder_extensions.begin(),
                                        audio.folder_extensions.end());
  }();
  return *extensions;
}

bool IsAudioPath(const std::string& path) {
  return formats::FormatFromName(path) == formats::FormatId::kAudio;
}

std::vector<std::string> ExtensionsOf(const std::string& rpc, bool spine_skeletons) {
  // The formats the command reads, as IN or through a flag naming a file beside it (a
  // recording), in the table's order. Spine skeletons share *.json with motion3.json, so a
  // folder is read as one or the other, as the command's flags say.
  const bool skeletons_only =
      spine_skeletons && formats::TakesInput(formats::FormatOf(formats::FormatId::kSpine), rpc);
  std::vector<std::string> extensions;
  for (const formats::FormatRow& row : formats::FormatTable()) {
    const bool taken = std::any_of(row.inputs.begin(), row.inputs.end(),
                                   [&](const formats::CommandInput& input) {
                                     return input.command == rpc;
                                   });
    if (!taken || skeletons_only != (row.id == formats::FormatId::kSpine)) continue;
    extensions.insert(extensions.end(), row.folder_extensions.begin(),
                      row.folder_extensions.end());
  }
  return extensions;
}

std::string BesidePath(const std::string& output, const std::vector<std::string>& extensions,
                       const std::string& suffix) {
  for (const std::string& extension : extensions) {
    if (absl::EndsWithIgnoreCase(output, extension)) {
      return absl::StrCat(output.substr(0, output.size() - extension.size()), suffix);
    }
  }
  return absl::StrCat(output, suffix);
}

absl::StatusOr<std::vector<BatchItem>> DiscoverInputs(const std::vector<std::string>& arguments,
                                                      const std::vector<std::string>& extensions,
                                                      const std::string& out_dir,
                                                      bool with_timing, bool with_report,
                                                      bool with_xdts, bool audio_beside) {
  Collector collector(extensions, out_dir);
  for (const std::string& argument : arguments) {
    absl::Status status = absl::StartsWith(argument, "@")
                              ? AddList(argument.substr(1), collector)
                              : collector.Add(argument, "input");
    if (!status.ok()) return status;
  }
  std::vector<BatchItem> items = collector.Take();
  if (audio_beside) items = PairRecordingsBeside(std::move(items));
  // Every file the batch writes, with the input that writes it: no two may coincide.
  std::map<std::string, const std::string*> writer;
  for (BatchItem& item : items) {
    if (with_timing) item.timing = TimingPathFor(item.output, extensions);
    if (with_report) item.report = ReportPathFor(item.output, extensions);
    if (with_xdts) item.xdts = XdtsPathFor(item.output, extensions);
    for (const std::string* path : {&item.output, &item.timing, &item.report, &item.xdts}) {
      if (path->empty()) continue;
      const std::string key = fs::path(*path).lexically_normal().string();
      auto [it, inserted] = writer.emplace(key, &item.input);
      if (!inserted) {
        return absl::InvalidArgumentError(
            absl::StrCat("inputs ", *it->second, " and ", item.input, " would both write ", key,
                         " (give their folder instead, or run them in two batches)"));
      }
    }
  }
  return items;
}

}  // namespace koma::client::batch
