// RetimeCurvesResponse wire bytes written straight from the core's result, without building
// the response as protobuf messages first. A 60-curve x 300-frame answer has ~6,700 stepped
// segments; as messages each was three arena objects, sized and then serialised one by one,
// which perf put at about a third of the server's CPU on that call. The bytes are exactly what
// FillCurvesResponse (server/curves_request.h) + SerializeToString give: fields in number
// order, proto3 defaults (0, empty, +0.0) left out, repeated scalars packed, the stepped curve
// always present (tests/server/curves_response_test.cc compares the two on random answers).
#ifndef KOMA_SERVER_CURVES_RESPONSE_H_
#define KOMA_SERVER_CURVES_RESPONSE_H_

#include <grpcpp/support/slice.h>

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "core/curves.h"
#include "core/koma_uchi.h"

namespace koma::server {

// Sizes the response once on construction; `set` and `result` must outlive the encoder and
// stay unchanged, except that a curve whose part is written may be freed (EncodeInSlices).
// set.curves[c].id names result.curves[c].
class CurvesResponseEncoder {
 public:
  CurvesResponseEncoder(const CurveSet& set, const KomaUchiResult& result);

  // The serialised response's length in bytes.
  size_t size() const { return size_; }

  // Writes exactly size() bytes at `out`: the whole response in one buffer. The service sends
  // it in slices instead (EncodeInSlices); the tests check the two give the same bytes.
  void WriteTo(uint8_t* out) const;

  // The same bytes in parts, for a response written into several buffers: the head (key
  // frames and timings), then one field per curve, in order. Each Write returns the end of
  // what it wrote. Curve c's part reads only result.curves[c], so the caller may free that
  // once it is written.
  size_t head_size() const { return head_size_; }
  size_t curve_count() const { return curves_.size(); }
  size_t curve_size(size_t c) const { return curves_[c].field; }
  uint8_t* WriteHead(uint8_t* out) const;
  uint8_t* WriteCurve(size_t c, uint8_t* out) const;
  // The fields after the curves (the film grid's: timing_fps, key_grid_frames).
  size_t tail_size() const { return tail_size_; }
  uint8_t* WriteTail(uint8_t* out) const;
  // The fields numbered after a file request's file (6 or 7), which goes between the tail and
  // these: key_frames_merged and timing_groups (20, 21). A few hundred bytes, serialised by
  // protobuf itself.
  const std::string& late_tail() const { return late_tail_; }

 private:
  struct TimingSizes {
    size_t drawing_of_frame;  // packed varints, bytes
    size_t drawing_start;
    size_t drawing_start_grid;
    size_t body;  // the DrawingTiming message
  };
  struct CurveSizes {
    size_t stepped;  // the Curve message
    size_t body;     // the RetimedCurve message
    size_t field;    // the response's field holding it: tag, length, body
  };

  const CurveSet& set_;
  const KomaUchiResult& result_;
  size_t key_frames_ = 0;  // packed varints, bytes
  size_t head_size_ = 0;
  size_t key_grid_frames_ = 0;  // packed varints, bytes
  size_t tail_size_ = 0;
  std::string late_tail_;
  std::vector<TimingSizes> timings_;
  std::vector<CurveSizes> curves_;
  size_t size_ = 0;
};

// The bytes `encoder` gives, in slices of whole parts (the head, then curves, the tail in the
// last slice), each slice
// closed once it holds `slice_bytes` or more; one slice when the whole response is smaller.
// `result` must be the encoder's own result: each of its curves (values, steps, histogram) is
// freed as soon as its bytes are written, so a large result and its response are never both
// held in full (for 500 curves x 10k frames each is ~80 MiB). Its key frames and timings are
// left as they were.
// `file_field` (a file request's serialised file field, CurvesFileField) goes between the tail
// and the late tail, in a slice of its own.
std::vector<grpc::Slice> EncodeInSlices(const CurvesResponseEncoder& encoder,
                                        KomaUchiResult& result, size_t slice_bytes,
                                        std::string file_field = std::string());

}  // namespace koma::server

#endif  // KOMA_SERVER_CURVES_RESPONSE_H_
