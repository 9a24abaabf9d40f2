#include "client/batch/batch_state.h"

#include <filesystem>
#include <system_error>

#include <nlohmann/json.hpp>

#include "client/files.h"

namespace koma::client::batch {
namespace fs = std::filesystem;
namespace {

constexpr int kFormatVersion = 2;

// Not older than `input`; false when either cannot be read.
bool NotOlder(const std::string& output, const std::string& input) {
  std::error_code error;
  const fs::file_time_type out_time = fs::last_write_time(output, error);
  if (error) return false;
  const fs::file_time_type in_time = fs::last_write_time(input, error);
  if (error) return false;
  return out_time >= in_time;
}

}  // namespace

Manifest Manifest::Load(const std::string& out_dir, const std::string& file_name) {
  Manifest manifest;
  manifest.path_ = (fs::path(out_dir) / file_name).string();
  absl::StatusOr<std::string> text = ReadFile(manifest.path_);
  if (!text.ok()) return manifest;
  const nlohmann::json json = nlohmann::json::parse(*text, nullptr, /*allow_exceptions=*/false);
  if (!json.is_object() || json.value("version", 0) != kFormatVersion) return manifest;
  const auto outputs = json.find("outputs");
  if (outputs == json.end() || !outputs->is_object()) return manifest;
  for (const auto& [relative, entry] : outputs->items()) {
    if (!entry.is_object()) continue;
    const auto input = entry.find("input");
    const auto options = entry.find("options");
    if (input == entry.end() || !input->is_string() || options == entry.end() ||
        !options->is_string()) {
      continue;
    }
    const auto audio = entry.find("audio");
    manifest.entries_[relative] =
        Entry{input->get<std::string>(), options->get<std::string>(),
              audio != entry.end() && audio->is_string() ? audio->get<std::string>() : ""};
  }
  return manifest;
}

std::string Manifest::AbsoluteInput(const std::string& path) {
  std::error_code error;
  const fs::path absolute = fs::absolute(path, error);
  return error ? path : absolute.lexically_normal().string();
}

bool Manifest::UpToDate(const BatchItem& item, const std::string& fingerprint) const {
  const auto it = entries_.find(item.relative);
  if (it == entries_.end() || it->second.options != fingerprint ||
      it->second.input != AbsoluteInput(item.input) ||
      it->second.audio != (item.audio.empty() ? "" : AbsoluteInput(item.audio))) {
    return false;
  }
  // Every output at least as new as every source (the input and its recording).
  for (const std::string* source : {&item.input, &item.audio}) {
    if (source->empty()) continue;
    if (!NotOlder(item.output, *source)) return false;
    for (const std::string* sheet : {&item.timing, &item.report, &item.xdts}) {
      if (!sheet->empty() && !NotOlder(*sheet, *source)) return false;
    }
  }
  return true;
}

absl::Status Manifest::Save() const {
  nlohmann::json json;
  json["version"] = kFormatVersion;
  json["outputs"] = nlohmann::json::object();
  for (const auto& [relative, entry] : entries_) {
    json["outputs"][relative] = {{"input", entry.input}, {"options", entry.options}};
    if (!entry.audio.empty()) json["outputs"][relative]["audio"] = entry.audio;
  }
  std::error_code ignored;
  fs::create_directories(fs::path(path_).parent_path(), ignored);
  return WriteFile(path_, json.dump(1) + "\n");
}

}  // namespace koma::client::batch
