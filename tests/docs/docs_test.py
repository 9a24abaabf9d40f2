"""The docs cannot rot: checks README.md and docs/ against the tree, the server and the proto.

Usage: docs_test.py REPO_ROOT KOMA_SERVER_BINARY

Fails (exit 1, every problem listed) when
- README.md is over 250 lines or docs/benchmarks.md over 300;
- a relative link in README.md or docs/*.md names a file that does not exist, or an anchor
  (#section) that is not a heading of the target page;
- any file of the source tree (not .git, not a build tree) refers to the design notes outside
  the repository (the FORBIDDEN words below): docs/semantics.md is the reference;
- a flag that `koma_server --help` lists is not in docs/operations.md as `--flag`;
- a message, a field, an enum or an enum value of proto/koma/v1/*.proto is not in docs/api.md
  as `name`.

Run with Debian's /usr/bin/python3; standard library only.
"""
import os
import re
import subprocess
import sys

from code_blocks import verdict

README_MAX_LINES = 250
BENCHMARKS_MAX_LINES = 300
# Built from parts so this file does not match its own check.
FORBIDDEN = ["../" + "shared", "algorithms" + ".md"]


def markdown_files(root):
    files = [os.path.join(root, "README.md")]
    docs = os.path.join(root, "docs")
    files += sorted(os.path.join(docs, name) for name in os.listdir(docs) if name.endswith(".md"))
    return files


def strip_code(text):
    """The text without fenced code blocks and inline code spans (links there are not links)."""
    text = re.sub(r"^(```|~~~).*?^\1[^\n]*$", "", text, flags=re.S | re.M)
    return re.sub(r"`[^`\n]*`", "", text)


def heading_anchors(text):
    """GitHub's anchors for the headings of a markdown page."""
    anchors, seen = set(), {}
    for line in strip_code_blocks_only(text).splitlines():
        match = re.match(r"^#{1,6}\s+(.*?)\s*#*\s*$", line)
        if not match:
            continue
        title = re.sub(r"\[([^\]]*)\]\([^)]*\)", r"\1", match.group(1))  # a link's text
        slug = re.sub(r"[^\w\- ]", "", title.lower().replace("`", "")).replace(" ", "-")
        count = seen.get(slug, 0)
        seen[slug] = count + 1
        anchors.add(slug if count == 0 else f"{slug}-{count}")
    return anchors


def strip_code_blocks_only(text):
    return re.sub(r"^(```|~~~).*?^\1[^\n]*$", "", text, flags=re.S | re.M)


def check_lengths(root, problems):
    limits = (("README.md", README_MAX_LINES), ("docs/benchmarks.md", BENCHMARKS_MAX_LINES))
    for rel, limit in limits:
        with open(os.path.join(root, rel), encoding="utf-8") as f:
            count = len(f.read().splitlines())
        if count > limit:
            problems.append(f"{rel}: {count} lines, more than {limit}")


def check_links(root, problems):
    checked = 0
    for path in markdown_files(root):
        rel = os.path.relpath(path, root)
        with open(path, encoding="utf-8") as f:
            text = f.read()
        for match in re.finditer(r"\[[^\]]*\]\(([^)\s]+)(?:\s+\"[^\"]*\")?\)", strip_code(text)):
            target = match.group(1)
            if re.match(r"^[a-z][a-z0-9+.-]*:", target):  # https:, mailto:, ...
                continue
            checked += 1
            file_part, _, anchor = target.partition("#")
            target_path = os.path.normpath(os.path.join(os.path.dirname(path), file_part)) \
                if file_part else path
            if not os.path.exists(target_path):
                problems.append(f"{rel}: link ({target}): {file_part} does not exist")
                continue
            if os.path.commonpath([os.path.realpath(target_path), os.path.realpath(root)]) != \
                    os.path.realpath(root):
                problems.append(f"{rel}: link ({target}) leaves the repository")
                continue
            if anchor and target_path.endswith(".md"):
                with open(target_path, encoding="utf-8") as f:
                    anchors = heading_anchors(f.read())
                if anchor not in anchors:
                    problems.append(f"{rel}: link ({target}): no heading #{anchor} in "
                                    f"{os.path.relpath(target_path, root)}")
    if checked == 0:
        problems.append("no relative link found at all: is the link pattern broken?")


