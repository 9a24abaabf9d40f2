"""Writes a Mixamo-style binary FBX from scratch (issue 43's acceptance: "rigs with
pre-rotations and pivots as Mixamo's files have them"), with its own small node writer: the
binary layout is public (the 27-byte header "Kaydara FBX Binary  \\0\\x1a\\0" and the version;
node records of end offset, property count, property bytes, name length and name, typed
properties, children closed by a null record; arrays raw or zlib-compressed; the footer).

The rig is Mixamo's: Y up, centimetres (UnitScaleFactor 1), 30 frames a second (TimeMode 6),
"mixamorig:" LimbNodes with PreRotation (RotationActive 1) and translation pivots
(RotationPivot, ScalingPivot, and here also RotationOffset and ScalingOffset), InheritType 1
(RSrs). Beyond Mixamo, to exercise more of the transform chain: PostRotation, RotationOrder
other than XYZ, non-uniform Lcl Scaling, and curves of every kind koma evaluates (cubic with
stored tangents, weighted and not; linear; constant and "constant next").

What the readers that check koma can show is chosen, not hidden:
- Blender 3.4's importer turns PreRotation and PostRotation with the node's RotationOrder and
  applies PostRotation uninverted; the FBX SDK's documented chain, which koma follows, uses
  XYZ for both and Rpost^-1. On this file both readings agree: joints with another
  RotationOrder have pre-rotations about one axis only, and PostRotation is a half turn about
  one axis (its own inverse). --strict writes the general case instead, which
  fbx.pivot_rig_chain (pivot_rig_chain_test.py) checks koma on against the documented chain.
- Blender's bones have no scale at rest: Lcl Scaling is 1 at rest and non-uniform when
  animated (--strict: also at rest). And Blender connects a bone whose head lies on its
  parent's tail (on the parent's Y axis, at its one child's distance) and then ignores its
  location: the joints whose heads move (a translation curve, or a rotation about a pivot off
  the joint) are a little off their parent's axis.
- Blender's and three.js's importers interpolate every curve linearly between its keys, and
  Blender re-keys a joint at the union of its curves' key times: each animated joint has one
  curve keyed on every frame; curves keyed sparsely are linear, or cubic with tangents along
  the segment (a straight line, so the same at every frame whatever the reader), and constant
  curves are keyed on every frame.

  python3 make_pivot_rig.py OUT.fbx [--strict] [--version 7400]
"""
import argparse
import math
import struct
import zlib

KTIME = 46186158000  # FBX ticks a second
FPS = 30
FRAMES = 61  # 0..60: two seconds

# Key attribute flags (FbxAnimCurveDef).
CONSTANT, LINEAR, CUBIC = 0x2, 0x4, 0x8
TANGENT_USER, CONSTANT_NEXT = 0x400, 0x100
WEIGHTED_RIGHT, WEIGHTED_NEXT_LEFT = 0x1000000, 0x2000000


# ---- the node writer --------------------------------------------------------------------

class Node:
    def __init__(self, name, *props, children=None, scope=False):
        self.name = name
        self.props = list(props)
        self.children = list(children or [])
        self.scope = scope  # a null record even without children (assimp expects one: "{}")

    def add(self, *nodes):
        self.children.extend(nodes)
        return self


class Arr:
    """An array property: type 'd', 'f', 'l', 'i' or 'b'."""

    def __init__(self, kind, values, compress=None):
        self.kind, self.values = kind, list(values)
        self.compress = len(self.values) >= 16 if compress is None else compress


class Raw(bytes):
    pass


class I32(int):
    pass


class I16(int):
    pass


class F32(float):
    pass


