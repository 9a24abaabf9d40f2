"""Checks the N tasks of a sharded `koma batch` against one unsharded run of the same batch.

Usage: batch_shard_check.py N SINGLE_SUMMARY SINGLE_OUT SHARD_SUMMARY_PATTERN SHARDED_OUT
  SHARD_SUMMARY_PATTERN holds {k} for the task's index (out/sum.{k}-of-8.json).
Checks that:
- each task's summary names its shard, and lists exactly the clips whose shard is its own by an
  independent implementation of koma's rule (FNV-1a 64 of the output path below OUTDIR, then
  SplitMix64's finalizer, mod N), every one "ok" or "up_to_date";
- together the tasks list every clip of the single run once (a partition);
- SHARDED_OUT holds the same files as SINGLE_OUT, byte for byte, except the manifests (one per
  task, .koma-batch.K-of-N.json, there; .koma-batch.json in SINGLE_OUT) and the tasks'
  summaries when they are written into SHARDED_OUT.
Prints a line of counts; exits 1 with the first mismatch.
"""
import json
import os
import sys

MASK = (1 << 64) - 1


def shard_of(relative, count):
    h = 1469598103934665603
    for byte in relative.encode():
        h = ((h ^ byte) * 1099511628211) & MASK
    h = ((h ^ (h >> 30)) * 0xBF58476D1CE4E5B9) & MASK
    h = ((h ^ (h >> 27)) * 0x94D049BB133111EB) & MASK
    return (h ^ (h >> 31)) % count


def fail(message):
    print("FAIL: " + message, file=sys.stderr)
    sys.exit(1)


def relative_outputs(summary):
    out_dir = summary["out_dir"].rstrip("/") + "/"
    names = []
    for f in summary["files"]:
        if not f["output"].startswith(out_dir):
            fail("%s is not below %s" % (f["output"], out_dir))
        names.append(f["output"][len(out_dir):])
    return names


def tree(root):
    files = {}
    for folder, _, names in os.walk(root):
        for name in names:
            path = os.path.join(folder, name)
            files[os.path.relpath(path, root)] = open(path, "rb").read()
    return files


def main():
    count = int(sys.argv[1])
    single_summary, single_out, pattern, sharded_out = sys.argv[2:6]
    single = json.load(open(single_summary))
    everything = relative_outputs(single)
    seen = {}
    for k in range(count):
        summary = json.load(open(pattern.format(k=k)))
        shard = summary.get("shard")
        if count > 1 and shard != {"index": k, "count": count, "batch_total": len(everything)}:
            fail("task %d's summary names shard %r" % (k, shard))
        names = relative_outputs(summary)
        for name, f in zip(names, summary["files"]):
            if f["status"] not in ("ok", "up_to_date"):
                fail("task %d: %s is %s: %s" % (k, name, f["status"], f.get("error")))
            if name in seen:
                fail("%s is in tasks %d and %d" % (name, seen[name], k))
            if shard_of(name, count) != k:
                fail("%s is in task %d; the rule puts it in %d" % (name, k, shard_of(name, count)))
            seen[name] = k
    missing = sorted(set(everything) - set(seen))
    extra = sorted(set(seen) - set(everything))
    if missing or extra:
        fail("the tasks miss %s and add %s" % (missing[:5], extra[:5]))

    want = tree(single_out)
    got = tree(sharded_out)
    if ".koma-batch.json" not in want:
        fail("the single run left no .koma-batch.json")
    del want[".koma-batch.json"]
    manifests = {".koma-batch.%d-of-%d.json" % (k, count) for k in range(count)}
    if count == 1:
        manifests = {".koma-batch.json"}
    for name in manifests:
        if name not in got:
            fail("no manifest %s in %s" % (name, sharded_out))
        del got[name]
    for k in range(count):  # the tasks' summaries, when written into the output folder
        summary = os.path.relpath(pattern.format(k=k), sharded_out)
        got.pop(summary, None)
    if sorted(want) != sorted(got):
        fail("files differ: only single %s, only sharded %s"
             % (sorted(set(want) - set(got))[:5], sorted(set(got) - set(want))[:5]))
    for name in want:
        if want[name] != got[name]:
            fail("%s differs between the single run and the tasks" % name)
    sizes = [sum(1 for v in seen.values() if v == k) for k in range(count)]
    print("%d clips in %d tasks (%s), %d files equal byte for byte"
          % (len(seen), count, " ".join(map(str, sizes)), len(want)))


if __name__ == "__main__":
    main()
