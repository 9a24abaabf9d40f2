// The LipBlink report of a voice (`koma lipblink --audio FILE` or `--rhubarb FILE`): the
// recording's loudness on the film grid with the noise floor, the speech thresholds and the
// speech found, the mouth drawings under it, the resulting curves, and a face player in sync
// with the recording, which the page carries (or links to when it is large).
#ifndef KOMA_CLIENT_REPORT_LIP_BLINK_VOICE_REPORT_H_
#define KOMA_CLIENT_REPORT_LIP_BLINK_VOICE_REPORT_H_

#include <cstdint>
#include <string>
#include <string_view>

#include "absl/status/status.h"
#include "client/report/report_writer.h"
#include "koma/v1/retime.pb.h"

namespace koma::client::report {

// Recordings up to this many bytes are embedded in the page (base64: the page grows by 4/3 of
// it); larger ones are linked (`koma lipblink --report-audio-max-bytes`).
inline constexpr int64_t kDefaultReportAudioMaxBytes = 16 << 20;

// What the page is made of besides the request and the response.
struct VoiceReportSources {
  std::string voice_name;   // the --audio or --rhubarb path, as the user gave it
  std::string motion_name;  // the body motion's path; empty for a new motion
  double motion_fps = 0;    // frames per second of the response's curves
  // The recording (empty for Rhubarb cues) and how the page plays it: embedded when
  // audio.size() <= audio_max_bytes, else `audio_link` (a URL relative to the page, or a file://
  // URL) is what the page's <audio> loads.
  std::string_view audio;
  int64_t audio_max_bytes = kDefaultReportAudioMaxBytes;
  std::string audio_link;
};

// The MIME type of a recording from its first bytes (RIFF/RF64 WAV, FLAC, Ogg, MP3, AIFF);
// "application/octet-stream" when none matches.
std::string AudioMimeType(std::string_view audio);

// The URL a page at `report_path` links the recording at `audio_path` by: relative to the
// page's folder, or file:// and absolute for a page written to standard output. Characters
// outside RFC 3986's unreserved set and "/" are percent-encoded.
std::string AudioLink(const std::string& audio_path, const std::string& report_path);

class LipBlinkVoiceReportWriter : public ReportWriter {
 public:
  // Keeps references: request, response and sources.audio must outlive the writer.
  LipBlinkVoiceReportWriter(const v1::LipBlinkRequest& request,
                            const v1::LipBlinkResponse& response, VoiceReportSources sources)
      : request_(request), response_(response), sources_(std::move(sources)) {}

  std::string_view Kind() const override { return "lipblink_voice"; }
  std::string Title() const override;
  nlohmann::json Data() const override;

 private:
  const v1::LipBlinkRequest& request_;
  const v1::LipBlinkResponse& response_;
  VoiceReportSources sources_;
};

// `koma lipblink --audio FILE --report PATH`: writes the report of this call to `path`.
absl::Status WriteLipBlinkVoiceReport(const std::string& path,
                                      const v1::LipBlinkRequest& request,
                                      const v1::LipBlinkResponse& response,
                                      const VoiceReportSources& sources);

}  // namespace koma::client::report

#endif  // KOMA_CLIENT_REPORT_LIP_BLINK_VOICE_REPORT_H_
