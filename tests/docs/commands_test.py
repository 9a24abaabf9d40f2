"""Runs every `koma ...` command of the docs' sh code blocks against a real koma_server.

Usage: commands_test.py REPO_ROOT KOMA_SERVER_BINARY KOMA_CLIENT_BINARY [MARKDOWN ...]

MARKDOWN files default to README.md (paths relative to REPO_ROOT). Each line of a ```sh block
that starts with `koma ` runs as written, through `bash -o pipefail -c` (so pipes and
redirections work and a failing `koma` fails its pipeline), in document order, from one scratch
folder that has `samples/` (the repository's) and an empty `out/`, with the client first on
PATH and KOMA_SERVER naming a koma_server started here on 127.0.0.1 (a free port). A command must exit 0,
or N when its trailing comment says "exit N"; "exit N: TEXT ..." also requires TEXT (up to
an ellipsis) in its output; a line whose comment says "not run" is skipped (for examples that
need TLS files or several servers). The server is stopped with SIGTERM at the end and
must exit 0. Every wait is bounded. Fails (exit 1) on any command that exits otherwise, or when
no command was found.

The ```python blocks of each file run too, as one program per file in document order (later
blocks use names the first defines), with Debian's python3, this build's package on
PYTHONPATH and the documented address 127.0.0.1:50051 replaced by the test server's. It must
exit 0, and for every `print(...)  # TEXT` line TEXT (up to an ellipsis) must appear in its
output, in order. The scratch folder also holds broken.bvh, samples/pitch.bvh with its first
Xrotation misspelt Xrot, for the error examples.
"""
import os
import re
import shutil
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "testing"))
from koma_server import KomaServer  # noqa: E402  (tests/testing/koma_server.py)

from code_blocks import SHELL, block_lines

COMMAND_TIMEOUT_S = 60


def commands(markdown_path):
    """(line number, command, expected exit code, expected text) of `koma ` lines in sh blocks."""
    found = []
    for number, line in block_lines(markdown_path, SHELL):
        stripped = line.strip()
        if stripped.startswith("koma "):
            comment = stripped.partition("#")[2]
            if "not run" in comment:
                continue  # needs what this harness lacks (TLS files, several servers)
            expected = re.search(r"\bexit (\d+)(?::\s*(.*?)\s*(?:\.\.\.|…|$))?", comment)
            code = int(expected.group(1)) if expected else 0
            text = expected.group(2) if expected and expected.group(2) else ""
            found.append((number, stripped, code, text))
    return found


def python_program(markdown_path):
    """(first line number, the file's python blocks joined, expected printed texts)."""
    lines = block_lines(markdown_path, ("python",))
    expected = []
    for _, line in lines:
        said = re.match(r"\s*print\(.*\)\s*#\s*(.*?)\s*(?:\.\.\.|…|$)", line)
        if said and said.group(1):
            expected.append(said.group(1))
    first = lines[0][0] if lines else 0
    return first, "\n".join(line for _, line in lines) + "\n", expected


def run_python(document, program, address, work, python_path):
    """Failures (strings) of one file's python blocks run as one program."""
    first, code, expected = program
    code = code.replace("127.0.0.1:50051", address)
    env = dict(os.environ, PYTHONPATH=python_path)
    try:
        result = subprocess.run([sys.executable, "-c", code], cwd=work, env=env,
                                capture_output=True, text=True, timeout=COMMAND_TIMEOUT_S)
    except subprocess.TimeoutExpired:
        return [f"{document}:{first}: python blocks still running after {COMMAND_TIMEOUT_S} s"]
    output = result.stdout + result.stderr
    failures, position = [], 0
    if result.returncode != 0:
        failures.append(f"{document}:{first}: python blocks exited {result.returncode}:\n{output}")
    for text in expected:
        found = result.stdout.find(text, position)
        if found < 0:
            failures.append(f"{document}:{first}: python blocks did not print {text!r} "
                            f"(in order); printed:\n{result.stdout}")
        else:
            position = found + len(text)
    print(f"{'ok' if not failures else 'FAIL'}: {document}:{first}: python blocks "
          f"({len(expected)} printed texts checked)")
    return failures


def main():
    root, server, client = sys.argv[1:4]
    documents = sys.argv[4:] or ["README.md"]
    work = tempfile.mkdtemp(prefix="koma-docs-")
    os.symlink(os.path.join(os.path.abspath(root), "samples"), os.path.join(work, "samples"))
    os.mkdir(os.path.join(work, "out"))
    with open(os.path.join(root, "samples", "pitch.bvh"), encoding="utf-8") as f:
        broken = f.read().replace("Xrotation", "Xrot", 1)
    with open(os.path.join(work, "broken.bvh"), "w", encoding="utf-8") as f:
        f.write(broken)
    python_path = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(client))),
                               "python")
    try:
        koma_server = KomaServer(server, work, "--log_level=warn")
    except RuntimeError as error:
        raise SystemExit(str(error))
    env = dict(os.environ, KOMA_SERVER=koma_server.address,
               PATH=os.path.dirname(os.path.abspath(client)) + os.pathsep + os.environ["PATH"])
    failures, ran = [], 0
    try:
        for document in documents:
            for number, text, expected, message in commands(os.path.join(root, document)):
                ran += 1
                try:
                    result = subprocess.run(["bash", "-o", "pipefail", "-c", text], cwd=work,
                                            env=env, capture_output=True, text=True,
                                            timeout=COMMAND_TIMEOUT_S)
                    code, output = result.returncode, result.stdout + result.stderr
                except subprocess.TimeoutExpired:
                    code, output = "timeout", ""
                good = code == expected and message in output
                print(f"{'ok' if good else 'FAIL'}: {document}:{number}: {text} -> exit {code}")
                if not good:
                    failures.append(f"{document}:{number}: `{text}` exited {code}, expected "
                                    f"{expected}" + (f" and {message!r}" if message else "") +
                                    f"; its output:\n{output}")
            program = python_program(os.path.join(root, document))
            if program[1].strip():
                ran += 1
                failures += run_python(document, program, koma_server.address, work,
                                       python_path)
    finally:
        server_code = koma_server.stop(timeout_s=30)
        if server_code is None:
            server_code = "killed after 30 s"
    if server_code != 0:
        failures.append(f"koma_server exited {server_code} after SIGTERM")
    if ran == 0:
        failures.append(f"no `koma ` command found in {documents}")
    for failure in failures:
        print(failure)
    if not failures:
        shutil.rmtree(work)
    print(f"{ran} command(s), {len(failures)} failure(s)")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
