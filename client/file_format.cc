#include "client/file_format.h"

#include <string_view>
#include <vector>

#include "client/files.h"

namespace koma::client {
namespace {

std::string_view View(absl::string_view text) { return {text.data(), text.size()}; }

// "A, B or C" (`last` " or " or " and "). std::string, not absl::StrCat: the table's
// std::string_view is not Debian abseil's absl::string_view.
std::string Listed(const std::vector<std::string>& items, std::string_view last) {
  std::string out;
  for (size_t i = 0; i < items.size(); ++i) {
    if (i > 0) out += i + 1 == items.size() ? last : std::string_view(", ");
    out += items[i];
  }
  return out;
}

// The formats `command` takes as IN that a name says (Spine JSON is told from motion3.json by
// its contents only, and counts as one of "the JSON curve files" here).
std::vector<const formats::FormatRow*> NamedInputsOf(std::string_view command) {
  std::vector<const formats::FormatRow*> rows;
  for (const formats::FormatRow& row : formats::FormatTable()) {
    if (!row.extensions.empty() && formats::TakesInput(row, command)) rows.push_back(&row);
  }
  return rows;
}

const formats::CommandRow* CommandOf(std::string_view name) {
  for (const formats::CommandRow& row : formats::CommandTable()) {
    if (row.name == name) return &row;
  }
  return nullptr;
}

}  // namespace

FormatId FormatFromName(const std::string& path) { return formats::FormatFromName(path); }

FormatId SniffFormat(absl::string_view text) { return formats::SniffFormat(View(text)); }

absl::Status CheckInputFormat(const std::string& path, absl::string_view text,
                              absl::string_view command_line) {
  const formats::FormatRow& found = formats::FormatOf(SniffFormat(text));
  const std::string_view command = View(command_line.substr(0, command_line.find(' ')));
  const formats::CommandRow* reader = CommandOf(command);
  if (found.id == FormatId::kUnknown || reader == nullptr || formats::TakesInput(found, command)) {
    return absl::OkStatus();
  }
  std::vector<std::string> names;
  std::vector<std::string> described;
  for (const formats::FormatRow* row : NamedInputsOf(command)) {
    names.emplace_back(row->name);
    described.emplace_back(row->described);
  }
  std::vector<std::string> elsewhere;
  for (const formats::CommandInput& input : found.inputs) {
    if (input.flag.empty()) elsewhere.push_back("`koma " + std::string(input.command) + "`");
  }
  std::string message = InputName(path) + " is a " + std::string(found.name) + " file, not " +
                        Listed(names, " or ") + ": `koma " + std::string(command_line) +
                        "` reads " + Listed(described, reader->conjunction);
  if (!elsewhere.empty()) {
    message += "; retime " + std::string(found.retimed_as) + " with " + Listed(elsewhere, " or ");
  }
  return absl::InvalidArgumentError(message);
}

}  // namespace koma::client
