// `koma lipblink IN -o OUT ...`: mouth and eye curves in (motion3.json or per-frame CSV),
// LipBlink, three-drawing mouths and anime blinks out; other curves untouched. The steps are
// separate functions so other drivers (`koma batch`) run them per file:
//   ReadCurveInput (client/curve_files.h) -> BuildLipBlinkRequest -> (the RPC)
//   -> WriteLipBlinkOutputs -> LipBlinkSummaryText / LipBlinkSummaryJson
//   (client/lip_blink_summary.h).
#ifndef KOMA_CLIENT_LIP_BLINK_COMMAND_H_
#define KOMA_CLIENT_LIP_BLINK_COMMAND_H_

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "absl/status/status.h"
#include "absl/status/statusor.h"
#include "client/curve_files.h"
#include "client/flag_values.h"
#include "koma/v1/retime.pb.h"

namespace koma::client {

struct LipBlinkArgs : CurveFileArgs {
  // mouth (MouthSettings)
  std::vector<std::string> mouth_ids;     // --mouth / --mouth-ids; empty: ParamMouthOpenY
  std::string mode;  // --mode / --mouth-mode random|follow; empty: random (follow for --rhubarb)
  std::optional<int> frames_per_shape;    // --on / --mouth-frames-per-shape
  std::optional<double> mouth_mid_ratio;  // --mouth-mid-ratio r, 0 < r < 1
  std::optional<double> mouth_min;        // --mouth-min: the closed level
  std::optional<double> mouth_max;        // --mouth-max: the open level
  std::vector<FlagInterval> speech;       // --speech / --mouth-speech BEGIN-END,...
  // eyes (EyeSettings)
  std::vector<std::string> eye_ids;      // --eyes / --eyes-ids; empty: ParamEyeLOpen, ...R
  std::optional<double> eyes_mid_ratio;  // --eyes-mid-ratio r, 0 < r < 1
  std::optional<double> eyes_threshold;  // --eyes-threshold delta, 0 < delta < 0.5
  std::optional<double> eyes_min;        // --eyes-min
  std::optional<double> eyes_max;        // --eyes-max
  bool unlinked_eyes = false;            // --unlinked-eyes (= --eyes-linked false)
  std::optional<bool> eyes_linked;       // --eyes-linked true|false
  // eyes.auto_blink (AutoBlink)
  std::optional<double> auto_blink_mean_s;    // --auto-blink / --auto-blink-mean-interval-s
  std::optional<bool> auto_blink_enabled;     // --auto-blink-enabled; unset: on when any
                                              // other auto-blink flag is given
  std::optional<double> auto_blink_spread_s;  // --auto-blink-spread-s
  std::optional<int> auto_blink_hold;         // --auto-blink-hold 1..3
  std::vector<FlagInterval> auto_blink_keep;  // --auto-blink-keep BEGIN-END,...
  std::optional<uint64_t> seed;               // --seed; unset: the server's default
  // A voice instead of a moving mouth curve (LipBlinkRequest.audio / .rhubarb_cues):
  std::string audio;    // --audio FILE: a recording (WAV, FLAC, Ogg, MP3, ...)
  std::string rhubarb;  // --rhubarb FILE: Rhubarb Lip Sync's mouth cues (JSON or TSV)
  std::string motion;   // --motion FILE: the motion the mouth goes into (= IN)
  std::string cues;     // --cues OUT.json|OUT.tsv: the mouth as Rhubarb cues
  // voice_settings (LipBlinkVoiceSettings): --voice-settings-<field>
  std::optional<double> noise_floor_dbfs, noise_percentile, start_above_floor_db,
      stay_above_floor_db, min_speech_dbfs, open_below_peak_db, closed_below_peak_db,
      hysteresis_db, pause_above_floor_db;
  std::optional<int> bridge_gap_frames, faint_gap_frames, min_speech_frames;
  bool any_sound = false;  // --voice-settings-any-sound: speech by loudness alone
  std::optional<double> voice_motion_fps;  // --voice-motion-fps; unset: --fps
  std::string voice_output;                // --voice-output motion3|csv; empty: from -o
  // --report-audio-max-bytes: a recording up to this size is embedded in --report's page,
  // a larger one linked; unset: report::kDefaultReportAudioMaxBytes.
  std::optional<int> report_audio_max_bytes;
  // A Spine skeleton IN (client/spine_lip_blink.h): the animation written into and the slots.
  std::string spine_animation;                 // --animation NAME (created when missing)
  std::string mouth_slot;                      // --mouth-slot SLOT
  std::vector<std::string> mouth_attachments;  // --mouth-attachments CLOSED,MID,OPEN
  std::vector<std::string> eye_slots;          // --eye-slot SLOT,...
  std::vector<std::string> eye_attachments;    // --eye-attachments OPEN,HALF,CLOSED
};

// True when any flag only a Spine skeleton uses is given.
inline bool HasSpineFlags(const LipBlinkArgs& args) {
  return !args.spine_animation.empty() || !args.mouth_slot.empty() ||
         !args.mouth_attachments.empty() || !args.eye_slots.empty() ||
         !args.eye_attachments.empty();
}

// True when --audio or --rhubarb is given.
inline bool HasVoice(const LipBlinkArgs& args) {
  return !args.audio.empty() || !args.rhubarb.empty();
}

// A voice request: `voice` (the --audio or --rhubarb file's bytes) with the motion `input`
// (sent as its file, so the server adds a missing mouth curve and keeps every other curve) or,
// without one, a new motion at --fps in the format of -o.
v1::LipBlinkRequest BuildLipBlinkVoiceRequest(const LipBlinkArgs& args, std::string voice,
                                              const CurveInput* input, bool csv_output);

// Writes -o (and --cues, --xdts) from a voice answer: the server's file, as CSV when -o asks
// for CSV and the server wrote motion3.json. `source_fps`: the written motion's frames per
// second (the input motion's, or voice_motion_fps for a new one), the XDTS sheet's source rate.
absl::Status WriteLipBlinkVoiceOutputs(const LipBlinkArgs& args, bool csv_output,
                                       double source_fps, const v1::LipBlinkResponse& response);

v1::LipBlinkRequest BuildLipBlinkRequest(const LipBlinkArgs& args, const CurveSet& curves);

// BuildLipBlinkRequest(args, input.curves); with --send-file the request carries input.text
// in motion3_json or csv_text (with csv_fps = --fps) instead of curves.
v1::LipBlinkRequest BuildLipBlinkFileRequest(const LipBlinkArgs& args, const CurveInput& input);

// Usage errors: -o missing, two outputs on standard output.
absl::Status CheckLipBlinkFlags(const LipBlinkArgs& args);

// Writes -o from `response` (only the converted curves replaced).
absl::Status WriteLipBlinkOutputs(const LipBlinkArgs& args, const CurveInput& input,
                                  const v1::LipBlinkResponse& response);

// Exit code: 0 ok, 1 failure, 2 usage error (messages on stderr).
int RunLipBlink(const LipBlinkArgs& args);

}  // namespace koma::client

#endif  // KOMA_CLIENT_LIP_BLINK_COMMAND_H_
