// The binary FBX node tree (formats/fbx.h): reading, array decoding and writing.
#include <zlib.h>

#include <algorithm>
#include <cstring>
#include <string>
#include <utility>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_join.h"
#include "core/status_macros.h"
#include "core/stop_check.h"
#include "formats/fbx.h"

namespace koma::formats {
namespace {

constexpr std::string_view kMagic("Kaydara FBX Binary  \0", 21);
constexpr size_t kHeaderBytes = 27;      // the magic, 0x1A 0x00, the version (uint32)
constexpr uint32_t kWideVersion = 7500;  // 64-bit offsets and counts from here on

size_t ElementBytes(char type) {
  switch (type) {
    case 'f':
    case 'i':
      return 4;
    case 'd':
    case 'l':
      return 8;
    case 'b':
      return 1;
    default:
      return 0;
  }
}

template <typename T>
T Load(const char* at) {
  T value;
  std::memcpy(&value, at, sizeof(T));  // FBX is little-endian, as is every machine koma runs on
  return value;
}

template <typename T>
void Append(std::string& out, T value) {
  char bytes[sizeof(T)];
  std::memcpy(bytes, &value, sizeof(T));
  out.append(bytes, sizeof(T));
}

class TreeReader {
 public:
  TreeReader(const std::string& file, uint32_t version, const FbxReadLimits& limits)
      : file_(file), wide_(version >= kWideVersion), limits_(limits) {}

  // The list of nodes from `at` up to and including its null record, which must end by
  // `end`. Returns where the list ended.
  absl::StatusOr<size_t> ReadList(size_t at, size_t end, int depth, std::vector<FbxNode>& nodes) {
    if (depth > limits_.max_depth) {
      return Refused(at, absl::StrCat("nodes nested deeper than ", limits_.max_depth, " levels"));
    }
    for (;;) {
      if (stop_.Stop()) return stop_.status();
      if (at + HeaderBytes() > end) {
        return Invalid(at, "the file ends inside a node record (cut short?)");
      }
      const uint64_t node_end = Count(at);
      if (node_end == 0) {
        if (!AllZero(at, HeaderBytes())) {
          return Invalid(at, "a node record with end offset 0 that is not a null record");
        }
        return at + HeaderBytes();
      }
      FbxNode node;
      KOMA_ASSIGN_OR_RETURN(at, ReadNode(at, end, depth, node));
      nodes.push_back(std::move(node));
    }
  }

 private:
  size_t HeaderBytes() const { return wide_ ? 25 : 13; }  // three counts and the name length
  uint64_t Count(size_t at) const {
    return wide_ ? Load<uint64_t>(file_.data() + at) : Load<uint32_t>(file_.data() + at);
  }
  bool AllZero(size_t at, size_t bytes) const {
    return std::all_of(file_.begin() + static_cast<std::ptrdiff_t>(at),
                       file_.begin() + static_cast<std::ptrdiff_t>(at + bytes),
                       [](char c) { return c == 0; });
  }
  std::string Path() const { return absl::StrJoin(path_, "/"); }
  absl::Status Invalid(size_t at, absl::string_view what) const {
    return absl::InvalidArgumentError(absl::StrCat(
        "byte ", at, path_.empty() ? "" : absl::StrCat(" (", Path(), ")"), ": ", what));
  }
  absl::Status Refused(size_t at, absl::string_view what) const {
    return absl::ResourceExhaustedError(absl::StrCat(
        "byte ", at, path_.empty() ? "" : absl::StrCat(" (", Path(), ")"), ": ", what));
  }