def source_files(root):
    for directory, subdirs, files in os.walk(root):
        # Not git's store, not build trees (they hold copies and generated files).
        subdirs[:] = sorted(d for d in subdirs if d != ".git" and
                            not os.path.exists(os.path.join(directory, d, "CMakeCache.txt")))
        for name in sorted(files):
            yield os.path.join(directory, name)


def check_no_outside_references(root, problems):
    scanned = 0
    for path in source_files(root):
        try:
            with open(path, encoding="utf-8") as f:
                lines = f.read().splitlines()
        except (UnicodeDecodeError, OSError):
            continue  # binary files
        scanned += 1
        for number, line in enumerate(lines, 1):
            for word in FORBIDDEN:
                if word in line:
                    problems.append(f"{os.path.relpath(path, root)}:{number}: refers to {word!r} "
                                    "outside the repository; cite docs/semantics.md")
    if scanned < 50:
        problems.append(f"only {scanned} text files scanned under {root}: wrong root?")


def server_flags(server):
    result = subprocess.run([server, "--help"], capture_output=True, text=True, timeout=30)
    flags = re.findall(r"^\s+--([a-z0-9_]+) \(", result.stdout + result.stderr, flags=re.M)
    return sorted(set(flags))


def check_server_flags(root, server, problems):
    flags = server_flags(server)
    if len(flags) < 10:
        problems.append(f"koma_server --help listed only {flags}: did its format change?")
    with open(os.path.join(root, "docs", "operations.md"), encoding="utf-8") as f:
        text = f.read()
    for flag in flags:
        if not re.search(rf"`--{flag}(`|=)", text):
            problems.append(f"docs/operations.md: koma_server flag --{flag} is not documented")


def proto_messages(path):
    """{message: [field names]} of a .proto file: fields of oneofs count as the message's."""
    with open(path, encoding="utf-8") as f:
        text = re.sub(r"//[^\n]*", "", f.read())
    messages, stack = {}, []
    for token in re.finditer(r"(message|enum|oneof|service)\s+(\w+)\s*\{|\{|\}|[^{};]+;", text):
        kind, name = token.group(1), token.group(2)
        item = token.group(0)
        if kind:
            stack.append((kind, name))
            if kind == "message":
                messages[name] = []
        elif item == "{":
            stack.append(("block", None))
        elif item == "}":
            stack.pop()
        else:
            owner = next((n for k, n in reversed(stack) if k == "message"), None)
            inside_enum = any(k == "enum" for k, _ in stack)
            field = re.match(r"\s*(?:optional\s+|repeated\s+)?[\w.]+\s+(\w+)\s*=\s*\d+", item)
            if owner and field and not inside_enum:
                messages[owner].append(field.group(1))
    return messages


def proto_enums(path):
    """{enum: [value names]} of a .proto file."""
    with open(path, encoding="utf-8") as f:
        text = re.sub(r"//[^\n]*", "", f.read())
    return {m.group(1): re.findall(r"(\w+)\s*=\s*-?\d+", m.group(2))
            for m in re.finditer(r"enum\s+(\w+)\s*\{([^}]*)\}", text)}


def check_proto_fields(root, problems):
    proto_dir = os.path.join(root, "proto", "koma", "v1")
    with open(os.path.join(root, "docs", "api.md"), encoding="utf-8") as f:
        api = f.read()
    total = 0
    for name in sorted(os.listdir(proto_dir)):
        if not name.endswith(".proto"):
            continue
        for message, fields in proto_messages(os.path.join(proto_dir, name)).items():
            if f"`{message}`" not in api:
                problems.append(f"docs/api.md: message {message} ({name}) is not documented")
            for field in fields:
                total += 1
                if f"`{field}`" not in api:
                    problems.append(f"docs/api.md: field {message}.{field} ({name}) "
                                    "is not documented")
        for enum, values in proto_enums(os.path.join(proto_dir, name)).items():
            for item in [enum] + values:
                total += 1
                if f"`{item}`" not in api:
                    problems.append(f"docs/api.md: enum {enum}: {item} ({name}) is not documented")
    if total < 100:
        problems.append(f"only {total} proto fields found: is the .proto parser broken?")


def main():
    root, server = sys.argv[1], sys.argv[2]
    problems = []
    check_lengths(root, problems)
    check_links(root, problems)
    check_no_outside_references(root, problems)
    check_server_flags(root, server, problems)
    check_proto_fields(root, problems)
    return verdict(problems, "docs OK")


if __name__ == "__main__":
    sys.exit(main())
