// Writes the fuzz targets' seed corpora from the project's sample and test files:
//   make_seeds TESTDATA_DIR SAMPLES_DIR OUT_DIR
// OUT_DIR/<target>/ gets, for
//   bvh:        every .bvh file, and each cut to its first 4 frames (small seeds run fast);
//   motion3:    every .motion3.json file;
//   curve_csv:  curves_crlf.csv and each motion3 file's curves as per-frame CSV (12 frames);
//   spine:      every Spine skeleton (TESTDATA_DIR/spine/*.json, SAMPLES_DIR/*.json), which also
//              become retime_curves requests carrying spine_json;
//   gltf:       the test arm of tests/testing/gltf_builder.h as .glb and .gltf;
//   fbx:        the real binary FBX files of TESTDATA_DIR/fbx;
//   retime_skeletal, retime_curves, lip_blink: serialised requests built from those files
//              (cut short, some with a film grid), after the slice selector byte the RPC
//              targets read first (fuzz/rpc_fuzz_input.h): 0 = one slice, 200 = 73-byte slices.
// The same files give the same corpora, so a CI run starts from the same seeds every time.
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <iterator>
#include <optional>
#include <string>
#include <vector>

#include "client/curves_convert.h"
#include "client/skeletal_convert.h"
#include "core/curves.h"
#include "core/film_grid.h"
#include "formats/bvh.h"
#include "formats/curve_csv.h"
#include "formats/motion3.h"
#include "formats/spine.h"
#include "formats/spine_attachments.h"
#include "koma/v1/retime.pb.h"
#include "tests/testing/gltf_builder.h"

namespace fs = std::filesystem;

