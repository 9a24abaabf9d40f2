"""Hostile and extreme files for koma's newer formats, made here (no file is checked in).

Each maker returns the file's bytes. They are what a hostile or careless client sends: files
that pass every size limit but cost far more to decode, files the format's own tools refuse,
and files whose numbers sit at the edge of what the format can say. tests/e2e/hostile_wire_test.py
sends each over the wire; fuzz/make_seeds.py (the cost cases) writes some of them as seeds.
"""
import json
import struct

# --- FLAC made of CONSTANT subframes: seconds of audio in a few bytes per 65,535 samples ------

_CRC8 = []
for _byte in range(256):
    _c = _byte
    for _ in range(8):
        _c = ((_c << 1) ^ 0x07) & 0xFF if _c & 0x80 else (_c << 1) & 0xFF
    _CRC8.append(_c)

_CRC16 = []
for _byte in range(256):
    _c = _byte << 8
    for _ in range(8):
        _c = ((_c << 1) ^ 0x8005) & 0xFFFF if _c & 0x8000 else (_c << 1) & 0xFFFF
    _CRC16.append(_c)


def _crc8(data):
    c = 0
    for b in data:
        c = _CRC8[c ^ b]
    return c


def _crc16(data):
    c = 0
    for b in data:
        c = ((c << 8) & 0xFFFF) ^ _CRC16[(c >> 8) ^ b]
    return c


def _utf8_number(n):
    """FLAC's "UTF-8" coding of a frame number (up to 31 bits)."""
    if n < 0x80:
        return bytes([n])
    for length, lead in ((2, 0xC0), (3, 0xE0), (4, 0xF0), (5, 0xF8), (6, 0xFC)):
        if n < 1 << (5 * length + 1):
            out = [0x80 | ((n >> (6 * i)) & 0x3F) for i in range(length - 1)]
            first = lead | (n >> (6 * (length - 1)))
            return bytes([first] + out[::-1])
    raise ValueError(n)


def flac_silence(rate, channels, frames_written, claimed_samples, block=65535):
    """A FLAC stream of `frames_written` frames of `block` silent samples per channel (16-bit),
    whose STREAMINFO claims `claimed_samples` per channel (0: unknown length). Every subframe
    is CONSTANT, so an hour of 8 channels at 1 MHz is a few megabytes."""
    assert 1 <= channels <= 8 and rate < 1 << 20
    info = struct.pack('>HH', block, block) + b'\0' * 6
    packed = (rate << 44) | ((channels - 1) << 41) | (15 << 36) | claimed_samples
    info += packed.to_bytes(8, 'big') + b'\0' * 16
    out = bytearray(b'fLaC' + bytes([0x80, 0, 0, len(info)]) + info)
    subframes = b'\0\0\0' * channels  # CONSTANT type, the value 0
    for n in range(frames_written):
        header = bytearray([0xFF, 0xF8, 0x70, ((channels - 1) << 4) | 0x08])
        header += _utf8_number(n) + struct.pack('>H', block - 1)
        header.append(_crc8(header))
        frame = bytes(header) + subframes
        out += frame + struct.pack('>H', _crc16(frame))
    return bytes(out)


def wav(rate, channels, samples, bits=16, data_claim=None):
    """A PCM WAV of `samples` silent sample frames; `data_claim` overrides the data chunk's
    size (a header that lies)."""
    block_align = channels * bits // 8
    data = b'\0' * (samples * block_align)
    fmt = struct.pack('<HHIIHH', 1, channels, rate, rate * block_align, block_align, bits)
    size = len(data) if data_claim is None else data_claim
    body = b'WAVE' + b'fmt ' + struct.pack('<I', len(fmt)) + fmt + b'data' + struct.pack('<I', size)
    return b'RIFF' + struct.pack('<I', len(body) + len(data)) + body + data


# --- glTF -----------------------------------------------------------------------------------

def glb(doc, data=b''):
    """A GLB container of the JSON `doc` and the binary chunk `data`."""
    text = json.dumps(doc, separators=(',', ':')).encode()
    text += b' ' * (-len(text) % 4)
    data += b'\0' * (-len(data) % 4)
    chunks = struct.pack('<I', len(text)) + b'JSON' + text
    if data:
        chunks += struct.pack('<I', len(data)) + b'BIN\0' + data
    return b'glTF' + struct.pack('<II', 2, 12 + len(chunks)) + chunks


