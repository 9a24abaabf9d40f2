"""The Python package's format table is the C++ one (formats/format_table.h), applied alike.

Usage: format_table_check.py EXPORT_BIN SOURCE_DIR   (PYTHONPATH: the assembled package)

Fails (exit 1, every difference listed) when
- koma/_formats.py differs from what koma_format_table_export writes now (a stale export);
- for any file of samples/ and tests/testdata, or any of the texts below, the format Python
  gives its name or its bytes (koma/_format_table.py) differs from the C++ table's answer;
- the package's own tests of a file (_client._is_spine, __main__._is_csv_path) disagree with
  the table.

Run with Debian's /usr/bin/python3; standard library and the koma package only.
"""
import os
import subprocess
import sys
import tempfile

import koma
from koma import _format_table, _formats
from koma import __main__ as cli
from koma import _client

# Texts at the edges of the sniffing rules (the C++ test's, tests/formats/format_table_test.cc).
EDGE_TEXTS = [
    b"glTF\x02\x00\x00\x00", b"Kaydara FBX Binary  \x00", b"; FBX 7.4.0 project file",
    b"\xef\xbb\xbf \r\n\tHIERARCHY", b'"frame";"a"\n', b"frame,a\n0,1\n", b'{"asset":{}}',
    b'{"asset":{},"Curves":[]}', b'{ "skeleton": {}, "Meta": {}}', b'{"bones":[],"skeleton":{}}',
    b'{"Meta":{},"skeleton":1}', b"{}", b" glTF", b"RIFF....WAVE", b"", b"frames,x",
    b"\xef\xbb\xbf{\x0b\"skeleton\":1}", b'["skeleton"]',
]
NAMES = ["walk.BVH", "a.glb", "a.GLTF", "x.vrm", "x.vrma", "take.Fbx", "s.json", "s.motion3.json",
         "c.csv", "v.wav", "v.FLAC", "v.mp3", "cues.tsv", "notes.txt", "-", "x.skel"]


def cpp_answers(export_bin, paths):
    out = subprocess.run([export_bin, "--sniff", *paths], check=True, capture_output=True,
                         text=True).stdout
    answers = {}
    for line in out.splitlines():
        by_name, by_content, path = line.split(" ", 2)
        answers[path] = (None if by_name == "-" else by_name,
                         None if by_content == "-" else by_content)
    return answers


def main():
    export_bin, source_dir = sys.argv[1], sys.argv[2]
    problems = []
    with tempfile.TemporaryDirectory() as scratch:
        fresh = os.path.join(scratch, "_formats.py")
        subprocess.run([export_bin, fresh], check=True)
        installed = os.path.join(os.path.dirname(koma.__file__), "_formats.py")
        if open(fresh, "rb").read() != open(installed, "rb").read():
            problems.append(f"{installed} is not what {export_bin} writes now: rebuild")

        paths = []
        for folder in ("samples", "tests/testdata"):
            for root, _, names in os.walk(os.path.join(source_dir, folder)):
                paths += [os.path.join(root, name) for name in sorted(names)]
        for i, text in enumerate(EDGE_TEXTS):
            path = os.path.join(scratch, f"edge{i}")
            with open(path, "wb") as f:
                f.write(text)
            paths.append(path)
        for name in NAMES:
            path = os.path.join(scratch, "named-" + name)
            with open(path, "wb") as f:
                f.write(b"")
            paths.append(path)

        answers = cpp_answers(export_bin, paths)
        for path in paths:
            with open(path, "rb") as f:
                data = f.read()
            python = (_format_table.format_from_name(path), _format_table.sniff(data))
            if python != answers[path]:
                problems.append(f"{path}: Python says (name, contents) {python}, "
                                f"C++ {answers[path]}")
            spine = _format_table.row("spine")
            if _client._is_spine(data, None) != _format_table.matches("spine", data):
                problems.append(f"{path}: _client._is_spine disagrees with {spine['key']}'s rule")
            if cli._is_csv_path(path) != (answers[path][0] == "csv"):
                problems.append(f"{path}: __main__._is_csv_path disagrees with the table")
        print(f"format table: {len(_formats.FORMATS)} formats, {len(paths)} files and texts "
              f"compared with the C++ table")

    for problem in problems:
        print("FAIL:", problem)
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
