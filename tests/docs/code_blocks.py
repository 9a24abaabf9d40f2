"""The lines of a Markdown page's fenced code blocks, and the verdict, for the docs tests."""

SHELL = ("sh", "bash", "shell")


def block_lines(markdown_path, languages):
    """(line number, line without its newline) of every line inside ```LANG blocks, LANG one
    of `languages`, in page order; the fences themselves are left out."""
    found, inside = [], False
    with open(markdown_path, encoding="utf-8") as f:
        for number, line in enumerate(f, 1):
            stripped = line.strip()
            if stripped.startswith("```"):
                inside = not inside and stripped[3:] in languages
                continue
            if inside:
                found.append((number, line.rstrip("\n")))
    return found


def verdict(problems, ok_message):
    """Prints every problem and a FAIL count, or `ok_message`; the exit code (1 or 0)."""
    for problem in problems:
        print(problem)
    if problems:
        print(f"FAIL: {len(problems)} problem(s)")
        return 1
    print(ok_message)
    return 0
