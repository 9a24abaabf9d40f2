"""The lines of a Markdown page's fenced code blocks, for the tests that run the docs."""

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
