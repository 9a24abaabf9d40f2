// Every file format koma reads or writes, described once: its name, the file names and first
// bytes that identify it, which `koma` commands take it (as IN or through a flag), which
// request fields carry it over the wire, its reader and writer, and the server's memory per
// byte of it. The CLI (naming a file given to the wrong command, choosing the reader),
// `koma batch` (what a folder holds, which call a file needs), the server's file requests
// (their memory budget), the Python package (koma/_formats.py, exported from this table at
// build time by formats/format_table_export.cc) and the docs look formats up here, so a new
// format is one row here plus its reader and writer (docs/development.md, "Adding a format").
#ifndef KOMA_FORMATS_FORMAT_TABLE_H_
#define KOMA_FORMATS_FORMAT_TABLE_H_

#include <cstddef>
#include <cstdint>
#include <string_view>
#include <vector>

namespace koma::formats {

// One per row; kUnknown is no row (a name or text no row claims).
enum class FormatId { kUnknown, kBvh, kGltf, kFbx, kSpine, kMotion3, kCsv, kRhubarb, kAudio };

// How a `koma` command takes a file of the format.
struct CommandInput {
  std::string_view command;  // "skeletal", "curves" or "lipblink"
  std::string_view flag;     // empty: the positional IN; else the flag naming it ("--audio")
};

// A request field that carries the file whole, for the server to read.
struct RequestField {
  std::string_view message;  // "RetimeSkeletalRequest"
  std::string_view field;    // "bvh_text"
};

// A JSON text (its first non-blank byte "{") is the format when it matches one of the row's
// rules: its first member named `first_key` (when set), else every one of `has` and none of
// `lacks` appearing anywhere in the text (quoted member names: a cheap test on the first
// bytes read, not a parse).
struct JsonRule {
  std::string_view first_key;
  std::vector<std::string_view> has;
  std::vector<std::string_view> lacks;
};

struct FormatRow {
  FormatId id = FormatId::kUnknown;
  std::string_view key;   // stable lower-case id: Python's and the export's ("bvh")
  std::string_view name;  // in messages: "x.bvh is a BVH file, ..."
  // What a command reading it says it reads ("`koma skeletal` reads BVH motion capture, ..."),
  // and what the file holds to retime ("retime BVH clips with `koma skeletal`").
  std::string_view described;
  std::string_view retimed_as;
  // File names that say the format (lower case, matched in any case): unique to the row. A
  // format with no name of its own (Spine and Rhubarb JSON are .json, as motion3.json is) is
  // told by its contents only.
  std::vector<std::string_view> extensions;
  // What `koma batch` collects from a folder for this format, longest first (a folder's
  // *.json is not all motion3.json: only *.motion3.json is taken).
  std::vector<std::string_view> folder_extensions;
  // Sniffing, in SniffFormat's order: byte prefixes of the raw file; then, after a UTF-8 byte
  // order mark and ASCII white space, text prefixes, then JSON rules. A row with none of the
  // three is never sniffed (audio: libsndfile tells its formats apart itself; Rhubarb cues
  // come through --rhubarb only).
  std::vector<std::string_view> magic;
  std::vector<std::string_view> text_starts;
  std::vector<JsonRule> json;
  std::vector<CommandInput> inputs;          // the commands that read it
  std::vector<std::string_view> written_by;  // the commands that write it (-o)
  std::vector<RequestField> request_fields;
  // true: the client sends the file whole and the server answers the same file (glTF, FBX);
  // false: the client decodes it unless told to send the file (--send-file).
  bool sent_whole = false;
  std::string_view reader;  // its entry points in formats/ (for readers of this table)
  std::string_view writer;  // empty: koma never writes the format
  // The server's memory per byte of the file (server/call_footprint.h): while it is parsed,
  // and beside the decoded request until the answer is written. bench/format_memory.py's
  // measured peak per MB of file, rounded up with a quarter to spare; the JSON formats at
  // least 24, what a JSON document of only empty strings or objects costs nlohmann (16 bytes a
  // value and 40 more for the string or object, per 3 bytes of text). Measured (MiB per MB):
  // BVH 5.0 (whole call), motion3.json 22.6, curve CSV 7.5, Spine JSON 12.1, Rhubarb JSON
  // 16.4, WAV 2.8; FBX: the file, koma's node tree (arrays stay encoded until asked for) and
  // the written file; glTF: the bytes and the buffers copied out of them (its JSON structure
  // is counted apart, server/call_footprint.cc).
  int64_t parse_bytes_per_byte = 0;
  int64_t kept_bytes_per_byte = 0;
};

// The commands of the CLI that read files, in the order messages list them.
struct CommandRow {
  std::string_view name;  // "skeletal"
  std::string_view rpc;   // "RetimeSkeletal"
  // How "`koma skeletal` reads A, B and C" joins its formats (skeletal reads all three;
  // curves reads one file, motion3.json or CSV).
  std::string_view conjunction;
};

const std::vector<FormatRow>& FormatTable();
const std::vector<CommandRow>& CommandTable();

// The row of `id`; FormatOf(FormatId::kUnknown) is a row with an empty key and name "unknown".
const FormatRow& FormatOf(FormatId id);
// The row whose key is `key`, or nullptr.
const FormatRow* FormatByKey(std::string_view key);

// From the name: the row one of whose extensions ends `path` (any case); kUnknown for "-" and
// names no row claims.
FormatId FormatFromName(std::string_view path);

// The length of the longest extension or folder extension of any row that ends `name` (any
// case) and leaves something before it ("take.motion3.json": 13); 0 when none does.
size_t FormatExtensionLength(std::string_view name);

// From the first bytes: the first row (in table order) whose magic starts `text`; else, after
// a UTF-8 byte order mark and ASCII white space, the first whose text_starts start it; else,
// for JSON ("{"), the first whose JSON rule matches; else kUnknown.
FormatId SniffFormat(std::string_view text);

// `text` matches `row`'s own sniffing rules, whatever rows come before it in the table.
bool MatchesSniff(const FormatRow& row, std::string_view text);

// Whether `command` reads the format as its IN (`flag` empty) or through `flag`.
bool TakesInput(const FormatRow& row, std::string_view command, std::string_view flag = "");
bool WrittenBy(const FormatRow& row, std::string_view command);

// The row of the request field `message`.`field`, or nullptr.
const FormatRow* FormatOfRequestField(std::string_view message, std::string_view field);

}  // namespace koma::formats

#endif  // KOMA_FORMATS_FORMAT_TABLE_H_
