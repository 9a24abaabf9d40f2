#include "client/spine_lip_blink.h"

#include <string>
#include <utility>
#include <vector>

#include "absl/strings/str_cat.h"
#include "client/channel.h"
#include "client/files.h"
#include "client/report/lip_blink_report.h"
#include "client/report/lip_blink_voice_report.h"
#include "client/retime_call.h"
#include "client/xdts_sheets.h"
#include "formats/spine_attachments.h"
#include "formats/xdts.h"
#include "koma/v1/retime.grpc.pb.h"

namespace koma::client {
namespace {

const convert::SpineLipBlinkNames& CliNames() {
  static const convert::SpineLipBlinkNames* const names = new convert::SpineLipBlinkNames{
      "--animation",
      "--mouth-slot",
      "--mouth-attachments",
      "--eye-slot",
      "--eye-attachments",
      "a voice (--audio FILE, --rhubarb FILE) or --speech intervals",
      "a voice (--audio, --rhubarb) or --speech"};
  return *names;
}

}  // namespace

v1::SpineLipBlinkSettings SpineSettingsOf(const LipBlinkArgs& args) {
  v1::SpineLipBlinkSettings settings;
  settings.set_animation(args.spine_animation);
  settings.set_mouth_slot(args.mouth_slot);
  for (const std::string& name : args.mouth_attachments) settings.add_mouth_attachments(name);
  for (const std::string& slot : args.eye_slots) settings.add_eye_slots(slot);
  for (const std::string& name : args.eye_attachments) settings.add_eye_attachments(name);
  return settings;
}

absl::StatusOr<convert::SpineLipBlinkSlots> CheckSpineSlots(const LipBlinkArgs& args,
                                                           const formats::SpineFile& file) {
  return convert::SpineLipBlinkSlotsOf(SpineSettingsOf(args), file, HasVoice(args),
                                       !args.speech.empty(), CliNames());
}

v1::LipBlinkRequest BuildSpineLipBlinkRequest(const LipBlinkArgs& args, std::string skeleton,
                                              std::string voice) {
  v1::LipBlinkRequest request = BuildLipBlinkRequest(args, CurveSet{});
  // The server decides what spine_json decides: the ids are the slots, the levels 0 and 1.
  request.mutable_mouth()->clear_ids();
  request.mutable_mouth()->clear_min();
  request.mutable_mouth()->clear_max();
  request.mutable_eyes()->clear_ids();
  request.mutable_eyes()->clear_min();
  request.mutable_eyes()->clear_max();
  request.set_spine_json(std::move(skeleton));  // replaces the empty curves
  *request.mutable_spine() = SpineSettingsOf(args);
  if (HasVoice(args)) {
    if (!args.audio.empty()) {
      request.set_audio(std::move(voice));
    } else {
      request.set_rhubarb_cues(std::move(voice));
      // Unset: the server follows the cues' drawings.
      if (args.mode.empty()) request.mutable_mouth()->clear_mode();
    }
  }
  return request;
}

int RunLipBlinkSpine(const LipBlinkArgs& args, const CommandOutput& out, const CurveInput& input) {
  // --send-file is what a skeleton always does: the server writes it.
  if (!args.motion.empty() || args.voice_motion_fps || !args.voice_output.empty()) {
    return out.UsageFailure(absl::InvalidArgumentError(
        "--motion, --voice-motion-fps, --voice-output: not for a Spine skeleton (IN is the "
        "motion; its fps is the skeleton's)"));
  }
  if (absl::Status s = CheckWritable({args.output, args.cues, args.report, args.xdts}); !s.ok()) {
    return out.Failure(s);
  }
  const formats::SpineFile& file = *input.spine;
  absl::StatusOr<convert::SpineLipBlinkSlots> slots = CheckSpineSlots(args, file);
  if (!slots.ok()) return out.UsageFailure(slots.status());
  std::string voice;
  if (HasVoice(args)) {
    absl::StatusOr<std::string> read = ReadFile(args.audio.empty() ? args.rhubarb : args.audio);
    if (!read.ok()) return out.Failure(read.status());
    voice = *std::move(read);
  }
  const v1::LipBlinkRequest request = BuildSpineLipBlinkRequest(args, input.text, std::move(voice));
  v1::LipBlinkResponse response;
  if (int code = CallRetime(args, out, &v1::Retime::Stub::LipBlink, request, &response);
      code >= 0) {
    return code;
  }
  if (!response.has_spine_json()) {
    return out.Failure(absl::InternalError("the server answered no spine_json"));
  }
  if (absl::Status s = WriteFile(args.output, response.spine_json()); !s.ok()) {
    return out.Failure(s);
  }
  if (!args.xdts.empty()) {  // the exposure sheet of the same answer, as for a motion3.json
    absl::StatusOr<formats::XdtsSheet> sheet =
        LipBlinkXdtsSheet(response, file.fps, XdtsClipName(args.input, args.xdts));
    if (!sheet.ok()) return out.Failure(sheet.status());
    if (absl::Status s = WriteFile(args.xdts, formats::WriteXdts(*sheet)); !s.ok()) {
      return out.Failure(s);
    }
  }
  if (!args.cues.empty() && HasVoice(args)) {
    const bool tsv = args.cues.size() >= 4 && args.cues.substr(args.cues.size() - 4) == ".tsv";
    if (absl::Status s = WriteFile(args.cues, tsv ? response.rhubarb_tsv() : response.rhubarb_json());
        !s.ok()) {
      return out.Failure(s);
    }
  }
  if (!args.report.empty()) {
    // The decoded request the server answered (the slots as curves at skeleton.fps).
    absl::StatusOr<v1::LipBlinkRequest> decoded =
        convert::DecodedSpineLipBlinkRequest(request, file, *slots);
    if (!decoded.ok()) return out.Failure(decoded.status());
    absl::Status s;
    if (HasVoice(args)) {
      report::VoiceReportSources sources;
      sources.voice_name = args.audio.empty() ? args.rhubarb : args.audio;
      sources.motion_name = args.input;
      sources.motion_fps = file.fps;
      sources.audio = request.audio();
      sources.audio_max_bytes =
          args.report_audio_max_bytes.value_or(report::kDefaultReportAudioMaxBytes);
      if (!args.audio.empty()) sources.audio_link = report::AudioLink(args.audio, args.report);
      s = report::WriteLipBlinkVoiceReport(args.report, *decoded, response, sources);
    } else {
      s = report::WriteLipBlinkReport(args.report, *decoded, response, args.input);
    }
    if (!s.ok()) return out.Failure(s);
  }
  // The keys written, read back from the answer's skeleton.
  absl::StatusOr<formats::SpineFile> written = formats::ParseSpine(response.spine_json());
  if (!written.ok()) return out.Failure(absl::InternalError(written.status().message()));
  std::string text_summary =
      absl::StrCat(OutputName(args.output), ": animation \"", slots->animation, "\"",
                   response.spine_new_animation() ? " (new)" : "");
  nlohmann::json summary = {{"output", args.output}, {"animation", slots->animation},
                            {"new_animation", response.spine_new_animation()},
                            {"timing_fps", response.timing_fps()}};
  nlohmann::json slot_list = nlohmann::json::array();
  std::vector<std::string> keyed;
  if (!slots->mouth.empty()) keyed.push_back(slots->mouth);
  keyed.insert(keyed.end(), slots->eyes.begin(), slots->eyes.end());
  for (const std::string& slot : keyed) {
    absl::StatusOr<std::vector<formats::SpineAttachmentKey>> keys =
        formats::SpineAttachmentKeys(*written, slots->animation, slot);
    if (!keys.ok()) return out.Failure(absl::InternalError(keys.status().message()));
    if (keys->empty()) continue;  // a slot the answer did not key (a new animation's eyes)
    absl::StrAppend(&text_summary, ", slot ", slot, " ", keys->size(), " keys");
    nlohmann::json list = nlohmann::json::array();
    for (const formats::SpineAttachmentKey& k : *keys) {
      list.push_back({{"time", k.time}, {"name", k.name}});
    }
    slot_list.push_back({{"slot", slot}, {"keys", std::move(list)}});
  }
  summary["slots"] = std::move(slot_list);
  out.Success(text_summary + "\n" + XdtsLine(args.xdts) + ReportLine(args.report), summary,
              IsStdio(args.output) || IsStdio(args.cues) || IsStdio(args.xdts) ||
                  IsStdio(args.report));
  return kExitOk;
}

}  // namespace koma::client