def encode_prop(p):
    if isinstance(p, bool):
        return b'C' + struct.pack('<?', p)
    if isinstance(p, I16):
        return b'Y' + struct.pack('<h', p)
    if isinstance(p, I32):
        return b'I' + struct.pack('<i', p)
    if isinstance(p, int):
        return b'L' + struct.pack('<q', p)
    if isinstance(p, F32):
        return b'F' + struct.pack('<f', p)
    if isinstance(p, float):
        return b'D' + struct.pack('<d', p)
    if isinstance(p, Raw):
        return b'R' + struct.pack('<I', len(p)) + bytes(p)
    if isinstance(p, str):
        b = p.encode('utf-8')
        return b'S' + struct.pack('<I', len(b)) + b
    if isinstance(p, bytes):
        return b'S' + struct.pack('<I', len(p)) + p
    if isinstance(p, Arr):
        fmt = {'d': 'd', 'f': 'f', 'l': 'q', 'i': 'i', 'b': '?'}[p.kind]
        data = struct.pack('<%d%s' % (len(p.values), fmt), *p.values)
        if p.compress:
            data = zlib.compress(data, 9)
        return p.kind.encode() + struct.pack('<III', len(p.values), int(p.compress),
                                             len(data)) + data
    raise TypeError('property %r' % (p,))


def encode_node(node, offset, wide):
    word = 'Q' if wide else 'I'
    head_bytes = (24 if wide else 12) + 1
    sentinel = b'\0' * (head_bytes)
    props = b''.join(encode_prop(p) for p in node.props)
    name = node.name.encode()
    body_at = offset + head_bytes + len(name) + len(props)
    body = b''
    if node.children or node.scope or not node.props:
        at = body_at
        for child in node.children:
            chunk = encode_node(child, at, wide)
            body += chunk
            at += len(chunk)
        body += sentinel
    end = body_at + len(body)
    return (struct.pack('<' + word * 3, end, len(node.props), len(props)) +
            struct.pack('<B', len(name)) + name + props + body)


def write_fbx(path, nodes, version):
    wide = version >= 7500
    out = bytearray(b'Kaydara FBX Binary  \x00\x1a\x00' + struct.pack('<I', version))
    for node in nodes:
        out += encode_node(node, len(out), wide)
    out += b'\0' * (25 if wide else 13)  # the top level's null record
    # The footer, as the FBX SDK and Blender write it.
    out += bytes([0xfa, 0xbc, 0xab, 0x09, 0xd0, 0xc8, 0xd4, 0x66,
                  0xb1, 0x76, 0xfb, 0x83, 0x1c, 0xf7, 0x26, 0x7e])
    out += b'\0' * 4
    pad = ((len(out) + 15) & ~15) - len(out)
    out += b'\0' * (pad or 16)
    out += struct.pack('<I', version) + b'\0' * 120
    out += bytes([0xf8, 0x5a, 0x8c, 0x6a, 0xde, 0xf5, 0xd9, 0x7e,
                  0xec, 0xe9, 0x0c, 0xe3, 0x75, 0x8f, 0x29, 0x0b])
    with open(path, 'wb') as f:
        f.write(bytes(out))


# ---- FBX scene helpers -------------------------------------------------------------------

def P(name, kind, label, flags, *values):
    return Node('P', name, kind, label, flags, *values)


def p_int(name, v):
    return P(name, 'int', 'Integer', '', I32(v))


def p_enum(name, v):
    return P(name, 'enum', '', '', I32(v))


def p_bool(name, v):
    return P(name, 'bool', '', '', I32(1 if v else 0))


def p_double(name, v):
    return P(name, 'double', 'Number', '', float(v))


def p_vec(name, v, kind='Vector3D', label='Vector', flags=''):
    return P(name, kind, label, flags, float(v[0]), float(v[1]), float(v[2]))


def p_lcl(name, v):
    return P(name, name, '', 'A', float(v[0]), float(v[1]), float(v[2]))


def p_time(name, v):
    return P(name, 'KTime', 'Time', '', int(v))


def obj_name(name, cls):
    return name.encode() + b'\x00\x01' + cls.encode()


def frame_ticks(f):
    return f * KTIME // FPS


# ---- the rig -----------------------------------------------------------------------------

