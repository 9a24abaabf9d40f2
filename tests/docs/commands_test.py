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
"""
import os
import re
import shutil
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "testing"))
from koma_server import KomaServer  # noqa: E402  (tests/testing/koma_server.py)

COMMAND_TIMEOUT_S = 60


def commands(markdown_path):
    """(line number, command, expected exit code, expected text) of `koma ` lines in sh blocks."""
    found, in_sh = [], False
    with open(markdown_path, encoding="utf-8") as f:
        for number, line in enumerate(f, 1):
            stripped = line.strip()
            if stripped.startswith("```"):
                in_sh = not in_sh and stripped in ("```sh", "```bash", "```shell")
                continue
            if in_sh and stripped.startswith("koma "):
                comment = stripped.partition("#")[2]
                if "not run" in comment:
                    continue  # needs what this harness lacks (TLS files, several servers)
                expected = re.search(r"\bexit (\d+)(?::\s*(.*?)\s*(?:\.\.\.|…|$))?", comment)
                code = int(expected.group(1)) if expected else 0
                text = expected.group(2) if expected and expected.group(2) else ""
                found.append((number, stripped, code, text))
    return found


def main():
    root, server, client = sys.argv[1:4]
    documents = sys.argv[4:] or ["README.md"]
    work = tempfile.mkdtemp(prefix="koma-docs-")
    os.symlink(os.path.join(os.path.abspath(root), "samples"), os.path.join(work, "samples"))
    os.mkdir(os.path.join(work, "out"))
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
