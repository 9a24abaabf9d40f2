#!/usr/bin/env python3
"""Writes the real-take clips of issue 28 from a real BVH (tests/testdata/bvh_test1.bvh):

  tpose.bvh      a T-pose frame (every rotation 0, standing where frame 0 stands) prepended
  two_takes.bvh  frames 0-44, then the whole take backwards and 80 units along x (a jump)
  glitch.bvh     frame 37 replaced by a T-pose
  long.bvh       the take forwards and backwards (no jump at the turns) for 1200 frames
  take_60.bvh, take_120.bvh, long_120.bvh
                 the take and the long take resampled to 60 and 120 fps (linear in every
                 channel, rotations the short way round), as a suit at that rate records

Usage: make_real_takes.py IN.bvh OUT_DIR
"""
import sys


def read(path):
    text = open(path, encoding="utf-8").read().replace("\r\n", "\n")
    head, motion = text.split("\nMOTION\n")
    lines = motion.strip("\n").split("\n")
    frame_time = lines[1]
    frames = [line.split() for line in lines[2:] if line.strip()]
    rotations, x_position, column = [], None, 0
    for line in head.split("\n"):
        words = line.split()
        if words and words[0] == "CHANNELS":
            for name in words[2:]:
                if name.endswith("rotation"):
                    rotations.append(column)
                elif name == "Xposition" and x_position is None:
                    x_position = column
                column += 1
    return head, frame_time, frames, rotations, x_position


def write(path, head, frame_time, frames):
    with open(path, "w", encoding="utf-8") as out:
        out.write(head + "\nMOTION\n")
        out.write(f"Frames: {len(frames)}\n{frame_time}\n")
        for frame in frames:
            out.write(" ".join(frame) + "\n")


def main(source, folder):
    head, frame_time, frames, rotations, x_position = read(source)

    def t_pose(frame):
        pose = list(frame)
        for c in rotations:
            pose[c] = "0"
        return pose

    def moved(frame, dx):
        out = list(frame)
        out[x_position] = repr(float(out[x_position]) + dx)
        return out

    write(f"{folder}/tpose.bvh", head, frame_time, [t_pose(frames[0])] + frames)
    write(f"{folder}/two_takes.bvh", head, frame_time,
          frames[:45] + [moved(f, 80.0) for f in reversed(frames)])
    glitch = list(frames)
    glitch[37] = t_pose(frames[37])
    write(f"{folder}/glitch.bvh", head, frame_time, glitch)
    long_take, forwards = list(frames), False
    while len(long_take) < 1200:
        long_take += frames[1:] if forwards else list(reversed(frames))[1:]
        forwards = not forwards
    write(f"{folder}/long.bvh", head, frame_time, long_take[:1200])
    rotation_set = set(rotations)
    source_fps = round(1 / float(frame_time.split(":")[1]))
    for fps in (60, 120):
        name = f"Frame Time: {1 / fps:.7f}"
        write(f"{folder}/take_{fps}.bvh", head, name,
              resampled(frames, rotation_set, source_fps, fps))
    write(f"{folder}/long_120.bvh", head, f"Frame Time: {1 / 120:.7f}",
          resampled(long_take[:1200], rotation_set, source_fps, 120))


def resampled(frames, rotations, source_fps, fps):
    """The frames at `fps`, linear in every channel (a rotation the short way round)."""
    count = (len(frames) - 1) * fps // source_fps + 1
    out = []
    for i in range(count):
        at = i * source_fps / fps
        a = min(int(at), len(frames) - 1)
        b = min(a + 1, len(frames) - 1)
        u = at - a
        row = []
        for c, (x, y) in enumerate(zip(frames[a], frames[b])):
            x, y = float(x), float(y)
            d = y - x
            if c in rotations:
                d = (d + 180.0) % 360.0 - 180.0
            row.append(f"{x + u * d:.6f}")
        out.append(row)
    return out


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2])
