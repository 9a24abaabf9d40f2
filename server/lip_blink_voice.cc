#include "server/lip_blink_voice.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "absl/strings/str_cat.h"
#include "convert/curves_convert.h"
#include "convert/field_error.h"
#include "core/mouth_cues.h"
#include "core/status_macros.h"
#include "core/stop_check.h"
#include "core/voice_activity.h"
#include "core/voice_features.h"
#include "core/voice_gate.h"
#include "formats/audio_reader.h"
#include "formats/number_format.h"
#include "formats/rhubarb_cues.h"
#include "server/call_footprint.h"
#include "server/call_reservation.h"
#include "server/curve_convert.h"
#include "server/file_requests.h"
#include "server/lip_blink_request.h"

namespace koma::server {
namespace {

constexpr const char* kDefaultMouthId = "ParamMouthOpenY";
constexpr const char* kDefaultEyeIds[] = {"ParamEyeLOpen", "ParamEyeROpen"};
// Per analysis frame kept while decoding and answering: the sums, the loudness, the voice
// features, the drawing, the response's loudness (bytes, rounded up).
constexpr int64_t kBytesPerAnalysisFrame = 96;
// libsndfile's and its codecs' state and the decoder's blocks, bytes (generous).
constexpr int64_t kDecoderBytes = 8 << 20;


// The analysis of the recording on frames of `fps`, before it is fitted to the motion.
struct Voice {
  VoiceActivity activity;
  v1::LipBlinkVoiceAnalysis analysis;
  double duration_s = 0.0;
  int frames = 0;              // analysis frames the recording spans
  std::vector<MouthCue> cues;  // rhubarb_cues, as read
};

absl::Status InAudio(const absl::Status& status) {
  return absl::Status(status.code(), absl::StrCat("audio: ", status.message()));
}

absl::StatusOr<Voice> AnalyseAudio(const v1::LipBlinkRequest& request, double fps,
                                   const VoiceOptions& options, const RequestLimits& limits) {
  const std::string& bytes = request.audio();
  formats::AudioLimits audio_limits;
  audio_limits.max_seconds = limits.max_audio_seconds;
  audio_limits.max_channels = limits.max_audio_channels;
  audio_limits.max_samples = limits.max_audio_samples;
  absl::StatusOr<std::unique_ptr<formats::AudioDecoder>> decoder =
      formats::AudioDecoder::Open(bytes, audio_limits);
  if (!decoder.ok()) return InAudio(decoder.status());
  const formats::AudioInfo& info = (*decoder)->info();
  // Memory grows with the analysis frames: reserve for the longest the limit lets through.
  const double max_frames = std::min(limits.max_audio_seconds,
                                     static_cast<double>(info.frames) / info.sample_rate + 1.0) *
                                fps +
                            2;
  KOMA_RETURN_IF_ERROR(GrowCallReservation(
      ExpectedFootprint(request, static_cast<int64_t>(request.ByteSizeLong()), limits) +
          kDecoderBytes + static_cast<int64_t>(max_frames) * kBytesPerAnalysisFrame,
      "this LipBlink recording (its bytes, the decoder, the per-frame loudness)"));
  FrameLoudness loudness(info.sample_rate, fps);
  VoiceFeatures features(info.sample_rate, fps);
  StopPoll stop(/*steps_between_checks=*/1 << 20);  // samples: a check every ~1 ms of decoding
  for (;;) {
    absl::StatusOr<absl::Span<const float>> block = (*decoder)->Next();
    if (!block.ok()) return InAudio(block.status());
    if (block->empty()) break;
    loudness.Add(*block);
    if (options.gate.enabled) features.Add(*block);  // any_sound: loudness alone
    if (stop.Stop(static_cast<int64_t>(block->size()) * info.channels)) return stop.status();
  }
  if (loudness.samples() == 0) return absl::InvalidArgumentError("audio: holds no samples");
  Voice v;
  v.frames = loudness.frames_touched();
  v.duration_s = static_cast<double>(loudness.samples()) / info.sample_rate;
  const std::vector<double> dbfs = loudness.Dbfs(v.frames);
  std::vector<FrameInterval> voice_like;
  if (options.gate.enabled) {
    features.Finish();
    voice_like = VoiceLikeStretches(features, fps, options.gate);
  }
  v.activity = DetectVoice(dbfs, options, options.gate.enabled ? &voice_like : nullptr);
  v.analysis.set_sample_rate(info.sample_rate);
  v.analysis.set_channels(info.channels);
  v.analysis.mutable_loudness_dbfs()->Add(dbfs.begin(), dbfs.end());
  return v;
}

absl::StatusOr<Voice> ReadCues(const std::string& bytes, const RequestLimits& limits) {
  KOMA_RETURN_IF_ERROR(CheckLipBlinkFileSize(bytes, "rhubarb_cues", limits));
  absl::StatusOr<std::vector<MouthCue>> cues = formats::ParseRhubarbCues(bytes);
  if (!cues.ok()) {
    return absl::Status(cues.status().code(),
                        absl::StrCat("rhubarb_cues: ", cues.status().message()));
  }
  Voice v;
  v.cues = *std::move(cues);
  for (const MouthCue& cue : v.cues) {
    v.duration_s = std::max(v.duration_s, std::isfinite(cue.end_s) ? cue.end_s : cue.start_s);
  }
  if (v.duration_s > limits.max_audio_seconds) {
    return absl::ResourceExhaustedError(absl::StrCat(
        "rhubarb_cues: ", v.duration_s,
        " s of cues, over the server limit --max_audio_seconds=", limits.max_audio_seconds));
  }
  return v;
}

// A motion3.json of `frames` frames at `fps` with no curves: what a voice-only request's curves
// are added to.
absl::StatusOr<CurveFile> BlankMotion(double fps, int frames, bool csv) {
  const std::string duration = formats::FormatDouble((frames - 1) / fps);
  const std::string text =
      absl::StrCat("{\"Version\": 3, \"Meta\": {\"Duration\": ", duration,
                   ", \"Fps\": ", formats::FormatDouble(fps),
                   ", \"Loop\": false, \"AreBeziersRestricted\": true, \"CurveCount\": 0, "
                   "\"TotalSegmentCount\": 0, \"TotalPointCount\": 0, \"UserDataCount\": 0, "
                   "\"TotalUserDataSize\": 0}, \"Curves\": []}");
  absl::StatusOr<convert::CurveInput> input = convert::ParseCurveText(text, false, fps);
  if (!input.ok()) return absl::InternalError(input.status().message());
  return CurveFile{*std::move(input), csv};
}

bool HasCurve(const CurveSet& set, const std::string& id) {
  return std::any_of(set.curves.begin(), set.curves.end(),
                     [&id](const Curve& c) { return c.id == id; });
}

// A curve at `value` throughout, added to the file (and its motion3 document) or the set.
void AddConstantCurve(const std::string& id, double value, CurveSet* set,
                      formats::Motion3File* motion3) {
  Curve curve;
  curve.id = id;
  if (motion3 != nullptr) {
    const double end_s = (set->frame_count - 1) / set->fps;
    motion3->document["Curves"].push_back(nlohmann::ordered_json{
        {"Target", "Parameter"}, {"Id", id}, {"Segments", {0, value, 0, end_s, value}}});
    motion3->targets.push_back("Parameter");
    curve.start = {0.0, value};
    CurveSegment segment;
    segment.end = {static_cast<double>(set->frame_count - 1), value};
    curve.segments.push_back(segment);
  } else {
    curve.samples.assign(static_cast<size_t>(set->frame_count), value);
  }
  set->curves.push_back(std::move(curve));
}

// The mouth curves (and, with auto-blink, the eye curves) the motion lacks, added: a voice
// draws the mouth whether or not the body motion had one.
void AddMissingCurves(const v1::LipBlinkRequest& request, CurveSet* set,
                      formats::Motion3File* motion3) {
  const double closed = request.mouth().has_min() ? request.mouth().min() : 0.0;
  std::vector<std::string> mouths(request.mouth().ids().begin(), request.mouth().ids().end());
  if (mouths.empty()) mouths.push_back(kDefaultMouthId);
  for (const std::string& id : mouths) {
    if (!HasCurve(*set, id)) AddConstantCurve(id, closed, set, motion3);
  }
  if (!request.eyes().auto_blink().enabled()) return;
  const double open = request.eyes().has_max() ? request.eyes().max() : 1.0;
  std::vector<std::string> eyes(request.eyes().ids().begin(), request.eyes().ids().end());
  if (eyes.empty()) eyes.assign(std::begin(kDefaultEyeIds), std::end(kDefaultEyeIds));
  for (const std::string& id : eyes) {
    if (!HasCurve(*set, id)) AddConstantCurve(id, open, set, motion3);
  }
}

// The analysis fitted to `frames` analysis frames: silence (closed) past the recording, the
// recording past the motion cut off.
void Fit(int frames, VoiceActivity* activity) {
  activity->follow.resize(static_cast<size_t>(frames), MouthShape::kClosed);
  std::vector<FrameInterval> speech;
  for (FrameInterval i : activity->speech) {
    i.end = std::min(i.end, frames);
    if (i.end > i.begin) speech.push_back(i);
  }
  activity->speech = std::move(speech);
}

void FillAnalysis(const Voice& voice, double fps, v1::LipBlinkVoiceAnalysis* out) {
  *out = voice.analysis;
  out->set_duration_s(voice.duration_s);
  out->set_frame_fps(fps);
  out->set_noise_floor_dbfs(voice.activity.noise_floor_dbfs);
  out->set_start_dbfs(voice.activity.start_dbfs);
  out->set_stay_dbfs(voice.activity.stay_dbfs);
  out->set_loud_dbfs(voice.activity.loud_dbfs);
  for (const FrameInterval& i : voice.activity.speech) {
    v1::FrameInterval* s = out->add_speech();
    s->set_begin(i.begin);
    s->set_end(i.end);
  }
}

MouthShape FromProto(v1::MouthShape shape) {
  if (shape == v1::MOUTH_MID) return MouthShape::kMid;
  if (shape == v1::MOUTH_OPEN) return MouthShape::kOpen;
  return MouthShape::kClosed;
}

// The first mouth's holds as Rhubarb cues, JSON and TSV.
void PutCues(double fps, double duration_s, v1::LipBlinkResponse* response) {
  if (response->mouths().empty()) return;
  std::vector<MouthHold> holds;
  for (const v1::MouthHold& h : response->mouths(0).holds()) {
    holds.push_back({h.begin(), h.length(), FromProto(h.shape())});
  }
  const std::vector<MouthCue> cues = CuesOfHolds(holds, fps, duration_s);
  response->set_rhubarb_json(formats::WriteRhubarbJson(cues, duration_s, ""));
  response->set_rhubarb_tsv(formats::WriteRhubarbTsv(cues));
}

absl::Status CheckVoiceRequest(const v1::LipBlinkRequest& request) {
  if (!request.mouth().speech().empty()) {
    return absl::InvalidArgumentError(absl::StrCat(
        "mouth.speech: ", request.mouth().speech_size(),
        " intervals given with a voice (audio / rhubarb_cues), which gives the speech; send "
        "one or the other"));
  }
  const double fps = request.voice_motion_fps();
  if (!std::isfinite(fps) || fps < 0 || fps > kMaxTimingFps) {
    return absl::InvalidArgumentError(
        absl::StrCat("voice_motion_fps: ", fps,
                     " must be finite and in (0, 1000] (0: ", kDefaultVoiceMotionFps, ")"));
  }
  if (!v1::LipBlinkVoiceOutput_IsValid(request.voice_output())) {
    return absl::InvalidArgumentError(
        absl::StrCat("voice_output: ", static_cast<int>(request.voice_output()),
                     " is not a LipBlinkVoiceOutput (1 MOTION3_JSON, 2 CSV)"));
  }
  const double timing_fps = request.has_timing_fps() ? request.timing_fps() : kDefaultTimingFps;
  return ValidateTimingFps(timing_fps, "timing_fps");
}

}  // namespace

VoiceOptions VoiceOptionsFromProto(const v1::LipBlinkVoiceSettings& in) {
  VoiceOptions o;
  if (in.has_noise_floor_dbfs()) o.noise_floor_dbfs = in.noise_floor_dbfs();
  if (in.has_noise_percentile()) o.noise_percentile = in.noise_percentile();
  if (in.has_start_above_floor_db()) o.start_above_floor_db = in.start_above_floor_db();
  if (in.has_stay_above_floor_db()) o.stay_above_floor_db = in.stay_above_floor_db();
  if (in.has_min_speech_dbfs()) o.min_speech_dbfs = in.min_speech_dbfs();
  if (in.has_bridge_gap_frames()) o.bridge_gap_frames = in.bridge_gap_frames();
  if (in.has_faint_gap_frames()) o.faint_gap_frames = in.faint_gap_frames();
  if (in.has_pause_above_floor_db()) o.pause_above_floor_db = in.pause_above_floor_db();
  if (in.has_min_speech_frames()) o.min_speech_frames = in.min_speech_frames();
  if (in.has_open_below_peak_db()) o.open_below_peak_db = in.open_below_peak_db();
  if (in.has_closed_below_peak_db()) o.closed_below_peak_db = in.closed_below_peak_db();
  if (in.has_hysteresis_db()) o.hysteresis_db = in.hysteresis_db();
  if (in.has_any_sound()) o.gate.enabled = !in.any_sound();
  return o;
}

absl::Status HandleLipBlinkVoice(const v1::LipBlinkRequest& request, const RequestLimits& limits,
                                 v1::LipBlinkResponse* response, LipBlinkMotionShape* shape) {
  KOMA_RETURN_IF_ERROR(CheckVoiceRequest(request));
  const VoiceOptions options = VoiceOptionsFromProto(request.voice_settings());
  KOMA_RETURN_IF_ERROR(convert::Prefixed(ValidateVoiceOptions(options), "voice_settings."));

  // The motion: the request's (a file, or decoded curves), or none yet.
  std::optional<CurveFile> file;
  CurveSet set;
  if (CarriesFile(request)) {
    KOMA_ASSIGN_OR_RETURN(file, ParseLipBlinkFile(request, limits));
    set = file->input.curves;
  } else if (request.has_curves()) {
    KOMA_ASSIGN_OR_RETURN(set, CurveSetFromProto(request.curves(), "curves", limits));
  }
  const bool has_motion = file.has_value() || request.has_curves();
  const double motion_fps = has_motion                       ? set.fps
                            : request.voice_motion_fps() > 0 ? request.voice_motion_fps()
                                                             : kDefaultVoiceMotionFps;
  const double timing_fps = request.has_timing_fps() ? request.timing_fps() : kDefaultTimingFps;
  // The frames holds count: the film grid's, or the motion's own when there is none (as
  // ValidateLipBlinkRequest decides).
  const std::optional<FilmGrid> grid = FilmGrid::Make(motion_fps, timing_fps);
  const double fps = grid ? timing_fps : motion_fps;

  Voice voice;
  if (request.voice_case() == v1::LipBlinkRequest::kAudio) {
    KOMA_RETURN_IF_ERROR(CheckLipBlinkFileSize(request.audio(), "audio", limits));
    KOMA_ASSIGN_OR_RETURN(voice, AnalyseAudio(request, fps, options, limits));
  } else {
    KOMA_ASSIGN_OR_RETURN(voice, ReadCues(request.rhubarb_cues(), limits));
  }
  if (!has_motion) {
    // Frames 0 .. N - 1 at motion_fps, the last at or after the recording's end.
    const double last = std::ceil(voice.duration_s * motion_fps - 1e-9);
    if (!(last < static_cast<double>(limits.max_values))) {
      return absl::ResourceExhaustedError(absl::StrCat(
          "voice_motion_fps: ", voice.duration_s, " s at ", motion_fps, " fps is over ",
          limits.max_values, " frames (the server limit --max_values)"));
    }
    const int frames = std::max(2, static_cast<int>(last) + 1);
    KOMA_ASSIGN_OR_RETURN(
        file, BlankMotion(motion_fps, frames, request.voice_output() == v1::VOICE_OUTPUT_CSV));
    set = file->input.curves;
  }
  formats::Motion3File* motion3 = file && file->input.motion3 ? &*file->input.motion3 : nullptr;
  AddMissingCurves(request, &set, motion3);
  if (file) file->input.curves = set;

  // The ordinary job on the motion, then the voice in place of the mouth curves' motion.
  v1::LipBlinkRequest decoded;
  *decoded.mutable_curves() = convert::CurveSetToProto(set);
  *decoded.mutable_mouth() = request.mouth();
  *decoded.mutable_eyes() = request.eyes();
  if (request.has_seed()) decoded.set_seed(request.seed());
  if (request.has_timing_fps()) decoded.set_timing_fps(request.timing_fps());
  KOMA_ASSIGN_OR_RETURN(LipBlinkJob job, ValidateLipBlinkRequest(decoded, limits));
  decoded.Clear();
  DescribeMotion(job, shape);
  const int frames = job.grid ? job.grid_frames : job.set.frame_count;
  if (request.voice_case() == v1::LipBlinkRequest::kRhubarbCues) {
    voice.activity = CuesOnFrames(voice.cues, fps, frames);
  }
  Fit(frames, &voice.activity);
  job.voice = voice.activity;
  job.mouth.speech = voice.activity.speech;
  job.mouth.detect_speech = false;
  if (!job.mouth.min) job.mouth.min = 0.0;
  if (!job.mouth.max) job.mouth.max = std::max(1.0, *job.mouth.min + 1.0);
  if (request.voice_case() == v1::LipBlinkRequest::kRhubarbCues &&
      request.mouth().mode() == v1::MOUTH_MODE_UNSPECIFIED) {
    job.mouth.mode = MouthMode::kFollow;  // cues name their drawings: follow them
  }
  KOMA_RETURN_IF_ERROR(convert::Prefixed(ValidateMouthOptions(job.mouth, frames), "mouth."));
  KOMA_RETURN_IF_ERROR(RunLipBlinkJob(job, response));

  FillAnalysis(voice, fps, response->mutable_voice());
  PutCues(fps, voice.duration_s, response);
  if (file) KOMA_RETURN_IF_ERROR(PutLipBlinkFile(*file, response));
  return absl::OkStatus();
}

}  // namespace koma::server
