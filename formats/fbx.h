// Binary FBX files (version 7.1 to 7.7, as Maya, MotionBuilder, the FBX SDK, Blender and the
// mocap vendors write them; docs/formats.md, "FBX"): the node tree, read and written back.
//
// Written from the published description of the binary layout (Blender Foundation, 2013:
// a 27-byte header, then nested node records of an end offset, a property count, the
// properties' byte length, a name and typed properties; 64-bit offsets from version 7.5;
// arrays raw or zlib-compressed) and the files themselves, not from the FBX SDK.
//
// Reading keeps the file's bytes: an array is inflated only when asked for, and every node
// keeps its properties' bytes, so writing a document nobody changed gives the file back byte
// for byte; a changed node's properties are encoded again (arrays compressed with Debian's
// zlib when they came compressed).
#ifndef KOMA_FORMATS_FBX_H_
#define KOMA_FORMATS_FBX_H_

#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "absl/status/status.h"
#include "absl/status/statusor.h"

namespace koma::formats {

inline constexpr uint32_t kFbxMinVersion = 7100;
inline constexpr uint32_t kFbxMaxVersion = 7700;

// What a file may cost before it is refused (RESOURCE_EXHAUSTED naming the limit): a zip bomb
// is refused by its arrays' declared sizes, before anything is inflated.
struct FbxReadLimits {
  int max_depth = 32;                             // nested node levels
  int64_t max_nodes = 4'000'000;                  // node records in the file
  int64_t max_array_bytes = int64_t{256} << 20;   // one array, inflated
  int64_t max_inflated_bytes = int64_t{1} << 30;  // all arrays together, inflated
};

// One typed value of a node: a scalar (Y int16, C bool, I int32, L int64, F float, D double),
// bytes (S string, R raw) or an array (f float, d double, l int64, i int32, b bool).
struct FbxProperty {
  char type = 0;
  int64_t integer = 0;  // Y C I L
  double real = 0.0;    // F D
  std::string bytes;    // S R
  // An array: its element count, and (as read) its encoded bytes and encoding (0 raw, 1 zlib);
  // or (as built) the values, which the writer encodes.
  uint32_t count = 0;
  uint32_t encoding = 0;
  std::string_view encoded;
  std::vector<double> reals;      // f d, when built
  std::vector<int64_t> integers;  // l i b, when built
  // What `encoded` points into when the array was encoded in memory (EncodedIntegerArray),
  // shared by the property's copies.
  std::shared_ptr<const std::string> encoded_owner;

  bool is_array() const;
  static FbxProperty Int64(int64_t value);
  static FbxProperty Double(double value);
  static FbxProperty Int32(int32_t value);
  static FbxProperty String(std::string value);
  // Arrays to be written: zlib-compressed when `compress`.
  static FbxProperty DoubleArray(char type, std::vector<double> values, bool compress);
  static FbxProperty IntegerArray(char type, std::vector<int64_t> values, bool compress);
  // The same array encoded now, once: its copies share the bytes, so an array written into
  // many nodes (a take's key times, the same in every curve) is compressed once.
  static FbxProperty EncodedIntegerArray(char type, std::vector<int64_t> values, bool compress);
};

struct FbxNode {
  std::string name;
  std::vector<FbxProperty> properties;
  std::vector<FbxNode> children;
  // Whether the record ends with a null record (every node with children does; some without
  // children do too, as their writer chose).
  bool null_record = false;
  // The properties' bytes as read; empty once the node is changed (set_changed) or built.
  std::string_view property_bytes;
  bool changed = false;

  // The first child named `child_name`, or null.
  const FbxNode* Child(std::string_view child_name) const;
  FbxNode* Child(std::string_view child_name);
};

struct FbxDocument {
  uint32_t version = 0;
  std::vector<FbxNode> nodes;  // the top-level list
  // The file as read: the header's 27 bytes, the footer (everything after the top-level
  // list) and the bytes the nodes' views point into.
  std::shared_ptr<const std::string> file;
  size_t list_end = 0;  // where the top-level list ended in `file`
};

// True for the binary header ("Kaydara FBX Binary  \0").
bool IsFbxBinary(std::string_view bytes);

// The node tree. INVALID_ARGUMENT naming the byte offset and the node's path
// ("byte 1234 (Objects/Geometry): ...") for anything malformed, an ASCII FBX or a version
// outside 7.1-7.7; RESOURCE_EXHAUSTED past `limits`.
absl::StatusOr<FbxDocument> ReadFbx(std::string bytes, const FbxReadLimits& limits = {});

// An array property's values (inflated and converted): INVALID_ARGUMENT when its zlib data
// is broken or does not hold exactly its count of elements.
absl::StatusOr<std::vector<double>> FbxReals(const FbxProperty& property);
absl::StatusOr<std::vector<int64_t>> FbxIntegers(const FbxProperty& property);

// The document as a file: byte for byte the file it was read from when no node changed.
std::string WriteFbx(const FbxDocument& document);

}  // namespace koma::formats

#endif  // KOMA_FORMATS_FBX_H_
