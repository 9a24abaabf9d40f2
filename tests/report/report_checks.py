"""Checks of koma's HTML reports (docs/report.md), run by report_test.sh.

  report_checks.py validate REPORT...                 HTML5, html5lib's strict parser
  report_checks.py skeletal REPORT TIMING_CSV SUMMARY [SHOT.png]
  report_checks.py curves REPORT DRAWING_CSV SUMMARY [SHOT.png]
  report_checks.py lipblink REPORT SUMMARY [SHOT.png [VALUES_CSV]]
  report_checks.py xdts REPORT XDTS                   the exposure sheet against --xdts
  report_checks.py voice REPORT SUMMARY [SHOT.png]
  report_checks.py audio REPORT SUMMARY
  report_checks.py player REPORT TIMING_CSV
  report_checks.py bones REPORT BVH
  report_checks.py camera REPORT
  report_checks.py large REPORT TIMING_CSV MAX_SECONDS MAX_BYTES
  report_checks.py opens REPORT MAX_SECONDS MAX_BYTES

The oracles are the client's other outputs for the same call: the timing and drawing sheets
(formats/ writers) and the summary it prints, never the report's own data. Exit 1 with
"FAIL: ..." on the first difference."""
import collections
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
    background = collections.Counter(pixels).most_common(1)[0][0]
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


def read_sheet(browser, sheet_id="sheet"):
    """(header, rows) of a paged sheet table: `sheet_id` and its -page, -prev, -next controls."""
    script = SHEET_JS.replace("'sheet-", f"'{sheet_id}-").replace("#sheet ", f"#{sheet_id} ")
    sheet = browser.evaluate(script)
    return sheet["header"], sheet["rows"]


