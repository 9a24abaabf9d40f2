// Run half of server/lip_blink_request.h: validated request -> ConvertMouth / ConvertEyes ->
// response.
#include <vector>

#include "convert/curves_convert.h"
#include "core/lip_blink_given.h"
#include "core/lip_blink_grid.h"
#include "core/status_macros.h"
#include "server/curve_convert.h"
#include "server/file_requests.h"
#include "server/lip_blink_request.h"
#include "server/lip_blink_spine.h"
#include "server/lip_blink_voice.h"

namespace koma::server {
namespace {

v1::MouthShape ToProto(MouthShape shape) {
  switch (shape) {
    case MouthShape::kClosed:
      return v1::MOUTH_CLOSED;
    case MouthShape::kMid:
      return v1::MOUTH_MID;
    case MouthShape::kOpen:
      return v1::MOUTH_OPEN;
  }
  return v1::MOUTH_SHAPE_UNSPECIFIED;
}

void AddConvertedCurve(const std::string& id, const std::vector<double>& values,
                       const std::vector<CurvePoint>& steps, v1::LipBlinkResponse* response) {
  v1::ConvertedCurve* out = response->add_curves();
  out->set_id(id);
  out->mutable_values()->Add(values.begin(), values.end());
  out->mutable_stepped()->set_id(id);
  convert::SteppedKeyframesToProto(steps, out->mutable_stepped());
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
  std::vector<double> values =
      SampleEveryFrame(job.set.curves[index], job.set.frame_count, job.set.beziers_restricted);
  KOMA_RETURN_IF_ERROR(CheckEvaluatedFinite(values, index));
  return values;
}

// What the conversion runs on: the curve at every grid frame (with a grid), else `source`.
absl::StatusOr<std::vector<double>> ConversionInput(const LipBlinkJob& job, int index,
                                                    const std::vector<double>& source) {
  if (!job.grid) return source;
  std::vector<double> values =
      SampleOnGrid(job.set.curves[index], *job.grid, job.grid_frames, job.set.beziers_restricted);
  KOMA_RETURN_IF_ERROR(CheckEvaluatedFinite(values, index));
  return values;
}

// A voice job's mouth: the closed level at every source frame (the voice replaces the curve),
// and each analysis frame's drawing level as the conversion's input.
void VoiceInputs(const LipBlinkJob& job, std::vector<double>* source, std::vector<double>* input) {
  const double closed = job.mouth.min.value_or(0.0);
  const double open = job.mouth.max.value_or(1.0);
  const double mid = closed + job.mouth.mid_ratio * (open - closed);
  source->assign(static_cast<size_t>(job.set.frame_count), closed);
  input->clear();
  input->reserve(job.voice->follow.size());
  for (MouthShape shape : job.voice->follow) {
    input->push_back(shape == MouthShape::kClosed ? closed
                                                  : (shape == MouthShape::kMid ? mid : open));
  }
}

}  // namespace

absl::StatusOr<LipBlinkDrawing> DrawLipBlink(const LipBlinkJob& job) {
  LipBlinkDrawing drawing;
  // Mask lengths: grid frames with a grid, else source frames.
  const int frames = job.grid ? job.grid_frames : job.set.frame_count;
  for (size_t m = 0; m < job.mouth_curves.size(); ++m) {
    LipBlinkDrawnCurve curve;
    curve.index = job.mouth_curves[m];
    std::vector<double> input;
    if (job.voice) {
      VoiceInputs(job, &curve.source, &input);
    } else {
      KOMA_ASSIGN_OR_RETURN(curve.source, Sample(job, curve.index));
      KOMA_ASSIGN_OR_RETURN(input, ConversionInput(job, curve.index, curve.source));
    }
    // Mouth curve m draws from its own stream, seed + m, so adding a curve leaves the
    // others' shapes as they were.
    drawing.mouths.push_back(job.given_mouths
                                 ? PaintGivenMouth(input, job.mouth, (*job.given_mouths)[m])
                                 : ConvertMouth(input, job.mouth, job.seed + m));
    curve.drawn = drawing.mouths.back().values;
    curve.repainted = SpeechMask(drawing.mouths.back().speech, frames);
    drawing.curves.push_back(std::move(curve));
  }
  if (job.eye_curves.empty()) return drawing;
  std::vector<std::vector<double>> inputs;  // what the conversion runs on
  for (int index : job.eye_curves) {
    LipBlinkDrawnCurve curve;
    curve.index = index;
    KOMA_ASSIGN_OR_RETURN(curve.source, Sample(job, index));
    KOMA_ASSIGN_OR_RETURN(std::vector<double> input, ConversionInput(job, index, curve.source));
    inputs.push_back(std::move(input));
    drawing.curves.push_back(std::move(curve));
  }
  const std::vector<absl::Span<const double>> spans(inputs.begin(), inputs.end());
  drawing.eyes = job.given_eyes ? PaintGivenEyes(spans, job.eyes, *job.given_eyes)
                                : ConvertEyes(spans, job.eyes, job.seed);
  for (size_t i = 0; i < job.eye_curves.size(); ++i) {
    LipBlinkDrawnCurve& curve = drawing.curves[job.mouth_curves.size() + i];
    curve.drawn = drawing.eyes.values[i];
    curve.repainted = BlinkMask(drawing.eyes.blinks[i], frames);
  }
  return drawing;
}

void DescribeMotion(const LipBlinkJob& job, LipBlinkMotionShape* shape) {
  if (shape == nullptr) return;
  shape->frames = job.set.frame_count;
  shape->curves = static_cast<int>(job.set.curves.size());
}

absl::Status HandleLipBlink(const v1::LipBlinkRequest& request, const RequestLimits& limits,
                            v1::LipBlinkResponse* response, LipBlinkMotionShape* shape) {
  if (request.has_given_timing() && (request.input_case() == v1::LipBlinkRequest::kSpineJson ||
                                     request.voice_case() != v1::LipBlinkRequest::VOICE_NOT_SET)) {
    return absl::InvalidArgumentError(
        "given_timing: not with a voice (audio, rhubarb_cues) or spine_json; give the mouth "
        "and eye curves (curves, motion3_json or csv_text)");
  }
  if (request.input_case() == v1::LipBlinkRequest::kSpineJson) {
    return HandleLipBlinkSpine(request, limits, response, shape);
  }
  if (request.has_spine()) {
    return absl::InvalidArgumentError(
        "spine: only with spine_json (the Spine skeleton whose slots it names)");
  }
  if (request.voice_case() != v1::LipBlinkRequest::VOICE_NOT_SET) {
    return HandleLipBlinkVoice(request, limits, response, shape);
  }
  if (CarriesFile(request)) return HandleLipBlinkFile(request, limits, response, shape);
  KOMA_ASSIGN_OR_RETURN(const LipBlinkJob job, ValidateLipBlinkRequest(request, limits));
  DescribeMotion(job, shape);
  return RunLipBlinkJob(job, response);
}

absl::Status RunLipBlinkJob(const LipBlinkJob& job, v1::LipBlinkResponse* response) {
  KOMA_ASSIGN_OR_RETURN(const LipBlinkDrawing drawing, DrawLipBlink(job));
  for (size_t m = 0; m < drawing.mouths.size(); ++m) {
    v1::MouthTrack* track = response->add_mouths();
    FillMouth(job.set.curves[job.mouth_curves[m]].id, drawing.mouths[m], track);
    track->set_given(job.given_mouths.has_value());
  }
  for (size_t i = 0; i < job.eye_curves.size(); ++i) {
    v1::EyeTrack* track = response->add_eyes();
    FillEye(job.set.curves[job.eye_curves[i]].id, drawing.eyes, i, track);
    track->set_given(job.given_eyes.has_value());
  }
  // Every other frame keeps its input value (docs/semantics.md, "LipBlink").
  for (const LipBlinkDrawnCurve& curve : drawing.curves) {
    const std::string& id = job.set.curves[curve.index].id;
    if (!job.grid) {
      AddConvertedCurve(id, curve.drawn, SteppedFromValues(curve.drawn), response);
      continue;
    }
    const SourceRateCurve out = ExpandConverted(curve.drawn, curve.repainted, curve.source, *job.grid);
    AddConvertedCurve(id, out.values, out.steps, response);
  }
  response->set_seed(job.seed);
  if (job.grid) response->set_timing_fps(job.grid->timing_fps());
  return absl::OkStatus();
}

}  // namespace koma::server
