#include "client/file_job.h"

#include <algorithm>
#include <utility>

#include "absl/strings/str_cat.h"
#include "client/channel.h"
#include "client/cli.h"
#include "client/command_io.h"
#include "convert/curve_text.h"
#include "formats/audio_reader.h"
#include "formats/bvh.h"
#include "formats/format_table.h"
#include "formats/gltf.h"
#include "formats/spine.h"

namespace koma::client {
namespace {

// The report's default (client/report/lip_blink_voice_report.h): a recording up to this size
// is embedded in the report; a job's larger one gets the flag raised to its size, since a
// link to a file the job holds in memory would lead nowhere.
constexpr size_t kReportAudioMaxBytes = 16 * 1024 * 1024;

formats::FormatId FormatOfFile(const std::string& name, const std::string& bytes) {
  const formats::FormatId sniffed = formats::SniffFormat(bytes);
  return sniffed != formats::FormatId::kUnknown ? sniffed : formats::FormatFromName(name);
}

// "pitch.bvh" -> {"pitch", ".bvh"}; "arm.motion3.json" -> {"arm", ".motion3.json"}.
std::pair<std::string, std::string> SplitName(const std::string& name) {
  size_t ext = formats::FormatExtensionLength(name);
  if (ext == 0) {
    const size_t dot = name.rfind('.');
    ext = (dot == std::string::npos || dot == 0) ? 0 : name.size() - dot;
  }
  return {name.substr(0, name.size() - ext), name.substr(name.size() - ext)};
}

// The name the result is written under: a voice recording's mouth goes to motion3.json; any
// other input comes back in its own format.
std::string ResultName(const FileJob& job, bool voice) {
  const auto [stem, ext] = SplitName(job.input_name);
  if (voice) return stem + ".motion3.json";
  return stem + "_anime" + (ext.empty() ? std::string(".json") : ext);
}

struct Output {
  const char* role;
  const char* flag;
  std::string name;
};

std::vector<Output> Outputs(const FileJob& job, bool voice) {
  const std::string stem = SplitName(job.input_name).first;
  std::vector<Output> outputs{{"result", "-o", ResultName(job, voice)}};
  if (job.timing && job.command != "lipblink") {
    outputs.push_back({"timing", "--timing", stem + "_timing.csv"});
  }
  if (job.xdts) outputs.push_back({"xdts", "--xdts", stem + ".xdts"});
  if (job.report) outputs.push_back({"report", "--report", stem + "_report.html"});
  return outputs;
}

bool IsVoice(const FileJob& job) {
  return job.command == "lipblink" &&
         FormatOfFile(job.input_name, job.input) == formats::FormatId::kAudio;
}

}  // namespace

absl::StatusOr<std::vector<std::string>> FileJobCommandLine(const FileJob& job) {
  if (job.command != "skeletal" && job.command != "curves" && job.command != "lipblink") {
    return absl::InvalidArgumentError(absl::StrCat(
        "command \"", job.command, "\" is not one of skeletal, curves and lipblink"));
  }
  const std::string& name = job.input_name;
  if (name.empty() || name[0] == '-' || name[0] == '.' ||
      name.find_first_of("/\\") != std::string::npos ||
      std::any_of(name.begin(), name.end(),
                  [](char c) { return static_cast<unsigned char>(c) < 0x20; })) {
    return absl::InvalidArgumentError(absl::StrCat(
        "file name \"", name, "\": give a plain file name (no folder, not starting with - or .)"));
  }
  const bool voice = IsVoice(job);
  std::vector<std::string> line{"koma", job.command};
  if (voice) line.push_back("--audio");
  line.push_back(name);
  for (const Output& output : Outputs(job, voice)) {
    line.push_back(output.flag);
    line.push_back(output.name);
  }
  if (voice && job.report && job.input.size() > kReportAudioMaxBytes) {
    line.push_back("--report-audio-max-bytes");
    line.push_back(absl::StrCat(job.input.size()));
  }
  line.insert(line.end(), job.options.begin(), job.options.end());
  return line;
}

absl::StatusOr<FileJobResult> RunFileJob(const FileJob& job,
                                         const std::shared_ptr<grpc::Channel>& channel) {
  absl::StatusOr<std::vector<std::string>> line = FileJobCommandLine(job);
  if (!line.ok()) return line.status();
  FileJobResult result;
  result.command_line = *line;
  std::vector<std::string> args = *std::move(line);
  args.insert(args.begin() + 2, "--json");  // the summary, which writes no file

  MemoryCommandIo io;
  io.readable[job.input_name] = job.input;
  {
    const ScopedMemoryCommandIo memory(&io);
    const ScopedRetimeChannel call(channel);
    KomaCommandLine parsed;
    result.exit_code = ParseCommandLine(args, &parsed);
    if (result.exit_code < 0) result.exit_code = RunCommandLine(parsed);
  }
  result.messages = std::move(io.stderr_text);
  result.summary = nlohmann::json::parse(io.stdout_text, nullptr, /*allow_exceptions=*/false);
  if (result.summary.is_discarded()) result.summary = nullptr;
  if (result.exit_code != 0) return result;
  for (const Output& output : Outputs(job, IsVoice(job))) {
    const auto it = io.written.find(output.name);
    if (it == io.written.end()) continue;  // e.g. no XDTS for an answer without a timing
    result.files.push_back({output.role, output.name, std::move(it->second)});
  }
  return result;
}

namespace {

void InspectBvh(const std::string& bytes, nlohmann::json* out) {
  absl::StatusOr<SkeletalClip> clip = formats::ParseBvh(bytes);
  if (!clip.ok()) {
    (*out)["error"] = std::string(clip.status().message());
    return;
  }
  (*out)["frames"] = clip->frame_count;
  if (clip->frame_time > 0) (*out)["fps"] = 1.0 / clip->frame_time;
  (*out)["joints"] = clip->skeleton.joints.size();
}

void PutCurves(const CurveSet& curves, nlohmann::json* out) {
  (*out)["frames"] = curves.frame_count;
  (*out)["fps"] = curves.fps;
  nlohmann::json ids = nlohmann::json::array();
  for (const Curve& curve : curves.curves) ids.push_back(curve.id);
  (*out)["curves"] = std::move(ids);
}

void InspectCurves(const std::string& bytes, bool csv, nlohmann::json* out) {
  // A CSV names no rate: 30 fps, koma curves' --fps default.
  absl::StatusOr<convert::CurveInput> input = convert::ParseCurveText(bytes, csv, 30.0);
  if (!input.ok()) {
    (*out)["error"] = std::string(input.status().message());
    return;
  }
  PutCurves(input->curves, out);
}

void InspectSpine(const std::string& bytes, nlohmann::json* out) {
  absl::StatusOr<formats::SpineFile> file = formats::ParseSpine(bytes);
  if (!file.ok()) {
    (*out)["error"] = std::string(file.status().message());
    return;
  }
  (*out)["fps"] = file->fps;
  nlohmann::json names = nlohmann::json::array();
  for (const formats::SpineAnimation& animation : file->animations) names.push_back(animation.name);
  (*out)["animations"] = std::move(names);
  for (const formats::SpineAnimation& animation : file->animations) {
    if (animation.curves.curves.empty()) continue;
    PutCurves(animation.curves, out);  // the first animation with bone timelines
    break;
  }
}

void InspectGltf(const std::string& bytes, nlohmann::json* out) {
  absl::StatusOr<formats::GltfDocument> document = formats::ReadGltf(bytes);
  if (!document.ok()) {
    (*out)["error"] = std::string(document.status().message());
    return;
  }
  nlohmann::json names = nlohmann::json::array();
  for (const formats::GltfAnimation& animation : document->animations) {
    names.push_back(animation.name);
  }
  (*out)["animations"] = std::move(names);
  (*out)["joints"] = document->joints.size();
}

void InspectAudio(const std::string& bytes, nlohmann::json* out) {
  absl::StatusOr<std::unique_ptr<formats::AudioDecoder>> decoder =
      formats::AudioDecoder::Open(bytes, formats::AudioLimits{});
  if (!decoder.ok()) {
    (*out)["error"] = std::string(decoder.status().message());
    return;
  }
  const formats::AudioInfo& info = (*decoder)->info();
  (*out)["sample_rate"] = info.sample_rate;
  (*out)["channels"] = info.channels;
  (*out)["seconds"] = static_cast<double>(info.frames) / info.sample_rate;
}

}  // namespace

nlohmann::json InspectFile(const std::string& name, const std::string& bytes) {
  const formats::FormatRow& row = formats::FormatOf(FormatOfFile(name, bytes));
  nlohmann::json out = {{"format", std::string(row.key)},
                        {"format_name", std::string(row.name)},
                        {"bytes", bytes.size()}};
  nlohmann::json commands = nlohmann::json::array();
  for (const formats::CommandInput& input : row.inputs) {
    commands.push_back({{"command", std::string(input.command)}, {"flag", std::string(input.flag)}});
  }
  out["commands"] = std::move(commands);
  switch (row.id) {
    case formats::FormatId::kBvh: InspectBvh(bytes, &out); break;
    case formats::FormatId::kMotion3: InspectCurves(bytes, false, &out); break;
    case formats::FormatId::kCsv: InspectCurves(bytes, true, &out); break;
    case formats::FormatId::kSpine: InspectSpine(bytes, &out); break;
    case formats::FormatId::kGltf: InspectGltf(bytes, &out); break;
    case formats::FormatId::kAudio: InspectAudio(bytes, &out); break;
    default: break;  // FBX, Rhubarb cues: the format alone
  }
  return out;
}

}  // namespace koma::client