  absl::StatusOr<size_t> ReadNode(size_t at, size_t end, int depth, FbxNode& node) {
    if (++nodes_read_ > limits_.max_nodes) {
      return Refused(at, absl::StrCat("more than ", limits_.max_nodes, " nodes"));
    }
    const size_t word = wide_ ? 8 : 4;
    const uint64_t node_end = Count(at);
    const uint64_t property_count = Count(at + word);
    const uint64_t property_bytes = Count(at + 2 * word);
    const size_t name_length = static_cast<unsigned char>(file_[at + 3 * word]);
    const size_t name_at = at + HeaderBytes();
    if (name_length > end - name_at) {
      return Invalid(at, "the file ends inside a node's name (cut short?)");
    }
    node.name.assign(file_, name_at, name_length);
    path_.push_back(node.name);
    if (node_end > end || node_end < name_at + name_length) {
      return Invalid(at, absl::StrCat("the node record's end offset ", node_end,
                                      " is outside its parent (which ends at byte ", end, ")"));
    }
    const size_t properties_at = name_at + name_length;
    if (property_bytes > node_end - properties_at) {
      return Invalid(at, absl::StrCat("its properties' length ", property_bytes,
                                      " passes the end of the node record"));
    }
    const size_t properties_end = properties_at + static_cast<size_t>(property_bytes);
    size_t p = properties_at;
    // Each property takes at least its type byte: a count above the bytes is malformed (and
    // would otherwise reserve memory for nothing).
    if (property_count > property_bytes) {
      return Invalid(at, absl::StrCat(property_count, " properties in ", property_bytes, " bytes"));
    }
    node.properties.reserve(static_cast<size_t>(property_count));
    for (uint64_t i = 0; i < property_count; ++i) {
      FbxProperty property;
      KOMA_ASSIGN_OR_RETURN(p, ReadProperty(p, properties_end, i, property));
      node.properties.push_back(std::move(property));
    }
    if (p != properties_end) {
      return Invalid(p, absl::StrCat("the properties end ", properties_end - p,
                                     " bytes before their stated length"));
    }
    node.property_bytes = std::string_view(file_).substr(properties_at, property_bytes);
    if (properties_end < node_end) {
      KOMA_ASSIGN_OR_RETURN(
          const size_t list_end,
          ReadList(properties_end, static_cast<size_t>(node_end), depth + 1, node.children));
      if (list_end != node_end) {
        return Invalid(list_end, absl::StrCat("the children end ", node_end - list_end,
                                              " bytes before the node record's end offset"));
      }
      node.null_record = true;
    }
    path_.pop_back();
    return static_cast<size_t>(node_end);
  }

