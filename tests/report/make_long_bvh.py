"""Writes a long BVH for the report's size and load-time test: samples/pitch.bvh's 130 frames
played forwards and backwards (so the loop has no jump) until FRAMES frames.
  make_long_bvh.py IN.bvh OUT.bvh FRAMES"""
import sys


def main(source, target, frames):
    head, motion = open(source).read().split("MOTION", 1)
    lines = [line for line in motion.strip().split("\n") if line.strip()]
    frame_time, poses = lines[1], lines[2:]
    cycle = poses + poses[-2:0:-1]
    with open(target, "w") as out:
        out.write(f"{head}MOTION\nFrames: {frames}\n{frame_time}\n")
        for i in range(frames):
            out.write(cycle[i % len(cycle)] + "\n")


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2], int(sys.argv[3]))
