// Responses with the shape and size koma's would have, made without retiming: what
// koma_echo_server answers. koma's output size depends on what the retiming decides (how
// many drawings, holds and blinks), so these follow the request's own structure instead:
// one drawing every n frames, one mouth hold every 3 frames of non-zero mouth, one blink per
// run of shut eye. koma_load reports both servers' response bytes, so the match is checked,
// not assumed (docs/benchmarks.md lists them side by side).
#ifndef KOMA_BENCH_ECHO_SHAPES_H_
#define KOMA_BENCH_ECHO_SHAPES_H_

#include "koma/v1/retime.pb.h"

namespace koma::echo {

// source_frames 0..N-1 all ORIGINAL, N zero SSDs and the request's motion copied back
// (koma's retimed clip has the frame count and form of the input).
void SkeletalLookalike(const v1::RetimeSkeletalRequest& request,
                       v1::RetimeSkeletalResponse* response);

// The request's frames_per_drawing n (default 3): per frame its drawing and source time, per
// curve its values, one stepped point per drawing and a one-row hold histogram; the first
// curve's keyframe times as the key frames.
void CurvesLookalike(const v1::RetimeCurvesRequest& request, v1::RetimeCurvesResponse* response);

// For each curve whose id contains "Mouth" or "Eye": its values and a stepped curve. Mouths:
// one speech interval per run of non-zero samples, a hold (and a stepped point) every 3 frames
// of it; eyes: a blink (and two stepped points) per run of samples below 0.5.
void LipBlinkLookalike(const v1::LipBlinkRequest& request, v1::LipBlinkResponse* response);

}  // namespace koma::echo

#endif  // KOMA_BENCH_ECHO_SHAPES_H_
