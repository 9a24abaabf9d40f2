// Fuzz target: any bytes as a binary FBX file (formats/fbx.h).
//
// ReadFbx must answer OK or an error status for every input, never crash, hang or trip a
// sanitizer, and never inflate more than its limits let it. When it accepts the input:
// writing the document back gives the input byte for byte; every array decodes or names its
// broken zlib data; and an array changed and written reads back with the new values.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "formats/fbx.h"
#include "fuzz/fuzz_check.h"

namespace {

koma::formats::FbxReadLimits Limits() {
  koma::formats::FbxReadLimits limits;
  limits.max_array_bytes = 1 << 20;  // the fuzzer's own bound on work per input
  limits.max_inflated_bytes = 4 << 20;
  limits.max_nodes = 100000;
  return limits;
}

// Decodes every array below `nodes`; the first array of numbers found, for the change test.
void DecodeAll(std::vector<koma::formats::FbxNode>& nodes, koma::formats::FbxNode** changed) {
  for (koma::formats::FbxNode& node : nodes) {
    for (const koma::formats::FbxProperty& property : node.properties) {
      if (!property.is_array()) continue;
      const bool real = property.type == 'f' || property.type == 'd';
      const absl::Status status = real ? koma::formats::FbxReals(property).status()
                                       : koma::formats::FbxIntegers(property).status();
      KOMA_FUZZ_CHECK(status.ok() || !status.message().empty(), "an error must say what");
      if (real && status.ok() && *changed == nullptr) *changed = &node;
    }
    DecodeAll(node.children, changed);
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string bytes(reinterpret_cast<const char*>(data), size);
  absl::StatusOr<koma::formats::FbxDocument> document = koma::formats::ReadFbx(bytes, Limits());
  if (!document.ok()) {
    KOMA_FUZZ_CHECK(!document.status().message().empty(), "an error must say what is wrong");
    return 0;
  }
  KOMA_FUZZ_CHECK(koma::formats::WriteFbx(*document) == bytes, "unchanged writes back as read");
  koma::formats::FbxNode* changed = nullptr;
  DecodeAll(document->nodes, &changed);
  if (changed == nullptr) return 0;
  for (koma::formats::FbxProperty& property : changed->properties) {
    if (property.type != 'f' && property.type != 'd') continue;
    const absl::StatusOr<std::vector<double>> values = koma::formats::FbxReals(property);
    if (!values.ok()) continue;
    std::vector<double> next(values->size() + 1, 0.5);
    property = koma::formats::FbxProperty::DoubleArray(property.type, next, property.encoding == 1);
    changed->changed = true;
    const std::string written = koma::formats::WriteFbx(*document);
    const absl::StatusOr<koma::formats::FbxDocument> again =
        koma::formats::ReadFbx(written, Limits());
    KOMA_FUZZ_CHECK(again.ok(), std::string(again.status().message()).c_str());
    break;
  }
  return 0;
}
