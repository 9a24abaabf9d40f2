"""koma's file formats, looked up as the C++ CLI looks them up (formats/format_table.h).

The rows are the C++ table's own, exported at build time into koma/_formats.py; this module
only applies them, with the same rules as formats/format_table.cc, so a name or a file's bytes
get the same format in Python as in `koma`. tests/python/test_format_table.py checks the two
agree on every sample and test file.
"""
from koma._formats import COMMANDS, FORMATS

_BOM = b"\xef\xbb\xbf"
_ASCII_SPACE = b" \t\n\r\f\v"

_BY_KEY = {row["key"]: row for row in FORMATS}


def row(key):
    """The row of `key` ("bvh", "gltf", "fbx", "spine", "motion3", "csv", "rhubarb", "audio")."""
    return _BY_KEY[key]


def format_from_name(path):
    """The key of the row one of whose extensions ends `path` (any case), or None."""
    if path is None:
        return None
    lower = str(path).lower()
    for r in FORMATS:
        if r["extensions"] and lower.endswith(r["extensions"]):
            return r["key"]
    return None


def extension_length(name):
    """formats::FormatExtensionLength: the length of the longest extension or folder extension
    of any row that ends `name` (any case) and leaves something before it; 0 when none does."""
    lower = str(name).lower()
    return max((len(extension) for r in FORMATS
                for extension in r["extensions"] + r["folder_extensions"]
                if len(lower) > len(extension) and lower.endswith(extension)), default=0)


def _text_start(data):
    """After a UTF-8 byte order mark and ASCII white space."""
    return data.removeprefix(_BOM).lstrip(_ASCII_SPACE)


def _matches_json_rule(rule, json):
    if rule["first_key"]:
        first = _text_start(json[1:])
        return first.startswith(b'"' + rule["first_key"] + b'"')
    return (all(member in json for member in rule["has"]) and
            not any(member in json for member in rule["lacks"]))


def _matches_magic(r, data):
    return any(data.startswith(magic) for magic in r["magic"])


def _matches_text_start(r, text):
    return any(text.startswith(start) for start in r["text_starts"])


def _matches_json(r, text):
    return text.startswith(b"{") and any(_matches_json_rule(rule, text) for rule in r["json"])


def sniff(data):
    """The key of the format `data` (a file's bytes) is by its first bytes, or None: the first
    row whose magic starts it; else, after a byte order mark and white space, whose text starts
    start it; else, for JSON, whose JSON rule matches."""
    for r in FORMATS:
        if _matches_magic(r, data):
            return r["key"]
    text = _text_start(data)
    for r in FORMATS:
        if _matches_text_start(r, text):
            return r["key"]
    for r in FORMATS:
        if _matches_json(r, text):
            return r["key"]
    return None


def matches(key, data):
    """`data` matches the sniffing rules of `key`'s row, whatever rows come before it."""
    r = row(key)
    text = _text_start(data)
    return _matches_magic(r, data) or _matches_text_start(r, text) or _matches_json(r, text)


def is_json(data):
    """The text (after a byte order mark and white space) starts a JSON object."""
    return _text_start(data).startswith(b"{")


def request_field(key, message):
    """The field of request `message` ("RetimeSkeletalRequest") that carries a `key` file."""
    for carried_message, field in row(key)["request_fields"]:
        if carried_message == message:
            return field
    raise KeyError(f"{message} carries no {key} file")


def command_names():
    return tuple(command["name"] for command in COMMANDS)