def check_xdts(report, xdts_path):
    """The report's "Exposure sheet (XDTS)" table against the --xdts file of the same call, read
    by the tests' independent reader (OpenToonz's rules, tests/python/xdts_reference.py)."""
    import cdp
    sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "python"))
    import xdts_reference
    with open(xdts_path, "rb") as f:
        sheet = xdts_reference.read(f.read())
    b = cdp.Browser()
    try:
        b.open("file://" + os.path.abspath(report))
        header, rows = read_sheet(b, "xdts-sheet")
        expect("exposure sheet header", header,
               ["frame"] + [n for n, _ in sheet["cells"]] + [n for n, _ in sheet["dialog"]])
        expect("exposure sheet rows", len(rows), sheet["duration"])
        dialog = []
        for _, lines in sheet["dialog"]:
            column = [""] * sheet["duration"]
            for begin, end, values in lines:
                for r in range(begin, end):
                    column[r] = f"{values[0]}: {values[1] if len(values) > 1 else ''}" if r == begin else "|"
            dialog.append(column)
        for r, row in enumerate(rows):
            want = [str(r)]
            for _, cells in sheet["cells"]:
                cell = cells[r]
                want.append("×" if cell is None else cell if r == 0 or cells[r - 1] != cell else "|")
            want += [column[r] for column in dialog]
            expect(f"exposure sheet row {r}", [text for text, _ in row], want)
        if b.errors:
            fail(f"script errors: {b.errors}")
    finally:
        b.close()
    print(f"ok: {report}: the exposure sheet's {len(rows)} rows and {len(header) - 1} columns are "
          f"the --xdts file's")


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
        # Cuts (issue 28): one dashed mark per cut on the speed plot, at the source frame that
        # starts the shot after it, and a legend entry counting them; none on a clip of one shot.
        m = re.search(r"cuts +(\d+); shots retimed separately start at source frames 0, (.*)", summary)
        cuts = [int(v) for v in m.group(2).split(", ")] if m else []
        if m:
            expect("cuts counted in the summary", int(m.group(1)), len(cuts))
        cut_marks = b.evaluate("[...document.querySelectorAll('#ssd-plot line.mark-cut')].map((l) => +l.dataset.frame)")
        expect("cut marks", cut_marks, cuts)
        cut_legend = b.evaluate("[...document.querySelectorAll('.legend > span')].map((e) => e.textContent).filter((t) => t.startsWith('cuts: '))")
        expect("cut legend entries", cut_legend,
               [f"cuts: shots retimed separately ({len(cuts)})"] if cuts else [])
        if cuts:
            # The marks sit at the cut frames' source times on the plot's time axis, in order.
            xs = b.evaluate("[...document.querySelectorAll('#ssd-plot line.mark-cut')].map((l) => +l.getAttribute('x1'))")
            if xs != sorted(xs) or len(set(xs)) != len(xs):
                fail(f"cut marks not at distinct increasing x: {xs}")
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
              f"{len(omitted)} omitted, {len(hidden_marks)} hidden and {len(cut_marks)} cut marks, "
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
    keys = [int(k) for k in summary_field(summary, r"key poses \(\d+[^)]*\): (.*)").group(1).split(",")]
    m = re.search(r"key poses at grid frames (.*)", summary)
    key_rows = [int(k) for k in m.group(1).split(",")] if m else keys
    timings = re.findall(r"  on (\S+): (\d+) drawings \(holds (.*)\) for (.*)", summary)
    fps = Fraction(summary_field(summary, r"frames at (\S+) fps").group(1))
    frames = len(rows)
    with cdp.Browser() as b:
        b.open("file://" + os.path.abspath(report))
        plots = b.evaluate("[...document.querySelectorAll('svg.curve-plot')].map((s) => [s.dataset.curve, s.querySelectorAll('circle.drawing').length, s.querySelectorAll('line.key').length])")
        by_curve = {c: (d, k) for c, d, k in plots}
        # Curves that do not move are folded into one line instead of a plot each.
        flat = b.evaluate("(() => { const p = document.querySelector('p.flat-curves'); return p ? JSON.parse(p.dataset.curves) : []; })()")
        # Every key the summary counts is marked on its curve's plot: filled where drawn.
        m = re.search(r"keys drawn +(\d+) of (\d+)", summary)
        if m:
            marks = b.evaluate("[...document.querySelectorAll('svg.curve-plot path.keymark')].map((k) => +k.dataset.drawn)")
            expect("key marks on the plots", len(marks), int(m.group(2)))
            expect("drawn key marks", sum(marks), int(m.group(1)))
        for on, count, holds, ids in timings:
            for curve in ids.split(", "):
                if curve in flat:
                    continue
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
        expect("KEY rows", [i for i, r in enumerate(sheet) if r[2][0].startswith("KEY")], key_rows)
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
        # The player: the counter names each frame's drawing as the drawing sheet CSV does, and
        # the sheet's current row is the one that lists the frame.
        b.evaluate("(() => { const s = document.getElementById('scrubber'); s.value = 0; s.dispatchEvent(new Event('input')); })()")
        for t in range(min(frames, 60)):
            if t > 0:
                b.evaluate("document.getElementById('step-forward').click()")
            counter = b.evaluate("document.getElementById('counter').textContent")
            m = re.search(r"drawing (\d+) on", counter)
            expect(f"frame {t}: drawing in the counter", int(m.group(1)) - 1, int(rows[t]["drawing"]))
            row = int(b.evaluate("document.querySelector('#sheet tr.current').dataset.row"))
            if grid:
                span = sheet[row][3][0]
                shown = [] if span == "–" else ranges(span.replace("–", "-"))
            else:
                shown = [row]
            if t not in shown:
                fail(f"frame {t}: the sheet's current row {row} lists frames {shown}")
        print(f"ok: {report}: {len(plots)} curves, {len(sheet)} sheet rows, {numbered} drawings, {len(keys)} key poses")
        if shot:
            check_screenshot(b, shot)
        if b.errors:
            fail(f"script errors: {b.errors}")


