#include "client/report/lip_blink_voice_report.h"

#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

#include "absl/strings/ascii.h"
#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "client/files.h"
#include "client/report/report_data.h"
#include "client/xdts_sheets.h"
#include "convert/curves_convert.h"

namespace koma::client::report {
namespace {

nlohmann::json Levels(double closed, double mid, double open) {
  return {{"closed", Round6(closed)}, {"mid", Round6(mid)}, {"open", Round6(open)}};
}

nlohmann::json Intervals(const google::protobuf::RepeatedPtrField<v1::FrameInterval>& list) {
  nlohmann::json out = nlohmann::json::array();
  for (const v1::FrameInterval& i : list) out.push_back({i.begin(), i.end()});
  return out;
}

// "9 dB" when the request gave it, "9 dB (default)" when the server chose it.
std::string Setting(bool given, double value, std::string_view unit) {
  return absl::StrFormat("%.6g %s%s", value, unit, given ? "" : " (default)");
}

std::string PercentEncode(std::string_view path) {
  std::string out;
  for (unsigned char c : path) {
    if (absl::ascii_isalnum(c) || c == '-' || c == '.' || c == '_' || c == '~' || c == '/') {
      out.push_back(static_cast<char>(c));
    } else {
      absl::StrAppendFormat(&out, "%%%02X", c);
    }
  }
  return out;
}

}  // namespace

std::string AudioMimeType(std::string_view audio) {
  // absl's string_view is not std's in Debian's abseil: compare with std's own.
  const auto starts_with = [audio](std::string_view magic) {
    return audio.substr(0, magic.size()) == magic;
  };
  if (starts_with("RIFF") || starts_with("RF64")) return "audio/wav";
  if (starts_with("fLaC")) return "audio/flac";
  if (starts_with("OggS")) return "audio/ogg";
  if (starts_with("FORM")) return "audio/aiff";
  // An ID3 tag, or an MPEG audio frame's sync word (11 bits set).
  if (starts_with("ID3") ||
      (audio.size() >= 2 && static_cast<unsigned char>(audio[0]) == 0xFF &&
       (static_cast<unsigned char>(audio[1]) & 0xE0) == 0xE0)) {
    return "audio/mpeg";
  }
  return "application/octet-stream";
}

std::string AudioLink(const std::string& audio_path, const std::string& report_path) {
  namespace fs = std::filesystem;
  std::error_code error;
  const fs::path audio = fs::absolute(audio_path, error);
  if (report_path == "-" || error) {
    return absl::StrCat("file://", PercentEncode(audio.lexically_normal().generic_string()));
  }
  const fs::path folder = fs::absolute(report_path, error).parent_path();
  fs::path relative = audio.lexically_normal().lexically_relative(folder.lexically_normal());
  if (error || relative.empty()) {
    return absl::StrCat("file://", PercentEncode(audio.lexically_normal().generic_string()));
  }
  return PercentEncode(relative.generic_string());
}

std::string LipBlinkVoiceReportWriter::Title() const {
  return absl::StrCat("koma lipblink: ", InputName(sources_.voice_name));
}

nlohmann::json LipBlinkVoiceReportWriter::Data() const {
  const v1::LipBlinkRequest& q = request_;
  const v1::LipBlinkResponse& r = response_;
  const v1::LipBlinkVoiceAnalysis& v = r.voice();
  const v1::LipBlinkVoiceSettings& s = q.voice_settings();
  const bool audio = q.voice_case() == v1::LipBlinkRequest::kAudio;
  const bool grid = r.timing_fps() > 0;
  const double fps = sources_.motion_fps;
  const bool follow = q.mouth().mode() == v1::MOUTH_FOLLOW ||
                      (!audio && q.mouth().mode() == v1::MOUTH_MODE_UNSPECIFIED);

  nlohmann::json options = nlohmann::json::array();
  options.push_back({"voice", audio ? "recording" : "Rhubarb cues"});
  options.push_back({"motion", sources_.motion_name.empty()
                                   ? absl::StrFormat("new, %.6g fps", fps)
                                   : InputName(sources_.motion_name)});
  options.push_back({"mouth mode", follow ? "follow" : "random"});
  options.push_back({"frames_per_shape", q.mouth().has_frames_per_shape()
                                             ? absl::StrCat(q.mouth().frames_per_shape())
                                             : std::string("3 (default)")});
  if (audio) {
    options.push_back(
        {"noise floor", s.has_noise_floor_dbfs()
                            ? "given"
                            : absl::StrFormat("percentile %.6g%s",
                                              s.has_noise_percentile() ? s.noise_percentile() : 10,
                                              s.has_noise_percentile() ? "" : " (default)")});
    options.push_back({"speech starts above floor",
                       Setting(s.has_start_above_floor_db(),
                               s.has_start_above_floor_db() ? s.start_above_floor_db() : 9, "dB")});
    options.push_back({"speech stays above floor",
                       s.has_stay_above_floor_db()
                           ? Setting(true, s.stay_above_floor_db(), "dB")
                           : std::string("a fifth of the range, 2 dB to the start (default)")});
    options.push_back({"thresholds at least",
                       Setting(s.has_min_speech_dbfs(),
                               s.has_min_speech_dbfs() ? s.min_speech_dbfs() : -55, "dBFS")});
    options.push_back({"gaps bridged up to",
                       Setting(s.has_bridge_gap_frames(),
                               s.has_bridge_gap_frames() ? s.bridge_gap_frames() : 3, "frames")});
    options.push_back({"faint gaps bridged up to",
                       Setting(s.has_faint_gap_frames(),
                               s.has_faint_gap_frames() ? s.faint_gap_frames() : 4, "frames")});
    options.push_back({"a pause is within",
                       Setting(s.has_pause_above_floor_db(),
                               s.has_pause_above_floor_db() ? s.pause_above_floor_db() : 1,
                               "dB of the floor")});
    options.push_back({"speech is", s.has_any_sound() && s.any_sound()
                                        ? std::string("any loud sound")
                                        : std::string("a voice, not music or noise (default)")});
    options.push_back({"shortest speech",
                       Setting(s.has_min_speech_frames(),
                               s.has_min_speech_frames() ? s.min_speech_frames() : 2, "frames")});
  }
  options.push_back(
      {"auto-blink",
       q.eyes().auto_blink().enabled()
           ? absl::StrFormat("every %.6g s", q.eyes().auto_blink().has_mean_interval_s()
                                                 ? q.eyes().auto_blink().mean_interval_s()
                                                 : 4.0)
           : std::string("off")});
  options.push_back({"seed", absl::StrCat(r.seed())});
  options.push_back({"timing_fps", grid ? absl::StrFormat("%.6g (film grid)", r.timing_fps())
                                        : std::string("0 (counted in source frames)")});

  int holds = 0, blinks = 0;
  nlohmann::json mouths = nlohmann::json::array();
  for (const v1::MouthTrack& m : r.mouths()) {
    nlohmann::json shapes = nlohmann::json::array();
    for (const v1::MouthHold& h : m.holds()) {
      shapes.push_back({h.begin(), h.length(), convert::MouthShapeName(h.shape())});
    }
    holds += m.holds_size();
    mouths.push_back({{"id", m.id()},
                      {"speech", Intervals(m.speech())},
                      {"holds", shapes},
                      {"levels", Levels(m.closed_level(), m.mid_level(), m.open_level())}});
  }
  nlohmann::json eyes = nlohmann::json::array();
  for (const v1::EyeTrack& e : r.eyes()) {
    nlohmann::json list = nlohmann::json::array();
    for (const v1::Blink& b : e.blinks()) {
      list.push_back({{"closing_begin", b.closing_begin()},
                      {"closed_begin", b.closed_begin()},
                      {"closed_end", b.closed_end()},
                      {"open_span", b.open_span()},
                      {"hold", b.hold()},
                      {"automatic", b.automatic()}});
    }
    blinks += e.blinks_size();
    eyes.push_back({{"id", e.id()},
                    {"blinks", list},
                    {"levels", Levels(e.closed_level(), e.mid_level(), e.open_level())}});
  }
  // The curves after: plotted thinned, and every frame for the face player.
  int frames = 0;
  nlohmann::json curves = nlohmann::json::array();
  for (const v1::ConvertedCurve& c : r.curves()) {
    const absl::Span<const double> values(c.values().data(), c.values_size());
    std::vector<double> every;
    every.reserve(values.size());
    for (double value : values) every.push_back(Round6(value));
    frames = std::max(frames, c.values_size());
    curves.push_back({{"id", c.id()},
                      {"after", ThinnedPlot(values, 1.0 / fps)},
                      {"frames_after", every}});
  }

  // The analysis: loudness of frame g (covering [g, g + 1) / frame_fps s) plotted at its start.
  const double frame_fps = v.frame_fps() > 0 ? v.frame_fps() : fps;
  nlohmann::json voice = {
      {"kind", audio ? "audio" : "rhubarb"},
      {"duration_s", Round6(v.duration_s())},
      {"sample_rate", v.sample_rate()},
      {"channels", v.channels()},
      {"frame_fps", frame_fps},
      {"frames", v.loudness_dbfs_size()},
      {"loudness", ThinnedPlot(absl::MakeConstSpan(v.loudness_dbfs().data(),
                                                   v.loudness_dbfs_size()),
                               1.0 / frame_fps)},
      {"noise_floor_dbfs", Round6(v.noise_floor_dbfs())},
      {"start_dbfs", Round6(v.start_dbfs())},
      {"stay_dbfs", Round6(v.stay_dbfs())},
      {"loud_dbfs", Round6(v.loud_dbfs())},
      {"speech", Intervals(v.speech())}};

  nlohmann::json player_audio = nullptr;
  if (audio) {
    const int64_t size = static_cast<int64_t>(sources_.audio.size());
    const bool embed = size <= sources_.audio_max_bytes;
    const std::string mime = AudioMimeType(sources_.audio);
    player_audio = {
        {"bytes", size},
        {"mime", mime},
        {"embedded", embed},
        {"src", embed ? absl::StrCat("data:", mime, ";base64,",
                                     Base64(std::string(sources_.audio)))
                      : sources_.audio_link}};
  }

  nlohmann::json counts = nlohmann::json::array();
  counts.push_back({"duration", absl::StrFormat("%.3f s", v.duration_s())});
  if (audio) {
    counts.push_back({"sample rate", absl::StrFormat("%d Hz", v.sample_rate())});
    counts.push_back({"channels", v.channels()});
  }
  if (audio) {
    counts.push_back({"analysis frames", absl::StrFormat("%d at %.6g fps",
                                                         v.loudness_dbfs_size(), frame_fps)});
    counts.push_back({"noise floor", absl::StrFormat("%.1f dBFS", v.noise_floor_dbfs())});
    counts.push_back({"speech thresholds", absl::StrFormat("start %.1f, stay %.1f dBFS",
                                                           v.start_dbfs(), v.stay_dbfs())});
  }
  counts.push_back({"speech intervals", v.speech_size()});
  counts.push_back({"mouth drawings (holds)", holds});
  counts.push_back({"blinks (all eye curves)", blinks});
  counts.push_back({"motion frames", absl::StrFormat("%d at %.6g fps", frames, fps)});

  nlohmann::json data;
  data["header"] = Header("LipBlink", sources_.voice_name, options, counts);
  data["fps"] = fps;
  data["frames"] = frames;
  data["timing_fps"] = r.timing_fps();
  // Frame numbers in mouths, eyes and voice are grid frames with a grid: s = frame / unit_fps.
  data["unit_fps"] = grid ? r.timing_fps() : fps;
  data["voice"] = voice;
  data["audio"] = player_audio;
  data["mouths"] = mouths;
  data["eyes"] = eyes;
  data["curves"] = curves;
  // The sheet --xdts writes for the same call, named after the motion, else the voice.
  data["xdts"] = ExposureSheetData(LipBlinkXdtsSheet(
      r, fps,
      XdtsClipName(sources_.motion_name.empty() ? sources_.voice_name : sources_.motion_name,
                   "")));
  return data;
}

absl::Status WriteLipBlinkVoiceReport(const std::string& path,
                                      const v1::LipBlinkRequest& request,
                                      const v1::LipBlinkResponse& response,
                                      const VoiceReportSources& sources) {
  if (!(sources.motion_fps > 0) || response.curves().empty()) {
    return absl::InternalError(
        absl::StrCat("--report ", path, ": the answer has no curves to draw"));
  }
  return WriteReport(path, LipBlinkVoiceReportWriter(request, response, sources));
}

}  // namespace koma::client::report
