// Run half of server/lip_blink_request.h: validated request -> ConvertMouth / ConvertEyes ->
// response.
#include <vector>


#include "core/status_macros.h"
#include "server/curve_convert.h"
#include "server/lip_blink_request.h"

namespace koma::server {
namespace {

v1::MouthShape ToProto(MouthShape shape) {
  switch (shape) {
    case MouthShape::kClosed: return v1::MOUTH_CLOSED;
    case MouthShape::kMid: return v1::MOUTH_MID;
    case MouthShape::kOpen: return v1::MOUTH_OPEN;
  }
  return v1::MOUTH_SHAPE_UNSPECIFIED;
}

void AddConvertedCurve(const std::string& id, const std::vector<double>& values,
                       v1::LipBlinkResponse* response) {
  v1::ConvertedCurve* out = response->add_curves();
  out->set_id(id);
  out->mutable_values()->Add(values.begin(), values.end());
  out->mutable_stepped()->set_id(id);
  SteppedKeyframesToProto(SteppedFromValues(values), out->mutable_stepped());
}

void FillMouth(const std::string& id, const MouthResult& mouth, v1::MouthTrack* out) {
  out->set_id(id);
  for (const FrameInterval& interval : mouth.speech) {
    v1::FrameInterval* speech = out->add_speech();
    speech->set_begin(interval.begin);
    speech->set_end(interval.end);
  }
  for (const MouthHold& hold : mouth.holds) {
    v1::MouthHold* h = out->add_holds();
    h->set_begin(hold.begin);
    h->set_length(hold.length);
    h->set_shape(ToProto(hold.shape));
  }
  out->set_closed_level(mouth.closed);
  out->set_mid_level(mouth.mid);
  out->set_open_level(mouth.open);
}

void FillEye(const std::string& id, const EyeResult& eyes, size_t i, v1::EyeTrack* out) {
  out->set_id(id);
  for (const Blink& blink : eyes.blinks[i]) {
    v1::Blink* b = out->add_blinks();
    b->set_closing_begin(blink.closing_begin);
    b->set_closed_begin(blink.closed_begin);
    b->set_closed_end(blink.closed_end);
    b->set_open_span(blink.open_span);
    b->set_hold(blink.hold);
    b->set_automatic(blink.automatic);
  }
  out->set_closed_level(eyes.closed[i]);
  out->set_mid_level(eyes.mid[i]);
  out->set_open_level(eyes.open[i]);
}

// The curve at every frame, or OUT_OF_RANGE where it overflows (CheckEvaluatedFinite).
absl::StatusOr<std::vector<double>> Sample(const LipBlinkJob& job, int index) {
  std::vector<double> values = SampleEveryFrame(job.set.curves[index], job.set.frame_count,
                                                job.set.beziers_restricted);
  KOMA_RETURN_IF_ERROR(CheckEvaluatedFinite(values, index));
  return values;
}

absl::Status RunMouths(const LipBlinkJob& job, v1::LipBlinkResponse* response) {
  for (size_t m = 0; m < job.mouth_curves.size(); ++m) {
    const Curve& curve = job.set.curves[job.mouth_curves[m]];
    KOMA_ASSIGN_OR_RETURN(const std::vector<double> input, Sample(job, job.mouth_curves[m]));
    // Mouth curve m draws from its own stream, seed + m, so adding a curve leaves the
    // others' shapes as they were.
    const MouthResult mouth = ConvertMouth(input, job.mouth, job.seed + m);
    FillMouth(curve.id, mouth, response->add_mouths());
    AddConvertedCurve(curve.id, mouth.values, response);
  }
  return absl::OkStatus();
}

absl::Status RunEyes(const LipBlinkJob& job, v1::LipBlinkResponse* response) {
  if (job.eye_curves.empty()) return absl::OkStatus();
  std::vector<std::vector<double>> inputs;
  for (int index : job.eye_curves) {
    KOMA_ASSIGN_OR_RETURN(std::vector<double> input, Sample(job, index));
    inputs.push_back(std::move(input));
  }
  const std::vector<absl::Span<const double>> spans(inputs.begin(), inputs.end());
  const EyeResult eyes = ConvertEyes(spans, job.eyes, job.seed);
  for (size_t i = 0; i < job.eye_curves.size(); ++i) {
    const std::string& id = job.set.curves[job.eye_curves[i]].id;
    FillEye(id, eyes, i, response->add_eyes());
    AddConvertedCurve(id, eyes.values[i], response);
  }
  return absl::OkStatus();
}

}  // namespace

absl::Status HandleLipBlink(const v1::LipBlinkRequest& request, const RequestLimits& limits,
                            v1::LipBlinkResponse* response) {
  KOMA_ASSIGN_OR_RETURN(const LipBlinkJob job, ValidateLipBlinkRequest(request, limits));
  KOMA_RETURN_IF_ERROR(RunMouths(job, response));
  KOMA_RETURN_IF_ERROR(RunEyes(job, response));
  response->set_seed(job.seed);
  return absl::OkStatus();
}

}  // namespace koma::server
