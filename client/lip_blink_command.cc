#include "client/lip_blink_command.h"

#include <map>
#include <optional>
#include <string>
#include <vector>

#include "absl/strings/match.h"
#include "absl/strings/str_cat.h"
#include "convert/curve_text.h"
#include "client/channel.h"
#include "client/command_output.h"
#include "client/curves_convert.h"
#include "client/files.h"
#include "client/lip_blink_summary.h"
#include "client/report/lip_blink_report.h"
#include "client/report/lip_blink_voice_report.h"
#include "client/retime_call.h"
#include "client/spine_lip_blink.h"
#include "client/timing_from_curves.h"
#include "client/xdts_sheets.h"
#include "formats/xdts.h"
#include "koma/v1/retime.grpc.pb.h"

namespace koma::client {
namespace {

void AddIntervals(const std::vector<FlagInterval>& intervals,
                  google::protobuf::RepeatedPtrField<v1::FrameInterval>* out) {
  for (const FlagInterval& i : intervals) {
    v1::FrameInterval* f = out->Add();
    f->set_begin(i.begin);
    f->set_end(i.end);
  }
}

}  // namespace

v1::LipBlinkRequest BuildLipBlinkRequest(const LipBlinkArgs& args, const CurveSet& curves) {
  v1::LipBlinkRequest request;
  *request.mutable_curves() = CurveSetToProto(curves);
  v1::MouthSettings* mouth = request.mutable_mouth();
  for (const std::string& id : args.mouth_ids) mouth->add_ids(id);
  mouth->set_mode(args.mode == "follow" ? v1::MOUTH_FOLLOW : v1::MOUTH_RANDOM);
  if (args.frames_per_shape) mouth->set_frames_per_shape(*args.frames_per_shape);
  if (args.mouth_mid_ratio) mouth->set_mid_ratio(*args.mouth_mid_ratio);
  if (args.mouth_min) mouth->set_min(*args.mouth_min);
  if (args.mouth_max) mouth->set_max(*args.mouth_max);
  AddIntervals(args.speech, mouth->mutable_speech());

  v1::EyeSettings* eyes = request.mutable_eyes();
  for (const std::string& id : args.eye_ids) eyes->add_ids(id);
  if (args.eyes_mid_ratio) eyes->set_mid_ratio(*args.eyes_mid_ratio);
  if (args.eyes_threshold) eyes->set_threshold(*args.eyes_threshold);
  if (args.eyes_min) eyes->set_min(*args.eyes_min);
  if (args.eyes_max) eyes->set_max(*args.eyes_max);
  if (args.eyes_linked) {
    eyes->set_linked(*args.eyes_linked);
  } else if (args.unlinked_eyes) {
    eyes->set_linked(false);
  }
  const bool any_auto_blink = args.auto_blink_mean_s || args.auto_blink_spread_s ||
                              args.auto_blink_hold || !args.auto_blink_keep.empty();
  if (args.auto_blink_enabled.value_or(any_auto_blink)) {
    v1::AutoBlink* blink = eyes->mutable_auto_blink();
    blink->set_enabled(true);
    if (args.auto_blink_mean_s) blink->set_mean_interval_s(*args.auto_blink_mean_s);
    if (args.auto_blink_spread_s) blink->set_spread_s(*args.auto_blink_spread_s);
    if (args.auto_blink_hold) blink->set_hold(*args.auto_blink_hold);
    AddIntervals(args.auto_blink_keep, blink->mutable_keep());
  }
  if (args.seed) request.set_seed(*args.seed);
  if (args.timing_fps) request.set_timing_fps(*args.timing_fps);
  v1::LipBlinkVoiceSettings* voice = request.mutable_voice_settings();
  if (args.noise_floor_dbfs) voice->set_noise_floor_dbfs(*args.noise_floor_dbfs);
  if (args.noise_percentile) voice->set_noise_percentile(*args.noise_percentile);
  if (args.start_above_floor_db) voice->set_start_above_floor_db(*args.start_above_floor_db);
  if (args.stay_above_floor_db) voice->set_stay_above_floor_db(*args.stay_above_floor_db);
  if (args.min_speech_dbfs) voice->set_min_speech_dbfs(*args.min_speech_dbfs);
  if (args.bridge_gap_frames) voice->set_bridge_gap_frames(*args.bridge_gap_frames);
  if (args.faint_gap_frames) voice->set_faint_gap_frames(*args.faint_gap_frames);
  if (args.pause_above_floor_db) voice->set_pause_above_floor_db(*args.pause_above_floor_db);
  if (args.min_speech_frames) voice->set_min_speech_frames(*args.min_speech_frames);
  if (args.open_below_peak_db) voice->set_open_below_peak_db(*args.open_below_peak_db);
  if (args.closed_below_peak_db) voice->set_closed_below_peak_db(*args.closed_below_peak_db);
  if (args.hysteresis_db) voice->set_hysteresis_db(*args.hysteresis_db);
  if (args.any_sound) voice->set_any_sound(true);
  if (voice->ByteSizeLong() == 0) request.clear_voice_settings();
  if (args.voice_motion_fps) request.set_voice_motion_fps(*args.voice_motion_fps);
  if (!args.voice_output.empty()) {
    request.set_voice_output(args.voice_output == "csv" ? v1::VOICE_OUTPUT_CSV
                                                        : v1::VOICE_OUTPUT_MOTION3_JSON);
  }
  return request;
}

// True when any flag only a voice uses is given.
bool HasVoiceFlags(const LipBlinkArgs& args) {
  return args.noise_floor_dbfs || args.noise_percentile || args.start_above_floor_db ||
         args.stay_above_floor_db || args.min_speech_dbfs || args.bridge_gap_frames ||
         args.faint_gap_frames || args.pause_above_floor_db || args.min_speech_frames || args.open_below_peak_db || args.closed_below_peak_db ||
         args.hysteresis_db || args.any_sound || args.voice_motion_fps || !args.voice_output.empty() ||
         !args.motion.empty() || !args.cues.empty();
}

v1::LipBlinkRequest BuildLipBlinkFileRequest(const LipBlinkArgs& args, const CurveInput& input) {
  v1::LipBlinkRequest request = BuildLipBlinkRequest(args, input.curves);
  if (args.send_file) PutCurveFile(args, input, &request);
  return request;
}

absl::Status CheckLipBlinkFlags(const LipBlinkArgs& args) {
  if (args.output.empty()) {
    return absl::InvalidArgumentError("-o/--output OUT.motion3.json or OUT.csv is required");
  }
  if (!args.audio.empty() && !args.rhubarb.empty()) {
    return absl::InvalidArgumentError("--audio and --rhubarb: give one voice, not both");
  }
  if (!args.input.empty() && !args.motion.empty()) {
    return absl::InvalidArgumentError(absl::StrCat("IN (", args.input, ") and --motion (",
                                                   args.motion, ") name two motions; give one"));
  }
  if (!HasVoice(args)) {
    if (args.input.empty()) {
      return absl::InvalidArgumentError(
          "IN is required (a motion3.json or CSV), or --audio FILE / --rhubarb FILE");
    }
    if (HasVoiceFlags(args)) {
      return absl::InvalidArgumentError(
          "--motion, --cues, --voice-*: need a voice, --audio FILE or --rhubarb FILE");
    }
  }
  if (args.report_audio_max_bytes && args.audio.empty()) {
    return absl::InvalidArgumentError("--report-audio-max-bytes: needs --audio FILE");
  }
  if (HasVoice(args)) {
    return CheckOneOnStdout({{"-o", args.output},
                             {"--cues", args.cues},
                             {"--report", args.report},
                             {"--xdts", args.xdts}},
                            args.json);
  }
  return CheckOneOnStdout(
      {{"-o", args.output}, {"--report", args.report}, {"--xdts", args.xdts}}, args.json);
}

v1::LipBlinkRequest BuildLipBlinkVoiceRequest(const LipBlinkArgs& args, std::string voice,
                                              const CurveInput* input, bool csv_output) {
  CurveSet empty;
  v1::LipBlinkRequest request = BuildLipBlinkRequest(args, input ? input->curves : empty);
  request.clear_curves();
  if (input != nullptr) {
    PutCurveFile(args, *input, &request);
  } else {
    request.set_voice_motion_fps(args.voice_motion_fps.value_or(args.csv_fps));
    request.set_voice_output(csv_output ? v1::VOICE_OUTPUT_CSV : v1::VOICE_OUTPUT_MOTION3_JSON);
  }
  if (!args.audio.empty()) {
    request.set_audio(std::move(voice));
  } else {
    request.set_rhubarb_cues(std::move(voice));
    // Unset: the server follows the cues' drawings.
    if (args.mode.empty()) request.mutable_mouth()->clear_mode();
  }
  return request;
}

absl::Status WriteLipBlinkVoiceOutputs(const LipBlinkArgs& args, bool csv_output,
                                       double source_fps, const v1::LipBlinkResponse& response) {
  std::string text;
  if (response.has_csv_text()) {
    if (!csv_output) {
      return absl::InvalidArgumentError(absl::StrCat(
          "-o ", OutputName(args.output),
          ": a CSV motion cannot be written as motion3.json (no motion3 document)"));
    }
    text = response.csv_text();
  } else if (csv_output) {
    absl::StatusOr<convert::CurveInput> written =
        convert::ParseCurveText(response.motion3_json(), /*csv=*/false, 0);
    if (!written.ok()) return absl::InternalError(written.status().message());
    const std::vector<std::optional<CurveReplacement>> unchanged(written->curves.curves.size());
    absl::StatusOr<std::string> csv = convert::CurveOutputText(*written, unchanged, /*csv=*/true);
    if (!csv.ok()) return csv.status();
    text = *std::move(csv);
  } else {
    text = response.motion3_json();
  }
  if (absl::Status s = WriteFile(args.output, text); !s.ok()) return s;
  if (!args.cues.empty()) {
    const bool tsv = absl::EndsWithIgnoreCase(args.cues, ".tsv");
    if (absl::Status s =
            WriteFile(args.cues, tsv ? response.rhubarb_tsv() : response.rhubarb_json());
        !s.ok()) {
      return s;
    }
  }
  if (args.xdts.empty()) return absl::OkStatus();
  // Named after the motion, else the voice (a new motion has no file of its own).
  const std::string& motion = args.motion.empty() ? args.input : args.motion;
  const std::string& voice = args.audio.empty() ? args.rhubarb : args.audio;
  absl::StatusOr<formats::XdtsSheet> sheet = LipBlinkXdtsSheet(
      response, source_fps, XdtsClipName(motion.empty() ? voice : motion, args.xdts));
  if (!sheet.ok()) return sheet.status();
  return WriteFile(args.xdts, formats::WriteXdts(*sheet));
}

namespace {

int RunLipBlinkVoice(const LipBlinkArgs& args, const CommandOutput& out) {
  const std::string& voice_path = args.audio.empty() ? args.rhubarb : args.audio;
  const std::string& motion_path = args.motion.empty() ? args.input : args.motion;
  std::optional<CurveInput> input;
  if (!motion_path.empty()) {
    absl::StatusOr<CurveInput> read =
        ReadCurveInput(motion_path, args.csv_fps, CurveFormat::kAuto, "lipblink");
    if (!read.ok()) return out.Failure(read.status());
    input = *std::move(read);
  }
  bool csv_output = false;
  if (input) {
    absl::StatusOr<CurveFormat> format =
        CurveOutputFormat(args.output, CurveFormatFromFlag(args.format), *input);
    if (!format.ok()) return out.UsageFailure(format.status());
    csv_output = *format == CurveFormat::kCsv;
  } else {
    const CurveFormat format = CurveFormatFromFlag(
        args.voice_output.empty() ? args.format : args.voice_output);
    csv_output =
        format == CurveFormat::kCsv || (format == CurveFormat::kAuto && IsCsvPath(args.output));
  }
  if (absl::Status s = CheckWritable({args.output, args.cues, args.report, args.xdts}); !s.ok()) {
    return out.Failure(s);
  }
  absl::StatusOr<std::string> voice = ReadFile(voice_path);
  if (!voice.ok()) return out.Failure(voice.status());
  const v1::LipBlinkRequest request =
      BuildLipBlinkVoiceRequest(args, *std::move(voice), input ? &*input : nullptr, csv_output);
  v1::LipBlinkResponse response;
  if (int code = CallRetime(args, out, &v1::Retime::Stub::LipBlink, request, &response);
      code >= 0) {
    return code;
  }
  // The written motion's rate: the input's, or the new motion's (voice_motion_fps).
  const double source_fps = input ? input->curves.fps : request.voice_motion_fps();
  if (absl::Status s = WriteLipBlinkVoiceOutputs(args, csv_output, source_fps, response);
      !s.ok()) {
    return out.Failure(s);
  }
  if (!args.report.empty()) {
    report::VoiceReportSources sources;
    sources.voice_name = voice_path;
    sources.motion_name = motion_path;
    // The curves' rate: the body motion's, or the new motion's (BuildLipBlinkVoiceRequest).
    sources.motion_fps = source_fps;
    sources.audio = request.audio();
    sources.audio_max_bytes =
        args.report_audio_max_bytes.value_or(report::kDefaultReportAudioMaxBytes);
    if (!args.audio.empty()) sources.audio_link = report::AudioLink(args.audio, args.report);
    if (absl::Status s =
            report::WriteLipBlinkVoiceReport(args.report, request, response, sources);
        !s.ok()) {
      return out.Failure(s);
    }
  }
  out.Success(LipBlinkVoiceSummaryText(args, response) + XdtsLine(args.xdts) +
                  ReportLine(args.report),
              LipBlinkVoiceSummaryJson(args, response),
              IsStdio(args.output) || IsStdio(args.cues) || IsStdio(args.report) ||
                  IsStdio(args.xdts));
  return kExitOk;
}

}  // namespace

absl::Status WriteLipBlinkOutputs(const LipBlinkArgs& args, const CurveInput& input,
                                  const v1::LipBlinkResponse& response) {
  std::map<std::string, size_t> index_of;
  for (size_t i = 0; i < input.curves.curves.size(); ++i) index_of[input.curves.curves[i].id] = i;
  std::vector<std::optional<CurveReplacement>> replacements(input.curves.curves.size());
  for (const v1::ConvertedCurve& curve : response.curves()) {
    const auto it = index_of.find(curve.id());
    if (it == index_of.end()) {
      return absl::InternalError(
          absl::StrCat("the server answered a curve \"", curve.id(), "\" the input does not have"));
    }
    replacements[it->second] = convert::ReplacementFromProto(curve);
  }
  if (absl::Status s =
          WriteCurveOutput(args.output, input, replacements, CurveFormatFromFlag(args.format));
      !s.ok()) {
    return s;
  }
  if (!args.xdts.empty()) {
    absl::StatusOr<formats::XdtsSheet> sheet =
        LipBlinkXdtsSheet(response, input.curves.fps, XdtsClipName(args.input, args.xdts));
    if (!sheet.ok()) return sheet.status();
    if (absl::Status s = WriteFile(args.xdts, formats::WriteXdts(*sheet)); !s.ok()) return s;
  }
  return absl::OkStatus();
}

int RunLipBlink(const LipBlinkArgs& args) {
  const CommandOutput out("lipblink", args.json, args.quiet, args.server);
  if (absl::Status s = CheckLipBlinkFlags(args); !s.ok()) return out.UsageFailure(s);
  if (!args.timing_from.empty() && (HasVoice(args) || HasSpineFlags(args))) {
    return out.UsageFailure(absl::InvalidArgumentError(
        "--timing-from: not with a voice (--audio, --rhubarb) or a Spine skeleton"));
  }
  // A Spine skeleton IN goes its own way (client/spine_lip_blink.h), named by its flags.
  if (HasSpineFlags(args)) {
    if (args.input.empty()) {
      return out.UsageFailure(absl::InvalidArgumentError(
          "--animation, --mouth-slot, --eye-slot: IN, a Spine skeleton JSON, is required"));
    }
    absl::StatusOr<CurveInput> read =
        ReadCurveInput(args.input, args.csv_fps, CurveFormat::kAuto, kLipBlinkSpineCommand);
    if (!read.ok()) return out.Failure(read.status());
    if (!read->spine) {
      return out.UsageFailure(absl::InvalidArgumentError(
          absl::StrCat("--animation, --mouth-slot, --eye-slot, --mouth-attachments, "
                       "--eye-attachments: ", InputName(args.input), " is not a Spine skeleton")));
    }
    return RunLipBlinkSpine(args, out, *read);
  }
  if (HasVoice(args)) return RunLipBlinkVoice(args, out);
  absl::StatusOr<CurveInput> input =
      ReadCurveInput(args.input, args.csv_fps, CurveFormat::kAuto, "lipblink");
  if (!input.ok()) return out.Failure(input.status());
  absl::StatusOr<CurveFormat> format =
      CurveOutputFormat(args.output, CurveFormatFromFlag(args.format), *input);
  if (!format.ok()) return out.UsageFailure(format.status());
  if (absl::Status s = CheckWritable({args.output, args.report, args.xdts}); !s.ok()) return out.Failure(s);

  v1::LipBlinkRequest request = BuildLipBlinkRequest(args, input->curves);
  // --send-file: the wire carries the file; the report still reads the decoded request.
  std::optional<v1::LipBlinkRequest> file_request;
  if (args.send_file) file_request = BuildLipBlinkFileRequest(args, *input);
  v1::LipBlinkResponse response;
  if (!args.timing_from.empty()) {
    // The sheet's cells name koma's own answer's tracks: ask for it, then give the sheet's
    // timing (docs/usage.md, "Timing from an edited sheet").
    if (int code = CallRetime(args, out, &v1::Retime::Stub::LipBlink,
                              file_request ? *file_request : request, &response);
        code >= 0) {
      return code;
    }
    const std::string name = XdtsClipName(args.input, args.timing_from);
    for (v1::LipBlinkRequest* r : {&request, file_request ? &*file_request : nullptr}) {
      if (r == nullptr) continue;
      if (absl::Status s = SetLipBlinkTimingFrom(args.timing_from, name, input->curves.fps,
                                                 response, r, nullptr);
          !s.ok()) {
        return out.Failure(s);
      }
    }
    response.Clear();
  }
  if (int code = CallRetime(args, out, &v1::Retime::Stub::LipBlink,
                            file_request ? *file_request : request, &response);
      code >= 0) {
    return code;
  }
  if (absl::Status s = WriteLipBlinkOutputs(args, *input, response); !s.ok()) {
    return out.Failure(s);
  }
  if (!args.report.empty()) {
    if (absl::Status s = report::WriteLipBlinkReport(args.report, request, response, args.input);
        !s.ok()) {
      return out.Failure(s);
    }
  }
  out.Success(LipBlinkSummaryText(args, input->curves, response) + TimingFromLine(args.timing_from) +
                  XdtsLine(args.xdts) +
                  ReportLine(args.report),
              LipBlinkSummaryJson(args, input->curves, response),
              IsStdio(args.output) || IsStdio(args.report) || IsStdio(args.xdts));
  return kExitOk;
}

}  // namespace koma::client
