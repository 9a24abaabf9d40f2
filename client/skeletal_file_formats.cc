#include "client/skeletal_file_formats.h"

#include "client/file_format.h"
#include "client/skeletal_fbx.h"
#include "client/skeletal_gltf.h"

namespace koma::client {
namespace {

// In the format table's order, which is also the order a file's name, then its bytes, are
// tried in.
constexpr SkeletalFileFormat kFormats[] = {
    {FormatId::kGltf, RunSkeletalGltf, BuildGltfRequest, WriteGltfOutputs, WriteGltfReport},
    {FormatId::kFbx, RunSkeletalFbx, BuildFbxRequest, WriteFbxOutputs, WriteFbxReport},
};

}  // namespace

const SkeletalFileFormat* SkeletalFileFormatOf(const std::string& path, const std::string* bytes) {
  const FormatId named = FormatFromName(path);
  const FormatId sniffed = bytes == nullptr ? FormatId::kUnknown : SniffFormat(*bytes);
  for (const SkeletalFileFormat& format : kFormats) {
    if (format.id == named || format.id == sniffed) return &format;
  }
  return nullptr;
}

}  // namespace koma::client