  absl::StatusOr<size_t> ReadProperty(size_t p, size_t end, uint64_t index, FbxProperty& property) {
    if (p >= end) return Invalid(p, absl::StrCat("property ", index, ": missing"));
    property.type = file_[p++];
    const auto need = [&](size_t bytes) -> absl::Status {
      if (end - p >= bytes) return absl::OkStatus();
      return Invalid(p, absl::StrCat("property ", index, " ('", std::string(1, property.type),
                                     "'): its ", bytes, " bytes pass the properties' end"));
    };
    switch (property.type) {
      case 'Y':
        KOMA_RETURN_IF_ERROR(need(2));
        property.integer = Load<int16_t>(file_.data() + p);
        return p + 2;
      case 'C':
        KOMA_RETURN_IF_ERROR(need(1));
        property.integer = file_[p] != 0;
        return p + 1;
      case 'I':
        KOMA_RETURN_IF_ERROR(need(4));
        property.integer = Load<int32_t>(file_.data() + p);
        return p + 4;
      case 'L':
        KOMA_RETURN_IF_ERROR(need(8));
        property.integer = Load<int64_t>(file_.data() + p);
        return p + 8;
      case 'F':
        KOMA_RETURN_IF_ERROR(need(4));
        property.real = Load<float>(file_.data() + p);
        return p + 4;
      case 'D':
        KOMA_RETURN_IF_ERROR(need(8));
        property.real = Load<double>(file_.data() + p);
        return p + 8;
      case 'S':
      case 'R': {
        KOMA_RETURN_IF_ERROR(need(4));
        const uint32_t length = Load<uint32_t>(file_.data() + p);
        p += 4;
        KOMA_RETURN_IF_ERROR(need(length));
        property.bytes.assign(file_, p, length);
        return p + length;
      }
      default:
        break;
    }
    const size_t element = ElementBytes(property.type);
    if (element == 0) {
      return Invalid(p - 1, absl::StrCat("property ", index, ": unknown type byte 0x",
                                         absl::Hex(static_cast<unsigned char>(property.type),
                                                   absl::kZeroPad2)));
    }
    KOMA_RETURN_IF_ERROR(need(12));
    property.count = Load<uint32_t>(file_.data() + p);
    property.encoding = Load<uint32_t>(file_.data() + p + 4);
    const uint32_t stored = Load<uint32_t>(file_.data() + p + 8);
    p += 12;
    const int64_t inflated = int64_t{property.count} * static_cast<int64_t>(element);
    if (property.encoding > 1) {
      return Invalid(p - 8, absl::StrCat("property ", index, ": array encoding ", property.encoding,
                                         " (0 raw and 1 zlib are known)"));
    }
    if (property.encoding == 0 && stored != inflated) {
      return Invalid(p - 4, absl::StrCat("property ", index, ": a raw array of ", property.count,
                                         " elements in ", stored, " bytes"));
    }
    if (inflated > limits_.max_array_bytes) {
      return Refused(
          p - 12, absl::StrCat("property ", index, ": an array of ", property.count, " elements (",
                               inflated, " bytes inflated), over the limit of ",
                               limits_.max_array_bytes, " bytes"));
    }
    inflated_ += inflated;
    if (inflated_ > limits_.max_inflated_bytes) {
      return Refused(p - 12,
                     absl::StrCat("the arrays so far inflate to ", inflated_,
                                  " bytes, over the limit of ", limits_.max_inflated_bytes));
    }
    KOMA_RETURN_IF_ERROR(need(stored));
    property.encoded = std::string_view(file_).substr(p, stored);
    return p + stored;
  }

  const std::string& file_;
  const bool wide_;
  const FbxReadLimits& limits_;
  std::vector<std::string> path_;
  int64_t nodes_read_ = 0;
  int64_t inflated_ = 0;
  StopPoll stop_{/*steps_between_checks=*/4096};
};

// --- writing -------------------------------------------------------------------------------

template <typename T>
void Store(char* at, T value) {
  std::memcpy(at, &value, sizeof(T));
}

// A built array's bytes as stored in the file: its elements, compressed when its encoding
// says so.
std::string StoredArrayBytes(const FbxProperty& property) {
  const size_t element = ElementBytes(property.type);
  const size_t count = std::max(property.reals.size(), property.integers.size());
  std::string raw(count * element, '\0');
  char* at = raw.data();
  for (size_t i = 0; i < count; ++i, at += element) {
    switch (property.type) {
      case 'f':
        Store<float>(at, static_cast<float>(property.reals[i]));
        break;
      case 'd':
        Store<double>(at, property.reals[i]);
        break;
      case 'l':
        Store<int64_t>(at, property.integers[i]);
        break;
      case 'i':
        Store<int32_t>(at, static_cast<int32_t>(property.integers[i]));
        break;
      default:  // 'b'
        *at = property.integers[i] != 0 ? 1 : 0;
        break;
    }
  }
  if (property.encoding == 0) return raw;
  uLongf length = compressBound(static_cast<uLong>(raw.size()));
  std::string stored(length, '\0');
  // The fastest level: a take's rewritten curves are megabytes, and every reader inflates
  // any level the same (Z_DEFAULT_COMPRESSION took about 4x as long here).
  compress2(reinterpret_cast<Bytef*>(stored.data()), &length,
            reinterpret_cast<const Bytef*>(raw.data()), static_cast<uLong>(raw.size()),
            Z_BEST_SPEED);
  stored.resize(length);
  return stored;
}

void AppendArrayRecord(std::string& out, const FbxProperty& property, std::string_view stored) {
  out.push_back(property.type);
  Append<uint32_t>(out, property.count);
  Append<uint32_t>(out, property.encoding);
  Append<uint32_t>(out, static_cast<uint32_t>(stored.size()));
  out.append(stored);
}

void AppendArray(std::string& out, const FbxProperty& property) {
  if (!property.encoded.empty() || (property.reals.empty() && property.integers.empty())) {
    AppendArrayRecord(out, property, property.encoded);  // as read, or encoded already
    return;
  }
  AppendArrayRecord(out, property, StoredArrayBytes(property));
}

void AppendProperty(std::string& out, const FbxProperty& property) {
  if (property.is_array()) {
    AppendArray(out, property);
    return;
  }
  out.push_back(property.type);
  switch (property.type) {
    case 'Y':
      Append<int16_t>(out, static_cast<int16_t>(property.integer));
      break;
    case 'C':
      out.push_back(property.integer != 0 ? 1 : 0);
      break;
    case 'I':
      Append<int32_t>(out, static_cast<int32_t>(property.integer));
      break;
    case 'L':
      Append<int64_t>(out, property.integer);
      break;
    case 'F':
      Append<float>(out, static_cast<float>(property.real));
      break;
    case 'D':
      Append<double>(out, property.real);
      break;
    default:  // 'S', 'R'
      Append<uint32_t>(out, static_cast<uint32_t>(property.bytes.size()));
      out.append(property.bytes);
      break;
  }
}

class TreeWriter {
 public:
  TreeWriter(std::string& out, bool wide) : out_(out), wide_(wide) {}

