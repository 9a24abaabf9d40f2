#include "core/live_voice.h"

#include <algorithm>
#include <climits>
#include <cmath>

#include "absl/strings/str_cat.h"
#include "core/lip_blink_internal.h"
#include "core/voice_gate.h"

namespace koma {
namespace {

// Histogram bins: 0.1 dB wide from kSilenceDbfs; bin 0 holds digital silence (and anything
// within 0.1 dB of it), the last bin everything from 0.1 dBFS up (a float signal over full
// scale).
constexpr double kBinsPerDb = 10.0;
constexpr int kLastBin = 1501;
// The recording's range and FOLLOW's loud level: the 90th percentiles, as DetectVoice's.
constexpr double kLoudPercentile = 90.0;
// Bit 15 of a history entry: the frame was decided speech (bins fit in 11 bits).
constexpr uint16_t kSpeechBit = 0x8000;

// The two drawings a hold may show after `previous` (never the same twice), more closed first:
// core/lip_blink_mouth.cc's rule.
std::array<MouthShape, 2> Allowed(MouthShape previous) {
  if (previous == MouthShape::kClosed) return {MouthShape::kMid, MouthShape::kOpen};
  if (previous == MouthShape::kMid) return {MouthShape::kClosed, MouthShape::kOpen};
  return {MouthShape::kClosed, MouthShape::kMid};
}

// FOLLOW's Schmitt trigger, one frame (core/voice_activity.cc's Follow): a drawing is left only
// past its boundary by half the hysteresis.
MouthShape Trigger(MouthShape shape, double l, double open_at, double mid_at, double h) {
  switch (shape) {
    case MouthShape::kClosed:
      if (l > open_at + h) return MouthShape::kOpen;
      if (l > mid_at + h) return MouthShape::kMid;
      return shape;
    case MouthShape::kMid:
      if (l > open_at + h) return MouthShape::kOpen;
      if (l < mid_at - h) return MouthShape::kClosed;
      return shape;
    case MouthShape::kOpen:
      break;
  }
  if (l < mid_at - h) return MouthShape::kClosed;
  if (l < open_at - h) return MouthShape::kMid;
  return shape;
}

}  // namespace

absl::Status ValidateLiveVoiceOptions(const LiveVoiceOptions& o) {
  if (o.sample_rate < 1 || o.sample_rate > 1000000) {
    return absl::InvalidArgumentError(
        absl::StrCat("sample_rate: ", o.sample_rate, " must be in [1, 1000000] per second"));
  }
  if (!(o.frame_fps > 0.0 && o.frame_fps <= kMaxTimingFps)) {
    return absl::InvalidArgumentError(
        absl::StrCat("frame_fps: ", o.frame_fps, " must be in (0, 1000] frames per second"));
  }
  if (o.lookahead_frames < 0 || o.lookahead_frames > kMaxLookaheadFrames) {
    return absl::InvalidArgumentError(absl::StrCat(
        "lookahead_frames: ", o.lookahead_frames, " must be in [0, ", kMaxLookaheadFrames, "]"));
  }
  if (absl::Status s = ValidateVoiceOptions(o.voice); !s.ok()) return s;
  MouthOptions mouth = o.mouth;
  mouth.speech.clear();
  if (absl::Status s = ValidateMouthOptions(mouth, 0); !s.ok()) return s;
  EyeOptions eyes = o.eyes;
  eyes.auto_blink.keep.clear();
  return ValidateEyeOptions(eyes, 0);
}

int LiveVoice::Histogram::Bin(double dbfs) {
  const double x = std::floor((dbfs - kSilenceDbfs) * kBinsPerDb);
  if (!(x > 0.0)) return 0;  // NaN too
  return x >= kLastBin ? kLastBin : static_cast<int>(x);
}

double LiveVoice::Histogram::Percentile(double p) const {
  if (total_ == 0) return kSilenceDbfs;
  const auto rank = static_cast<int64_t>(p / 100.0 * static_cast<double>(total_ - 1));
  int64_t seen = 0;
  int group = 0;
  while (seen + groups_[group] <= rank) seen += groups_[group++];
  int bin = group * kGroup;
  while (seen + counts_[bin] <= rank) seen += counts_[bin++];
  // The bin's middle: within 0.05 dB of every value in it.
  return bin == 0 ? kSilenceDbfs : kSilenceDbfs + (bin + 0.5) / kBinsPerDb;
}

LiveVoice::LiveVoice(const LiveVoiceOptions& options)
    : options_(options),
      grid_(options.sample_rate, options.frame_fps),
      features_(options.sample_rate, options.frame_fps),
      mouth_rng_(options.seed),
      blink_rng_(options.seed ^ lip_blink_internal::kAutoBlinkStream) {
  // The levels as the server's voice LipBlink sets them.
  closed_ = options.mouth.min.value_or(0.0);
  open_ = options.mouth.max.value_or(std::max(1.0, closed_ + 1.0));
  mid_ = closed_ + options.mouth.mid_ratio * (open_ - closed_);
  eye_closed_ = options.eyes.min.value_or(0.0);
  eye_open_ = options.eyes.max.value_or(1.0);
  eye_half_ = eye_closed_ + options.eyes.mid_ratio * (eye_open_ - eye_closed_);
  options_.eyes.fps = options.frame_fps;
  next_boundary_ = grid_.FirstSample(1);
  dbfs_.assign(kLiveWindowFrames, kSilenceDbfs);
  voice_.assign(kLiveWindowFrames, VoiceFrame{});
  history_size_ = std::max(kMaxLookaheadFrames + 2,
                           static_cast<int>(std::floor(kLiveHistorySeconds * options.frame_fps)));
  history_.assign(static_cast<size_t>(history_size_), 0);
  window_dbfs_.reserve(kLiveWindowFrames);
  window_voice_.reserve(kLiveWindowFrames);
  if (options.eyes.auto_blink.enabled) {
    next_blink_ = lip_blink_internal::DrawBlinkInterval(blink_rng_, options.eyes.auto_blink,
                                                        options.frame_fps, INT_MAX - 1);
  }
}

void LiveVoice::Add(absl::Span<const float> mono) {
  if (finished_) return;  // the stream has ended: its last frames are decided
  size_t i = 0;
  for (;;) {
    while (samples_ == next_boundary_) CompleteFrame();
    if (i == mono.size()) break;
    const int64_t take =
        std::min<int64_t>(next_boundary_ - samples_, static_cast<int64_t>(mono.size() - i));
    // Sample by sample into one running sum: the same order whatever the blocks.
    for (int64_t k = 0; k < take; ++k) {
      const double x = mono[i + static_cast<size_t>(k)];
      sum_ += x * x;
    }
    count_ += take;
    features_.Add(mono.subspan(i, static_cast<size_t>(take)));
    samples_ += take;
    i += static_cast<size_t>(take);
  }
}

void LiveVoice::Finish() {
  if (finished_) return;
  finished_ = true;
  features_.Finish();
  if (count_ > 0) CompleteFrame();  // the partial last frame, over the samples it has
  const int64_t last = complete_ - 1;
  while (decided_ <= last) {
    Decide(decided_, last, std::max<int64_t>(0, samples_ - grid_.FirstSample(decided_ + 1)));
  }
}

bool LiveVoice::Pop(LiveFrame* frame) {
  if (ready_.empty()) return false;
  *frame = ready_.front();
  ready_.pop_front();
  return true;
}

void LiveVoice::CompleteFrame() {
  const int64_t c = complete_;
  const double dbfs =
      count_ > 0 ? MeanSquareToDbfs(sum_ / static_cast<double>(count_)) : kSilenceDbfs;
  sum_ = 0.0;
  count_ = 0;
  ++complete_;
  next_boundary_ = grid_.FirstSample(complete_ + 1);
  dbfs_[static_cast<size_t>(c % kLiveWindowFrames)] = dbfs;
  // The features decided since the last frame (frame c's is, once its last sample is in).
  features_.TakeFrames(taken_);
  int64_t f = features_.decided() - static_cast<int64_t>(taken_.size());
  for (const VoiceFrame& v : taken_) voice_[static_cast<size_t>(f++ % kLiveWindowFrames)] = v;
  // The history: frame c in, frame c - history_size_ out.
  uint16_t& slot = history_[static_cast<size_t>(c % history_size_)];
  if (c >= history_size_) {
    all_.Remove(slot & ~kSpeechBit);
    if (slot & kSpeechBit) speaking_.Remove(slot & ~kSpeechBit);
  }
  slot = static_cast<uint16_t>(Histogram::Bin(dbfs));
  all_.Add(slot);
  if (!finished_ && c >= options_.lookahead_frames) {
    const int64_t g = c - options_.lookahead_frames;
    Decide(g, c, samples_ - grid_.FirstSample(g + 1));
  }
}

bool LiveVoice::SpeechAt(int64_t g, int64_t last) {
  const VoiceOptions& vo = options_.voice;
  floor_dbfs_ = vo.noise_floor_dbfs.value_or(all_.Percentile(vo.noise_percentile));
  VoiceOptions o = vo;
  o.noise_floor_dbfs = floor_dbfs_;
  if (!vo.stay_above_floor_db) {
    // DetectVoice's unset stay, on the running range.
    const double range = all_.Percentile(kLoudPercentile) - floor_dbfs_;
    o.stay_above_floor_db = std::min(
        vo.start_above_floor_db, std::max(kMinStayAboveFloorDb, kStayFractionOfRange * range));
  }
  const int64_t first = std::max<int64_t>(0, last - kLiveWindowFrames + 1);
  window_dbfs_.clear();
  window_voice_.clear();
  for (int64_t f = first; f <= last; ++f) {
    window_dbfs_.push_back(dbfs_[static_cast<size_t>(f % kLiveWindowFrames)]);
    window_voice_.push_back(voice_[static_cast<size_t>(f % kLiveWindowFrames)]);
  }
  VoiceGateOptions gate = vo.gate;
  if (!features_.usable()) gate.enabled = false;
  // A held sound at the window's end (its two newest frames voiced and steady: music's notes)
  // ends a voice's stretch for the offline analysis too, which never widens a stretch into it.
  const auto held = [&](size_t i) {
    return window_voice_[i].voicing >= gate.min_voicing &&
           !(window_voice_[i].change >= gate.min_change);
  };
  const size_t n = window_voice_.size();
  const bool held_at_end = n >= 2 && held(n - 1) && held(n - 2);
  if (!finished_ && !held_at_end) {
    // The future, for the gate only: a stretch being built at the window's end counts as kept
    // when kLiveProvisionalFrames more voice-like frames would keep it (a voice's onset, 2 grid
    // frames sooner), and a stretch that may still go on is not ended early. Not past a held
    // sound: assumed frames would join the voice's stretch across it and keep the mouth open
    // over music for up to 3 frames after the voice.
    VoiceFrame pad;
    pad.voicing = 1.0;
    pad.change = 1.0;
    window_voice_.insert(window_voice_.end(), kLiveProvisionalFrames, pad);
  }
  const std::vector<FrameInterval> voice_like =
      VoiceLikeStretches(window_voice_, features_.step(), options_.frame_fps, gate);
  const VoiceActivity v = DetectVoice(window_dbfs_, o, &voice_like);
  const int at = static_cast<int>(g - first);
  for (const FrameInterval& i : v.speech) {
    if (i.begin <= at && at < i.end) return true;
  }
  return false;
}

void LiveVoice::Decide(int64_t g, int64_t last, int64_t late_samples) {
  LiveFrame out;
  out.frame = g;
  out.time_s = static_cast<double>(g) / options_.frame_fps;
  out.dbfs = dbfs_[static_cast<size_t>(g % kLiveWindowFrames)];
  out.speech = SpeechAt(g, last);
  out.noise_floor_dbfs = floor_dbfs_;
  out.late_samples = late_samples;
  if (out.speech) {
    uint16_t& slot = history_[static_cast<size_t>(g % history_size_)];
    slot |= kSpeechBit;
    speaking_.Add(slot & ~kSpeechBit);
  }
  Mouth(out.speech, g, last, out);
  out.new_drawing = out.mouth != shown_;
  shown_ = out.mouth;
  Eyes(g, out);
  ready_.push_back(out);
  ++decided_;
}

void LiveVoice::Mouth(bool speech, int64_t g, int64_t last, LiveFrame& out) {
  const MouthOptions& m = options_.mouth;
  if (!speech) {  // a pause closes the mouth; the next speech starts from closed
    in_speech_ = false;
    hold_left_ = 0;
    shape_ = follow_ = MouthShape::kClosed;
    out.mouth = MouthShape::kClosed;
    out.mouth_level = closed_;
    return;
  }
  loud_dbfs_ = speaking_.Percentile(kLoudPercentile);
  const double open_at = loud_dbfs_ - options_.voice.open_below_peak_db;
  const double mid_at = loud_dbfs_ - options_.voice.closed_below_peak_db;
  const double h = options_.voice.hysteresis_db / 2.0;
  if (!in_speech_) {
    in_speech_ = true;
    hold_left_ = 0;
  }
  if (hold_left_ == 0) {
    const std::array<MouthShape, 2> allowed = Allowed(shape_);
    if (m.mode == MouthMode::kRandom) {
      shape_ = allowed[mouth_rng_.Next() >> 63];  // the top bit, as ConvertMouth draws
    } else {
      // The allowed drawing nearest the mean level the trigger asks for over the hold's
      // frames known now (this one and the lookahead's), ties to the more closed.
      const int64_t known = std::min<int64_t>(
          {m.frames_per_shape, 1 + options_.lookahead_frames, last + 1 - g});
      MouthShape trigger = follow_;
      double sum = 0.0;
      for (int64_t f = g; f < g + known; ++f) {
        trigger = Trigger(trigger, dbfs_[static_cast<size_t>(f % kLiveWindowFrames)], open_at,
                          mid_at, h);
        sum += trigger == MouthShape::kClosed ? closed_
               : trigger == MouthShape::kMid  ? mid_
                                              : open_;
      }
      const double mean = sum / static_cast<double>(known);
      const auto level = [&](MouthShape s) {
        return s == MouthShape::kClosed ? closed_ : s == MouthShape::kMid ? mid_ : open_;
      };
      shape_ = std::fabs(level(allowed[1]) - mean) < std::fabs(level(allowed[0]) - mean)
                   ? allowed[1]
                   : allowed[0];
    }
    hold_left_ = m.frames_per_shape;
    out.hold_start = true;
  }
  --hold_left_;
  follow_ = Trigger(follow_, out.dbfs, open_at, mid_at, h);
  out.mouth = shape_;
  out.mouth_level = shape_ == MouthShape::kClosed ? closed_
                    : shape_ == MouthShape::kMid  ? mid_
                                                  : open_;
}

void LiveVoice::Eyes(int64_t g, LiveFrame& out) {
  const AutoBlinkOptions& a = options_.eyes.auto_blink;
  if (a.enabled && g == next_blink_) {
    // core/lip_blink_auto.cc's walk with nothing to avoid: closed `hold` frames, half-open
    // `hold` frames, then a fresh interval from the blink's end.
    blink_ = g;
    next_blink_ = g + 2 * a.hold +
                  lip_blink_internal::DrawBlinkInterval(blink_rng_, a, options_.frame_fps,
                                                        INT_MAX - 1);
    out.blink_start = true;
  }
  const int64_t into = blink_ >= 0 ? g - blink_ : INT64_MAX;
  if (into < a.hold) {
    out.eye = MouthShape::kClosed;
    out.eye_level = eye_closed_;
  } else if (into < 2 * a.hold) {
    out.eye = MouthShape::kMid;
    out.eye_level = eye_half_;
  } else {
    out.eye = MouthShape::kOpen;
    out.eye_level = eye_open_;
  }
}

}  // namespace koma