# name, parent, Lcl Translation (cm), RotationOrder, PreRotation, PostRotation,
# RotationPivot, RotationOffset, ScalingPivot, ScalingOffset, Lcl Scaling
def joints(strict):
    half_turn = (0.0, 180.0, 0.0)
    rows = [
        ('Hips', None, (0.0, 98.0, 1.5), 0, (-90.0, 0.0, 12.0), (0, 0, 0),
         (0.0, 3.0, -1.0), (0.5, 0.0, 0.0), (0.0, 2.0, 0.0), (0.0, 0.0, 0.0), (1.0, 1.0, 1.0)),
        ('Spine', 'Hips', (0.0, 9.5, -0.8), 0, (8.0, -4.0, 3.0), (0, 0, 0),
         (0.0, 1.5, 0.0), (0.0, 0.0, 0.0), (0.0, 0.0, 0.0), (0.0, 0.0, 0.0), (1.0, 1.0, 1.0)),
        ('Spine1', 'Spine', (0.0, 11.0, 0.0), 4, (0.0, 0.0, -7.0), (0, 0, 0),
         (0.0, 0.0, 0.0), (0.0, 0.0, 0.0), (0.0, 0.0, 0.0), (0.0, 0.0, 0.0), (1.1, 0.9, 1.0)),
        ('Spine2', 'Spine1', (0.0, 12.5, 0.3), 0, (5.0, 2.0, 0.0), half_turn,
         (0.2, 0.0, 0.4), (0.0, 0.0, 0.0), (0.0, 0.0, 0.0), (0.3, 0.0, 0.0), (1.0, 1.0, 1.0)),
        ('Neck', 'Spine2', (0.0, 14.0, 1.2), 0, (-15.0, 0.0, 0.0), (0, 0, 0),
         (0.0, 0.0, 0.0), (0.0, 0.0, 0.0), (0.0, 0.0, 0.0), (0.0, 0.0, 0.0), (1.0, 1.0, 1.0)),
        ('Head', 'Neck', (0.0, 9.0, 2.0), 5, (0.0, 0.0, 0.0), (0, 0, 0),
         (0.0, 4.0, 2.0), (0.0, 0.0, 0.0), (0.0, 4.0, 0.0), (0.0, 0.0, 0.0), (0.95, 1.05, 1.0)),
        ('LeftShoulder', 'Spine2', (6.0, 12.0, -0.5), 0, (90.0, 80.0, 0.0), (0, 0, 0),
         (0.0, 0.0, 0.0), (0.0, 0.0, 0.0), (0.0, 0.0, 0.0), (0.0, 0.0, 0.0), (1.0, 1.0, 1.0)),
        ('LeftArm', 'LeftShoulder', (0.0, 13.0, 0.0), 2, (0.0, 12.0, 0.0), (0, 0, 0),
         (0.0, 0.0, 0.0), (0.0, 0.0, 0.0), (0.0, 0.0, 0.0), (0.0, 0.0, 0.0), (1.0, 1.0, 1.0)),
        ('LeftForeArm', 'LeftArm', (0.0, 27.0, 0.0), 0, (0.0, 0.0, 0.0), half_turn,
         (0.0, 1.0, 0.0), (0.0, 0.0, 0.5), (0.0, 0.0, 0.0), (0.0, 0.0, 0.0), (1.0, 1.2, 1.0)),
        ('LeftHand', 'LeftForeArm', (0.0, 25.0, 0.0), 0, (3.0, -6.0, 9.0), (0, 0, 0),
         (0.0, 0.0, 0.0), (0.0, 0.0, 0.0), (0.0, 0.0, 0.0), (0.0, 0.0, 0.0), (1.0, 1.0, 1.0)),
        ('RightShoulder', 'Spine2', (-6.0, 12.0, -0.5), 0, (90.0, -80.0, 0.0), (0, 0, 0),
         (0.0, 0.0, 0.0), (0.0, 0.0, 0.0), (0.0, 0.0, 0.0), (0.0, 0.0, 0.0), (1.0, 1.0, 1.0)),
        ('RightArm', 'RightShoulder', (0.0, 13.0, 0.0), 3, (0.0, -12.0, 0.0), (0, 0, 0),
         (0.0, 0.0, 0.0), (0.0, 0.0, 0.0), (0.0, 0.0, 0.0), (0.0, 0.0, 0.0), (1.0, 1.0, 1.0)),
        ('RightForeArm', 'RightArm', (0.6, 27.0, 0.0), 0, (0.0, 0.0, 0.0), (0, 0, 0),
         (0.0, 2.0, 0.0), (0.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.5, 0.0), (1.0, 1.0, 1.0)),
        ('RightHand', 'RightForeArm', (0.0, 25.0, 0.0), 0, (-3.0, 6.0, -9.0), (0, 0, 0),
         (0.0, 0.0, 0.0), (0.0, 0.0, 0.0), (0.0, 0.0, 0.0), (0.0, 0.0, 0.0), (1.0, 1.0, 1.0)),
        ('LeftUpLeg', 'Hips', (8.5, -6.0, 0.2), 0, (0.0, 0.0, 180.0), (0, 0, 0),
         (0.0, 0.0, 0.0), (0.0, 0.0, 0.0), (0.0, 0.0, 0.0), (0.0, 0.0, 0.0), (1.0, 1.0, 1.0)),
        ('LeftLeg', 'LeftUpLeg', (0.0, 42.0, 0.0), 1, (0.0, 0.0, 0.0), (0, 0, 0),
         (0.0, 0.0, 0.0), (0.0, 0.0, 0.0), (0.0, 0.0, 0.0), (0.0, 0.0, 0.0), (1.0, 1.0, 1.0)),
        ('LeftFoot', 'LeftLeg', (0.0, 41.0, 0.0), 0, (-55.0, 3.0, 0.0), (0, 0, 0),
         (0.0, 0.0, 0.0), (0.0, 0.0, 0.0), (0.0, 0.0, 0.0), (0.0, 0.0, 0.0), (1.0, 1.0, 1.0)),
        ('RightUpLeg', 'Hips', (-8.5, -6.0, 0.2), 0, (0.0, 0.0, 180.0), (0, 0, 0),
         (0.0, 0.0, 0.0), (0.0, 0.0, 0.0), (0.0, 0.0, 0.0), (0.0, 0.0, 0.0), (1.0, 1.0, 1.0)),
        ('RightLeg', 'RightUpLeg', (0.0, 42.0, 0.7), 0, (0.0, 0.0, 0.0), (0, 0, 0),
         (0.0, 0.5, 0.0), (0.0, 0.0, 0.0), (0.0, 0.0, 0.0), (0.0, 0.0, 0.0), (1.0, 1.0, 1.0)),
        ('RightFoot', 'RightLeg', (0.0, 41.0, 0.0), 0, (-55.0, -3.0, 0.0), (0, 0, 0),
         (0.0, 0.0, 0.0), (0.0, 0.0, 0.0), (0.0, 0.0, 0.0), (0.0, 0.0, 0.0), (1.0, 1.0, 1.0)),
    ]
    if not strict:
        # Blender's bones have no scale at rest (it keeps the animated scale only).
        rows = [r[:10] + ((1.0, 1.0, 1.0),) for r in rows]
    if strict:
        # The general case: pre-rotations about several axes on joints of another order, and
        # post-rotations that are not their own inverse.
        rows = [list(r) for r in rows]
        for r in rows:
            if r[3] != 0:
                r[4] = (14.0, -9.0, 21.0)
            if tuple(r[5]) == half_turn:
                r[5] = (10.0, 25.0, -15.0)
        rows[4][5] = (-20.0, 5.0, 30.0)  # Neck
        rows = [tuple(r) for r in rows]
    return rows


