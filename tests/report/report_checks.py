"""Checks of koma's HTML reports (docs/report.md), run by report_test.sh.

  report_checks.py validate REPORT...                 HTML5, html5lib's strict parser
  report_checks.py skeletal REPORT TIMING_CSV SUMMARY [SHOT.png]
  report_checks.py curves REPORT DRAWING_CSV SUMMARY [SHOT.png]
  report_checks.py lipblink REPORT SUMMARY [SHOT.png]
  report_checks.py player REPORT TIMING_CSV
  report_checks.py large REPORT TIMING_CSV MAX_SECONDS MAX_BYTES

The oracles are the client's other outputs for the same call: the timing and drawing sheets
(formats/ writers) and the summary it prints, never the report's own data. Exit 1 with
"FAIL: ..." on the first difference."""
import csv
import os
import re
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))


def fail(message):
    print(f"FAIL: {message}", file=sys.stderr)
    sys.exit(1)


def expect(what, got, want):
    if got != want:
        fail(f"{what}: got {got!r}, want {want!r}")


def read_csv(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def ranges(text):
    """'3-5, 9' -> [3, 4, 5, 9]; 'none' -> []."""
    text = text.strip()
    if text == "none":
        return []
    out = []
    for part in text.split(","):
        part = part.strip()
        if "-" in part:
            a, b = part.split("-")
            out.extend(range(int(a), int(b) + 1))
        else:
            out.append(int(part))
    return out


def validate(paths):
    import html5lib
    for path in paths:
        with open(path, "rb") as f:
            data = f.read()
        parser = html5lib.HTMLParser(strict=True)
        try:
            parser.parse(data)
        except html5lib.html5parser.ParseError as e:
            fail(f"{path}: not valid HTML5: {e}")
        if parser.errors:
            fail(f"{path}: HTML5 parse errors: {parser.errors[:5]}")
        text = data.decode("utf-8")
        for needle in ("http://", "https://"):
            # The only URL a report may name is the SVG namespace, which loads nothing.
            rest = text.replace("http://www.w3.org/2000/svg", "")
            if needle in rest:
                fail(f"{path}: names a network address ({needle})")
        if re.search(r"<(script|link|img)[^>]+(src|href)=", text):
            fail(f"{path}: loads an external resource")
        if "{{" in text.split('id="koma-data"')[0]:
            fail(f"{path}: a template marker was left in the page")
        print(f"ok: {path}: valid HTML5 ({len(data)} bytes), self-contained")


def check_screenshot(browser, path, figure_selector=None):
    """The page is not blank: many colours and most of its pixels not the background; the
    figure (if given) has the 'after' colour in it."""
    from PIL import Image
    browser.screenshot(path)
    image = Image.open(path).convert("RGB")
    small = image.resize((image.width // 4, image.height // 4))
    pixels = list(small.getdata())
    background = max(set(pixels), key=pixels.count)
    ink = sum(1 for p in pixels if sum(abs(a - b) for a, b in zip(p, background)) > 60)
    colours = len(set(pixels))
    if colours < 50 or ink < 0.02 * len(pixels):
        fail(f"{path}: screenshot looks blank ({colours} colours, {ink}/{len(pixels)} inked pixels)")
    if figure_selector:
        box = browser.evaluate(
            f"(() => {{ const r = document.querySelector('{figure_selector}').getBoundingClientRect();"
            " return [r.left + scrollX, r.top + scrollY, r.width, r.height]; })()")
        x, y, w, h = (int(v) for v in box)
        crop = image.crop((x, y, x + w, y + h))
        # --after is #d2572b: orange strokes of the retimed figure.
        orange = sum(1 for (r, g, b) in crop.getdata() if r > 180 and 60 < g < 120 and b < 80)
        if orange < 50:
            fail(f"{path}: the figure {figure_selector} has no stroke drawn ({orange} orange pixels)")
    print(f"ok: {path}: screenshot {image.width}x{image.height}, not blank")


SHEET_JS = """(() => {
  const rows = [];
  const next = document.getElementById('sheet-next');
  const label = document.getElementById('sheet-page');
  document.getElementById('sheet-prev');
  // Back to page 1, then every page in turn.
  for (let i = 0; i < 100000 && !label.textContent.startsWith('page 1 '); ++i) document.getElementById('sheet-prev').click();
  for (let guard = 0; guard < 100000; ++guard) {
    for (const tr of document.querySelectorAll('#sheet tbody tr')) rows.push([...tr.children].map((td) => [td.textContent, td.className]));
    const m = label.textContent.match(/page (\\d+) of (\\d+)/);
    if (m[1] === m[2]) break;
    next.click();
  }
  return {rows, header: [...document.querySelectorAll('#sheet thead th')].map((th) => th.textContent)};
})()"""


def read_sheet(browser):
    sheet = browser.evaluate(SHEET_JS)
    return sheet["header"], sheet["rows"]


def summary_field(summary, pattern):
    m = re.search(pattern, summary)
    if not m:
        fail(f"summary has no match for {pattern!r}:\n{summary}")
    return m


def check_skeletal(report, timing_csv, summary_path, shot=None, browser=None):
    import cdp
    rows = read_csv(timing_csv)
    summary = open(summary_path).read()
    deleted = ranges(summary_field(summary, r"source frames gone: (.*)").group(1))
    hidden = ranges(summary_field(summary, r"source frames hidden by holds: (.*)").group(1))
    joints = int(summary_field(summary, r"(\d+) joints").group(1))
    grid = "grid_frame" in rows[0]
    n = len(rows)
    own = browser is None
    b = browser or cdp.Browser()
    try:
        b.open("file://" + os.path.abspath(report))
        expect("scrubber max", b.evaluate("+document.getElementById('scrubber').max"), n - 1)
        # The kinds band: one rectangle per run, their frames add up to the timing sheet's.
        band = b.evaluate("[...document.querySelectorAll('#kinds-band rect')].map((r) => [r.getAttribute('class'), +r.dataset.first, +r.dataset.count])")
        expect("band frames", sum(c for _, _, c in band), n)
        for kind, letter in (("HELD", "H"), ("DUPLICATE", "D"), ("ORIGINAL", "O")):
            got = sorted(t for cls, first, count in band if cls == f"kind-{letter}" for t in range(first, first + count))
            want = [int(r["output_frame"]) for r in rows if r["kind"] == kind]
            expect(f"{kind} frames in the band", got, want)
        omitted = b.evaluate("[...document.querySelectorAll('line.mark-omitted')].map((l) => +l.dataset.frame)")
        expect("omitted marks", omitted, deleted)
        hidden_marks = b.evaluate("[...document.querySelectorAll('line.mark-hidden')].map((l) => +l.dataset.frame)")
        expect("hidden-by-hold marks", hidden_marks, hidden)
        expect("SSD curve drawn", b.evaluate("document.getElementById('ssd-curve').getAttribute('d').length > 10"), True)
        # The figures: front and side (or camera) view before and after, one stroke per bone.
        bones = b.evaluate("[...document.querySelectorAll('path.figure')].map((p) => (p.getAttribute('d').match(/M/g) || []).length)")
        if len(bones) not in (2, 4):
            fail(f"figures: {len(bones)} views, want 4 (front and side, before and after) or 2 (camera)")
        for count in bones:
            expect("bones per figure", count, joints - 1)
        # The X-sheet: rows are output frames, or grid frames with a film grid.
        header, sheet = read_sheet(b)
        if grid:
            by_grid = {}
            for r in rows:
                by_grid.setdefault(int(r["grid_frame"]), r)
            want_rows = [by_grid[g] for g in sorted(by_grid)]
            expect("X-sheet first column", header[0], "grid frame")
        else:
            want_rows = rows
        expect("X-sheet rows", len(sheet), len(want_rows))
        drawings = 0
        previous = None
        for i, (got, want) in enumerate(zip(sheet, want_rows)):
            expect(f"X-sheet row {i} frame", got[0][0], str(want["grid_frame"] if grid else want["output_frame"]))
            expect(f"X-sheet row {i} source frame", got[4][0], want["source_frame"])
            expect(f"X-sheet row {i} kind", got[5][0], want["kind"])
            new = want["source_frame"] != previous
            previous = want["source_frame"]
            drawings += new
            expect(f"X-sheet row {i} drawing", got[3][0], str(drawings) if new else "|")
        print(f"ok: {report}: {n} output frames, {len(sheet)} X-sheet rows, {drawings} drawings, "
              f"{len(omitted)} omitted and {len(hidden_marks)} hidden marks, "
              f"{sum(1 for r in rows if r['kind'] == 'HELD')} HELD frames, {len(bones)} views of {joints - 1} bones")
        if shot:
            check_screenshot(b, shot, "#after svg")
        if b.errors:
            fail(f"script errors: {b.errors}")
    finally:
        if own:
            b.close()


def check_curves(report, drawing_csv, summary_path, shot=None):
    import cdp
    from fractions import Fraction
    rows = read_csv(drawing_csv)
    summary = open(summary_path).read()
    keys = [int(k) for k in summary_field(summary, r"key poses \(\d+\): (.*)").group(1).split(",")]
    m = re.search(r"key poses at grid frames (.*)", summary)
    key_rows = [int(k) for k in m.group(1).split(",")] if m else keys
    timings = re.findall(r"  on (\S+): (\d+) drawings \(holds (.*)\) for (.*)", summary)
    fps = Fraction(summary_field(summary, r"frames at (\S+) fps").group(1))
    frames = len(rows)
    with cdp.Browser() as b:
        b.open("file://" + os.path.abspath(report))
        plots = b.evaluate("[...document.querySelectorAll('svg.curve-plot')].map((s) => [s.dataset.curve, s.querySelectorAll('circle.drawing').length, s.querySelectorAll('line.key').length])")
        by_curve = {c: (d, k) for c, d, k in plots}
        for on, count, holds, ids in timings:
            for curve in ids.split(", "):
                if curve not in by_curve:
                    fail(f"no plot of {curve}")
                expect(f"{curve}: drawing marks", by_curve[curve][0], int(count))
                expect(f"{curve}: key pose lines", by_curve[curve][1], len(keys))
            want = sorted([int(l), int(d)] for d, l in re.findall(r"(\d+) x (\d+)f", holds))
            hist = b.evaluate(f"[...document.querySelectorAll('svg.histogram')].map((s) => [...s.querySelectorAll('rect')].map((r) => [+r.dataset.length, +r.dataset.drawings]))")
            if want not in hist:
                fail(f"on {on}: histogram {want} not among {hist}")
        header, sheet = read_sheet(b)
        grid = header[0] == "grid frame"
        if grid:
            timing_fps = 24  # the summary says "on the 24 fps film grid"
            expect("grid in summary", "24 fps film grid" in summary, True)
            want_rows = int((frames - 1) / fps * timing_fps) + 1
        else:
            want_rows = frames
        expect("drawing sheet rows", len(sheet), want_rows)
        expect("KEY rows", [i for i, r in enumerate(sheet) if r[2][0] == "KEY"], key_rows)
        first_column = 4 if grid else 3
        drawing = -1
        numbered = 0
        for i, r in enumerate(sheet):
            text = r[first_column][0]
            if text != "|":
                drawing = int(text) - 1
                numbered += 1
            if grid:
                span = r[3][0]
                shown = [] if span == "–" else ranges(span.replace("–", "-"))
            else:
                shown = [i]
            for k in shown:
                expect(f"sheet row {i}: drawing of output frame {k}", int(rows[k]["drawing"]), drawing)
        expect("drawings numbered in the sheet", numbered, int(timings[0][1]))
        print(f"ok: {report}: {len(plots)} curves, {len(sheet)} sheet rows, {numbered} drawings, {len(keys)} key poses")
        if shot:
            check_screenshot(b, shot)
        if b.errors:
            fail(f"script errors: {b.errors}")


def check_lipblink(report, summary_path, shot=None):
    import cdp
    summary = open(summary_path).read()
    mouths = re.findall(r"  mouth (\S+): speech at (?:grid )?frames (.*?); (\d+) holds: (.*)", summary)
    eyes = re.findall(r"  eye (\S+): (\d+) blinks(.*)", summary)
    with cdp.Browser() as b:
        b.open("file://" + os.path.abspath(report))
        for mouth, speech, holds, shapes in mouths:
            want_speech = [] if speech == "none" else [
                [int(a), int(z) + 1] for a, z in re.findall(r"(\d+)-(\d+)(?: \([^)]*\))?", speech)]
            got_speech = b.evaluate(f"[...document.querySelectorAll('svg[data-curve=\"{mouth}\"] rect.speech')].map((r) => [+r.dataset.begin, +r.dataset.end])")
            expect(f"{mouth}: speech intervals", got_speech, want_speech)
            got_shapes = b.evaluate(f"[...document.querySelectorAll('svg[data-mouth=\"{mouth}\"] rect')].map((r) => r.dataset.shape)")
            expect(f"{mouth}: mouth shapes", got_shapes, shapes.split())
            expect(f"{mouth}: holds", len(got_shapes), int(holds))
        for eye, count, rest in eyes:
            want = [[int(f), int(h)] for f, h in re.findall(r"frame (\d+)(?: \([^)]*\))? \(hold (\d+)", rest)]
            got = b.evaluate(f"[...document.querySelectorAll('svg[data-curve=\"{eye}\"] rect.blink')].map((r) => [+r.dataset.closedBegin, +r.dataset.hold])")
            expect(f"{eye}: blinks", got, want)
            expect(f"{eye}: blink count", len(got), int(count))
        plots = b.evaluate("document.querySelectorAll('svg.curve-plot').length")
        expect("curve plots", plots, len(mouths) + len(eyes))
        print(f"ok: {report}: {len(mouths)} mouth and {len(eyes)} eye curves, shapes, speech and blinks as summarised")
        if shot:
            check_screenshot(b, shot)
        if b.errors:
            fail(f"script errors: {b.errors}")


def check_player(report, timing_csv):
    """Steps and plays the player; the counter follows and the figures show the right frames:
    the retimed figure keeps its pose through a hold while the input's moves on."""
    import cdp
    import time
    rows = read_csv(timing_csv)
    n = len(rows)
    pose = ("[...document.querySelectorAll('#%s path.figure')].map((p) => p.getAttribute('d')).join('|')")
    with cdp.Browser() as b:
        b.open("file://" + os.path.abspath(report))
        expect("counter at start", b.evaluate("document.getElementById('counter').textContent").split(" ·")[0], f"frame 0 / {n - 1}")
        before, after = b.evaluate(pose % "before"), b.evaluate(pose % "after")
        frames_before, frames_after = [before], [after]
        for t in range(1, min(n, 40)):
            b.evaluate("document.getElementById('step-forward').click()")
            expect(f"counter after {t} steps", b.evaluate("document.getElementById('counter').textContent").split(" ·")[0], f"frame {t} / {n - 1}")
            expect(f"frame {t}: after figure's source frame",
                   b.evaluate("document.querySelector('#after path.figure').dataset.sourceFrame"), rows[t]["source_frame"])
            frames_before.append(b.evaluate(pose % "before"))
            frames_after.append(b.evaluate(pose % "after"))
        changed = held = 0
        for t in range(1, len(frames_after)):
            same_drawing = rows[t]["source_frame"] == rows[t - 1]["source_frame"]
            if same_drawing:
                expect(f"frame {t}: the retimed pose is held", frames_after[t], frames_after[t - 1])
                held += 1
            else:
                if frames_after[t] == frames_after[t - 1]:
                    fail(f"frame {t}: a new drawing (source {rows[t]['source_frame']}) but the pose did not change")
                changed += 1
        if frames_before[1] == frames_before[0]:
            fail("the input figure did not move from frame 0 to 1")
        # Stepping back, and the scrubber.
        b.evaluate("document.getElementById('step-back').click()")
        expect("counter after a step back", b.evaluate("+document.body.dataset.frame"), len(frames_after) - 2)
        b.evaluate(f"(() => {{ const s = document.getElementById('scrubber'); s.value = {n - 1}; s.dispatchEvent(new Event('input')); }})()")
        expect("counter after scrubbing to the end", b.evaluate("+document.body.dataset.frame"), n - 1)
        # Play from the start: the frame advances in real time, then pause stops it.
        b.evaluate("(() => { const s = document.getElementById('scrubber'); s.value = 0; s.dispatchEvent(new Event('input')); document.getElementById('play').click(); })()")
        deadline = time.monotonic() + 5
        while b.evaluate("+document.body.dataset.frame") < 3 and time.monotonic() < deadline:
            time.sleep(0.05)
        b.evaluate("document.getElementById('play').click()")
        stopped = b.evaluate("+document.body.dataset.frame")
        if stopped < 3:
            fail(f"play did not advance the player within 5 s (frame {stopped})")
        time.sleep(0.3)
        expect("frame after pause", b.evaluate("+document.body.dataset.frame"), stopped)
        if b.errors:
            fail(f"script errors: {b.errors}")
        print(f"ok: {report}: stepped {len(frames_after) - 1} frames ({changed} new drawings, {held} held poses), "
              f"stepped back, scrubbed, played to frame {stopped} and paused")


def check_large(report, timing_csv, max_seconds, max_bytes):
    import cdp
    size = os.path.getsize(report)
    if size > max_bytes:
        fail(f"{report}: {size} bytes, over {max_bytes}")
    rows = read_csv(timing_csv)
    with cdp.Browser(timeout_s=60) as b:
        seconds = b.open("file://" + os.path.abspath(report), ready_timeout_s=max_seconds)
        expect("scrubber max", b.evaluate("+document.getElementById('scrubber').max"), len(rows) - 1)
        band = b.evaluate("[...document.querySelectorAll('#kinds-band rect.kind-H')].reduce((s, r) => s + +r.dataset.count, 0)")
        expect("HELD frames in the band", band, sum(1 for r in rows if r["kind"] == "HELD"))
        points = b.evaluate("+document.getElementById('ssd-curve').dataset.points")
        if points > 2000:
            fail(f"the SSD plot keeps {points} points, want at most 2000")
        # The player keeps every frame: the last one shows its own source frame.
        b.evaluate(f"(() => {{ const s = document.getElementById('scrubber'); s.value = {len(rows) - 1}; s.dispatchEvent(new Event('input')); }})()")
        expect("last frame's source frame", b.evaluate("document.querySelector('#after path.figure').dataset.sourceFrame"), rows[-1]["source_frame"])
        pages = b.evaluate("document.getElementById('sheet-page').textContent")
        if b.errors:
            fail(f"script errors: {b.errors}")
    print(f"ok: {report}: {len(rows)} frames, {size / 1e6:.1f} MB, ready in {seconds:.2f} s "
          f"(limits {max_bytes / 1e6:.0f} MB, {max_seconds} s); SSD plot {points} points; X-sheet {pages}")


def main(argv):
    if len(argv) < 2:
        fail(__doc__)
    command, args = argv[1], argv[2:]
    if command == "validate":
        validate(args)
    elif command == "skeletal":
        check_skeletal(*args)
    elif command == "curves":
        check_curves(*args)
    elif command == "lipblink":
        check_lipblink(*args)
    elif command == "player":
        check_player(*args)
    elif command == "large":
        check_large(args[0], args[1], float(args[2]), int(args[3]))
    else:
        fail(f"unknown command {command}")


if __name__ == "__main__":
    main(sys.argv)