def check_face(browser, values_csv, mouths, eyes):
    """Steps the face player through every frame: the retimed mouth and eyes show the values
    the client wrote to its CSV output, and open wider exactly when those values are larger."""
    rows = read_csv(values_csv)
    mouth = mouths[0][0] if mouths else None
    eye_ids = [e[0] for e in eyes][:2]
    b = browser
    b.evaluate("(() => { const s = document.getElementById('scrubber'); s.value = 0; s.dispatchEvent(new Event('input')); })()")
    shown = []
    cursor_js = "[...document.querySelectorAll('svg.curve-plot line.cursor')].map((l) => +l.getAttribute('x1'))"
    cursors_at_start = b.evaluate(cursor_js)
    for t, row in enumerate(rows):
        if t > 0:
            b.evaluate("document.getElementById('step-forward').click()")
        got = b.evaluate("[...document.querySelectorAll('#face-after svg.face .mouth'), ...document.querySelectorAll('#face-after svg.face .eye')].map((e) => [e.getAttribute('class'), +e.dataset.value, +e.getAttribute('ry')])")
        mouth_value, mouth_ry = got[0][1], got[0][2]
        if mouth is not None:
            want = float(row[mouth])
            if abs(mouth_value - want) > 1e-5 * max(1.0, abs(want)):
                fail(f"face frame {t}: mouth value {mouth_value}, the CSV says {want}")
            shown.append((want, mouth_ry))
        for i, (cls, value, _) in enumerate(got[1:] if eye_ids else []):
            eye = eye_ids[min(i, len(eye_ids) - 1)]
            want = float(row[eye])
            if abs(value - want) > 1e-5 * max(1.0, abs(want)):
                fail(f"face frame {t}: eye {i} ({eye}) value {value}, the CSV says {want}")
    # The plots' time cursors follow the player: all at one x, further right at the end.
    cursors_at_end = b.evaluate(cursor_js)
    expect("a cursor per plot", len(cursors_at_end), len(mouths) + len(eyes))
    if len(set(cursors_at_end)) != 1 or not cursors_at_end[0] > cursors_at_start[0]:
        fail(f"face: plot cursors at {cursors_at_start} at the start and {cursors_at_end} at the end")
    for (v1, r1) in shown:
        for (v2, r2) in shown:
            if v1 < v2 and r1 > r2:
                fail(f"face: mouth value {v1} drawn wider ({r1}) than {v2} ({r2})")
    print(f"ok: face player: {len(rows)} frames, mouth and eyes as in the CSV output")


def check_lipblink(report, summary_path, shot=None, values_csv=None):
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
        if values_csv:
            check_face(b, values_csv, mouths, eyes)
        print(f"ok: {report}: {len(mouths)} mouth and {len(eyes)} eye curves, shapes, speech and blinks as summarised")
        if shot:
            check_screenshot(b, shot)
        if b.errors:
            fail(f"script errors: {b.errors}")


AUDIO_JS = """new Promise((resolve) => {
  const a = document.getElementById('voice-audio');
  const done = () => resolve({state: a.readyState, duration: a.duration, error: a.error ? a.error.code : null,
                              src: a.getAttribute('src').slice(0, 40), embedded: a.dataset.embedded});
  if (a.readyState >= 1 || a.error) { done(); return; }
  a.addEventListener('loadedmetadata', done);
  a.addEventListener('error', done);
  setTimeout(done, 15000);
})"""


def check_audio(browser, report, summary):
    """The page's <audio> decodes the recording: metadata loaded, no error, its duration the
    summary's within 50 ms."""
    duration = float(summary_field(summary, r"(\S+): ([\d.]+) s, (\d+) Hz, (\d+) channels?").group(2))
    audio = browser.evaluate(AUDIO_JS)
    if audio["error"] is not None or audio["state"] < 1:
        fail(f"{report}: the <audio> did not decode the recording: {audio}")
    if abs(audio["duration"] - duration) > 0.05:
        fail(f"{report}: <audio> lasts {audio['duration']} s, the summary says {duration} s")
    print(f"ok: {report}: <audio> decodes {audio['src']}... ({audio['duration']:.3f} s, "
          f"embedded {audio['embedded']})")


