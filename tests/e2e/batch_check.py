"""Checks a `koma batch` run against the single-file command, clip by clip.

Usage: batch_check.py CLIENT SERVER RPC SUMMARY_JSON STDERR_TXT BAD_LIST CLIP_ROOT -- OPTIONS...
For every clip in the summary: a clip whose path (below CLIP_ROOT) is listed in BAD_LIST must
be "failed" with a code and an error naming it, and that error must be on the batch's stderr;
every other clip must be "ok", and its output (and timing sheet and report, when the summary
names them) must equal, byte for byte, what `koma RPC IN -o OUT [--timing SHEET] [--report
REPORT] OPTIONS...` writes.
The single commands run 4 at a time. Prints a line of counts; exits 1 at the first mismatch.
"""
import concurrent.futures
import json
import os
import subprocess
import sys
import tempfile


def fail(message):
    print("FAIL: " + message, file=sys.stderr)
    sys.exit(1)


def main():
    client, server, rpc, summary_path, stderr_path, bad_list, clip_root = sys.argv[1:8]
    assert sys.argv[8] == "--"
    options = sys.argv[9:]
    summary = json.load(open(summary_path))
    stderr_text = open(stderr_path).read()
    bad = {line.strip() for line in open(bad_list) if line.strip()}
    files = summary["files"]
    if len(files) != summary["total"]:
        fail(f"summary lists {len(files)} files, total {summary['total']}")
    inputs = [f["input"] for f in files]
    if len(set(inputs)) != len(inputs):
        fail("an input is listed twice in the summary")
    failed = [f for f in files if f["status"] == "failed"]
    good = [f for f in files if os.path.relpath(f["input"], clip_root) not in bad]
    for f in files:
        relative = os.path.relpath(f["input"], clip_root)
        if relative in bad:
            if f["status"] != "failed" or not f.get("code") or f["input"] not in f.get("error", ""):
                fail(f"bad clip {relative}: {f}")
            if "koma: " + f["error"] not in stderr_text:
                fail(f"bad clip {relative}: its error is not on stderr: {f['error']}")
        elif f["status"] != "ok":
            fail(f"good clip {relative}: {f}")
    if summary["failed"] != len(failed) or summary["ok"] != len(good):
        fail(f"summary counts {summary['ok']} ok / {summary['failed']} failed, want "
             f"{len(good)} / {len(failed)}")

    reference = tempfile.mkdtemp(prefix="batch_ref_")

    def compare(index_and_file):
        index, f = index_and_file
        out = os.path.join(reference, f"{index}_" + os.path.basename(f["output"]))
        command = [client, rpc, f["input"], "-o", out, "--server", server, "--deadline", "60"]
        if "timing" in f:
            command += ["--timing", out + ".timing.csv"]
        if "report" in f:
            command += ["--report", out + ".report.html"]
        done = subprocess.run(command + options, stdout=subprocess.DEVNULL,
                              stderr=subprocess.PIPE, text=True, timeout=60)
        if done.returncode != 0:
            return f"single command failed on {f['input']}: {done.stderr}"
        pairs = [(out, f["output"])]
        if "timing" in f:
            pairs.append((out + ".timing.csv", f["timing"]))
        if "report" in f:
            pairs.append((out + ".report.html", f["report"]))
        for want_path, got_path in pairs:
            with open(want_path, "rb") as want, open(got_path, "rb") as got:
                if want.read() != got.read():
                    return f"{got_path} differs from the single command's {want_path}"
            os.remove(want_path)
        return None

    with concurrent.futures.ThreadPoolExecutor(max_workers=4) as pool:
        for problem in pool.map(compare, enumerate(good)):
            if problem:
                fail(problem)
    timing = sum(1 for f in good if "timing" in f)
    reports = sum(1 for f in good if "report" in f)
    print(f"{rpc}: {len(good)} outputs, {timing} timing sheets and {reports} reports equal the "
          "single command's; "
          f"{len(failed)} bad clips listed with their errors")


main()