def rest_rotation(name):
    """Lcl Rotation at rest: the legs hang from the hips (as Mixamo's do, a half turn)."""
    return (0.0, 0.0, 180.0) if name.endswith('UpLeg') else (0.0, 0.0, 0.0)


def curve(kind, frames, values, slopes=None, weights=None):
    """An AnimationCurve's data: key times and values, and one attribute per key (flags,
    right slope, next left slope, packed weights)."""
    return {'kind': kind, 'frames': frames, 'values': values, 'slopes': slopes,
            'weights': weights}


def dense(fn):
    return list(range(FRAMES)), [fn(f) for f in range(FRAMES)]


def animation():
    """Curves per (joint, 'T'|'R'|'S', axis). Each animated joint has a curve keyed on every
    frame (see the module's comment)."""
    anim = {}
    two_pi = 2 * math.pi

    def wave(amp, period, phase=0.0, base=0.0):
        return lambda f: base + amp * math.sin(two_pi * f / period + phase)

    # Cubic, keyed on every frame, with the derivative's slope (value per second) as tangents,
    # weighted on some keys.
    def cubic_dense(fn, d_fn, weighted=False):
        frames, values = dense(fn)
        slopes = [(d_fn(f) * FPS, d_fn(f) * FPS) for f in frames]
        weights = [(0.25, 0.4) if weighted and f % 3 == 0 else None for f in frames]
        return curve('cubic', frames, values, slopes, weights)

    def dwave(amp, period, phase=0.0):
        return lambda f: amp * two_pi / period * math.cos(two_pi * f / period + phase)

    # Linear, keyed sparsely.
    def linear_sparse(points):
        frames = [p[0] for p in points]
        return curve('linear', frames, [p[1] for p in points])

    # Cubic keyed sparsely, tangents along each segment (a straight line), some weighted.
    def cubic_line(points, weighted=False):
        frames = [p[0] for p in points]
        values = [p[1] for p in points]
        slopes, weights = [], []
        for k in range(len(points)):
            if k + 1 < len(points):
                chord = (values[k + 1] - values[k]) / ((frames[k + 1] - frames[k]) / FPS)
            else:
                chord = 0.0
            slopes.append((chord, chord))
            weights.append((0.2, 0.45) if weighted and k % 2 == 0 else None)
        return curve('cubic', frames, values, slopes, weights)

    # Constant, keyed on every frame: holds of a few frames, steps between.
    def constant_dense(levels, run, nxt=False):
        frames = list(range(FRAMES))
        values = [levels[(f // run) % len(levels)] for f in frames]
        return curve('constant_next' if nxt else 'constant', frames, values)

    a = anim
    a['Hips', 'T', 0] = cubic_dense(wave(6.0, 40), dwave(6.0, 40), weighted=True)
    a['Hips', 'T', 1] = linear_sparse([(0, 98.0), (15, 92.0), (30, 99.0), (45, 93.5), (60, 98.0)])
    a['Hips', 'T', 2] = cubic_line([(0, 1.5), (20, 30.0), (40, 55.0), (60, 70.0)], weighted=True)
    a['Hips', 'R', 1] = cubic_dense(wave(25.0, 60), dwave(25.0, 60))
    a['Hips', 'R', 2] = linear_sparse([(0, 0.0), (30, 8.0), (60, -4.0)])
    a['Spine', 'R', 0] = cubic_dense(wave(10.0, 30, 0.5, 4.0), dwave(10.0, 30, 0.5))
    a['Spine', 'R', 2] = constant_dense([0.0, 6.0, -4.0], 4)
    a['Spine1', 'R', 0] = cubic_dense(wave(8.0, 24, 1.0), dwave(8.0, 24, 1.0), weighted=True)
    a['Spine1', 'R', 1] = linear_sparse([(0, -10.0), (25, 15.0), (60, 0.0)])
    a['Spine1', 'R', 2] = cubic_line([(0, 0.0), (10, 12.0), (35, -8.0), (60, 5.0)])
    a['Spine1', 'S', 1] = linear_sparse([(0, 0.9), (30, 1.15), (60, 0.9)])
    a['Spine2', 'R', 1] = cubic_dense(wave(15.0, 45), dwave(15.0, 45))
    a['Neck', 'R', 0] = constant_dense([-5.0, 5.0], 6, nxt=True)
    a['Neck', 'R', 1] = linear_sparse([(0, 0.0), (20, 20.0), (40, -20.0), (60, 0.0)])
    a['Head', 'R', 0] = cubic_dense(wave(12.0, 20), dwave(12.0, 20))
    a['Head', 'R', 1] = cubic_line([(0, 0.0), (30, 35.0), (60, 0.0)], weighted=True)
    a['Head', 'R', 2] = linear_sparse([(0, 5.0), (60, -5.0)])
    a['Head', 'S', 0] = constant_dense([0.95, 1.1], 10)
    a['LeftForeArm', 'S', 1] = linear_sparse([(0, 1.2), (20, 0.8), (60, 1.1)])
    a['LeftShoulder', 'R', 2] = cubic_dense(wave(6.0, 30), dwave(6.0, 30))
    a['LeftArm', 'R', 0] = cubic_dense(wave(40.0, 30, 0.2, -20.0), dwave(40.0, 30, 0.2))
    a['LeftArm', 'R', 1] = linear_sparse([(0, 10.0), (30, -25.0), (60, 10.0)])
    a['LeftArm', 'R', 2] = cubic_line([(0, 30.0), (15, 50.0), (45, 10.0), (60, 30.0)])
    a['LeftForeArm', 'R', 2] = cubic_dense(wave(35.0, 30, 1.0, 40.0), dwave(35.0, 30, 1.0))
    a['LeftForeArm', 'R', 0] = constant_dense([0.0, 15.0, 30.0], 5)
    a['LeftHand', 'R', 0] = cubic_dense(wave(20.0, 15), dwave(20.0, 15))
    a['RightArm', 'R', 0] = cubic_dense(wave(40.0, 30, 2.0, -20.0), dwave(40.0, 30, 2.0))
    a['RightArm', 'R', 2] = linear_sparse([(0, -30.0), (30, -60.0), (60, -30.0)])
    a['RightForeArm', 'R', 2] = cubic_dense(wave(-35.0, 30, 2.5, -40.0), dwave(-35.0, 30, 2.5))
    a['RightForeArm', 'T', 1] = linear_sparse([(0, 27.0), (30, 30.0), (60, 27.0)])
    a['RightHand', 'R', 2] = cubic_dense(wave(15.0, 20), dwave(15.0, 20))
    a['LeftUpLeg', 'R', 0] = cubic_dense(wave(30.0, 60), dwave(30.0, 60))
    a['LeftUpLeg', 'R', 2] = linear_sparse([(0, 180.0), (30, 170.0), (60, 180.0)])
    a['LeftLeg', 'R', 0] = cubic_dense(wave(25.0, 60, 1.2, 30.0), dwave(25.0, 60, 1.2))
    a['LeftLeg', 'R', 1] = cubic_line([(0, 0.0), (30, 20.0), (60, 0.0)])
    a['LeftFoot', 'R', 0] = cubic_dense(wave(10.0, 30), dwave(10.0, 30))
    a['RightUpLeg', 'R', 0] = cubic_dense(wave(-30.0, 60), dwave(-30.0, 60))
    a['RightUpLeg', 'S', 2] = linear_sparse([(0, 1.0), (30, 1.25), (60, 1.0)])
    a['RightLeg', 'R', 0] = cubic_dense(wave(25.0, 60, 4.3, 30.0), dwave(25.0, 60, 4.3))
    a['RightFoot', 'R', 0] = constant_dense([0.0, -12.0, 8.0], 3)
    a['RightFoot', 'R', 1] = linear_sparse([(0, 0.0), (60, 15.0)])
    return anim


def pack_weights(w):
    right, next_left = w
    bits = int(round(right * 10000)) | (int(round(next_left * 10000)) << 16)
    return struct.unpack('<f', struct.pack('<I', bits))[0]


def curve_node(cid, c, default):
    times = [frame_ticks(f) for f in c['frames']]
    flags, data, counts = [], [], []
    for k in range(len(times)):
        if c['kind'] == 'linear':
            bits, attr = LINEAR, [0.0, 0.0, 0.0, 0.0]
        elif c['kind'] in ('constant', 'constant_next'):
            bits = CONSTANT | (CONSTANT_NEXT if c['kind'] == 'constant_next' else 0)
            attr = [0.0, 0.0, 0.0, 0.0]
        else:
            bits = CUBIC | TANGENT_USER
            right, next_left = c['slopes'][k]
            w = c['weights'][k]
            packed = pack_weights((1 / 3, 1 / 3))
            if w is not None:
                bits |= WEIGHTED_RIGHT | WEIGHTED_NEXT_LEFT
                packed = pack_weights(w)
            attr = [right, next_left, packed, 0.0]
        # One attribute per run of equal ones, as the SDK writes them.
        if flags and flags[-1] == bits and data[-4:] == attr:
            counts[-1] += 1
        else:
            flags.append(bits)
            data.extend(attr)
            counts.append(1)
    return Node('AnimationCurve', cid, obj_name('', 'AnimCurve'), '').add(
        Node('Default', float(default)),
        Node('KeyVer', I32(4009)),
        Node('KeyTime', Arr('l', times)),
        Node('KeyValueFloat', Arr('f', c['values'])),
        Node('KeyAttrFlags', Arr('i', flags)),
        Node('KeyAttrDataFloat', Arr('f', data)),
        Node('KeyAttrRefCount', Arr('i', counts)))


def build(strict, version=7400):
    ids = iter(range(1000000000, 2000000000, 7919))
    rig = joints(strict)
    anim = animation()
    stop = frame_ticks(FRAMES - 1)

    objects = Node('Objects')
    connections = Node('Connections')
    model_ids = {}
    counts = {'Model': 0, 'NodeAttribute': 0, 'AnimationCurveNode': 0, 'AnimationCurve': 0}
    for (name, parent, t, order, pre, post, rp, roff, sp, soff, s) in rig:
        full = 'mixamorig:' + name
        mid, aid = next(ids), next(ids)
        model_ids[name] = mid
        objects.add(Node('NodeAttribute', aid, obj_name(full, 'NodeAttribute'), 'LimbNode').add(
            Node('Properties70').add(p_double('Size', 10.0)),
            Node('TypeFlags', 'Skeleton')))
        props = Node('Properties70').add(
            p_enum('RotationOrder', order),
            p_vec('RotationOffset', roff),
            p_vec('RotationPivot', rp),
            p_vec('ScalingOffset', soff),
            p_vec('ScalingPivot', sp),
            p_vec('PreRotation', pre),
            p_vec('PostRotation', post),
            p_bool('RotationActive', True),
            p_enum('InheritType', 1),
            p_vec('ScalingMax', (0, 0, 0)),
            p_int('DefaultAttributeIndex', 0),
            p_lcl('Lcl Translation', t),
            p_lcl('Lcl Rotation', rest_rotation(name)),
            p_lcl('Lcl Scaling', s),
            P('MaxHandle', 'int', 'Integer', 'UH', I32(len(model_ids))))
        objects.add(Node('Model', mid, obj_name(full, 'Model'), 'LimbNode').add(
            Node('Version', I32(232)), props,
            Node('Shading', True), Node('Culling', 'CullingOff')))
        connections.add(Node('C', 'OO', aid, mid))
        connections.add(Node('C', 'OO', mid, model_ids[parent] if parent else 0))
        counts['Model'] += 1
        counts['NodeAttribute'] += 1

    stack_id, layer_id = next(ids), next(ids)
    objects.add(Node('AnimationStack', stack_id, obj_name('mixamo.com', 'AnimStack'), '').add(
        Node('Properties70').add(p_time('LocalStart', 0), p_time('LocalStop', stop),
                                 p_time('ReferenceStart', 0), p_time('ReferenceStop', stop))))
    objects.add(Node('AnimationLayer', layer_id, obj_name('BaseLayer', 'AnimLayer'), '',
                     scope=True))
    connections.add(Node('C', 'OO', layer_id, stack_id))
    rest = {row[0]: row for row in rig}
    groups = {}
    for (joint, channel, axis), c in anim.items():
        groups.setdefault((joint, channel), {})[axis] = c
    for (joint, channel), axes in sorted(groups.items()):
        row = rest[joint]
        rest_value = {'T': row[2], 'R': rest_rotation(joint), 'S': row[10]}[channel]
        prop = {'T': 'Lcl Translation', 'R': 'Lcl Rotation', 'S': 'Lcl Scaling'}[channel]
        cn = next(ids)
        objects.add(Node('AnimationCurveNode', cn, obj_name(channel, 'AnimCurveNode'), '').add(
            Node('Properties70').add(*[P('d|' + 'XYZ'[a], 'Number', '', 'A', float(rest_value[a]))
                                       for a in range(3)])))
        connections.add(Node('C', 'OO', cn, layer_id))
        connections.add(Node('C', 'OP', cn, model_ids[joint], prop))
        counts['AnimationCurveNode'] += 1
        for a in sorted(axes):
            cid = next(ids)
            objects.add(curve_node(cid, axes[a], rest_value[a]))
            connections.add(Node('C', 'OP', cid, cn, 'd|' + 'XYZ'[a]))
            counts['AnimationCurve'] += 1

    header = Node('FBXHeaderExtension').add(
        Node('FBXHeaderVersion', I32(1003)),
        Node('FBXVersion', I32(version)),
        Node('EncryptionType', I32(0)),
        Node('Creator', 'koma tests/e2e/fbx/make_pivot_rig.py'),
        Node('SceneInfo', obj_name('GlobalInfo', 'SceneInfo'), 'UserData').add(
            Node('Type', 'UserData'), Node('Version', I32(100))))
    settings = Node('GlobalSettings').add(
        Node('Version', I32(1000)),
        Node('Properties70').add(
            p_int('UpAxis', 1), p_int('UpAxisSign', 1),
            p_int('FrontAxis', 2), p_int('FrontAxisSign', 1),
            p_int('CoordAxis', 0), p_int('CoordAxisSign', 1),
            p_int('OriginalUpAxis', 1), p_int('OriginalUpAxisSign', 1),
            p_double('UnitScaleFactor', 1.0), p_double('OriginalUnitScaleFactor', 1.0),
            P('AmbientColor', 'ColorRGB', 'Color', '', 0.0, 0.0, 0.0),
            P('DefaultCamera', 'KString', '', '', 'Producer Perspective'),
            p_enum('TimeMode', 6),
            p_enum('TimeProtocol', 2),
            p_enum('SnapOnFrameMode', 0),
            p_time('TimeSpanStart', 0), p_time('TimeSpanStop', stop),
            p_double('CustomFrameRate', -1.0)))
    documents = Node('Documents').add(
        Node('Count', I32(1)),
        Node('Document', next(ids), '', 'Scene').add(
            Node('Properties70').add(P('SourceObject', 'object', '', ''),
                                     P('ActiveAnimStackName', 'KString', '', '', 'mixamo.com')),
            Node('RootNode', 0)))
    definitions = Node('Definitions').add(Node('Version', I32(100)),
                                          Node('Count', I32(sum(counts.values()) + 1)))
    definitions.add(Node('ObjectType', 'GlobalSettings').add(Node('Count', I32(1))))
    template = {
        'Model': ('FbxNode', [p_enum('RotationOrder', 0), p_bool('RotationActive', False),
                              p_enum('InheritType', 0), p_vec('ScalingMax', (0, 0, 0)),
                              p_lcl('Lcl Translation', (0, 0, 0)),
                              p_lcl('Lcl Rotation', (0, 0, 0)),
                              p_lcl('Lcl Scaling', (1, 1, 1))]),
        'NodeAttribute': ('FbxSkeleton', [p_double('Size', 100.0)]),
    }
    for kind in ('Model', 'NodeAttribute', 'AnimationCurveNode', 'AnimationCurve'):
        t = Node('ObjectType', kind).add(Node('Count', I32(counts[kind])))
        if kind in template:
            cls, props = template[kind]
            t.add(Node('PropertyTemplate', cls).add(Node('Properties70').add(*props)))
        definitions.add(t)
    takes = Node('Takes').add(
        Node('Current', 'mixamo.com'),
        Node('Take', 'mixamo.com').add(Node('FileName', 'mixamo.com.tak'),
                                       Node('LocalTime', 0, stop),
                                       Node('ReferenceTime', 0, stop)))
    return [header, Node('FileId', Raw(bytes(range(16)))),
            Node('CreationTime', '1970-01-01 10:00:00:000'),
            Node('Creator', 'koma tests/e2e/fbx/make_pivot_rig.py'),
            settings, documents, Node('References'), definitions, objects, connections, takes]


def main():
    parser = argparse.ArgumentParser(description=__doc__.split('\n\n')[0])
    parser.add_argument('out')
    parser.add_argument('--strict', action='store_true',
                        help='pre-rotations about several axes on non-XYZ joints, and '
                             'post-rotations that are not their own inverse')
    parser.add_argument('--version', type=int, default=7400)
    args = parser.parse_args()
    write_fbx(args.out, build(args.strict, args.version), args.version)


if __name__ == '__main__':
    main()
