#include "client/batch/batch_rpc.h"

#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <system_error>
#include <utility>

#include "absl/strings/str_cat.h"
#include "client/batch/batch_inputs.h"
#include "client/curve_files.h"
#include "client/file_format.h"
#include "client/files.h"
#include "client/report/curves_report.h"
#include "client/report/lip_blink_report.h"
#include "client/report/lip_blink_voice_report.h"
#include "client/report/skeletal_report.h"
#include "client/skeletal_file_formats.h"
#include "client/spine_curves.h"
#include "client/spine_lip_blink.h"
#include "client/timing_from.h"
#include "client/timing_from_curves.h"
#include "client/xdts_sheets.h"
#include "formats/xdts.h"

namespace koma::client::batch {
namespace {

// A request that cannot be built for this clip (a flag that does not fit it, such as
// --joint-weights for another skeleton): the error, naming the file.
absl::Status WithPath(const BatchItem& item, const absl::Status& status) {
  return absl::Status(status.code(), absl::StrCat(item.input, ": ", status.message()));
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

// Starts one call of the Retime service; one overload per RPC.
void StartCall(v1::Retime::Stub& stub, grpc::ClientContext* context,
               const v1::RetimeSkeletalRequest* request, v1::RetimeSkeletalResponse* response,
               std::function<void(grpc::Status)> done) {
  stub.async()->RetimeSkeletal(context, request, response, std::move(done));
}
void StartCall(v1::Retime::Stub& stub, grpc::ClientContext* context,
               const v1::RetimeCurvesRequest* request, v1::RetimeCurvesResponse* response,
               std::function<void(grpc::Status)> done) {
  stub.async()->RetimeCurves(context, request, response, std::move(done));
}
void StartCall(v1::Retime::Stub& stub, grpc::ClientContext* context,
               const v1::LipBlinkRequest* request, v1::LipBlinkResponse* response,
               std::function<void(grpc::Status)> done) {
  stub.async()->LipBlink(context, request, response, std::move(done));
}

// A clip's request and answer, and the Start every clip shares (a retry clears the answer).
// With a sheet to apply (--timing-from, SetSheet): each Start first asks for koma's own answer
// to the request as built (the sheet's cells name its drawings), applies the sheet to a copy
// of the request, then sends that, as `koma curves|lipblink --timing-from` does.
template <typename Request, typename Response>
class CallClip : public Clip {
 public:
  using ApplySheet = std::function<absl::Status(const Response& computed, Request* request)>;

  void Start(v1::Retime::Stub& stub, grpc::ClientContext* context,
             std::function<void(grpc::Status)> done) final {
    response_.Clear();
    if (!apply_sheet_) {
      StartCall(stub, context, &request_, &response_, std::move(done));
      return;
    }
    request_ = unapplied_;
    computed_.Clear();
    // Its own context (a context serves one call), under the batch's deadline for the clip.
    computed_context_ = std::make_unique<grpc::ClientContext>();
    computed_context_->set_deadline(context->deadline());
    StartCall(stub, computed_context_.get(), &unapplied_, &computed_,
              [this, &stub, context, done = std::move(done)](grpc::Status status) mutable {
                if (!status.ok()) return done(status);
                if (absl::Status s = apply_sheet_(computed_, &request_); !s.ok()) {
                  return done(grpc::Status(static_cast<grpc::StatusCode>(s.code()),
                                           std::string(s.message())));
                }
                StartCall(stub, context, &request_, &response_, std::move(done));
              });
  }

 protected:
  explicit CallClip(Request request) : request_(std::move(request)) {}

  void SetSheet(ApplySheet apply) {
    unapplied_ = request_;
    apply_sheet_ = std::move(apply);
  }

  Request request_;
  Response response_;

 private:
  ApplySheet apply_sheet_;
  Request unapplied_;  // the request as built, for koma's own answer
  Response computed_;
  std::unique_ptr<grpc::ClientContext> computed_context_;
};
using SkeletalCall = CallClip<v1::RetimeSkeletalRequest, v1::RetimeSkeletalResponse>;
using CurvesCall = CallClip<v1::RetimeCurvesRequest, v1::RetimeCurvesResponse>;
using LipBlinkCall = CallClip<v1::LipBlinkRequest, v1::LipBlinkResponse>;

// The batch's skeletal flags with this clip's own input, output and timing sheet.
SkeletalArgs ArgsFor(const SkeletalArgs& batch_args, const BatchItem& item) {
  SkeletalArgs args = batch_args;
  args.input = item.input;
  args.output = item.output;
  args.timing = item.timing;
  args.xdts = item.xdts;
  return args;
}

class SkeletalClipCall final : public SkeletalCall {
 public:
  SkeletalClipCall(const SkeletalArgs& args, SkeletalInput input, v1::RetimeSkeletalRequest request)
      : SkeletalCall(std::move(request)),
        args_(args),
        clip_(std::move(input.clip)),
        warnings_(std::move(input.warnings)) {}

  absl::Status Write(const BatchItem& item) override {
    if (absl::Status s = MakeParentFolder(item.output); !s.ok()) return s;
    const SkeletalArgs args = ArgsFor(args_, item);
    // The file's warnings as the single-file command words them, for the report.
    response_.clear_warnings();
    for (const std::string& warning : warnings_) response_.add_warnings(warning);
    if (absl::Status s = WriteSkeletalOutputs(args, clip_, response_); !s.ok()) return s;
    if (item.report.empty()) return absl::OkStatus();
    return report::WriteSkeletalReport(item.report, request_, response_, item.input);
  }

 private:
  const SkeletalArgs& args_;
  SkeletalClip clip_;
  std::vector<std::string> warnings_;
};

class SkeletalFileCall final : public SkeletalCall {
 public:
  SkeletalFileCall(const SkeletalArgs& args, const SkeletalFileFormat& format,
                   v1::RetimeSkeletalRequest request)
      : SkeletalCall(std::move(request)), args_(args), format_(format) {}

  absl::Status Write(const BatchItem& item) override {
    if (absl::Status s = MakeParentFolder(item.output); !s.ok()) return s;
    const SkeletalArgs args = ArgsFor(args_, item);
    if (absl::Status s = format_.write_outputs(args, response_); !s.ok()) return s;
    if (item.report.empty()) return absl::OkStatus();
    return format_.write_report(item.report, request_, response_, item.input);
  }

 private:
  const SkeletalArgs& args_;
  const SkeletalFileFormat& format_;
};

class SkeletalRpc final : public Rpc {
 public:
  explicit SkeletalRpc(const SkeletalArgs& args) : args_(args) {}

  absl::StatusOr<std::unique_ptr<Clip>> Read(const BatchItem& item) const override {
    // A file the server reads and answers whole (glTF, FBX; by its name): the request is
    // built and the answer written by that format's own functions, as `koma skeletal` does.
    // --timing-from: one sheet for every clip, or a folder with each clip's sheet.
    SkeletalArgs args = args_;
    args.input = item.input;
    if (!args.timing_from.empty()) {
      absl::StatusOr<std::string> sheet = TimingFromFor(args.timing_from, item.input);
      if (!sheet.ok()) return sheet.status();
      args.timing_from = *sheet;
    }
    if (const SkeletalFileFormat* file = SkeletalFileFormatOf(item.input)) {
      const SkeletalFileFormat& format = *file;
      absl::StatusOr<std::string> bytes = ReadFile(item.input);
      if (!bytes.ok()) return bytes.status();
      absl::StatusOr<v1::RetimeSkeletalRequest> request = format.build(args, *std::move(bytes));
      if (!request.ok()) return WithPath(item, request.status());
      return std::make_unique<SkeletalFileCall>(args_, format, *std::move(request));
    }
    absl::StatusOr<SkeletalInput> input = ReadSkeletalFile(item.input);
    if (!input.ok()) return input.status();
    absl::StatusOr<v1::RetimeSkeletalRequest> request = BuildSkeletalRequest(args, input->clip);
    if (!request.ok()) return WithPath(item, request.status());
    if (absl::Status s = SetSkeletalTimingFromArgs(args, input->clip, &*request, &input->warnings);
        !s.ok()) {
      return WithPath(item, s);
    }
    std::string().swap(input->text);  // not kept: the batch sends the decoded clip
    return std::make_unique<SkeletalClipCall>(args_, *std::move(input), *std::move(request));
  }

 private:
  SkeletalArgs args_;
};

class CurvesClipCall final : public CurvesCall {
 public:
  CurvesClipCall(const CurvesArgs& args, CurveInput input, v1::RetimeCurvesRequest request)
      : CurvesCall(std::move(request)), args_(args), input_(std::move(input)) {}

  // --timing-from: this clip's sheet (SetCurvesTimingFrom), its tracks named after `name`.
  void ApplyTimingFrom(const std::string& sheet, const std::string& name) {
    SetSheet([sheet, name](const v1::RetimeCurvesResponse& computed,
                           v1::RetimeCurvesRequest* request) {
      return SetCurvesTimingFrom(sheet, name, computed, request, nullptr);
    });
  }

  absl::Status Write(const BatchItem& item) override {
    if (absl::Status s = MakeParentFolder(item.output); !s.ok()) return s;
    CurvesArgs args = args_;
    args.input = item.input;
    args.output = item.output;
    args.timing = item.timing;
    args.xdts = item.xdts;
    if (absl::Status s = WriteCurvesOutputs(args, input_, response_); !s.ok()) return s;
    if (item.report.empty()) return absl::OkStatus();
    return report::WriteCurvesReport(item.report, request_, response_, item.input);
  }

 private:
  const CurvesArgs& args_;
  CurveInput input_;
};

class CurvesRpc final : public Rpc {
 public:
  explicit CurvesRpc(const CurvesArgs& args) : args_(args) {}

  absl::StatusOr<std::unique_ptr<Clip>> Read(const BatchItem& item) const override {
    absl::StatusOr<CurveInput> input =
        ReadCurveInput(item.input, args_.csv_fps, CurveFormat::kAuto, "curves");
    if (!input.ok()) return input.status();
    if (!input->spine && !args_.animations.empty()) {  // as `koma curves` refuses it
      return absl::InvalidArgumentError(
          absl::StrCat("--animation: ", item.input, " is not a Spine skeleton"));
    }
    if (input->spine) {  // one call per file: one animation, named or the only one
      if (absl::Status s = SelectOneSpineAnimation(*input, args_.animations); !s.ok()) {
        return WithPath(item, s);
      }
    }
    if (input->spine && !args_.timing_from.empty()) {  // as `koma curves` refuses it
      return absl::InvalidArgumentError(
          absl::StrCat("--timing-from: not for a Spine skeleton (", item.input, ")"));
    }
    absl::StatusOr<v1::RetimeCurvesRequest> request = BuildCurvesRequest(args_, input->curves);
    if (!request.ok()) return WithPath(item, request.status());
    auto call = std::make_unique<CurvesClipCall>(args_, *std::move(input), *std::move(request));
    if (!args_.timing_from.empty()) {
      // One sheet for every clip, or a folder with each clip's NAME.xdts / NAME.timing.csv.
      absl::StatusOr<std::string> sheet = TimingFromFor(args_.timing_from, item.input);
      if (!sheet.ok()) return sheet.status();
      call->ApplyTimingFrom(*sheet, XdtsClipName(item.input, *sheet));
    }
    return call;
  }

 private:
  CurvesArgs args_;
};

class LipBlinkClipCall final : public LipBlinkCall {
 public:
  LipBlinkClipCall(const LipBlinkArgs& args, CurveInput input)
      : LipBlinkCall(BuildLipBlinkRequest(args, input.curves)),
        args_(args),
        input_(std::move(input)) {}

  // --timing-from: this clip's sheet (SetLipBlinkTimingFrom), its tracks named after `name`.
  void ApplyTimingFrom(const std::string& sheet, const std::string& name) {
    const double source_fps = input_.curves.fps;
    SetSheet([sheet, name, source_fps](const v1::LipBlinkResponse& computed,
                                       v1::LipBlinkRequest* request) {
      return SetLipBlinkTimingFrom(sheet, name, source_fps, computed, request, nullptr);
    });
  }

  absl::Status Write(const BatchItem& item) override {
    if (absl::Status s = MakeParentFolder(item.output); !s.ok()) return s;
    LipBlinkArgs args = args_;
    args.input = item.input;
    args.output = item.output;
    args.xdts = item.xdts;
    if (absl::Status s = WriteLipBlinkOutputs(args, input_, response_); !s.ok()) return s;
    if (item.report.empty()) return absl::OkStatus();
    return report::WriteLipBlinkReport(item.report, request_, response_, item.input);
  }

 private:
  const LipBlinkArgs& args_;
  CurveInput input_;
};

LipBlinkArgs WithAudio(const LipBlinkArgs& args, const std::string& path) {
  LipBlinkArgs with = args;
  with.audio = path;
  return with;
}

// The voice report's sources of `recording` (its bytes `audio`), sent with the motion or
// skeleton `motion_name` (empty: none), as the single-file command fills them for
// [IN] --audio REC --report OUT.
report::VoiceReportSources VoiceSources(const LipBlinkArgs& args, const std::string& recording,
                                        const std::string& motion_name, const BatchItem& item,
                                        double motion_fps, const std::string& audio) {
  report::VoiceReportSources sources;
  sources.voice_name = recording;
  sources.motion_name = motion_name;
  sources.motion_fps = motion_fps;
  sources.audio = audio;
  sources.audio_max_bytes =
      args.report_audio_max_bytes.value_or(report::kDefaultReportAudioMaxBytes);
  sources.audio_link = report::AudioLink(recording, item.report);
  return sources;
}

// A Spine skeleton with --animation and the slots: the server writes the skeleton
// (LipBlinkRequest.spine_json, client/spine_lip_blink.h); --speech and auto-blink as given,
// and with --audio-beside the skeleton's recording (`voice`, read from item.audio).
class LipBlinkSpineCall final : public LipBlinkCall {
 public:
  LipBlinkSpineCall(const LipBlinkArgs& args, CurveInput input, convert::SpineLipBlinkSlots slots,
                    const std::string& audio_path, std::string voice)
      : LipBlinkCall(
            BuildSpineLipBlinkRequest(WithAudio(args, audio_path), input.text, std::move(voice))),
        args_(args),
        input_(std::move(input)),
        slots_(std::move(slots)) {}

  absl::Status Write(const BatchItem& item) override {
    if (absl::Status s = MakeParentFolder(item.output); !s.ok()) return s;
    if (!response_.has_spine_json()) {
      return absl::InternalError(absl::StrCat(item.input, ": the server answered no spine_json"));
    }
    if (absl::Status s = WriteFile(item.output, response_.spine_json()); !s.ok()) return s;
    if (!item.xdts.empty()) {
      absl::StatusOr<formats::XdtsSheet> sheet =
          LipBlinkXdtsSheet(response_, input_.spine->fps, XdtsClipName(item.input, item.xdts));
      if (!sheet.ok()) return sheet.status();
      if (absl::Status s = WriteFile(item.xdts, formats::WriteXdts(*sheet)); !s.ok()) return s;
    }
    if (item.report.empty()) return absl::OkStatus();
    absl::StatusOr<v1::LipBlinkRequest> decoded =
        convert::DecodedSpineLipBlinkRequest(request_, *input_.spine, slots_);
    if (!decoded.ok()) return WithPath(item, decoded.status());
    if (!item.audio.empty()) {
      return report::WriteLipBlinkVoiceReport(
          item.report, *decoded, response_,
          VoiceSources(args_, item.audio, item.input, item, input_.spine->fps, request_.audio()));
    }
    return report::WriteLipBlinkReport(item.report, *decoded, response_, item.input);
  }

 private:
  const LipBlinkArgs& args_;
  CurveInput input_;
  convert::SpineLipBlinkSlots slots_;
};

// A recording (LipBlinkRequest.audio): a new motion written from it, or with `input` (a
// motion3.json or CSV with its recording beside it, --audio-beside) the mouth written into
// that motion, as `koma lipblink [IN] --audio REC -o OUT` writes them.
class LipBlinkVoiceCall final : public LipBlinkCall {
 public:
  LipBlinkVoiceCall(const LipBlinkArgs& args, std::optional<CurveInput> input, bool csv_output,
                    const std::string& audio_path, std::string voice)
      : LipBlinkCall(BuildLipBlinkVoiceRequest(WithAudio(args, audio_path), std::move(voice),
                                               input ? &*input : nullptr, csv_output)),
        args_(args),
        input_(std::move(input)),
        csv_output_(csv_output) {}

  absl::Status Write(const BatchItem& item) override {
    if (absl::Status s = MakeParentFolder(item.output); !s.ok()) return s;
    // A recording alone is the item's input; one beside a motion is item.audio.
    const std::string& recording = input_ ? item.audio : item.input;
    const std::string motion_name = input_ ? item.input : "";
    const double fps = input_ ? input_->curves.fps : request_.voice_motion_fps();
    LipBlinkArgs args = WithAudio(args_, recording);
    if (input_) args.input = item.input;
    args.output = item.output;
    args.cues.clear();
    args.xdts = item.xdts;
    if (absl::Status s = WriteLipBlinkVoiceOutputs(args, csv_output_, fps, response_);
        !s.ok() || item.report.empty()) {
      return s;
    }
    return report::WriteLipBlinkVoiceReport(
        item.report, request_, response_,
        VoiceSources(args_, recording, motion_name, item, fps, request_.audio()));
  }

 private:
  const LipBlinkArgs& args_;
  std::optional<CurveInput> input_;  // none: a new motion
  bool csv_output_;
};

class LipBlinkRpc final : public Rpc {
 public:
  explicit LipBlinkRpc(const LipBlinkArgs& args) : args_(args) {}

  absl::StatusOr<std::unique_ptr<Clip>> Read(const BatchItem& item) const override {
    if (!item.audio_error.empty()) return absl::InvalidArgumentError(item.audio_error);
    if (IsAudioPath(item.input)) {
      if (!args_.timing_from.empty()) {  // as `koma lipblink` refuses a voice with a sheet
        return absl::InvalidArgumentError(
            absl::StrCat("--timing-from: not with a voice (", item.input, ")"));
      }
      if (HasSpineFlags(args_)) {
        return absl::InvalidArgumentError(absl::StrCat(
            "--animation, --mouth-slot, --eye-slot: for Spine skeletons, not a recording (",
            item.input, ")"));
      }
      absl::StatusOr<std::string> audio = ReadFile(item.input);
      if (!audio.ok()) return audio.status();
      return std::make_unique<LipBlinkVoiceCall>(args_, std::nullopt, /*csv_output=*/false,
                                                 item.input, *std::move(audio));
    }
    // With the Spine flags a skeleton is read (and anything else refused); without, refused.
    const bool spine = HasSpineFlags(args_);
    absl::StatusOr<CurveInput> input = ReadCurveInput(item.input, args_.csv_fps, CurveFormat::kAuto,
                                                      spine ? kLipBlinkSpineCommand : "lipblink");
    if (!input.ok()) return input.status();
    // --audio-beside: the recording read after the input, so an input error names the input.
    std::string voice;
    if (!item.audio.empty()) {
      absl::StatusOr<std::string> read = ReadFile(item.audio);
      if (!read.ok()) return read.status();
      voice = *std::move(read);
    }
    if (spine) {
      if (!input->spine) {
        return absl::InvalidArgumentError(absl::StrCat(
            "--animation, --mouth-slot, --eye-slot: ", item.input, " is not a Spine skeleton"));
      }
      absl::StatusOr<convert::SpineLipBlinkSlots> slots =
          CheckSpineSlots(WithAudio(args_, item.audio), *input->spine);
      if (!slots.ok()) return WithPath(item, slots.status());
      return std::make_unique<LipBlinkSpineCall>(args_, *std::move(input), *std::move(slots),
                                                 item.audio, std::move(voice));
    }
    if (!item.audio.empty()) {
      absl::StatusOr<CurveFormat> format =
          CurveOutputFormat(item.output, CurveFormatFromFlag(args_.format), *input);
      if (!format.ok()) return WithPath(item, format.status());
      const bool csv_output = *format == CurveFormat::kCsv;
      return std::make_unique<LipBlinkVoiceCall>(args_, *std::move(input), csv_output, item.audio,
                                                 std::move(voice));
    }
    auto call = std::make_unique<LipBlinkClipCall>(args_, *std::move(input));
    if (!args_.timing_from.empty()) {
      absl::StatusOr<std::string> sheet = TimingFromFor(args_.timing_from, item.input);
      if (!sheet.ok()) return sheet.status();
      call->ApplyTimingFrom(*sheet, XdtsClipName(item.input, *sheet));
    }
    return call;
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
