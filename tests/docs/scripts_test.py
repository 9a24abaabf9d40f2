"""Runs every `./scripts/...` command of the docs' sh code blocks, as a newcomer would.

Usage: scripts_test.py REPO_ROOT BUILD_DIR [MARKDOWN ...]

MARKDOWN files default to README.md (paths relative to REPO_ROOT). Each line of a ```sh block
that starts with `./scripts/` is either
- a line of .ci/run, which CI runs on a fresh clone after every session (the README's test
  command: running it here would run this test again), checked to be there word for word; or
- run as written from REPO_ROOT through bash, with KOMA_BUILD_DIR=BUILD_DIR (the build this
  test belongs to: the scripts' build step then finds nothing to do), KOMA_OUT_DIR in a
  scratch folder and KOMA_NO_PTH=1 (the user's Python site is left alone), bounded by COMMAND_TIMEOUT_S. It must exit 0; for run-sample.sh every file it
  says it writes must exist and be non-empty, and the server must have stopped cleanly.
Fails (exit 1) on any command that fails, or when no command was found.

Run with Debian's /usr/bin/python3; standard library only.
"""
import os
import shutil
import subprocess
import sys
import tempfile

from code_blocks import SHELL, block_lines, verdict

COMMAND_TIMEOUT_S = 600
# What run-sample.sh writes into its out folder (README "Two commands").
RUN_SAMPLE_OUTPUTS = [
    "pitch_anime.bvh", "pitch_timing.csv", "pitch_report.html",
    "mocap_120fps_anime.bvh", "mocap_120fps_timing.csv", "mocap_120fps_report.html",
    "arm_head_anime.motion3.json", "arm_head_drawings.csv", "arm_head_report.html",
    "talk_blink_anime.motion3.json", "talk_blink_report.html", "server.log", "build.log",
]


def script_commands(markdown_path):
    """(line number, command without its comment) of `./scripts/` lines in sh blocks."""
    return [(number, line.strip().partition("#")[0].strip())
            for number, line in block_lines(markdown_path, SHELL)
            if line.strip().startswith("./scripts/")]


def ci_lines(root):
    with open(os.path.join(root, ".ci", "run"), encoding="utf-8") as f:
        return {line.strip() for line in f if line.strip() and not line.startswith("#")}


def check_run_sample(out, output, problems, where):
    for name in RUN_SAMPLE_OUTPUTS:
        path = os.path.join(out, name)
        if not os.path.isfile(path) or os.path.getsize(path) == 0:
            problems.append(f"{where}: run-sample.sh did not write {name}")
    for text in ("koma_server is SERVING", "koma_server stopped cleanly",
                 "Before/after reports"):
        if text not in output:
            problems.append(f"{where}: run-sample.sh did not print {text!r}")


def main():
    root, build = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2])
    pages = sys.argv[3:] or ["README.md"]
    in_ci = ci_lines(root)
    problems, ran, by_ci = [], 0, 0
    scratch = tempfile.mkdtemp(prefix="koma-scripts-test-")
    try:
        for page in pages:
            for number, command in script_commands(os.path.join(root, page)):
                where = f"{page}:{number}: {command}"
                if command in in_ci:
                    by_ci += 1
                    print(f"{where}: run by .ci/run (CI)")
                    continue
                out = os.path.join(scratch, f"out{ran}")
                # KOMA_NO_PTH: the build step leaves the user's Python site alone (a test
                # must not repoint koma.pth at whatever build folder it runs in).
                env = dict(os.environ, KOMA_BUILD_DIR=build, KOMA_OUT_DIR=out, KOMA_NO_PTH="1")
                try:
                    result = subprocess.run(["bash", "-o", "pipefail", "-c", command], cwd=root,
                                            env=env, stdout=subprocess.PIPE,
                                            stderr=subprocess.STDOUT, text=True,
                                            timeout=COMMAND_TIMEOUT_S)
                except subprocess.TimeoutExpired:
                    problems.append(f"{where}: still running after {COMMAND_TIMEOUT_S} s")
                    continue
                ran += 1
                print(f"{where}: exit {result.returncode}")
                if result.returncode != 0:
                    problems.append(f"{where}: exit {result.returncode}\n{result.stdout[-3000:]}")
                    continue
                if command.startswith("./scripts/run-sample.sh"):
                    check_run_sample(out, result.stdout, problems, where)
    finally:
        shutil.rmtree(scratch, ignore_errors=True)
    if ran + by_ci == 0:
        problems.append("no ./scripts/ command found")
    return verdict(problems, f"scripts OK: {ran} run here, {by_ci} run by CI")


if __name__ == "__main__":
    sys.exit(main())
