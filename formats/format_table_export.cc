// koma_format_table_export: formats/format_table.h for the Python package, so Python reads
// the one table instead of keeping a copy by hand.
//
//   koma_format_table_export OUT.py          writes koma/_formats.py (python/CMakeLists.txt)
//   koma_format_table_export --sniff FILE... prints "KEY_BY_NAME KEY_BY_CONTENT FILE" per file
//                                            ("-" for no row), the C++ answers the Python
//                                            package's test compares its own with
#include <cstdio>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include "formats/format_table.h"

namespace {

using koma::formats::FormatRow;

// A Python literal of `text`: printable ASCII as is, the rest escaped, so the module is
// plain ASCII whatever a row holds. `bytes_literal` writes b"..." (what the sniffing compares
// with a file's bytes).
std::string Quoted(std::string_view text, bool bytes_literal = false) {
  std::string out = bytes_literal ? "b\"" : "\"";
  for (const char c : text) {
    const auto byte = static_cast<unsigned char>(c);
    if (c == '"' || c == '\\') {
      out += '\\';
      out += c;
    } else if (byte >= 0x20 && byte < 0x7f) {
      out += c;
    } else {
      char escaped[8];
      std::snprintf(escaped, sizeof escaped, "\\x%02x", byte);
      out += escaped;
    }
  }
  return out + "\"";
}

std::string Tuple(const std::vector<std::string_view>& items, bool bytes_literal = false) {
  std::string out = "(";
  for (std::string_view item : items) out += Quoted(item, bytes_literal) + ", ";
  return out + ")";
}

std::string PythonRow(const FormatRow& row) {
  std::ostringstream out;
  out << "    {\n"
      << "        \"key\": " << Quoted(row.key) << ",\n"
      << "        \"name\": " << Quoted(row.name) << ",\n"
      << "        \"described\": " << Quoted(row.described) << ",\n"
      << "        \"retimed_as\": " << Quoted(row.retimed_as) << ",\n"
      << "        \"extensions\": " << Tuple(row.extensions) << ",\n"
      << "        \"folder_extensions\": " << Tuple(row.folder_extensions) << ",\n"
      << "        \"magic\": " << Tuple(row.magic, true) << ",\n"
      << "        \"text_starts\": " << Tuple(row.text_starts, true) << ",\n"
      << "        \"json\": (";
  for (const koma::formats::JsonRule& rule : row.json) {
    out << "{\"first_key\": " << Quoted(rule.first_key, true)
        << ", \"has\": " << Tuple(rule.has, true) << ", \"lacks\": " << Tuple(rule.lacks, true)
        << "}, ";
  }
  out << "),\n        \"inputs\": (";
  for (const koma::formats::CommandInput& input : row.inputs) {
    out << "(" << Quoted(input.command) << ", " << Quoted(input.flag) << "), ";
  }
  out << "),\n        \"written_by\": " << Tuple(row.written_by) << ",\n"
      << "        \"request_fields\": (";
  for (const koma::formats::RequestField& field : row.request_fields) {
    out << "(" << Quoted(field.message) << ", " << Quoted(field.field) << "), ";
  }
  out << "),\n        \"sent_whole\": " << (row.sent_whole ? "True" : "False") << ",\n"
      << "        \"reader\": " << Quoted(row.reader) << ",\n"
      << "        \"writer\": " << Quoted(row.writer) << ",\n"
      << "    },\n";
  return out.str();
}

std::string PythonModule() {
  std::string out =
      "\"\"\"koma's file formats, one row each: formats/format_table.cc, written by "
      "koma_format_table_export\nat build time. Do not edit; koma/_format_table.py reads it."
      "\"\"\"\n\nFORMATS = (\n";
  for (const FormatRow& row : koma::formats::FormatTable()) out += PythonRow(row);
  out += ")\n\nCOMMANDS = (\n";
  for (const koma::formats::CommandRow& command : koma::formats::CommandTable()) {
    out += "    {\"name\": " + Quoted(command.name) + ", \"rpc\": " + Quoted(command.rpc) +
           ", \"conjunction\": " + Quoted(command.conjunction) + "},\n";
  }
  return out + ")\n";
}

std::string_view KeyOr(koma::formats::FormatId id) {
  const std::string_view key = koma::formats::FormatOf(id).key;
  return key.empty() ? "-" : key;
}

int PrintSniffed(int argc, char** argv) {
  for (int i = 2; i < argc; ++i) {
    std::ifstream in(argv[i], std::ios::binary);
    if (!in) {
      std::cerr << "koma_format_table_export: cannot read " << argv[i] << "\n";
      return 1;
    }
    std::ostringstream bytes;
    bytes << in.rdbuf();
    std::cout << KeyOr(koma::formats::FormatFromName(argv[i])) << " "
              << KeyOr(koma::formats::SniffFormat(bytes.str())) << " " << argv[i] << "\n";
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc >= 2 && std::string_view(argv[1]) == "--sniff") return PrintSniffed(argc, argv);
  if (argc != 2) {
    std::cerr << "usage: koma_format_table_export OUT.py | --sniff FILE...\n";
    return 2;
  }
  std::ofstream out(argv[1], std::ios::binary);
  out << PythonModule();
  out.close();
  if (!out) {
    std::cerr << "koma_format_table_export: cannot write " << argv[1] << "\n";
    return 1;
  }
  return 0;
}