  void WriteList(const std::vector<FbxNode>& nodes) {
    for (const FbxNode& node : nodes) WriteNode(node);
    out_.append(wide_ ? 25 : 13, '\0');
  }

 private:
  void PutCount(size_t at, uint64_t value) {
    if (wide_) {
      std::memcpy(&out_[at], &value, 8);
    } else {
      const auto narrow = static_cast<uint32_t>(value);
      std::memcpy(&out_[at], &narrow, 4);
    }
  }

  void WriteNode(const FbxNode& node) {
    const size_t at = out_.size();
    const size_t word = wide_ ? 8 : 4;
    out_.append(3 * word, '\0');  // end offset, property count, property bytes: below
    out_.push_back(static_cast<char>(node.name.size()));
    out_.append(node.name);
    const size_t properties_at = out_.size();
    if (!node.changed && !node.property_bytes.empty()) {
      out_.append(node.property_bytes);
    } else {
      for (const FbxProperty& property : node.properties) AppendProperty(out_, property);
    }
    PutCount(at + word, node.properties.size());
    PutCount(at + 2 * word, out_.size() - properties_at);
    if (!node.children.empty() || node.null_record) WriteList(node.children);
    PutCount(at, out_.size());
  }

  std::string& out_;
  const bool wide_;
};

}  // namespace

bool FbxProperty::is_array() const { return ElementBytes(type) != 0; }

FbxProperty FbxProperty::Int64(int64_t value) {
  FbxProperty p;
  p.type = 'L';
  p.integer = value;
  return p;
}
FbxProperty FbxProperty::Int32(int32_t value) {
  FbxProperty p;
  p.type = 'I';
  p.integer = value;
  return p;
}
FbxProperty FbxProperty::Double(double value) {
  FbxProperty p;
  p.type = 'D';
  p.real = value;
  return p;
}
FbxProperty FbxProperty::String(std::string value) {
  FbxProperty p;
  p.type = 'S';
  p.bytes = std::move(value);
  return p;
}
FbxProperty FbxProperty::DoubleArray(char type, std::vector<double> values, bool compress) {
  FbxProperty p;
  p.type = type;
  p.count = static_cast<uint32_t>(values.size());
  p.encoding = compress ? 1 : 0;
  p.reals = std::move(values);
  return p;
}
FbxProperty FbxProperty::IntegerArray(char type, std::vector<int64_t> values, bool compress) {
  FbxProperty p;
  p.type = type;
  p.count = static_cast<uint32_t>(values.size());
  p.encoding = compress ? 1 : 0;
  p.integers = std::move(values);
  return p;
}

FbxProperty FbxProperty::EncodedIntegerArray(char type, std::vector<int64_t> values,
                                             bool compress) {
  FbxProperty p = IntegerArray(type, std::move(values), compress);
  p.encoded_owner = std::make_shared<const std::string>(StoredArrayBytes(p));
  p.encoded = *p.encoded_owner;
  p.integers.clear();
  return p;
}

const FbxNode* FbxNode::Child(std::string_view child_name) const {
  for (const FbxNode& child : children) {
    if (child.name == child_name) return &child;
  }
  return nullptr;
}
FbxNode* FbxNode::Child(std::string_view child_name) {
  for (FbxNode& child : children) {
    if (child.name == child_name) return &child;
  }
  return nullptr;
}

bool IsFbxBinary(std::string_view bytes) { return bytes.substr(0, kMagic.size()) == kMagic; }

absl::StatusOr<FbxDocument> ReadFbx(std::string bytes, const FbxReadLimits& limits) {
  if (!IsFbxBinary(bytes)) {
    const std::string_view head = std::string_view(bytes).substr(0, 1024);
    if (head.find("FBXHeaderExtension") != std::string_view::npos || head.rfind("; FBX", 0) == 0) {
      return absl::InvalidArgumentError(
          "an ASCII FBX file: koma reads binary FBX 7.1 to 7.7 (Blender's importer refuses "
          "ASCII too); export it as binary");
    }
    return absl::InvalidArgumentError(
        "not a binary FBX file (it does not start with \"Kaydara FBX Binary\")");
  }
  if (bytes.size() < kHeaderBytes) {
    return absl::InvalidArgumentError(
        absl::StrCat("the file ends in its header (", bytes.size(), " bytes)"));
  }
  FbxDocument document;
  document.version = Load<uint32_t>(bytes.data() + 23);
  if (document.version < kFbxMinVersion || document.version > kFbxMaxVersion) {
    return absl::InvalidArgumentError(absl::StrCat(
        "FBX version ", document.version / 1000, ".", document.version % 1000 / 100, " (",
        document.version, "): koma reads binary FBX 7.1 to 7.7",
        document.version < kFbxMinVersion
            ? " (Blender's importer also refuses files before 7.1); save it as FBX 7.4 or later"
            : ""));
  }
  auto file = std::make_shared<const std::string>(std::move(bytes));
  TreeReader reader(*file, document.version, limits);
  KOMA_ASSIGN_OR_RETURN(document.list_end,
                        reader.ReadList(kHeaderBytes, file->size(), 0, document.nodes));
  document.file = std::move(file);
  return document;
}

namespace {

// The array's elements as raw little-endian bytes (inflated when zlib-encoded) into `raw`,
// which holds count x the element's size.
absl::Status RawArrayInto(const FbxProperty& property, char* raw, size_t bytes) {
  if (property.encoding == 0) {
    if (property.encoded.size() != bytes) {
      return absl::InvalidArgumentError(
          absl::StrCat("an array of ", property.count, " '", std::string(1, property.type),
                       "' elements stored in ", property.encoded.size(), " bytes"));
    }
    std::memcpy(raw, property.encoded.data(), bytes);
    return absl::OkStatus();
  }
  uLongf length = static_cast<uLongf>(bytes);
  const int result = uncompress(reinterpret_cast<Bytef*>(raw), &length,
                                reinterpret_cast<const Bytef*>(property.encoded.data()),
                                static_cast<uLong>(property.encoded.size()));
  if (result != Z_OK || length != bytes) {
    return absl::InvalidArgumentError(absl::StrCat(
        "an array of ", property.count, " '", std::string(1, property.type),
        "' elements whose zlib data is broken or holds another size (", zError(result), ")"));
  }
  return absl::OkStatus();
}

absl::StatusOr<std::string> RawArray(const FbxProperty& property) {
  std::string raw(static_cast<size_t>(property.count) * ElementBytes(property.type), '\0');
  KOMA_RETURN_IF_ERROR(RawArrayInto(property, raw.data(), raw.size()));
  return raw;
}

}  // namespace

absl::StatusOr<std::vector<double>> FbxReals(const FbxProperty& property) {
  if (property.type != 'f' && property.type != 'd') {
    return absl::InvalidArgumentError(absl::StrCat("an array of '", std::string(1, property.type),
                                                   "' where numbers (f, d) are expected"));
  }
  if (property.encoded.empty() && !property.reals.empty()) return property.reals;  // as built
  std::vector<double> values(property.count);
  if (property.type == 'd') {  // little-endian doubles: inflated in place
    KOMA_RETURN_IF_ERROR(RawArrayInto(property, reinterpret_cast<char*>(values.data()),
                                      values.size() * sizeof(double)));
    return values;
  }
  KOMA_ASSIGN_OR_RETURN(const std::string raw, RawArray(property));
  for (size_t i = 0; i < values.size(); ++i) {
    values[i] =
        property.type == 'f' ? Load<float>(raw.data() + 4 * i) : Load<double>(raw.data() + 8 * i);
  }
  return values;
}

absl::StatusOr<std::vector<int64_t>> FbxIntegers(const FbxProperty& property) {
  if (property.type != 'l' && property.type != 'i' && property.type != 'b') {
    return absl::InvalidArgumentError(absl::StrCat("an array of '", std::string(1, property.type),
                                                   "' where integers (l, i, b) are expected"));
  }
  if (property.encoded.empty() && !property.integers.empty()) return property.integers;
  std::vector<int64_t> values(property.count);
  if (property.type == 'l') {  // little-endian int64s: inflated in place
    KOMA_RETURN_IF_ERROR(RawArrayInto(property, reinterpret_cast<char*>(values.data()),
                                      values.size() * sizeof(int64_t)));
    return values;
  }
  KOMA_ASSIGN_OR_RETURN(const std::string raw, RawArray(property));
  for (size_t i = 0; i < values.size(); ++i) {
    values[i] = property.type == 'l'   ? Load<int64_t>(raw.data() + 8 * i)
                : property.type == 'i' ? Load<int32_t>(raw.data() + 4 * i)
                                       : static_cast<int64_t>(raw[i] != 0);
  }
  return values;
}

std::string WriteFbx(const FbxDocument& document) {
  std::string out;
  out.reserve(document.file != nullptr ? document.file->size() : 1024);
  if (document.file != nullptr) {
    out.append(*document.file, 0, kHeaderBytes);
  } else {
    out.append(kMagic);
    out.push_back('\x1a');
    out.push_back('\0');
    Append<uint32_t>(out, document.version);
  }
  TreeWriter(out, document.version >= kWideVersion).WriteList(document.nodes);
  if (document.file == nullptr) return out;
  const std::string_view footer = std::string_view(*document.file).substr(document.list_end);
  if (out.size() == document.list_end || footer.size() < 16 + 4 + 136) {
    out.append(footer);  // where it was (or too short to have the usual layout): as it was
    return out;
  }
  // The footer: a 16-byte id, zeros, then from the version on. The zeros put the version at
  // the same offset modulo 16 as in the file (writers differ: Blender aligns it to 16, the FBX
  // SDK to 4 past 16), at least 4 of them.
  const size_t zeros_then = footer.find_first_not_of('\0', 16) - 16;
  const size_t version_at = document.list_end + 16 + zeros_then;
  size_t zeros = 4;
  while ((out.size() + 16 + zeros) % 16 != version_at % 16) ++zeros;
  if (version_at % 16 == 0 && zeros == 4) zeros += 16;  // Blender's: 1 to 16 after the 4
  out.append(footer.substr(0, 16));
  out.append(zeros, '\0');
  out.append(footer.substr(16 + zeros_then));
  return out;
}

}  // namespace koma::formats
