#include "client/batch/batch_rpc.h"

#include <google/protobuf/io/coded_stream.h>
#include <google/protobuf/io/zero_copy_stream_impl_lite.h>

#include <cstdint>
#include <filesystem>
#include <system_error>
#include <utility>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "client/curve_files.h"
#include "client/files.h"
#include "formats/bvh.h"

namespace koma::client::batch {
namespace {

// Protobuf bytes with map entries in key order, so equal messages give equal bytes.
std::string DeterministicBytes(const google::protobuf::MessageLite& message) {
  std::string bytes;
  {
    google::protobuf::io::StringOutputStream stream(&bytes);
    google::protobuf::io::CodedOutputStream coded(&stream);
    coded.SetSerializationDeterministic(true);
    message.SerializeToCodedStream(&coded);
  }
  return bytes;
}

// 64-bit FNV-1a of the parts, each prefixed with its length (so "ab"+"c" != "a"+"bc"), as
// 16 hex digits. Not a security digest: it tells option sets apart.
std::string Digest(std::initializer_list<std::string> parts) {
  uint64_t hash = 1469598103934665603ULL;
  auto mix = [&hash](const std::string& bytes) {
    for (unsigned char c : bytes) {
      hash ^= c;
      hash *= 1099511628211ULL;
    }
  };
  for (const std::string& part : parts) {
    mix(absl::StrCat(part.size(), ":"));
    mix(part);
  }
  return absl::StrFormat("%016x", hash);
}

// The bytes of a request built from the flags alone (no clip), or the reason it cannot be built:
// what the fingerprint of an option set is made of.
template <typename Request>
std::string RequestBytes(const absl::StatusOr<Request>& request) {
  return request.ok() ? DeterministicBytes(*request)
                      : absl::StrCat("error:", request.status().ToString());
}

absl::Status MakeParentFolder(const std::string& path) {
  const std::filesystem::path parent = std::filesystem::path(path).parent_path();
  if (parent.empty()) return absl::OkStatus();
  std::error_code error;
  std::filesystem::create_directories(parent, error);
  if (error) {
    return absl::PermissionDeniedError(
        absl::StrCat("cannot create folder ", parent.string(), ": ", error.message()));
  }
  return absl::OkStatus();
}

class SkeletalClipCall final : public Clip {
 public:
  SkeletalClipCall(const SkeletalArgs& args, SkeletalClip clip, v1::RetimeSkeletalRequest request)
      : args_(args), clip_(std::move(clip)), request_(std::move(request)) {}

  void Start(v1::Retime::Stub& stub, grpc::ClientContext* context,
             std::function<void(grpc::Status)> done) override {
    response_.Clear();
    stub.async()->RetimeSkeletal(context, &request_, &response_, std::move(done));
  }

  absl::Status Write(const BatchItem& item) override {
    if (absl::Status s = MakeParentFolder(item.output); !s.ok()) return s;
    SkeletalArgs args = args_;
    args.input = item.input;
    args.output = item.output;
    args.timing = item.timing;
    return WriteSkeletalOutputs(args, clip_, response_);
  }

 private:
  const SkeletalArgs& args_;
  SkeletalClip clip_;
  v1::RetimeSkeletalRequest request_;
  v1::RetimeSkeletalResponse response_;
};

class SkeletalRpc final : public Rpc {
 public:
  explicit SkeletalRpc(const SkeletalArgs& args) : args_(args) {}

  absl::StatusOr<std::unique_ptr<Clip>> Read(const BatchItem& item) const override {
    absl::StatusOr<std::string> text = ReadFile(item.input);
    if (!text.ok()) return text.status();
    absl::StatusOr<SkeletalClip> clip = formats::ParseBvh(*text);
    if (!clip.ok()) {
      return absl::InvalidArgumentError(absl::StrCat(item.input, ": ", clip.status().message()));
    }
    absl::StatusOr<v1::RetimeSkeletalRequest> request = BuildSkeletalRequest(args_, *clip);
    if (!request.ok()) {
      return absl::InvalidArgumentError(absl::StrCat(item.input, ": ", request.status().message()));
    }
    return std::make_unique<SkeletalClipCall>(args_, *std::move(clip), *std::move(request));
  }

  std::string Fingerprint() const override {
    // The timing sheet path itself is per clip; whether there is one is not.
    return Digest({"skeletal", RequestBytes(BuildSkeletalRequest(args_, SkeletalClip{}))});
  }

