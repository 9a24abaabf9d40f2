"""Writes the fuzz targets' cost cases (issue 42) beside the seeds fuzz/make_seeds.cc writes:
small versions of the hostile files tests/e2e/hostile_wire_test.py sends (a FLAC header
claiming 8 channels at 1 MHz for 2 hours, one of unknown length, WAV headers that lie, glTF
files over the animation limit or with key times of 1e30 s and below 0, Spine bones that are
their own parents, cycles and duplicates, a UTF-16 skeleton, many keys, Rhubarb cues ending
at 1e308 s, an FBX zip bomb, deep nesting and ASCII), as files for the format targets and as
requests for the RPC targets.

Usage: python3 fuzz/make_cost_seeds.py SEEDS_DIR
"""
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), '..', 'tests', 'e2e',
                                'hostile'))
import hostile_files as hf  # noqa: E402


def varint(n):
    out = bytearray()
    while True:
        byte = n & 0x7F
        n >>= 7
        out.append(byte | (0x80 if n else 0))
        if not n:
            return bytes(out)


def bytes_field(number, data):
    """A protobuf length-delimited field: the RPC targets' requests, without the generated code."""
    return varint(number << 3 | 2) + varint(len(data)) + data


def request(selector, *fields):
    """An RPC target's input: the slice selector (fuzz/rpc_fuzz_input.h), then the message."""
    return bytes([selector]) + b''.join(fields)


def main():
    seeds = sys.argv[1]
    spines = {
        'self_parent': hf.spine([{"name": "root"}, {"name": "arm", "parent": "arm"}]),
        'cycle': hf.spine([{"name": "root"}, {"name": "arm", "parent": "leg"},
                           {"name": "leg", "parent": "arm"}]),
        'duplicate': hf.spine([{"name": "root"}, {"name": "arm", "parent": "root"},
                               {"name": "arm", "parent": "root"}]),
        'utf16': b'\xff\xfe' + hf.spine().decode().encode('utf-16-le'),
        'keys_2000': hf.spine(keys=2000, duration=60.0),
    }
    glbs = {
        'animations_300': hf.gltf_animations(300),
        'empty_animations_300': hf.gltf_animations(300, empty=True),
        'key_time_1e30': hf.gltf_animations(1, (0, 1e30)),
        'key_time_negative': hf.gltf_animations(1, (-1.0, 1.0)),
    }
    audio = {
        'flac_8ch_1mhz_2h.flac': hf.flac_silence(1_000_000, 8, 2, 7200 * 1_000_000),
        'flac_8ch_1mhz_unknown_length.flac': hf.flac_silence(1_000_000, 8, 12, 0),
        'wav_0hz.wav': hf.wav(0, 1, 100),
        'wav_claims_4gib.wav': hf.wav(48000, 2, 480, data_claim=0xFFFFFF00),
    }
    files = {}
    for name, data in spines.items():
        files['spine/cost_%s.json' % name] = data
        # RetimeCurvesRequest.spine_json = 45
        files['retime_curves/cost_spine_%s' % name] = request(0, bytes_field(45, data))
    for name, data in glbs.items():
        files['gltf/cost_%s.glb' % name] = data
        # RetimeSkeletalRequest.gltf = 30
        files['retime_skeletal/cost_gltf_%s' % name] = request(0, bytes_field(30, data))
    for name, data in audio.items():
        files['audio/cost_' + name] = data
        # LipBlinkRequest.audio = 20
        files['lip_blink/cost_audio_' + name] = request(0, bytes_field(20, data))
    fbxs = {
        'zip_bomb': hf.fbx_zip_bomb(),
        'nested_40': hf.fbx_nested(40),
        'ascii': b'; FBX 7.4.0 project file\nFBXHeaderExtension:  {\n',
    }
    for name, data in fbxs.items():
        files['fbx/cost_%s.fbx' % name] = data
        # RetimeSkeletalRequest.fbx = 36
        files['retime_skeletal/cost_fbx_%s' % name] = request(0, bytes_field(36, data))
    # LipBlinkRequest.rhubarb_cues = 21
    files['lip_blink/cost_rhubarb_1e308'] = request(
        0, bytes_field(21, hf.rhubarb(3, last_end=1e308)))
    for path, data in files.items():
        os.makedirs(os.path.join(seeds, os.path.dirname(path)), exist_ok=True)
        with open(os.path.join(seeds, path), 'wb') as out:
            out.write(data)


if __name__ == '__main__':
    main()
