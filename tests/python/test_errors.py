"""Bad files through the wire: the Python caller gets KomaError with the gRPC code and the
message the C++ CLI prints for the same file (which it parses locally), the request field in
place of the path; the field and the line are parsed out. Tables of >= 10 files per format."""
import re
import pytest

import koma
from conftest import run_cli

BVH = """HIERARCHY
ROOT Hips
{
\tOFFSET 0 0 0
\tCHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation
\tJOINT Chest
\t{
\t\tOFFSET 0 5 0
\t\tCHANNELS 3 Zrotation Xrotation Yrotation
\t\tEnd Site
\t\t{
\t\t\tOFFSET 0 10 0
\t\t}
\t}
}
MOTION
Frames: 3
Frame Time: 0.0416667
0 90 0 0 0 0 10 20 30
0 91 0 1 0 0 11 21 31
0 92 0 2 0 0 12 22 32
"""

MOTION3 = """{
  "Version": 3,
  "Meta": {"Duration": 1, "Fps": 30, "Loop": true, "CurveCount": 1},
  "Curves": [
    {"Target": "Parameter", "Id": "ParamMouthOpenY", "Segments": [0, 0, 0, 0.5, 1, 0, 1, 0]}
  ]
}
"""

CSV = "frame,ParamMouthOpenY,ParamEyeLOpen\n0,0,1\n1,0.5,1\n2,1,0\n3,0,1\n"


def broken(text, old, new):
    assert old in text, old
    return text.replace(old, new, 1)


BAD_BVH = {
    "no HIERARCHY": broken(BVH, "HIERARCHY", "HIERARCHIE"),
    "unknown channel": broken(BVH, "CHANNELS 3 Zrotation", "CHANNELS 3 Zrot"),
    "7 channels": broken(BVH, "CHANNELS 6", "CHANNELS 7"),
    "unbalanced braces": broken(BVH, "\t\t}\n\t}\n", "\t\t}\n"),
    "duplicate joint": broken(BVH, "JOINT Chest", "JOINT Hips"),
    "joint without OFFSET": broken(BVH, "\t\tOFFSET 0 5 0\n", ""),
    "malformed number": broken(BVH, "0 91 0 1", "0 9x1 0 1"),
    "nan value": broken(BVH, "0 91 0 1", "0 nan 0 1"),
    "too few values": broken(BVH, "0 92 0 2 0 0 12 22 32\n", "0 92 0 2\n"),
    "too many values": BVH + "1 2 3\n",
    "negative frames": broken(BVH, "Frames: 3", "Frames: -3"),
    "frame time 0": broken(BVH, "Frame Time: 0.0416667", "Frame Time: 0"),
}

BAD_MOTION3 = {
    "malformed JSON": broken(MOTION3, '"Version": 3,', '"Version": 3'),
    "root is an array": "[" + MOTION3 + "]",
    "no Meta": broken(MOTION3, '"Meta"', '"Mesa"'),
    "Fps 0": broken(MOTION3, '"Fps": 30', '"Fps": 0'),
    "Fps a string": broken(MOTION3, '"Fps": 30', '"Fps": "30"'),
    "negative Duration": broken(MOTION3, '"Duration": 1', '"Duration": -1'),
    "Curves not an array": broken(MOTION3, '"Curves": [', '"Curves": 5, "X": ['),
    "unknown Target": broken(MOTION3, '"Target": "Parameter"', '"Target": "Param"'),
    "Id a number": broken(MOTION3, '"Id": "ParamMouthOpenY"', '"Id": 7'),
    "segment value a string": broken(MOTION3, "[0, 0, 0, 0.5", '[0, "0", 0, 0.5'),
    "unknown segment identifier": broken(MOTION3, "[0, 0, 0, 0.5", "[0, 0, 7, 0.5"),
    "segment cut short": broken(MOTION3, "0, 1, 0]}", "0, 1]}"),
}

