#include "formats/rhubarb_cues.h"

#include <cmath>
#include <limits>
#include <nlohmann/json.hpp>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_split.h"
#include "absl/strings/strip.h"
#include "core/status_macros.h"
#include "formats/error_text.h"
#include "formats/json_text.h"
#include "formats/number_format.h"

namespace koma::formats {
namespace {

constexpr std::string_view kBom = "\xEF\xBB\xBF";
// Deepest JSON nesting read (a cue file needs 3), as motion3.json: no stack exhaustion.
constexpr int kMaxDepth = 32;

bool IsCueLetter(char c) { return (c >= 'A' && c <= 'H') || c == 'X'; }

absl::Status Invalid(absl::string_view where, absl::string_view what) {
  return absl::InvalidArgumentError(absl::StrCat(where, ": ", what));
}

absl::StatusOr<char> Letter(const std::string& text, absl::string_view where) {
  if (text.size() != 1 || !IsCueLetter(text[0])) {
    return Invalid(where, absl::StrCat(QuoteForError(text), " is not one of A-H, X"));
  }
  return text[0];
}

absl::Status CheckTime(double t, absl::string_view where) {
  if (std::isfinite(t) && t >= 0) return absl::OkStatus();
  return Invalid(where, absl::StrCat(t, " must be a finite number of seconds >= 0"));
}

// Cues in order and not overlapping, each ending after it starts.
absl::Status CheckOrder(const std::vector<MouthCue>& cues, bool tsv) {
  if (cues.empty()) return absl::InvalidArgumentError("no mouth cues");
  for (size_t i = 0; i < cues.size(); ++i) {
    const std::string where = tsv ? absl::StrCat("line ", i + 1) : absl::StrCat("mouthCues[", i, "]");
    if (!(cues[i].end_s > cues[i].start_s)) {
      return Invalid(where, absl::StrCat("ends at ", cues[i].end_s, " s, not after its start ",
                                         cues[i].start_s, " s"));
    }
    if (i > 0 && cues[i].start_s < cues[i - 1].end_s) {
      return Invalid(where, absl::StrCat("starts at ", cues[i].start_s,
                                         " s, before the previous cue ends (",
                                         cues[i - 1].end_s, " s)"));
    }
  }
  return absl::OkStatus();
}

absl::StatusOr<std::vector<MouthCue>> ParseJson(std::string_view text) {
  // Errors with the byte offset, in koma's words (formats/json_text.h).
  KOMA_ASSIGN_OR_RETURN(const nlohmann::ordered_json doc, ParseJsonTextWithin(text, kMaxDepth));
  if (!doc.is_object() || !doc.contains("mouthCues") || !doc["mouthCues"].is_array()) {
    return absl::InvalidArgumentError("mouthCues: missing, or not an array");
  }
  std::vector<MouthCue> cues;
  const nlohmann::ordered_json& list = doc["mouthCues"];
  for (size_t i = 0; i < list.size(); ++i) {
    const std::string where = absl::StrCat("mouthCues[", i, "]");
    const nlohmann::ordered_json& cue = list[i];
    if (!cue.is_object()) return Invalid(where, "not an object");
    MouthCue out;
    for (const char* key : {"start", "end"}) {
      const std::string path = absl::StrCat(where, ".", key);
      if (!cue.contains(key) || !cue[key].is_number()) return Invalid(path, "missing, or not a number");
      const double t = cue[key].get<double>();
      if (absl::Status s = CheckTime(t, path); !s.ok()) return s;
      (key[0] == 's' ? out.start_s : out.end_s) = t;
    }
    const std::string path = absl::StrCat(where, ".value");
    if (!cue.contains("value") || !cue["value"].is_string()) return Invalid(path, "missing, or not a string");
    absl::StatusOr<char> letter = Letter(cue["value"].get<std::string>(), path);
    if (!letter.ok()) return letter.status();
    out.shape = *letter;
    cues.push_back(out);
  }
  if (absl::Status s = CheckOrder(cues, /*tsv=*/false); !s.ok()) return s;
  return cues;
}

absl::StatusOr<std::vector<MouthCue>> ParseTsv(std::string_view text) {
  std::vector<MouthCue> cues;
  int line_number = 0;
  for (absl::string_view line : absl::StrSplit(absl::string_view(text.data(), text.size()), '\n')) {
    ++line_number;
    line = absl::StripSuffix(line, "\r");
    if (line.empty()) continue;  // a final newline, blank lines between
    const std::string where = absl::StrCat("line ", line_number);
    const std::vector<absl::string_view> fields = absl::StrSplit(line, '\t');
    if (fields.size() != 2) {
      return Invalid(where, absl::StrCat("expected TIME<tab>LETTER, got ",
                                         QuoteForError(std::string(line))));
    }
    absl::StatusOr<double> t = ParseDouble(std::string_view(fields[0].data(), fields[0].size()));
    if (!t.ok()) return Invalid(where, t.status().message());
    if (absl::Status s = CheckTime(*t, where); !s.ok()) return s;
    absl::StatusOr<char> letter = Letter(std::string(fields[1]), where);
    if (!letter.ok()) return letter.status();
    if (!cues.empty()) {
      if (!(*t > cues.back().start_s)) {
        return Invalid(where, absl::StrCat("starts at ", *t, " s, not after the previous line (",
                                           cues.back().start_s, " s)"));
      }
      cues.back().end_s = *t;
    }
    cues.push_back({*t, std::numeric_limits<double>::infinity(), *letter});
  }
  if (cues.empty()) return absl::InvalidArgumentError("no mouth cues");
  return cues;
}

}  // namespace

absl::StatusOr<std::vector<MouthCue>> ParseRhubarbCues(std::string_view text) {
  if (text.substr(0, kBom.size()) == kBom) text.remove_prefix(kBom.size());
  const size_t first = text.find_first_not_of(" \t\r\n");
  if (first != std::string_view::npos && text[first] == '{') return ParseJson(text);
  return ParseTsv(text);
}

std::string WriteRhubarbJson(const std::vector<MouthCue>& cues, double duration_s,
                             std::string_view sound_file) {
  std::string out = absl::StrCat("{\n  \"metadata\": {\n    \"soundFile\": ",
                                 nlohmann::json(std::string(sound_file)).dump(
                                     -1, ' ', false, nlohmann::json::error_handler_t::replace),
                                 ",\n    \"duration\": ", FormatDouble(duration_s),
                                 "\n  },\n  \"mouthCues\": [\n");
  for (size_t i = 0; i < cues.size(); ++i) {
    absl::StrAppend(&out, "    { \"start\": ", FormatDouble(cues[i].start_s),
                    ", \"end\": ", FormatDouble(cues[i].end_s), ", \"value\": \"",
                    std::string(1, cues[i].shape), "\" }", i + 1 < cues.size() ? "," : "", "\n");
  }
  out += "  ]\n}\n";
  return out;
}

std::string WriteRhubarbTsv(const std::vector<MouthCue>& cues) {
  std::string out;
  for (const MouthCue& cue : cues) {
    absl::StrAppend(&out, FormatDouble(cue.start_s), "\t", std::string(1, cue.shape), "\n");
  }
  if (!cues.empty()) absl::StrAppend(&out, FormatDouble(cues.back().end_s), "\tX\n");
  return out;
}

}  // namespace koma::formats
