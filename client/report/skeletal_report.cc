#include "client/report/skeletal_report.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "client/report/report_data.h"
#include "client/xdts_sheets.h"
#include "core/forward_kinematics.h"
#include "core/skeleton.h"

namespace koma::client::report {
namespace {

// The figure's precision: positions are rounded to 1/kStepsPerBody of the body's size (the
// largest distance of a joint from the root along one axis, doubled). A figure drawn 500 px
// tall moves in steps under a pixel.
constexpr double kStepsPerBody = 1024.0;

absl::StatusOr<Skeleton> SkeletonFromProto(const v1::Skeleton& proto) {
  Skeleton skeleton;
  for (const v1::Joint& j : proto.joints()) {
    Joint joint;
    joint.name = j.name();
    joint.parent = j.parent();
    joint.offset = {j.offset().x(), j.offset().y(), j.offset().z()};
    for (const std::string& name : j.channels()) {
      absl::StatusOr<ChannelKind> kind = ParseChannelName(name);
      if (!kind.ok()) return kind.status();
      joint.channels.push_back(*kind);
    }
    skeleton.joints.push_back(std::move(joint));
  }
  return skeleton;
}

// World positions of every input frame, frames x joints x 3.
absl::StatusOr<std::vector<double>> WorldPositions(const v1::SkeletalMotion& motion) {
  if (motion.has_positions()) {
    return std::vector<double>(motion.positions().values().begin(),
                               motion.positions().values().end());
  }
  absl::StatusOr<Skeleton> skeleton = SkeletonFromProto(motion.skeleton());
  if (!skeleton.ok()) return skeleton.status();
  if (absl::Status s = ValidateSkeleton(*skeleton); !s.ok()) return s;
  const auto& values = motion.channels().values();
  absl::StatusOr<LargeArray<double>> world = ComputeWorldPositions(
      *skeleton, absl::MakeConstSpan(values.data(), values.size()), motion.frame_count());
  if (!world.ok()) return world.status();
  return std::vector<double>(world->begin(), world->end());
}

// Through a column-major 4x4 view-projection matrix to normalised device x, y (a point
// behind the camera, w <= 0, lands on 0, 0).
std::vector<double> Project(const std::vector<double>& world,
                            const google::protobuf::RepeatedField<double>& m) {
  std::vector<double> ndc;
  ndc.reserve(world.size() / 3 * 2);
  for (size_t i = 0; i + 2 < world.size(); i += 3) {
    const double x = world[i], y = world[i + 1], z = world[i + 2];
    const double cx = m[0] * x + m[4] * y + m[8] * z + m[12];
    const double cy = m[1] * x + m[5] * y + m[9] * z + m[13];
    const double cw = m[3] * x + m[7] * y + m[11] * z + m[15];
    ndc.push_back(cw > 0 ? cx / cw : 0.0);
    ndc.push_back(cw > 0 ? cy / cw : 0.0);
  }
  return ndc;
}

// The body's size: twice the largest |joint - root| along one axis over all frames.
double BodySize(const std::vector<double>& points, int joints, int dims) {
  double largest = 0;
  const size_t per_frame = static_cast<size_t>(joints) * dims;
  for (size_t f = 0; f + per_frame <= points.size(); f += per_frame) {
    for (size_t k = dims; k < per_frame; ++k) {
      const double d = std::fabs(points[f + k] - points[f + k % dims]);
      if (std::isfinite(d)) largest = std::max(largest, d);
    }
  }
  return largest > 0 ? 2 * largest : 1.0;
}

nlohmann::json Pose(const v1::RetimeSkeletalRequest& request) {
  const v1::SkeletalMotion& motion = request.motion();
  const int joints = motion.skeleton().joints_size();
  absl::StatusOr<std::vector<double>> world = WorldPositions(motion);
  if (!world.ok() || joints == 0 ||
      world->size() != static_cast<size_t>(joints) * 3 * motion.frame_count()) {
    return {{"error", world.ok() ? "positions do not fit the skeleton"
                                 : std::string(world.status().message())}};
  }
  const bool camera = request.camera_size() == 16;
  const int dims = camera ? 2 : 3;
  const std::vector<double> points = camera ? Project(*world, request.camera()) : *world;
  const double step = Round6(BodySize(points, joints, dims) / kStepsPerBody);
  return {{"camera", camera},
          {"dims", dims},
          {"step", step},
          {"data", PackQuantised(points, joints * dims, step)}};
}

char KindLetter(int kind) {
  switch (kind) {
    case v1::DUPLICATE:
      return 'D';
    case v1::HELD:
      return 'H';
    default:
      return 'O';
  }
}

const char* OrderName(int order) {
  return order == v1::HOLD_THEN_OMIT ? "holds, then omissions" : "omissions, then holds";
}

}  // namespace

std::string SkeletalReportWriter::Title() const {
  return absl::StrCat("koma skeletal: ", input_name_);
}

nlohmann::json SkeletalReportWriter::Data() const {
  const v1::RetimeSkeletalRequest& q = request_;
  const v1::RetimeSkeletalResponse& r = response_;
  const double frame_time_in = q.motion().frame_time();
  const bool grid = r.timing_fps() > 0;
  double frame_time_out = frame_time_in;
  if (r.has_motion() && r.motion().frame_time() > 0) {
    frame_time_out = r.motion().frame_time();
  } else if (grid && q.output_rate() == v1::TIMING_RATE) {
    frame_time_out = 1.0 / r.timing_fps();
  }
  std::string kinds;
  kinds.reserve(r.kinds_size());
  int held = 0, duplicated = 0;
  for (int kind : r.kinds()) {
    kinds.push_back(KindLetter(kind));
    held += kind == v1::HELD;
    duplicated += kind == v1::DUPLICATE;
  }
  int drawings = 0;
  for (int t = 0; t < r.source_frames_size(); ++t) {
    drawings += t == 0 || r.source_frames(t) != r.source_frames(t - 1);
  }

  nlohmann::json options = nlohmann::json::array();
  options.push_back({"omissions", r.omissions_requested()});
  options.push_back({"holds", r.holds_requested()});
  options.push_back({"max_hold", r.max_hold()});
  if (r.omissions_per_second() > 0) {
    options.push_back({"omissions_per_second", r.omissions_per_second()});
  }
  if (r.drawings_per_second() > 0) {
    options.push_back({"drawings_per_second", r.drawings_per_second()});
  }
  options.push_back({"keep_length", !q.has_keep_length() || q.keep_length()});
  options.push_back({"order", OrderName(q.order())});
  options.push_back({"root_relative", q.root_relative()});
  options.push_back({"camera", q.camera_size() == 16 ? "given" : "none (front and side views)"});
  options.push_back({"joint_weights", q.joint_weights_size() > 0 ? "given" : "all 1"});
  options.push_back({"timing_fps", grid ? absl::StrFormat("%.6g (film grid)", r.timing_fps())
                                        : std::string("0 (counted in source frames)")});
  if (grid) {
    options.push_back({"output_rate", q.output_rate() == v1::TIMING_RATE ? "timing" : "source"});
  }
  nlohmann::json counts = nlohmann::json::array();
  counts.push_back({"input frames", q.motion().frame_count()});
  counts.push_back({"input fps", Round6(1.0 / frame_time_in)});
  counts.push_back({"joints", q.motion().skeleton().joints_size()});
  if (grid) counts.push_back({"grid frames", r.grid_source_frames_size()});
  counts.push_back({"output frames", r.source_frames_size()});
  counts.push_back({"output fps", Round6(1.0 / frame_time_out)});
  counts.push_back({"omissions applied", r.omissions_applied()});
  counts.push_back({"duplicates inserted", r.duplicates_applied()});
  // Duplicates a later step changed are not DUPLICATE frames: say so, so the counts add up.
  if (r.duplicates_held() > 0) {
    counts.push_back({"duplicates later held over (now HELD)", r.duplicates_held()});
  }
  if (r.duplicates_omitted() > 0) {
    counts.push_back({"duplicates later omitted", r.duplicates_omitted()});
  }
  if (r.duplicates_skipped() > 0) counts.push_back({"duplicates skipped", r.duplicates_skipped()});
  counts.push_back({"hold steps applied", r.holds_applied()});
  counts.push_back({"HELD output frames", held});
  counts.push_back({"DUPLICATE output frames", duplicated});
  counts.push_back({"drawings", drawings});
  if (r.cut_frames_size() > 0) counts.push_back({"cuts (shots retimed separately)", r.cut_frames_size()});

  nlohmann::json data;
  data["header"] = Header("RetimeSkeletal", input_name_, options, counts);
  if (r.warnings_size() > 0) {
    data["header"]["warnings"] =
        std::vector<std::string>(r.warnings().begin(), r.warnings().end());
  }
  data["fps_in"] = Round6(1.0 / frame_time_in);
  data["frame_time_in"] = frame_time_in;
  data["frames_in"] = q.motion().frame_count();
  data["fps_out"] = Round6(1.0 / frame_time_out);
  data["frame_time_out"] = frame_time_out;
  data["timing_fps"] = r.timing_fps();
  data["source_frames"] = std::vector<int>(r.source_frames().begin(), r.source_frames().end());
  data["kinds"] = kinds;
  data["grid_frames"] = std::vector<int>(r.grid_frames().begin(), r.grid_frames().end());
  data["grid_source_frames"] =
      std::vector<int>(r.grid_source_frames().begin(), r.grid_source_frames().end());
  data["deleted"] = std::vector<int>(r.deleted_frames().begin(), r.deleted_frames().end());
  data["hidden"] = std::vector<int>(r.hidden_frames().begin(), r.hidden_frames().end());
  // Per cut, the source frame that starts the shot after it (docs/semantics.md, Cuts and shots).
  data["cuts"] = std::vector<int>(r.cut_frames().begin(), r.cut_frames().end());
  // input_ssd has one value per grid frame with a grid, else per source frame.
  data["ssd"] = ThinnedPlot(absl::MakeConstSpan(r.input_ssd().data(), r.input_ssd_size()),
                            grid ? 1.0 / r.timing_fps() : frame_time_in);
  std::vector<std::string> names;
  std::vector<int> parents;
  for (const v1::Joint& j : q.motion().skeleton().joints()) {
    names.push_back(j.name());
    parents.push_back(j.parent());
  }
  data["joints"] = {{"names", names}, {"parents", parents}};
  data["pose"] = Pose(q);
  data["xdts"] = ExposureSheetData(SkeletalXdtsSheet(r, XdtsClipName(input_name_, "")));
  return data;
}

absl::Status WriteSkeletalReport(const std::string& path, const v1::RetimeSkeletalRequest& request,
                                 const v1::RetimeSkeletalResponse& response,
                                 const std::string& input_name) {
  if (!request.has_motion()) {
    // The file form (bvh_text) is not parsed here: the CLI always sends the parsed clip.
    return absl::InvalidArgumentError(
        absl::StrCat("--report ", path, ": the request has no parsed motion to draw"));
  }
  return WriteReport(path, SkeletalReportWriter(request, response, input_name));
}

}  // namespace koma::client::report
