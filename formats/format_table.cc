#include "formats/format_table.h"

#include <cstddef>

#include "formats/text_encoding.h"

namespace koma::formats {
namespace {

// The rows. Sniffing tries them in this order, so a more specific JSON rule comes before a
// looser one: glTF (an "asset" member), then Spine (a "skeleton" member), then motion3.json
// (any other JSON). Messages list a command's formats in this order too ("not BVH, glTF or
// FBX").
std::vector<FormatRow> MakeTable() {
  std::vector<FormatRow> rows;
  FormatRow* row = nullptr;
  const auto add = [&](FormatId id, std::string_view key, std::string_view name) {
    row = &rows.emplace_back();
    row->id = id;
    row->key = key;
    row->name = name;
  };

  add(FormatId::kBvh, "bvh", "BVH");
  row->described = "BVH motion capture";
  row->retimed_as = "BVH clips";
  row->extensions = {".bvh"};
  row->folder_extensions = {".bvh"};
  row->text_starts = {"HIERARCHY"};
  row->inputs = {{"skeletal", ""}};
  row->written_by = {"skeletal"};
  row->request_fields = {{"RetimeSkeletalRequest", "bvh_text"}};
  row->reader = "formats::ParseBvh (formats/bvh.h)";
  row->writer = "formats::WriteBvh";
  row->parse_bytes_per_byte = 3;  // the text and its numbers
  row->kept_bytes_per_byte = 2;

  add(FormatId::kGltf, "gltf", "glTF");
  row->described = "glTF 2.0 / VRM";
  row->retimed_as = "glTF files";
  row->extensions = {".glb", ".gltf", ".vrm", ".vrma"};
  row->folder_extensions = row->extensions;
  // The GLB container's magic; a .gltf is JSON with an "asset" member (a motion3.json never
  // has one, unless it also has "Curves").
  row->magic = {"glTF"};
  row->json = {{"", {"\"asset\""}, {"\"Curves\""}}};
  row->inputs = {{"skeletal", ""}};
  row->written_by = {"skeletal"};
  row->request_fields = {{"RetimeSkeletalRequest", "gltf"}};
  row->sent_whole = true;
  row->reader = "formats::ReadGltf (formats/gltf.h)";
  row->writer = "formats::WriteGltf";
  row->parse_bytes_per_byte = 3;  // plus its JSON structure's, server/call_footprint.cc
  row->kept_bytes_per_byte = 3;

  add(FormatId::kFbx, "fbx", "FBX");
  row->described = "binary FBX";
  row->retimed_as = "FBX takes";
  row->extensions = {".fbx"};
  row->folder_extensions = {".fbx"};
  // Binary FBX's header; an ASCII FBX's first comment (named FBX, then refused by the reader,
  // which reads binary FBX only).
  row->magic = {"Kaydara FBX Binary", "; FBX"};
  row->inputs = {{"skeletal", ""}};
  row->written_by = {"skeletal"};
  row->request_fields = {{"RetimeSkeletalRequest", "fbx"}};
  row->sent_whole = true;
  row->reader = "formats::ReadFbx (formats/fbx.h)";
  row->writer = "formats::WriteFbx";
  row->parse_bytes_per_byte = 8;
  row->kept_bytes_per_byte = 8;

  add(FormatId::kSpine, "spine", "Spine JSON");
  row->described = "Spine skeleton JSON";
  row->retimed_as = "Spine animations";
  row->folder_extensions = {".json"};  // with the Spine flags: every *.json is a skeleton
  // As formats::IsSpineJson: Spine exports "skeleton" first; a hand-edited skeleton has it
  // somewhere and no motion3.json "Meta".
  row->json = {{"skeleton", {}, {}}, {"", {"\"skeleton\""}, {"\"Meta\""}}};
  row->inputs = {{"curves", ""}, {"lipblink", ""}};
  row->written_by = {"curves", "lipblink"};
  row->request_fields = {{"RetimeCurvesRequest", "spine_json"}, {"LipBlinkRequest", "spine_json"}};
  row->reader = "formats::ParseSpine (formats/spine.h)";
  row->writer = "formats::WriteSpine";
  row->parse_bytes_per_byte = 24;
  row->kept_bytes_per_byte = 24;

  add(FormatId::kMotion3, "motion3", "motion3.json");
  row->described = "Live2D motion3.json";
  row->retimed_as = "curves";
  row->extensions = {".json"};
  row->folder_extensions = {".motion3.json"};
  row->json = {{"", {}, {}}};  // any other JSON
  row->inputs = {{"curves", ""}, {"lipblink", ""}};
  row->written_by = {"curves", "lipblink"};
  row->request_fields = {{"RetimeCurvesRequest", "motion3_json"},
                         {"LipBlinkRequest", "motion3_json"}};
  row->reader = "formats::ParseMotion3 (formats/motion3.h)";
  row->writer = "formats::WriteMotion3";
  row->parse_bytes_per_byte = 28;
  row->kept_bytes_per_byte = 28;

  add(FormatId::kCsv, "csv", "CSV");
  row->described = "per-frame CSV";
  row->retimed_as = "curves";
  row->extensions = {".csv"};
  row->folder_extensions = {".csv"};
  // The header's first cell, quoted or not, with either separator.
  row->text_starts = {"frame,", "frame;", "\"frame\",", "\"frame\";"};
  row->inputs = {{"curves", ""}, {"lipblink", ""}};
  row->written_by = {"curves", "lipblink"};
  row->request_fields = {{"RetimeCurvesRequest", "csv_text"}, {"LipBlinkRequest", "csv_text"}};
  row->reader = "formats::ParseCurveCsv (formats/curve_csv.h)";
  row->writer = "formats::WriteCurveCsv";
  row->parse_bytes_per_byte = 10;
  row->kept_bytes_per_byte = 10;

  // Given through --rhubarb only, as JSON or TSV: no name or first bytes of its own.
  add(FormatId::kRhubarb, "rhubarb", "Rhubarb cues");
  row->described = "Rhubarb Lip Sync's mouth cues";
  row->retimed_as = "mouth cues";
  row->inputs = {{"lipblink", "--rhubarb"}};
  row->written_by = {"lipblink"};  // --cues
  row->request_fields = {{"LipBlinkRequest", "rhubarb_cues"}};
  row->reader = "formats::ParseRhubarbCues (formats/rhubarb_cues.h)";
  row->writer = "formats::WriteRhubarbJson, formats::WriteRhubarbTsv";
  row->parse_bytes_per_byte = 24;
  row->kept_bytes_per_byte = 24;

  // Recordings: not sniffed, libsndfile tells its formats apart itself.
  add(FormatId::kAudio, "audio", "audio");
  row->described = "a voice recording";
  row->retimed_as = "recordings";
  row->extensions = {".wav", ".flac", ".ogg", ".oga", ".opus", ".mp3"};
  row->folder_extensions = row->extensions;
  row->inputs = {{"lipblink", "--audio"}};
  row->request_fields = {{"LipBlinkRequest", "audio"}};
  row->reader = "formats::AudioDecoder::Open (formats/audio_reader.h, libsndfile)";
  row->parse_bytes_per_byte = 4;
  row->kept_bytes_per_byte = 4;
  return rows;
}

const FormatRow& UnknownRow() {
  static const FormatRow* const row = [] {
    auto* unknown = new FormatRow();
    unknown->name = "unknown";
    return unknown;
  }();
  return *row;
}

bool StartsWith(std::string_view text, std::string_view prefix) {
  return text.substr(0, prefix.size()) == prefix;
}

bool EndsWithIgnoreCase(std::string_view text, std::string_view suffix) {
  if (text.size() < suffix.size()) return false;
  const std::string_view tail = text.substr(text.size() - suffix.size());
  for (size_t i = 0; i < suffix.size(); ++i) {
    const char c =
        tail[i] >= 'A' && tail[i] <= 'Z' ? static_cast<char>(tail[i] - 'A' + 'a') : tail[i];
    if (c != suffix[i]) return false;
  }
  return true;
}

bool IsAsciiSpace(char c) {
  return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\f' || c == '\v';
}

// After a UTF-8 byte order mark (Windows tools write one; it says nothing of the format) and
// ASCII white space.
std::string_view TextStart(std::string_view text) {
  if (StartsWith(text, kUtf8Bom)) text.remove_prefix(kUtf8Bom.size());
  size_t i = 0;
  while (i < text.size() && IsAsciiSpace(text[i])) ++i;
  return text.substr(i);
}

// `json` starts with "{".
bool MatchesJsonRule(const JsonRule& rule, std::string_view json) {
  if (!rule.first_key.empty()) {
    const std::string_view first = TextStart(json.substr(1));
    return StartsWith(first, "\"") && StartsWith(first.substr(1), rule.first_key) &&
           StartsWith(first.substr(1 + rule.first_key.size()), "\"");
  }
  for (std::string_view member : rule.has) {
    if (json.find(member) == std::string_view::npos) return false;
  }
  for (std::string_view member : rule.lacks) {
    if (json.find(member) != std::string_view::npos) return false;
  }
  return true;
}

bool MatchesMagic(const FormatRow& row, std::string_view raw) {
  for (std::string_view magic : row.magic) {
    if (StartsWith(raw, magic)) return true;
  }
  return false;
}

bool MatchesTextStart(const FormatRow& row, std::string_view text) {
  for (std::string_view start : row.text_starts) {
    if (StartsWith(text, start)) return true;
  }
  return false;
}

bool MatchesJson(const FormatRow& row, std::string_view text) {
  if (!StartsWith(text, "{")) return false;
  for (const JsonRule& rule : row.json) {
    if (MatchesJsonRule(rule, text)) return true;
  }
  return false;
}

}  // namespace

const std::vector<FormatRow>& FormatTable() {
  static const std::vector<FormatRow>* const table = new std::vector<FormatRow>(MakeTable());
  return *table;
}

const std::vector<CommandRow>& CommandTable() {
  static const std::vector<CommandRow>* const commands = new std::vector<CommandRow>{
      {"skeletal", "RetimeSkeletal", " and "},
      {"curves", "RetimeCurves", " or "},
      {"lipblink", "LipBlink", " or "},
  };
  return *commands;
}

const FormatRow& FormatOf(FormatId id) {
  for (const FormatRow& row : FormatTable()) {
    if (row.id == id) return row;
  }
  return UnknownRow();
}

const FormatRow* FormatByKey(std::string_view key) {
  for (const FormatRow& row : FormatTable()) {
    if (row.key == key) return &row;
  }
  return nullptr;
}

FormatId FormatFromName(std::string_view path) {
  for (const FormatRow& row : FormatTable()) {
    for (std::string_view extension : row.extensions) {
      if (EndsWithIgnoreCase(path, extension)) return row.id;
    }
  }
  return FormatId::kUnknown;
}

size_t FormatExtensionLength(std::string_view name) {
  size_t longest = 0;
  for (const FormatRow& row : FormatTable()) {
    for (const auto* list : {&row.extensions, &row.folder_extensions}) {
      for (std::string_view extension : *list) {
        if (extension.size() > longest && name.size() > extension.size() &&
            EndsWithIgnoreCase(name, extension)) {
          longest = extension.size();
        }
      }
    }
  }
  return longest;
}

FormatId SniffFormat(std::string_view raw) {
  for (const FormatRow& row : FormatTable()) {
    if (MatchesMagic(row, raw)) return row.id;
  }
  const std::string_view text = TextStart(raw);
  for (const FormatRow& row : FormatTable()) {
    if (MatchesTextStart(row, text)) return row.id;
  }
  for (const FormatRow& row : FormatTable()) {
    if (MatchesJson(row, text)) return row.id;
  }
  return FormatId::kUnknown;
}

bool MatchesSniff(const FormatRow& row, std::string_view raw) {
  const std::string_view text = TextStart(raw);
  return MatchesMagic(row, raw) || MatchesTextStart(row, text) || MatchesJson(row, text);
}

bool TakesInput(const FormatRow& row, std::string_view command, std::string_view flag) {
  for (const CommandInput& input : row.inputs) {
    if (input.command == command && input.flag == flag) return true;
  }
  return false;
}

bool WrittenBy(const FormatRow& row, std::string_view command) {
  for (std::string_view writer : row.written_by) {
    if (writer == command) return true;
  }
  return false;
}

const FormatRow* FormatOfRequestField(std::string_view message, std::string_view field) {
  for (const FormatRow& row : FormatTable()) {
    for (const RequestField& carried : row.request_fields) {
      if (carried.message == message && carried.field == field) return &row;
    }
  }
  return nullptr;
}

}  // namespace koma::formats
