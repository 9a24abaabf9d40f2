#include "server/curves_response.h"

#include <google/protobuf/io/coded_stream.h>
#include <google/protobuf/wire_format_lite.h>

#include <cstring>
#include <string>

#include "absl/base/config.h"
#include "convert/curves_convert.h"
#include "koma/v1/motion.pb.h"
#include "koma/v1/retime.pb.h"
#include "server/response_slice.h"
#include "server/wire_bytes.h"

namespace koma::server {
namespace {

using wire::Bits;
using wire::CodedOutputStream;
using wire::kFixed64;
using wire::kLength;
using wire::kVarint;
using wire::LengthField;
using wire::Tag;
using wire::WireFormatLite;
using wire::WriteLength;

// The field tags, all one byte (fields 1-15).
namespace response {  // RetimeCurvesResponse
constexpr uint8_t kKeyFrames = Tag(1, kLength);
constexpr uint8_t kTimings = Tag(2, kLength);
constexpr uint8_t kCurves = Tag(3, kLength);
constexpr uint8_t kTimingFps = Tag(4, wire::kFixed64);
constexpr uint8_t kKeyGridFrames = Tag(5, kLength);
}  // namespace response
namespace timing {  // DrawingTiming
constexpr uint8_t kFramesPerDrawing = Tag(1, kVarint);
constexpr uint8_t kDrawingOfFrame = Tag(2, kLength);
constexpr uint8_t kSourceFrame = Tag(3, kLength);
constexpr uint8_t kDrawingStart = Tag(4, kLength);
constexpr uint8_t kDrawingStartGrid = Tag(5, kLength);
constexpr uint8_t kDrawingSourceFrame = Tag(6, kLength);
constexpr uint8_t kGiven = Tag(7, kVarint);
}  // namespace timing
namespace retimed {  // RetimedCurve
constexpr uint8_t kId = Tag(1, kLength);
constexpr uint8_t kTiming = Tag(2, kVarint);
constexpr uint8_t kValues = Tag(3, kLength);
constexpr uint8_t kStepped = Tag(4, kLength);
constexpr uint8_t kHoldHistogram = Tag(5, kLength);
constexpr uint8_t kKeys = Tag(6, kLength);
}  // namespace retimed
namespace curve {  // Curve (stepped: id, start, then stepped segments)
constexpr uint8_t kId = Tag(1, kLength);
constexpr uint8_t kStart = Tag(2, kLength);
constexpr uint8_t kSegments = Tag(3, kLength);
}  // namespace curve
namespace segment {  // CurveSegment
constexpr uint8_t kType = Tag(1, kVarint);
constexpr uint8_t kEnd = Tag(4, kLength);
}  // namespace segment
namespace point {  // CurvePoint
constexpr uint8_t kFrame = Tag(1, kFixed64);
constexpr uint8_t kValue = Tag(2, kFixed64);
}  // namespace point
namespace key {  // KeyDrawing
constexpr uint8_t kFrame = Tag(1, kFixed64);
constexpr uint8_t kValue = Tag(2, kFixed64);
constexpr uint8_t kRole = Tag(3, kVarint);
constexpr uint8_t kDrawing = Tag(4, kVarint);
constexpr uint8_t kDrawn = Tag(5, kVarint);
constexpr uint8_t kDisplaced = Tag(6, kVarint);
}  // namespace key
namespace hold {  // HoldCount
constexpr uint8_t kLength = Tag(1, kVarint);
constexpr uint8_t kDrawings = Tag(2, kVarint);
}  // namespace hold

static_assert(v1::SEGMENT_STEPPED < 128, "the stepped type is a one-byte varint");

// A singular int32 field: left out when 0; negatives are ten-byte varints.
size_t Int32Field(int value) {
  return value == 0 ? 0 : 1 + WireFormatLite::Int32Size(static_cast<int32_t>(value));
}

size_t PackedInt32Bytes(const std::vector<int>& values) {
  size_t bytes = 0;
  for (const int v : values) bytes += WireFormatLite::Int32Size(static_cast<int32_t>(v));
  return bytes;
}

// A packed repeated field: left out when empty.
size_t PackedField(size_t data_bytes) { return data_bytes == 0 ? 0 : LengthField(data_bytes); }

// A CurvePoint's body: each double left out when its bits are all zero (proto3 keeps -0.0).
size_t PointBody(const CurvePoint& p) {
  return (Bits(p.frame) != 0 ? 9 : 0) + (Bits(p.value) != 0 ? 9 : 0);
}

size_t HoldBody(int length, int drawings) { return Int32Field(length) + Int32Field(drawings); }

// A KeyDrawing's body: at most 9 + 9 + 2 + 11 + 2 + 2 = 35 bytes, so its length is one byte.
size_t KeyBody(const KeyDrawing& k) {
  return (Bits(k.frame) != 0 ? 9 : 0) + (Bits(k.value) != 0 ? 9 : 0) + 2 +
         Int32Field(k.drawing) + (k.drawn ? 2 : 0) + (k.displaced ? 2 : 0);
}

size_t SteppedBody(const std::string& id, const std::vector<CurvePoint>& steps) {
  size_t bytes = id.empty() ? 0 : LengthField(id.size());
  if (steps.empty()) return bytes;
  bytes += 2 + PointBody(steps.front());  // start: tag, one-byte length (<= 18), point
  // Each segment: tag, length, type field (2), end field (2 + point); all lengths one byte.
  for (size_t k = 1; k < steps.size(); ++k) bytes += 6 + PointBody(steps[k]);
  return bytes;
}

uint8_t* WriteInt32Field(uint8_t tag, int value, uint8_t* out) {
  if (value == 0) return out;
  *out++ = tag;
  return CodedOutputStream::WriteVarint32SignExtendedToArray(static_cast<int32_t>(value), out);
}

uint8_t* WritePackedInt32(uint8_t tag, size_t data_bytes, const std::vector<int>& values,
                          uint8_t* out) {
  if (data_bytes == 0) return out;
  out = WriteLength(tag, data_bytes, out);
  for (const int v : values) {
    out = CodedOutputStream::WriteVarint32SignExtendedToArray(static_cast<int32_t>(v), out);
  }
  return out;
}

uint8_t* WritePackedDouble(uint8_t tag, const std::vector<double>& values, uint8_t* out) {
  if (values.empty()) return out;
  out = WriteLength(tag, 8 * values.size(), out);
#ifdef ABSL_IS_LITTLE_ENDIAN
  std::memcpy(out, values.data(), 8 * values.size());
  return out + 8 * values.size();
#else
  for (const double v : values) out = CodedOutputStream::WriteLittleEndian64ToArray(Bits(v), out);
  return out;
#endif
}

uint8_t* WriteString(uint8_t tag, const std::string& text, uint8_t* out) {
  if (text.empty()) return out;
  out = WriteLength(tag, text.size(), out);
  std::memcpy(out, text.data(), text.size());
  return out + text.size();
}

uint8_t* WriteDouble(uint8_t tag, double value, uint8_t* out) {
  const uint64_t bits = Bits(value);
  if (bits == 0) return out;
  *out++ = tag;
  return CodedOutputStream::WriteLittleEndian64ToArray(bits, out);
}

uint8_t* WritePoint(const CurvePoint& p, uint8_t* out) {
  out = WriteDouble(point::kFrame, p.frame, out);
  return WriteDouble(point::kValue, p.value, out);
}

uint8_t* WriteStepped(const std::string& id, const std::vector<CurvePoint>& steps, uint8_t* out) {
  out = WriteString(curve::kId, id, out);
  if (steps.empty()) return out;
  *out++ = curve::kStart;
  *out++ = static_cast<uint8_t>(PointBody(steps.front()));
  out = WritePoint(steps.front(), out);
  for (size_t k = 1; k < steps.size(); ++k) {
    const size_t point_body = PointBody(steps[k]);
    out[0] = curve::kSegments;
    out[1] = static_cast<uint8_t>(4 + point_body);
    out[2] = segment::kType;
    out[3] = static_cast<uint8_t>(v1::SEGMENT_STEPPED);
    out[4] = segment::kEnd;
    out[5] = static_cast<uint8_t>(point_body);
    out = WritePoint(steps[k], out + 6);
  }
  return out;
}

}  // namespace

CurvesResponseEncoder::CurvesResponseEncoder(const CurveSet& set, const KomaUchiResult& result)
    : set_(set), result_(result) {
  key_frames_ = PackedInt32Bytes(result.key_frames);
  size_ = PackedField(key_frames_);
  timings_.reserve(result.timings.size());
  for (const DrawingTiming& t : result.timings) {
    TimingSizes sizes;
    sizes.drawing_of_frame = PackedInt32Bytes(t.drawing_of_frame);
    sizes.drawing_start = PackedInt32Bytes(t.drawing_start);
    sizes.drawing_start_grid = PackedInt32Bytes(t.drawing_start_grid);
    sizes.body = Int32Field(t.frames_per_drawing) + PackedField(sizes.drawing_of_frame) +
                 PackedField(8 * t.source_frame.size()) + PackedField(sizes.drawing_start) +
                 PackedField(sizes.drawing_start_grid) +
                 PackedField(8 * t.drawing_tau.size()) + (t.given ? 2 : 0);
    size_ += LengthField(sizes.body);
    timings_.push_back(sizes);
  }
  head_size_ = size_;
  curves_.reserve(result.curves.size());
  for (size_t c = 0; c < result.curves.size(); ++c) {
    const RetimedCurve& in = result.curves[c];
    const std::string& id = set.curves[c].id;
    CurveSizes sizes;
    sizes.stepped = SteppedBody(id, in.steps);
    sizes.body = (id.empty() ? 0 : LengthField(id.size())) + Int32Field(in.timing) +
                 PackedField(8 * in.values.size()) + LengthField(sizes.stepped);
    for (const auto& [length, drawings] : in.hold_histogram) {
      sizes.body += LengthField(HoldBody(length, drawings));
    }
    for (const KeyDrawing& key : in.keys) sizes.body += 2 + KeyBody(key);
    sizes.field = LengthField(sizes.body);
    size_ += sizes.field;
    curves_.push_back(sizes);
  }
  key_grid_frames_ = PackedInt32Bytes(result.key_grid_frames);
  tail_size_ = (Bits(result.timing_fps) != 0 ? 9 : 0) + PackedField(key_grid_frames_);
  size_ += tail_size_;
  v1::RetimeCurvesResponse late;
  late.mutable_key_frames_merged()->Add(result.key_merged.begin(), result.key_merged.end());
  for (const TimingGroupResult& group : result.groups) {
    v1::CurveTimingGroupResult* out = late.add_timing_groups();
    out->set_name(group.name);
    out->mutable_curves()->Add(group.curves.begin(), group.curves.end());
    out->set_frames_per_drawing(group.frames_per_drawing);
    out->mutable_key_frames()->Add(group.key_frames.begin(), group.key_frames.end());
    out->mutable_key_grid_frames()->Add(group.key_grid_frames.begin(),
                                        group.key_grid_frames.end());
    out->mutable_key_frames_merged()->Add(group.key_merged.begin(), group.key_merged.end());
    out->set_timing(group.timing);
  }
  late.SerializeToString(&late_tail_);
  size_ += late_tail_.size();
}

void CurvesResponseEncoder::WriteTo(uint8_t* out) const {
  out = WriteHead(out);
  for (size_t c = 0; c < curves_.size(); ++c) out = WriteCurve(c, out);
  out = WriteTail(out);
  std::memcpy(out, late_tail_.data(), late_tail_.size());
}

uint8_t* CurvesResponseEncoder::WriteTail(uint8_t* out) const {
  out = WriteDouble(response::kTimingFps, result_.timing_fps, out);
  return WritePackedInt32(response::kKeyGridFrames, key_grid_frames_, result_.key_grid_frames, out);
}

uint8_t* CurvesResponseEncoder::WriteHead(uint8_t* out) const {
  out = WritePackedInt32(response::kKeyFrames, key_frames_, result_.key_frames, out);
  for (size_t i = 0; i < timings_.size(); ++i) {
    const DrawingTiming& t = result_.timings[i];
    const TimingSizes& sizes = timings_[i];
    out = WriteLength(response::kTimings, sizes.body, out);
    out = WriteInt32Field(timing::kFramesPerDrawing, t.frames_per_drawing, out);
    out =
        WritePackedInt32(timing::kDrawingOfFrame, sizes.drawing_of_frame, t.drawing_of_frame, out);
    out = WritePackedDouble(timing::kSourceFrame, t.source_frame, out);
    out = WritePackedInt32(timing::kDrawingStart, sizes.drawing_start, t.drawing_start, out);
    out = WritePackedInt32(timing::kDrawingStartGrid, sizes.drawing_start_grid,
                           t.drawing_start_grid, out);
    out = WritePackedDouble(timing::kDrawingSourceFrame, t.drawing_tau, out);
    if (t.given) {
      *out++ = timing::kGiven;
      *out++ = 1;
    }
  }
  return out;
}

uint8_t* CurvesResponseEncoder::WriteCurve(size_t c, uint8_t* out) const {
  const RetimedCurve& in = result_.curves[c];
  const std::string& id = set_.curves[c].id;
  out = WriteLength(response::kCurves, curves_[c].body, out);
  out = WriteString(retimed::kId, id, out);
  out = WriteInt32Field(retimed::kTiming, in.timing, out);
  out = WritePackedDouble(retimed::kValues, in.values, out);
  out = WriteLength(retimed::kStepped, curves_[c].stepped, out);
  out = WriteStepped(id, in.steps, out);
  for (const auto& [length, drawings] : in.hold_histogram) {
    out = WriteLength(retimed::kHoldHistogram, HoldBody(length, drawings), out);
    out = WriteInt32Field(hold::kLength, length, out);
    out = WriteInt32Field(hold::kDrawings, drawings, out);
  }
  for (const KeyDrawing& key : in.keys) {
    *out++ = retimed::kKeys;
    *out++ = static_cast<uint8_t>(KeyBody(key));
    out = WriteDouble(key::kFrame, key.frame, out);
    out = WriteDouble(key::kValue, key.value, out);
    *out++ = key::kRole;
    *out++ = static_cast<uint8_t>(convert::KeyRoleToProto(key.role));
    out = WriteInt32Field(key::kDrawing, key.drawing, out);
    if (key.drawn) {
      *out++ = key::kDrawn;
      *out++ = 1;
    }
    if (key.displaced) {
      *out++ = key::kDisplaced;
      *out++ = 1;
    }
  }
  return out;
}

std::vector<grpc::Slice> EncodeInSlices(const CurvesResponseEncoder& encoder,
                                        KomaUchiResult& result, size_t slice_bytes,
                                        std::string file_field) {
  std::vector<grpc::Slice> slices;
  size_t next = 0;  // the first curve not yet written
  do {
    const bool head = slices.empty();
    size_t bytes = head ? encoder.head_size() : 0;
    size_t end = next;
    while (end < encoder.curve_count() && (bytes < slice_bytes || bytes == 0)) {
      bytes += encoder.curve_size(end++);
    }
    const bool tail = end == encoder.curve_count();  // the last slice ends with the tail
    if (tail) bytes += encoder.tail_size();
    grpc::Slice slice = UninitialisedSlice(bytes);
    uint8_t* out = const_cast<uint8_t*>(slice.begin());
    if (head) out = encoder.WriteHead(out);
    for (; next < end; ++next) {
      out = encoder.WriteCurve(next, out);
      result.curves[next] = RetimedCurve();  // frees its memory
    }
    if (tail) out = encoder.WriteTail(out);
    slices.push_back(std::move(slice));
  } while (next < encoder.curve_count());
  if (!file_field.empty()) slices.emplace_back(std::move(file_field));
  if (!encoder.late_tail().empty()) slices.emplace_back(encoder.late_tail());
  return slices;
}

}  // namespace koma::server
