#include "client/report/lip_blink_report.h"

#include <string>
#include <vector>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "absl/strings/str_join.h"
#include "convert/curves_convert.h"
#include "client/report/input_curves.h"
#include "client/report/report_data.h"
#include "client/xdts_sheets.h"

namespace koma::client::report {
namespace {

nlohmann::json Levels(double closed, double mid, double open) {
  return {{"closed", Round6(closed)}, {"mid", Round6(mid)}, {"open", Round6(open)}};
}

}  // namespace

std::string LipBlinkReportWriter::Title() const {
  return absl::StrCat("koma lipblink: ", input_name_);
}

nlohmann::json LipBlinkReportWriter::Data() const {
  const v1::LipBlinkRequest& q = request_;
  const v1::LipBlinkResponse& r = response_;
  const double fps = q.curves().fps();
  const bool grid = r.timing_fps() > 0;

  nlohmann::json options = nlohmann::json::array();
  options.push_back({"mouth mode", q.mouth().mode() == v1::MOUTH_FOLLOW ? "follow" : "random"});
  options.push_back({"frames_per_shape", q.mouth().has_frames_per_shape()
                                             ? absl::StrCat(q.mouth().frames_per_shape())
                                             : std::string("3 (default)")});
  options.push_back({"speech", q.mouth().speech_size() > 0 ? "given" : "detected"});
  options.push_back({"linked eyes", !q.eyes().has_linked() || q.eyes().linked()});
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
    nlohmann::json speech = nlohmann::json::array();
    for (const v1::FrameInterval& i : m.speech()) speech.push_back({i.begin(), i.end()});
    nlohmann::json shapes = nlohmann::json::array();
    for (const v1::MouthHold& h : m.holds()) {
      shapes.push_back({h.begin(), h.length(), convert::MouthShapeName(h.shape())});
    }
    holds += m.holds_size();
    mouths.push_back({{"id", m.id()},
                      {"speech", speech},
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
  nlohmann::json curves = nlohmann::json::array();
  for (const v1::ConvertedCurve& c : r.curves()) {
    std::vector<double> before;
    for (int k = 0; k < q.curves().curves_size(); ++k) {
      if (q.curves().curves(k).id() == c.id()) before = SampleInputCurve(q.curves(), k);
    }
    // The face player needs every frame; the plots, what a screen shows.
    std::vector<double> every_before, every_after;
    for (double v : before) every_before.push_back(Round6(v));
    for (double v : c.values()) every_after.push_back(Round6(v));
    curves.push_back(
        {{"id", c.id()},
         {"before", ThinnedPlot(before, 1.0 / fps)},
         {"after", ThinnedPlot(absl::MakeConstSpan(c.values().data(), c.values_size()), 1.0 / fps)},
         {"frames_before", every_before},
         {"frames_after", every_after}});
  }

  nlohmann::json counts = nlohmann::json::array();
  counts.push_back({"frames", q.curves().frame_count()});
  counts.push_back({"fps", Round6(fps)});
  counts.push_back({"mouth curves", r.mouths_size()});
  counts.push_back({"mouth drawings (holds)", holds});
  counts.push_back({"eye curves", r.eyes_size()});
  counts.push_back({"blinks (all eye curves)", blinks});

  nlohmann::json data;
  data["header"] = Header("LipBlink", input_name_, options, counts);
  data["fps"] = fps;
  data["frames"] = q.curves().frame_count();
  data["timing_fps"] = r.timing_fps();
  // Frame numbers in mouths and eyes are grid frames with a grid: seconds = frame / unit_fps.
  data["unit_fps"] = grid ? r.timing_fps() : fps;
  data["mouths"] = mouths;
  data["eyes"] = eyes;
  data["curves"] = curves;
  data["xdts"] = ExposureSheetData(LipBlinkXdtsSheet(r, fps, XdtsClipName(input_name_, "")));
  return data;
}

absl::Status WriteLipBlinkReport(const std::string& path, const v1::LipBlinkRequest& request,
                                 const v1::LipBlinkResponse& response,
                                 const std::string& input_name) {
  if (!request.has_curves()) {
    // The file forms (motion3_json, csv_text) are not parsed here: the CLI sends the curves.
    return absl::InvalidArgumentError(
        absl::StrCat("--report ", path, ": the request has no parsed curves to draw"));
  }
  return WriteReport(path, LipBlinkReportWriter(request, response, input_name));
}

}  // namespace koma::client::report
