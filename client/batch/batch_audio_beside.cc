#include "client/batch/batch_audio_beside.h"

#include <algorithm>
#include <filesystem>
#include <set>
#include <system_error>
#include <utility>

#include "absl/strings/match.h"
#include "absl/strings/str_cat.h"
#include "absl/strings/str_join.h"

namespace koma::client::batch {
namespace fs = std::filesystem;
namespace {

// One spelling per file (symlinks and "a/../b" resolved) to tell whether two paths meet.
std::string Canonical(const std::string& path) {
  std::error_code error;
  const fs::path canonical = fs::canonical(path, error);
  return error ? fs::path(path).lexically_normal().string() : canonical.string();
}

bool IsAudioExtension(const std::string& text) {
  return std::any_of(AudioExtensions().begin(), AudioExtensions().end(),
                     [&](const std::string& extension) {
                       return absl::EqualsIgnoreCase(text, extension);
                     });
}

// A file beside `recording` that would have taken it but is not among the inputs (a skeleton
// in a folder searched without the Spine flags): "; skel/hero.json is beside it but not an
// input (...)", else "".
std::string UntakenPartnerHint(const std::string& recording) {
  const fs::path path(recording);
  const std::string stem = path.stem().string();
  for (const char* ending : {".json", ".motion3.json", ".csv"}) {
    const fs::path partner = path.parent_path() / (stem + ending);
    std::error_code error;
    if (fs::is_regular_file(partner, error)) {
      return absl::StrCat("; ", partner.string(),
                          " is beside it but not an input (name it, or give the Spine flags so "
                          "that folders collect *.json)");
    }
  }
  return "";
}

}  // namespace

std::string RecordingStem(const std::string& file_name) {
  for (const char* ending : {".motion3.json", ".json", ".csv"}) {
    const absl::string_view end(ending);
    if (file_name.size() > end.size() && absl::EndsWithIgnoreCase(file_name, end)) {
      return file_name.substr(0, file_name.size() - end.size());
    }
  }
  return fs::path(file_name).stem().string();
}

std::vector<std::string> RecordingsBeside(const std::string& input) {
  const fs::path path(input);
  const std::string stem = RecordingStem(path.filename().string());
  const fs::path folder = path.parent_path();
  std::vector<std::string> found;
  std::error_code error;
  for (fs::directory_iterator it(folder.empty() ? fs::path(".") : folder, error);
       !error && it != fs::directory_iterator(); it.increment(error)) {
    const std::string name = it->path().filename().string();
    std::error_code ignored;
    if (name.size() <= stem.size() || !absl::StartsWith(name, stem) ||
        !IsAudioExtension(name.substr(stem.size())) || !it->is_regular_file(ignored)) {
      continue;
    }
    found.push_back((folder / name).string());
  }
  std::sort(found.begin(), found.end());
  return found;
}

std::vector<BatchItem> PairRecordingsBeside(std::vector<BatchItem> items) {
  std::set<std::string> taken;  // canonical paths of the recordings some input takes
  for (BatchItem& item : items) {
    if (IsAudioPath(item.input)) continue;
    const std::vector<std::string> recordings = RecordingsBeside(item.input);
    if (recordings.size() == 1) {
      item.audio = recordings[0];
      taken.insert(Canonical(item.audio));
      continue;
    }
    const std::string stem = RecordingStem(fs::path(item.input).filename().string());
    if (recordings.empty()) {
      std::vector<std::string> names;
      for (const std::string& extension : AudioExtensions()) names.push_back(stem + extension);
      item.audio_error = absl::StrCat("--audio-beside: no recording beside ", item.input,
                                      " (looked for ", absl::StrJoin(names, ", "), ")");
    } else {
      item.audio_error =
          absl::StrCat("--audio-beside: ", recordings.size(), " recordings beside ", item.input,
                       ": ", absl::StrJoin(recordings, ", "), " (keep one of them there)");
    }
  }
  std::vector<BatchItem> kept;
  for (BatchItem& item : items) {
    if (IsAudioPath(item.input)) {
      if (taken.count(Canonical(item.input)) > 0) continue;  // sent with its input
      item.audio_error = absl::StrCat(
          "--audio-beside: ", item.input,
          " is a recording with no input of its name beside it (with --audio-beside a "
          "recording goes with its skeleton or motion; run it without --audio-beside)",
          UntakenPartnerHint(item.input));
    }
    kept.push_back(std::move(item));
  }
  return kept;
}

}  // namespace koma::client::batch