namespace {

std::string ReadFile(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

void WriteFile(const fs::path& path, const std::string& bytes) {
  fs::create_directories(path.parent_path());
  std::ofstream out(path, std::ios::binary);
  out << bytes;
  if (!out) {
    std::cerr << "make_seeds: cannot write " << path << "\n";
    std::exit(1);
  }
}

std::vector<fs::path> FilesEndingIn(const std::vector<fs::path>& dirs, const std::string& end) {
  std::vector<fs::path> found;
  for (const fs::path& dir : dirs) {
    for (const fs::directory_entry& entry : fs::directory_iterator(dir)) {
      const std::string name = entry.path().filename().string();
      if (name.size() >= end.size() &&
          name.compare(name.size() - end.size(), end.size(), end) == 0) {
        found.push_back(entry.path());
      }
    }
  }
  std::sort(found.begin(), found.end());
  return found;
}

// The RPC targets' input: the slice selector, then the message.
void WriteRequest(const fs::path& dir, const std::string& name,
                  const google::protobuf::MessageLite& request) {
  for (const unsigned char selector : {0, 200}) {
    WriteFile(dir / (name + "_s" + std::to_string(selector)),
              std::string(1, static_cast<char>(selector)) + request.SerializeAsString());
  }
}

koma::SkeletalClip FirstFrames(koma::SkeletalClip clip, int frames) {
  frames = std::min(frames, clip.frame_count);
  clip.values.resize(static_cast<size_t>(frames) * koma::ChannelCount(clip.skeleton));
  clip.frame_count = frames;
  return clip;
}

// The curves sampled at every frame, cut to `frames` frames, as dense curves.
koma::CurveSet Dense(const koma::CurveSet& set, int frames) {
  koma::CurveSet dense = set;
  dense.frame_count = std::min(frames, set.frame_count);
  for (koma::Curve& curve : dense.curves) {
    curve.samples = koma::SampleEveryFrame(curve, dense.frame_count, set.beziers_restricted);
    curve.segments.clear();
  }
  return dense;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 4) {
    std::cerr << "usage: make_seeds TESTDATA_DIR SAMPLES_DIR OUT_DIR\n";
    return 2;
  }
  const std::vector<fs::path> inputs = {argv[1], argv[2]};
  const fs::path out = argv[3];

  for (const fs::path& path : FilesEndingIn(inputs, ".bvh")) {
    const std::string text = ReadFile(path);
    const std::string stem = path.stem().string();
    WriteFile(out / "bvh" / (stem + ".bvh"), text);
    const absl::StatusOr<koma::SkeletalClip> clip = koma::formats::ParseBvh(text);
    if (!clip.ok()) {
      std::cerr << "make_seeds: " << path << ": " << clip.status() << "\n";
      return 1;
    }
    WriteFile(out / "bvh" / (stem + "_4_frames.bvh"),
              koma::formats::WriteBvh(FirstFrames(*clip, 4)));

    koma::v1::RetimeSkeletalRequest request;
    *request.mutable_motion() = koma::client::ToProto(FirstFrames(*clip, 12));
    WriteRequest(out / "retime_skeletal", stem, request);
    request.set_timing_fps(24);
    request.set_omissions(2);
    request.set_holds(1);
    WriteRequest(out / "retime_skeletal", stem + "_grid", request);
    // A given timing (issue 46): holds, a repeat and a swap over the first grid frames.
    for (int s : {0, 0, 3, 3, 3, 1, 9, 9, 2}) request.mutable_given_timing()->add_source_frames(s);
    WriteRequest(out / "retime_skeletal", stem + "_given", request);
  }

  for (const fs::path& path : FilesEndingIn(inputs, ".csv")) {
    WriteFile(out / "curve_csv" / path.filename(), ReadFile(path));
  }

  for (const fs::path& path : FilesEndingIn(inputs, ".motion3.json")) {
    const std::string text = ReadFile(path);
    const std::string stem = path.filename().string().substr(0, path.filename().string().find('.'));
    WriteFile(out / "motion3" / path.filename(), text);
    const absl::StatusOr<koma::formats::Motion3File> file = koma::formats::ParseMotion3(text);
    if (!file.ok()) {
      std::cerr << "make_seeds: " << path << ": " << file.status() << "\n";
      return 1;
    }
    const koma::CurveSet dense = Dense(file->curves, 12);
    std::vector<std::string> ids;
    std::vector<std::vector<double>> values;
    for (const koma::Curve& curve : dense.curves) {
      ids.push_back(curve.id);
      values.push_back(curve.samples);
    }
    WriteFile(out / "curve_csv" / (stem + ".csv"), koma::formats::WriteCurveCsv(ids, values));

    koma::v1::RetimeCurvesRequest curves;
    *curves.mutable_curves() = koma::client::CurveSetToProto(file->curves);
    WriteRequest(out / "retime_curves", stem, curves);
    curves.set_timing_fps(24);
    curves.set_frames_per_drawing(2);
    WriteRequest(out / "retime_curves", stem + "_grid", curves);
    {  // A given timing for the default group, on twos, one tau per grid frame.
      koma::v1::RetimeCurvesRequest given = curves;
      given.set_default_timing_groups(false);
      const std::optional<koma::FilmGrid> grid = koma::FilmGrid::Make(file->curves.fps, 24);
      const int counted =
          grid ? grid->GridFrameCount(file->curves.frame_count) : file->curves.frame_count;
      koma::v1::GivenDrawingTiming* timing = given.add_given_timings();
      for (int g = 0; g < counted; ++g) timing->add_source_frame((g / 2 * 2) % file->curves.frame_count);
      WriteRequest(out / "retime_curves", stem + "_given", given);
    }
    *curves.mutable_curves() = koma::client::CurveSetToProto(dense);
    WriteRequest(out / "retime_curves", stem + "_dense", curves);

    // LipBlink: mouth and eye curves by their usual Live2D names, when the file has them.
    koma::v1::LipBlinkRequest lip;
    *lip.mutable_curves() = koma::client::CurveSetToProto(file->curves);
    for (const koma::Curve& curve : file->curves.curves) {
      if (curve.id.find("Mouth") != std::string::npos) lip.mutable_mouth()->add_ids(curve.id);
      if (curve.id.find("Eye") != std::string::npos) lip.mutable_eyes()->add_ids(curve.id);
    }
    WriteRequest(out / "lip_blink", stem, lip);
    lip.mutable_eyes()->mutable_auto_blink()->set_enabled(true);
    lip.set_seed(7);
    lip.set_timing_fps(24);
    WriteRequest(out / "lip_blink", stem + "_auto_grid", lip);
    {  // A given timing: a mouth hold and a blink per curve, on the grid's first frames.
      koma::v1::LipBlinkRequest given = lip;
      for (const std::string& id : lip.mouth().ids()) {
        koma::v1::GivenMouthTiming* m = given.mutable_given_timing()->add_mouths();
        m->set_id(id);
        koma::v1::MouthHold* h = m->add_holds();
        h->set_begin(1);
        h->set_length(2);
        h->set_shape(koma::v1::MOUTH_OPEN);
      }
      for (const std::string& id : lip.eyes().ids()) {
        koma::v1::GivenEyeTiming* e = given.mutable_given_timing()->add_eyes();
        e->set_id(id);
        koma::v1::Blink* b = e->add_blinks();
        b->set_closing_begin(1);
        b->set_closed_begin(2);
        b->set_closed_end(2);
        b->set_open_span(1);
        b->set_hold(1);
      }
      WriteRequest(out / "lip_blink", stem + "_given", given);
    }
  }
  for (const fs::path& path : FilesEndingIn({inputs[0] / "spine", inputs[1]}, ".json")) {
    const std::string text = ReadFile(path);
    if (!koma::formats::IsSpineJson(text)) continue;
    const std::string stem = path.stem().string();
    WriteFile(out / "spine" / path.filename(), text);
    const absl::StatusOr<koma::formats::SpineFile> file = koma::formats::ParseSpine(text);
    if (!file.ok()) {
      std::cerr << "make_seeds: " << path << ": " << file.status() << "\n";
      return 1;
    }
    for (const koma::formats::SpineAnimation& animation : file->animations) {
      if (!animation.retimable()) continue;
      koma::v1::RetimeCurvesRequest curves;
      curves.set_spine_json(text);
      curves.set_spine_animation(animation.name);
      WriteRequest(out / "retime_curves", stem + "_" + animation.name + "_spine", curves);
    }
    // LipBlink into the skeleton's mouth and eye slots (the hero files: "mouth" with
    // mouth_closed/_mid/_open, "eyes" with eyes_open/_half/_closed), an existing animation
    // with speech and auto-blink, and a new one from Rhubarb cues.
    const absl::StatusOr<std::vector<std::string>> mouths =
        koma::formats::SpineSlotAttachments(*file, "mouth");
    const absl::StatusOr<std::vector<std::string>> eyes =
        koma::formats::SpineSlotAttachments(*file, "eyes");
    const auto has = [](const absl::StatusOr<std::vector<std::string>>& names,
                        const std::string& name) {
      return names.ok() && std::find(names->begin(), names->end(), name) != names->end();
    };
    if (has(mouths, "mouth_mid") && has(eyes, "eyes_half") && !file->animations.empty()) {
      koma::v1::LipBlinkRequest lip;
      lip.set_spine_json(text);
      lip.mutable_spine()->set_animation(file->animations[0].name);
      lip.mutable_spine()->set_mouth_slot("mouth");
      lip.mutable_spine()->add_eye_slots("eyes");
      koma::v1::FrameInterval* speech = lip.mutable_mouth()->add_speech();
      speech->set_begin(2);
      speech->set_end(12);
      lip.mutable_eyes()->mutable_auto_blink()->set_enabled(true);
      lip.set_seed(5);
      WriteRequest(out / "lip_blink", stem + "_spine", lip);
      lip.mutable_spine()->set_animation("talk");
      lip.mutable_mouth()->clear_speech();
      lip.set_rhubarb_cues("0.00\tX\n0.10\tD\n0.30\tC\n0.50\tX\n");
      WriteRequest(out / "lip_blink", stem + "_spine_cues", lip);
    }
  }

  // Recordings: each as it is and cut to its first 4 KiB (a header and a few blocks), for the
  // audio decoder and, with Rhubarb cues, as LipBlink voice requests.
  for (const std::string ending : {".flac", ".wav"}) {
    for (const fs::path& path : FilesEndingIn(inputs, ending)) {
      const std::string bytes = ReadFile(path);
      const std::string stem = path.stem().string();
      WriteFile(out / "audio" / path.filename(), bytes);
      WriteFile(out / "audio" / (stem + "_4k" + ending), bytes.substr(0, 4096));
      koma::v1::LipBlinkRequest voice;
      voice.set_audio(bytes.substr(0, 4096));
      WriteRequest(out / "lip_blink", stem + "_voice", voice);
    }
  }
  koma::v1::LipBlinkRequest cues;
  cues.set_rhubarb_cues("0.00\tX\n0.05\tD\n0.27\tC\n0.40\tB\n1.25\tX\n");
  WriteRequest(out / "lip_blink", "rhubarb_tsv", cues);
  cues.set_rhubarb_cues(
      "{\"mouthCues\": [{\"start\": 0, \"end\": 0.5, \"value\": \"X\"}, "
      "{\"start\": 0.5, \"end\": 0.9, \"value\": \"D\"}]}");
  WriteRequest(out / "lip_blink", "rhubarb_json", cues);
  // glTF: the test arm (tests/testing/gltf_builder.h) as GLB and .gltf, LINEAR and STEP, and
  // as a RetimeSkeletal request carrying it.
  for (const char* interpolation : {"LINEAR", "STEP"}) {
    const koma::testing::TestGltf arm = koma::testing::ArmGltf(interpolation);
    WriteFile(out / "gltf" / (std::string("arm_") + interpolation + ".glb"), arm.Glb());
    WriteFile(out / "gltf" / (std::string("arm_") + interpolation + ".gltf"), arm.GltfText());
    koma::v1::RetimeSkeletalRequest request;
    request.set_gltf(arm.Glb());
    WriteRequest(out / "retime_skeletal", std::string("arm_") + interpolation + "_glb", request);
  }
  // FBX: the real files of tests/testdata/fbx (Blender 7.4, Maya 7.5).
  for (const fs::path& path : FilesEndingIn({inputs[0] / "fbx"}, ".fbx")) {
    WriteFile(out / "fbx" / path.filename(), ReadFile(path));
  }
  std::cout << "make_seeds: corpora written to " << out << "\n";
  return 0;
}
