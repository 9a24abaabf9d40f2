"""The layers of docs/development.md hold: core/ pure, the others one way.

Usage: layering_test.py REPO_ROOT

Fails (exit 1, every problem listed) when
- koma_core's link line (core/CMakeLists.txt) names anything but abseil targets;
- a file in core/ includes anything but core/, absl/ and standard C++ headers, or a standard
  header that starts threads or touches files (core gets threads and memory from the program:
  core/task_runner.h, core/large_array.h);
- a file of one layer includes a layer it must not see: core sees no other koma folder;
  platform/ sees core/; formats/ sees core/; convert/ sees core/, formats/ and the proto;
  server/ never sees client/ (but the page, server/page_*: its file jobs run the CLI's own
  commands, client/file_job.h, and only koma_server links it); client/ never sees server/ or
  platform/.

Run with Debian's /usr/bin/python3; standard library only.
"""
import os
import re
import sys

from code_blocks import verdict

KOMA_FOLDERS = {"core", "platform", "formats", "convert", "server", "client"}
# The koma folders each layer may include (the proto's generated headers are koma/...).
MAY_INCLUDE = {
    "core": {"core"},
    "platform": {"platform", "core"},
    "formats": {"formats", "core"},
    "convert": {"convert", "formats", "core"},
    "server": {"server", "convert", "formats", "core", "platform"},
    "client": {"client", "convert", "formats", "core"},
}
# The one exception to "server/ never sees client/": the page's files (koma_page_lib,
# server/page.cmake), linked into koma_server only, never into koma_server_lib.
PAGE_FILES = re.compile(r"^server/page_[a-z_]+\.(h|cc)$")
# Standard headers core must not use: threads, files and streams belong to the programs.
CORE_FORBIDDEN_STD = {"thread", "future", "mutex", "shared_mutex", "condition_variable",
                      "fstream", "filesystem", "iostream", "cstdio"}
INCLUDE = re.compile(r'^\s*#\s*include\s*([<"])([^>"]+)[>"]', re.M)


def sources(root, folder):
    for dirpath, _, names in os.walk(os.path.join(root, folder)):
        for name in sorted(names):
            if name.endswith((".h", ".cc")):
                yield os.path.join(dirpath, name)


def check_core_link_line(root, problems):
    text = open(os.path.join(root, "core", "CMakeLists.txt"), encoding="utf-8").read()
    calls = re.findall(r"target_link_libraries\(\s*koma_core\b([^)]*)\)", text)
    if not calls:
        problems.append("core/CMakeLists.txt: no target_link_libraries(koma_core ...) found")
    for call in calls:
        for word in call.split():
            if word in ("PUBLIC", "PRIVATE", "INTERFACE") or word.startswith("absl::"):
                continue
            problems.append(f"core/CMakeLists.txt: koma_core links {word}; core links abseil only")


def check_includes(root, problems):
    for folder, allowed in MAY_INCLUDE.items():
        for path in sources(root, folder):
            relative = os.path.relpath(path, root)
            text = open(path, encoding="utf-8").read()
            for kind, header in INCLUDE.findall(text):
                top = header.split("/")[0]
                page_sees_client = top == "client" and PAGE_FILES.match(relative)
                if kind == '"' and top in KOMA_FOLDERS and top not in allowed and not page_sees_client:
                    problems.append(f"{relative}: includes {header}; {folder}/ may not see {top}/")
                if folder != "core":
                    continue
                if kind == '"' and top not in ("core", "absl"):
                    problems.append(f"{relative}: includes \"{header}\"; core/ includes core/, "
                                    "absl/ and standard headers only")
                if kind == "<" and ("/" in header or "." in header or
                                    header in CORE_FORBIDDEN_STD):
                    problems.append(f"{relative}: includes <{header}>; core/ starts no threads "
                                    "and touches no files or system calls")


def main():
    root = sys.argv[1]
    problems = []
    check_core_link_line(root, problems)
    check_includes(root, problems)
    return verdict(problems, "layering OK")


if __name__ == "__main__":
    sys.exit(main())