def check_audio_only(report, summary_path):
    import cdp
    with cdp.Browser() as b:
        b.open("file://" + os.path.abspath(report))
        check_audio(b, report, open(summary_path).read())
        if b.errors:
            fail(f"script errors: {b.errors}")


def check_voice(report, summary_path, shot=None):
    """The report of `koma lipblink --audio`: the <audio> element decodes the recording (its
    duration is the summary's), the loudness plot's lines are the summary's noise floor and
    thresholds, its speech the summary's, the player follows the recording while it plays and
    seeks it when stepped."""
    import cdp
    summary = open(summary_path).read()
    head = summary_field(summary, r"(\S+): ([\d.]+) s, (\d+) Hz, (\d+) channels?")
    duration = float(head.group(2))
    levels = summary_field(summary, r"noise floor (-?[\d.]+) dBFS; speech starts above (-?[\d.]+) dBFS, "
                                    r"stays above (-?[\d.]+) dBFS; loud (-?[\d.]+) dBFS")
    speech_text = summary_field(summary, r"  mouth \S+: speech at (?:grid )?frames (.*?); \d+ holds").group(1)
    want_speech = [] if speech_text == "none" else [
        [int(a), int(z) + 1] for a, z in re.findall(r"(\d+)-(\d+)(?: \([^)]*\))?", speech_text)]
    with cdp.Browser() as b:
        b.open("file://" + os.path.abspath(report))
        check_audio(b, report, summary)
        got = b.evaluate("Object.fromEntries([...document.querySelectorAll('svg.loudness-plot line.level')].map((l) => [l.classList[1], +l.dataset.dbfs]))")
        for name, index in (("noise-floor", 1), ("threshold-start", 2), ("threshold-stay", 3), ("loud-level", 4)):
            want = float(levels.group(index))
            if name not in got or abs(got[name] - want) > 0.051:
                fail(f"{report}: {name} line at {got.get(name)} dBFS, the summary says {want}")
        expect("speech shaded under the loudness",
               b.evaluate("[...document.querySelectorAll('svg.loudness-plot rect.speech')].map((r) => [+r.dataset.begin, +r.dataset.end])"),
               want_speech)
        # One loudness step per grid frame of the recording (fewer than 2000: not thinned).
        points = b.evaluate("+document.querySelector('svg.loudness-plot path.loudness').dataset.points")
        frames = duration * 24
        if not (frames - 1 <= points <= frames + 1):
            fail(f"{report}: {points} loudness points for {duration} s on the 24 fps grid")
        print(f"ok: {report}: loudness ({points} grid frames), floor and thresholds, {len(want_speech)} speech intervals as summarised")
        # Stepping seeks the recording to the frame's time.
        fps = b.evaluate("KOMA.fps")
        b.evaluate("(() => { const s = document.getElementById('scrubber'); s.value = 0; s.dispatchEvent(new Event('input')); })()")
        for _ in range(7):
            b.evaluate("document.getElementById('step-forward').click()")
        t = b.evaluate("new Promise((r) => setTimeout(() => r(document.getElementById('voice-audio').currentTime), 200))")
        if abs(t - 7 / fps) > 0.01:
            fail(f"{report}: after 7 steps the recording is at {t} s, want {7 / fps:.4f}")
        # Play: the recording plays and the face shows the frame at its current time.
        b.evaluate("document.getElementById('play').click()")
        state = b.evaluate("""new Promise((r) => setTimeout(() => {
          const a = document.getElementById('voice-audio');
          r({paused: a.paused, time: a.currentTime, frame: +document.body.dataset.frame});
        }, 700))""")
        if state["paused"] or state["time"] < 7 / fps + 0.2:
            fail(f"{report}: Play did not play the recording: {state}")
        lag = state["time"] * fps - state["frame"]
        if not (-1 <= lag <= 4):
            fail(f"{report}: playing, the face shows frame {state['frame']} at {state['time']:.3f} s ({lag:.1f} frames off)")
        b.evaluate("document.getElementById('play').click()")
        if not b.evaluate("document.getElementById('voice-audio').paused"):
            fail(f"{report}: Pause did not pause the recording")
        print(f"ok: {report}: stepping seeks the recording; Play plays it and the face follows "
              f"(frame {state['frame']} at {state['time']:.3f} s)")
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
        # The onion skin is the input's pose at the same time, and goes with its checkbox.
        ghost = "[...document.querySelectorAll('#after path.ghost')].map((p) => p.getAttribute('d')).join('|')"
        expect("onion skin = the input's pose", b.evaluate(ghost), frames_before[-1])
        b.evaluate("document.getElementById('onion').click()")
        expect("onion skin off", b.evaluate(ghost).strip("|"), "")
        b.evaluate("document.getElementById('onion').click()")
        expect("onion skin on again", b.evaluate(ghost), frames_before[-1])
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
        # The keyboard: arrows step once per press, from the page and from the focused scrubber.
        def press(key, code):
            for kind in ("keyDown", "keyUp"):
                b.call("Input.dispatchKeyEvent", type=kind, key=key, code=key, windowsVirtualKeyCode=code)
        b.evaluate("(() => { const s = document.getElementById('scrubber'); s.value = 10; s.dispatchEvent(new Event('input')); s.blur(); })()")
        press("ArrowRight", 39)
        press("ArrowRight", 39)
        press("ArrowLeft", 37)
        expect("frame after right, right, left", b.evaluate("+document.body.dataset.frame"), 11)
        b.evaluate("document.getElementById('scrubber').focus()")
        press("ArrowRight", 39)
        expect("frame after right on the focused scrubber", b.evaluate("+document.body.dataset.frame"), 12)
        if b.errors:
            fail(f"script errors: {b.errors}")
        print(f"ok: {report}: stepped {len(frames_after) - 1} frames ({changed} new drawings, {held} held poses), "
              f"stepped back, scrubbed, played to frame {stopped} and paused")


