// `koma batch lipblink --audio-beside`: each input (a Spine skeleton, a motion3.json, a CSV)
// is sent with the voice recording of the same name beside it, as the single-file
// `koma lipblink IN --audio REC` sends it: hero.json + hero.wav, walk.motion3.json + walk.flac.
#ifndef KOMA_CLIENT_BATCH_BATCH_AUDIO_BESIDE_H_
#define KOMA_CLIENT_BATCH_BATCH_AUDIO_BESIDE_H_

#include <string>
#include <vector>

#include "client/batch/batch_inputs.h"

namespace koma::client::batch {

// The name a recording must share with `file_name`: the name less its input ending
// (".motion3.json", ".json" or ".csv", any case), else less its last extension.
// "hero.json" -> "hero", "walk.motion3.json" -> "walk", "take.bvh" -> "take".
std::string RecordingStem(const std::string& file_name);

// The recordings beside `input` (in its folder) named RecordingStem + one of AudioExtensions
// (the stem as written, the extension in any case), sorted by name; paths as `input` is
// written ("skel/hero.json" -> "skel/hero.wav").
std::vector<std::string> RecordingsBeside(const std::string& input);

// Sets BatchItem::audio of every input that is not itself a recording to its one recording
// beside it, or BatchItem::audio_error when it has none or several (the item then fails,
// naming the input and the candidates; the rest of the batch goes on). A recording among the
// inputs that some input takes is dropped (it writes nothing of its own); one that no input
// takes keeps an audio_error (with --audio-beside recordings are not inputs of their own).
// The items keep their order.
std::vector<BatchItem> PairRecordingsBeside(std::vector<BatchItem> items);

}  // namespace koma::client::batch

#endif  // KOMA_CLIENT_BATCH_BATCH_AUDIO_BESIDE_H_