def gltf_animations(count, times=(0.0, 1.0), empty=False):
    """A two-node GLB whose `count` animations each move the second node along one shared
    pair of accessors (key times `times`); `empty`: every animation is `{}` (no channels, no
    samplers, which the glTF schema forbids)."""
    keys = len(times)
    data = struct.pack('<%df' % keys, *times) + struct.pack('<%df' % (3 * keys),
                                                            *[float(i) for i in range(3 * keys)])
    doc = {"asset": {"version": "2.0"}, "scenes": [{"nodes": [0]}], "scene": 0,
           "nodes": [{"name": "root", "children": [1]}, {"name": "arm", "translation": [0, 1, 0]}],
           "buffers": [{"byteLength": len(data)}],
           "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 4 * keys},
                           {"buffer": 0, "byteOffset": 4 * keys, "byteLength": 12 * keys}],
           "accessors": [{"bufferView": 0, "componentType": 5126, "count": keys, "type": "SCALAR",
                          "min": [min(times)], "max": [max(times)]},
                         {"bufferView": 1, "componentType": 5126, "count": keys, "type": "VEC3"}]}
    one = {"channels": [{"sampler": 0, "target": {"node": 1, "path": "translation"}}],
           "samplers": [{"input": 0, "output": 1}]}
    doc["animations"] = [{} if empty else dict(one, name="a%d" % i) for i in range(count)]
    return glb(doc, data)


def gltf_text_broken_data_uri(length):
    """A .gltf whose one buffer is a data: URI of `length` characters that are not base64."""
    doc = {"asset": {"version": "2.0"},
           "buffers": [{"byteLength": length, "uri": "data:application/octet-stream;base64," +
                        "!" * length}]}
    return json.dumps(doc).encode()


# --- Spine ----------------------------------------------------------------------------------

def spine(bones=None, keys=2, duration=1.0):
    """A Spine 4.1 skeleton whose animation "run" keys bone "arm"'s rotation `keys` times
    over `duration` seconds. `bones` replaces the bone list."""
    if bones is None:
        bones = [{"name": "root"}, {"name": "arm", "parent": "root", "length": 50}]
    step = duration / max(1, keys - 1)
    rotate = [{"time": round(i * step, 6), "value": (i * 7) % 360} for i in range(keys)]
    doc = {"skeleton": {"spine": "4.1.24", "fps": 30}, "bones": bones,
           "animations": {"run": {"bones": {"arm": {"rotate": rotate}}}}}
    return json.dumps(doc, separators=(',', ':')).encode()


# --- Rhubarb --------------------------------------------------------------------------------

def rhubarb(count, last_end=None):
    """Rhubarb Lip Sync's JSON with `count` cues of 0.1 s; `last_end` overrides the last end."""
    cues = [{"start": round(i * 0.1, 2), "end": round(i * 0.1 + 0.1, 2), "value": "ABCX"[i % 4]}
            for i in range(count)]
    if last_end is not None and cues:
        cues[-1]["end"] = last_end
    return json.dumps({"metadata": {"soundFile": "x.wav", "duration": 0},
                       "mouthCues": cues}).encode()


# --- FBX ------------------------------------------------------------------------------------

def _fbx(records, version=7400):
    """A binary FBX of the given top-level records (bytes each), then the null record."""
    return (b'Kaydara FBX Binary  \0\x1a\0' + struct.pack('<I', version) + b''.join(records) +
            b'\0' * 13)


def _fbx_record(start, name, properties, count, children=b''):
    """One 7.4 node record at byte `start`: its end offset, counts, name and properties."""
    body = bytes([len(name)]) + name + properties + children
    return struct.pack('<III', start + 12 + len(body), count, len(properties)) + body


def fbx_zip_bomb(claimed=1 << 31):
    """A node whose one array of doubles claims `claimed` elements in 10 zlib bytes."""
    prop = b'd' + struct.pack('<III', claimed, 1, 10) + b'x' * 10
    return _fbx([_fbx_record(27, b'N', prop, 1)])


def fbx_nested(depth):
    """`depth` nodes "N", each the only child of the one before."""
    header = 27
    record = 13 + 1
    total = header + depth * (record + 13) + 13
    out = bytearray()
    for i in range(depth):
        end = total - 13 - i * 13
        out += struct.pack('<III', end, 0, 0) + b'\x01N'
    out += b'\0' * (13 * depth)
    return _fbx([bytes(out)])


def fbx_long_take(source, seconds):
    """`source` (a binary FBX) with its take's LocalStop, and every other time property equal to
    it (ReferenceStop, Takes' times), made `seconds` long (the Definitions' template default,
    0, left alone)."""
    at = 0
    while True:
        at = source.index(b'LocalStop', at) + len(b'LocalStop')
        p = at
        for _ in range(3):  # the P record's type, label and flags: three S properties
            if source[p:p + 1] != b'S':
                break
            p += 5 + struct.unpack('<I', source[p + 1:p + 5])[0]
        if source[p:p + 1] == b'L' and struct.unpack('<q', source[p + 1:p + 9])[0] != 0:
            stop = source[p:p + 9]  # the L type byte and the ticks
            return source.replace(stop, b'L' + struct.pack('<q', int(seconds * 46186158000)))