BAD_CSV = {
    "header not frame": broken(CSV, "frame,", "time,"),
    "no curve column": "frame\n0\n1\n",
    "empty id": broken(CSV, ",ParamEyeLOpen", ","),
    "duplicate id": broken(CSV, "ParamEyeLOpen", "ParamMouthOpenY"),
    "quote in id": broken(CSV, "ParamEyeLOpen", 'Param"Eye'),
    "empty line": broken(CSV, "1,0.5,1\n", "\n1,0.5,1\n"),
    "extra field": broken(CSV, "1,0.5,1\n", "1,0.5,1,7\n"),
    "missing field": broken(CSV, "1,0.5,1\n", "1,0.5\n"),
    "frame out of order": broken(CSV, "2,1,0\n", "5,1,0\n"),
    "invalid number": broken(CSV, "1,0.5,1\n", "1,x,1\n"),
    "nan": broken(CSV, "1,0.5,1\n", "1,nan,1\n"),
    "no rows": "frame,ParamMouthOpenY\n",
}


def cli_message(command, path, output, server):
    """What `koma COMMAND PATH` prints for a bad file, without "koma: PATH: "."""
    done = run_cli(command, str(path), "-o", str(output), "--server", server.address, check=False)
    assert done.returncode == 1, done.stderr
    # "koma: PATH (BVH): ", the format the CLI read the file as in parentheses.
    prefix = re.match(rf"koma: {re.escape(str(path))}(?: \((?:BVH|CSV|motion3\.json)\))?: ",
                      done.stderr)
    assert prefix, done.stderr
    return done.stderr[prefix.end():].rstrip("\n")


def test_tables_have_ten_cases_per_format_and_good_bases(client):
    assert min(len(BAD_BVH), len(BAD_MOTION3), len(BAD_CSV)) >= 10
    assert client.retime_skeletal(BVH).counts["frames"] == 3
    assert client.lip_blink(MOTION3).output is not None
    assert client.retime_curves(CSV, format="csv").output is not None


def refused_as_the_cli_says(server, client, tmp_path, rpc, text, suffix, field):
    """Sends `text` as a file (bad.SUFFIX) through `rpc` ("skeletal", "curves", "lipblink"):
    the call must fail INVALID_ARGUMENT with the message `koma RPC` prints for the same file,
    prefixed with `field` (the request field that carried the file). Returns the error and the
    CLI's message."""
    path = tmp_path / ("bad" + suffix)
    path.write_text(text)
    expected = cli_message(rpc, path, tmp_path / ("out" + suffix), server)
    call = {"skeletal": client.retime_skeletal, "curves": client.retime_curves,
            "lipblink": client.lip_blink}[rpc]
    with pytest.raises(koma.KomaError) as caught:
        call(str(path))
    error = caught.value
    assert error.code.name == "INVALID_ARGUMENT"
    assert error.message == field + ": " + expected
    assert error.field == field
    return error, expected


@pytest.mark.parametrize("name", sorted(BAD_BVH))
def test_bad_bvh_gets_the_cli_message_with_field_and_line(server, client, tmp_path, name):
    error, expected = refused_as_the_cli_says(server, client, tmp_path, "skeletal", BAD_BVH[name],
                                              ".bvh", "bvh_text")
    assert error.line is not None and error.line >= 1
    assert f"line {error.line}" in expected


@pytest.mark.parametrize("name", sorted(BAD_MOTION3))
@pytest.mark.parametrize("rpc", ["curves", "lipblink"])
def test_bad_motion3_gets_the_cli_message(server, client, tmp_path, name, rpc):
    refused_as_the_cli_says(server, client, tmp_path, rpc, BAD_MOTION3[name], ".motion3.json",
                            "motion3_json")


@pytest.mark.parametrize("name", sorted(BAD_CSV))
@pytest.mark.parametrize("rpc", ["curves", "lipblink"])
def test_bad_csv_gets_the_cli_message_with_field_and_line(server, client, tmp_path, name, rpc):
    error, _ = refused_as_the_cli_says(server, client, tmp_path, rpc, BAD_CSV[name], ".csv",
                                       "csv_text")
    assert error.line is not None


def test_python_m_koma_prints_the_code_and_message(server, tmp_path):
    from conftest import run_python_cli
    path = tmp_path / "bad.bvh"
    path.write_text(BAD_BVH["unknown channel"])
    done = run_python_cli("skeletal", str(path), "-o", str(tmp_path / "o.bvh"),
                          "--server", server.address)
    assert done.returncode == 1
    assert done.stderr.startswith("koma: INVALID_ARGUMENT: bvh_text: line 9: unknown channel name")
    assert not (tmp_path / "o.bvh").exists()
