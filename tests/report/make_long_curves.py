"""Writes two long per-frame curve CSVs (30 fps) for the report's size and load-time test:
  make_long_curves.py FRAMES TALK.csv CURVES.csv
TALK.csv: a mouth that talks 4 s and rests 4 s, eyes that blink every 4 s (LipBlink).
CURVES.csv: three slow sine curves (RetimeCurves)."""
import math
import sys


def main(frames, talk_path, curves_path):
    with open(talk_path, "w") as f:
        f.write("frame,ParamMouthOpenY,ParamEyeLOpen,ParamEyeROpen\n")
        for k in range(frames):
            t = k / 30
            speaking = int(t / 4) % 2 == 0
            mouth = max(0.0, math.sin(t * 9) * math.sin(t * 2.3)) if speaking else 0.0
            eye = 0.0 if k % 120 < 4 else 1.0
            f.write(f"{k},{mouth:.4f},{eye},{eye}\n")
    with open(curves_path, "w") as f:
        f.write("frame,ParamAngleX,ParamAngleY,ParamBodyAngleX\n")
        for k in range(frames):
            t = k / 30
            f.write(f"{k},{30 * math.sin(t):.4f},{10 * math.cos(t * 0.7):.4f},"
                    f"{5 * math.sin(t * 1.3):.4f}\n")


if __name__ == "__main__":
    main(int(sys.argv[1]), sys.argv[2], sys.argv[3])