 private:
  SkeletalArgs args_;
};

class CurvesClipCall final : public Clip {
 public:
  CurvesClipCall(const CurvesArgs& args, CurveInput input, v1::RetimeCurvesRequest request)
      : args_(args), input_(std::move(input)), request_(std::move(request)) {}

  void Start(v1::Retime::Stub& stub, grpc::ClientContext* context,
             std::function<void(grpc::Status)> done) override {
    response_.Clear();
    stub.async()->RetimeCurves(context, &request_, &response_, std::move(done));
  }

  absl::Status Write(const BatchItem& item) override {
    if (absl::Status s = MakeParentFolder(item.output); !s.ok()) return s;
    CurvesArgs args = args_;
    args.input = item.input;
    args.output = item.output;
    args.timing = item.timing;
    return WriteCurvesOutputs(args, input_, response_);
  }

 private:
  const CurvesArgs& args_;
  CurveInput input_;
  v1::RetimeCurvesRequest request_;
  v1::RetimeCurvesResponse response_;
};

class CurvesRpc final : public Rpc {
 public:
  explicit CurvesRpc(const CurvesArgs& args) : args_(args) {}

  absl::StatusOr<std::unique_ptr<Clip>> Read(const BatchItem& item) const override {
    absl::StatusOr<CurveInput> input = ReadCurveInput(item.input, args_.csv_fps);
    if (!input.ok()) return input.status();
    absl::StatusOr<v1::RetimeCurvesRequest> request = BuildCurvesRequest(args_, input->curves);
    if (!request.ok()) {
      return absl::InvalidArgumentError(absl::StrCat(item.input, ": ", request.status().message()));
    }
    return std::make_unique<CurvesClipCall>(args_, *std::move(input), *std::move(request));
  }

  std::string Fingerprint() const override {
    return Digest({"curves", RequestBytes(BuildCurvesRequest(args_, CurveSet{})),
                   absl::StrFormat("%.17g", args_.csv_fps)});
  }

 private:
  CurvesArgs args_;
};

class LipBlinkClipCall final : public Clip {
 public:
  LipBlinkClipCall(const LipBlinkArgs& args, CurveInput input)
      : args_(args), input_(std::move(input)), request_(BuildLipBlinkRequest(args_, input_.curves)) {}

  void Start(v1::Retime::Stub& stub, grpc::ClientContext* context,
             std::function<void(grpc::Status)> done) override {
    response_.Clear();
    stub.async()->LipBlink(context, &request_, &response_, std::move(done));
  }

  absl::Status Write(const BatchItem& item) override {
    if (absl::Status s = MakeParentFolder(item.output); !s.ok()) return s;
    LipBlinkArgs args = args_;
    args.input = item.input;
    args.output = item.output;
    return WriteLipBlinkOutputs(args, input_, response_);
  }

 private:
  const LipBlinkArgs& args_;
  CurveInput input_;
  v1::LipBlinkRequest request_;
  v1::LipBlinkResponse response_;
};

class LipBlinkRpc final : public Rpc {
 public:
  explicit LipBlinkRpc(const LipBlinkArgs& args) : args_(args) {}

  absl::StatusOr<std::unique_ptr<Clip>> Read(const BatchItem& item) const override {
    absl::StatusOr<CurveInput> input = ReadCurveInput(item.input, args_.csv_fps);
    if (!input.ok()) return input.status();
    return std::make_unique<LipBlinkClipCall>(args_, *std::move(input));
  }

  std::string Fingerprint() const override {
    return Digest({"lipblink", DeterministicBytes(BuildLipBlinkRequest(args_, CurveSet{})),
                   absl::StrFormat("%.17g", args_.csv_fps)});
  }

 private:
  LipBlinkArgs args_;
};

}  // namespace

std::unique_ptr<Rpc> MakeSkeletalRpc(const SkeletalArgs& args) {
  return std::make_unique<SkeletalRpc>(args);
}
std::unique_ptr<Rpc> MakeCurvesRpc(const CurvesArgs& args) {
  return std::make_unique<CurvesRpc>(args);
}
std::unique_ptr<Rpc> MakeLipBlinkRpc(const LipBlinkArgs& args) {
  return std::make_unique<LipBlinkRpc>(args);
}

}  // namespace koma::client::batch
