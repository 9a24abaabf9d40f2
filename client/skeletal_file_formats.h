// The skeletal formats the server reads whole (formats/format_table.h's `sent_whole` rows:
// glTF, FBX): per format, the functions `koma skeletal` and `koma batch` call for it. A new
// such format is its row in the format table plus one entry here.
#ifndef KOMA_CLIENT_SKELETAL_FILE_FORMATS_H_
#define KOMA_CLIENT_SKELETAL_FILE_FORMATS_H_

#include <string>

#include "absl/status/status.h"
#include "absl/status/statusor.h"
#include "client/skeletal_command.h"
#include "formats/format_table.h"
#include "koma/v1/retime.pb.h"

namespace koma::client {

struct SkeletalFileFormat {
  formats::FormatId id;
  // `koma skeletal` on the file's bytes: checks the flags, calls, writes; the exit code.
  int (*run)(const SkeletalArgs& args, std::string bytes);
  // `koma batch`'s steps of the same: the request, the outputs, the --report page.
  absl::StatusOr<v1::RetimeSkeletalRequest> (*build)(const SkeletalArgs&, std::string);
  absl::Status (*write_outputs)(const SkeletalArgs&, const v1::RetimeSkeletalResponse&);
  absl::Status (*write_report)(const std::string&, const v1::RetimeSkeletalRequest&,
                               const v1::RetimeSkeletalResponse&, const std::string&);
};

// The entry of the format `path` names, else (when `bytes` is given) the one its bytes are;
// nullptr for a file the client decodes itself (BVH).
const SkeletalFileFormat* SkeletalFileFormatOf(const std::string& path,
                                               const std::string* bytes = nullptr);

}  // namespace koma::client

#endif  // KOMA_CLIENT_SKELETAL_FILE_FORMATS_H_