def bvh_bone_lengths(path):
    """Per joint (BVH declaration order): the length of its OFFSET, the bone from its parent.
    End Sites are not joints. Only valid where non-root joints have no position channels."""
    lengths = []
    in_end_site = False
    for line in open(path):
        words = line.split()
        if not words:
            continue
        if words[0] == "MOTION":
            break
        if words[0] == "End":
            in_end_site = True
        elif words[0] == "}" and in_end_site:
            in_end_site = False
        elif words[0] == "OFFSET" and not in_end_site:
            x, y, z = (float(w) for w in words[1:4])
            lengths.append((x * x + y * y + z * z) ** 0.5)
    return lengths


def check_bones(report, bvh):
    """The figures are the clip's skeleton: every bone, rebuilt in 3D from the front (x, y) and
    side (z, y) views the page draws, is as long as its BVH OFFSET in every frame stepped
    through, within the positions' rounding. Checks forward kinematics, the packing, the
    page's unpacking and drawing together."""
    import cdp
    want = bvh_bone_lengths(bvh)[1:]  # the root has no bone
    segments = ("[...document.querySelectorAll('#%s path.figure')].map((p) => "
                "p.getAttribute('d').split('M').filter((s) => s).map((s) => s.split(/[ L]/).map(Number)))")
    worst = 0.0
    with cdp.Browser() as b:
        b.open("file://" + os.path.abspath(report))
        step = b.evaluate("KOMA.pose.step")
        frames = b.evaluate("+document.getElementById('scrubber').max") + 1
        for t in range(0, frames, max(1, frames // 25)):
            b.evaluate(f"(() => {{ const s = document.getElementById('scrubber'); s.value = {t}; s.dispatchEvent(new Event('input')); }})()")
            for side in ("before", "after"):
                front, profile = b.evaluate(segments % side)
                expect(f"frame {t} {side}: bones", len(front), len(want))
                for i, ((x1, y1, x2, y2), (z1, _, z2, _), length) in enumerate(zip(front, profile, want)):
                    got = ((x2 - x1) ** 2 + (y2 - y1) ** 2 + (z2 - z1) ** 2) ** 0.5
                    worst = max(worst, abs(got - length))
                    # Each end rounded by half a step per axis: at most sqrt(3) steps apart.
                    if abs(got - length) > 1.8 * step:
                        fail(f"frame {t} {side}: bone {i + 1} is {got:.4f} long, its OFFSET {length:.4f} (step {step})")
        if b.errors:
            fail(f"script errors: {b.errors}")
    print(f"ok: {report}: {len(want)} bones as long as their OFFSETs in every frame checked "
          f"(worst {worst:.4f}, step {step:.4f})")


def check_camera(report):
    """write_camera_report's call: one 'camera' view per side, each bone drawn where the
    camera puts it (recomputed here), the retimed figure on twos."""
    import cdp
    import math

    def project(x, y, z):
        w = 1 + 0.01 * z
        return 0.1 * x / w, 0.2 * y / w

    def pose(f):
        return [project(0.5 * f, 0, 0), project(0.5 * f + math.sin(f), 10, math.cos(f))]

    with cdp.Browser() as b:
        b.open("file://" + os.path.abspath(report))
        views = b.evaluate("[...document.querySelectorAll('path.figure')].map((p) => p.dataset.view)")
        expect("views", views, ["camera", "camera"])
        step = b.evaluate("KOMA.pose.step")
        worst = 0.0
        for t in range(48):
            if t > 0:
                b.evaluate("document.getElementById('step-forward').click()")
            for side, frame in (("before", t), ("after", t - t % 2)):
                d = b.evaluate(f"document.querySelector('#{side} path.figure').getAttribute('d')")
                got = [float(v) for v in re.split(r"[ML ]+", d) if v]
                want = [c for point in pose(frame) for c in point]
                for g, w in zip(got, want):
                    worst = max(worst, abs(g - w))
                    if abs(g - w) > step / 2 + 1e-5:
                        fail(f"frame {t} {side}: drew {got}, the camera puts the bone at {want} (step {step})")
                expect(f"frame {t} {side}: coordinates", len(got), 4)
        if b.errors:
            fail(f"script errors: {b.errors}")
    print(f"ok: {report}: one camera view per side, 48 frames projected within half a step "
          f"(worst {worst:.2e}, step {step:.2e}), the retimed figure on twos")


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


def check_opens(report, max_seconds, max_bytes):
    """Any report: under max_bytes, ready within max_seconds, every plot line thinned."""
    import cdp
    size = os.path.getsize(report)
    if size > max_bytes:
        fail(f"{report}: {size} bytes, over {max_bytes}")
    with cdp.Browser(timeout_s=60) as b:
        seconds = b.open("file://" + os.path.abspath(report), ready_timeout_s=max_seconds)
        points = b.evaluate("Math.max(0, ...[...document.querySelectorAll('path.before, path.after')].map((p) => (p.getAttribute('d').match(/[MLH]/g) || []).length))")
        # A thinned plot has at most 2000 points; a stepped one two commands per point.
        if points > 2 * 2000 + 2:
            fail(f"{report}: a plot line has {points} points")
        rows = b.evaluate("document.getElementById('sheet-page') ? document.getElementById('sheet-page').textContent : 'no sheet'")
        if b.errors:
            fail(f"script errors: {b.errors}")
    print(f"ok: {report}: {size / 1e6:.1f} MB, ready in {seconds:.2f} s (limits {max_bytes / 1e6:.0f} MB, "
          f"{max_seconds} s); longest plot line {points} points; sheet {rows}")


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
    elif command == "xdts":
        check_xdts(*args)
    elif command == "voice":
        check_voice(*args)
    elif command == "audio":
        check_audio_only(*args)
    elif command == "player":
        check_player(*args)
    elif command == "camera":
        check_camera(*args)
    elif command == "bones":
        check_bones(*args)
    elif command == "opens":
        check_opens(args[0], float(args[1]), int(args[2]))
    elif command == "large":
        check_large(args[0], args[1], float(args[2]), int(args[3]))
    else:
        fail(f"unknown command {command}")


if __name__ == "__main__":
    main(sys.argv)
