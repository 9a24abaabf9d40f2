"""koma's page in Debian's headless chromium, as a person uses it (docs/page.md): open the
page, give the file input a file (DOM.setFileInputFiles), choose the command and a preset,
press Enter in an option field, wait for the report to draw in its frame, download every file
the page offers (Browser.setDownloadBehavior), and check each is byte for byte what the real
`koma` CLI writes with the command line the page shows. Screenshots at 1280 and 390 px wide:
not blank, the report's figure drawn inside the frame.

  page_browser.py URL KOMA GRPC_TARGET SAMPLES TESTDATA WORK
"""
import os
import shlex
import shutil
import subprocess
import sys
import time

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "report"))
from cdp import Browser  # noqa: E402
from report_checks import check_screenshot  # noqa: E402

url, koma, target, samples, testdata, work = sys.argv[1:7]
koma, samples, testdata, work = (os.path.abspath(p) for p in (koma, samples, testdata, work))

# (file, command, the page's fields to set, the number field Enter is pressed in)
CASES = [
    (f"{samples}/pitch.bvh", "skeletal", {"preset": "twos"}, "omit"),
    (f"{samples}/arm_head.motion3.json", "curves", {"preset": "snappy", "tame": "1.5"}, "tsume"),
    (f"{testdata}/spine/hero-4.2.json", "curves", {"preset": "threes"}, "tame"),
    (f"{samples}/wave.glb", "skeletal", {"preset": "threes"}, "omit"),
    (f"{samples}/voice.flac", "lipblink", {"preset": "subtle", "seed": "7"}, "auto_blink"),
]


def fail(message):
    print(f"FAIL: {message}", file=sys.stderr)
    sys.exit(1)


def wait_for(browser, expression, what, seconds=30):
    deadline = time.monotonic() + seconds
    while time.monotonic() < deadline:
        value = browser.evaluate(expression)
        if value:
            return value
        time.sleep(0.05)
    status = browser.evaluate("document.getElementById('status').textContent")
    fail(f"{what}: not within {seconds} s (status: {status!r}; errors {browser.errors})")


def browser_call(browser, method, **params):
    """A Browser-domain call: sent to the browser, not the page's session."""
    session, browser.session = browser.session, None
    try:
        return browser.call(method, **params)
    finally:
        browser.session = session


def set_file(browser, path):
    root = browser.call("DOM.getDocument", depth=0)["root"]["nodeId"]
    node = browser.call("DOM.querySelector", nodeId=root, selector="#file")["nodeId"]
    browser.call("DOM.setFileInputFiles", files=[path], nodeId=node)


def press_enter(browser):
    for kind in ("rawKeyDown", "char", "keyUp"):
        params = {"type": kind, "key": "Enter", "code": "Enter", "windowsVirtualKeyCode": 13}
        if kind == "char":
            params["text"] = "\r"
        browser.call("Input.dispatchKeyEvent", **params)


def cli_files(command_line, source):
    """The page's command line run by the real koma on the file in a fresh folder."""
    words = shlex.split(command_line)
    if words[0] != "koma":
        fail(f"the page's command line does not start with koma: {command_line}")
    folder = os.path.join(work, "cli-" + os.path.basename(source))
    shutil.rmtree(folder, ignore_errors=True)
    os.makedirs(folder)
    shutil.copy(source, folder)
    run = subprocess.run([koma] + words[1:] + ["--server", target, "--quiet"], cwd=folder,
                         capture_output=True, text=True, timeout=60)
    if run.returncode != 0:
        fail(f"{command_line}: exit {run.returncode}: {run.stderr}")
    return folder


def download_all(browser, downloads, names):
    for name in names:
        path = os.path.join(downloads, name)
        if os.path.exists(path):
            os.remove(path)
    # One click at a time, each as a person's (a user gesture: chromium holds back a page's
    # later downloads that come without one).
    for i, name in enumerate(names):
        browser.call("Runtime.evaluate", userGesture=True, returnByValue=True,
                     expression=f"document.querySelectorAll('#downloads a')[{i}].click()")
        path = os.path.join(downloads, name)
        deadline = time.monotonic() + 20
        while not (os.path.exists(path) and not os.path.exists(path + ".crdownload")):
            if time.monotonic() > deadline:
                fail(f"download {name}: not in {downloads} within 20 s: {os.listdir(downloads)}")
            time.sleep(0.05)


def run_case(browser, downloads, source, command, fields, enter_field):
    name = os.path.basename(source)
    browser.evaluate("document.getElementById('report').dataset.shown = 'old'; true")
    set_file(browser, source)
    wait_for(browser, f"document.querySelector('#about dd') && document.querySelector('#about dd').textContent.startsWith({name!r}) && !document.getElementById('command').disabled",
             f"{name}: inspected")
    about = browser.evaluate("[...document.querySelectorAll('#about dt')].map((d) => d.textContent + ': ' + d.nextElementSibling.textContent).join('; ')")
    commands = browser.evaluate("[...document.getElementById('command').options].map((o) => o.value)")
    if command not in commands:
        fail(f"{name}: the page offers {commands}, not {command}")
    # A person picks the command, then the fields (the command's own fieldset appears).
    browser.evaluate(f"""(() => {{
      const c = document.getElementById('command');
      c.value = {command!r}; c.dispatchEvent(new Event('change'));
      const set = {fields!r};
      for (const [key, value] of Object.entries(set)) {{
        const field = [...document.querySelectorAll('[name="' + key + '"]')].find((f) => !f.matches(':disabled'));
        field.value = value; field.dispatchEvent(new Event('change'));
      }}
      return true; }})()""")
    enter = browser.evaluate(f"(() => {{ const f = document.getElementById({enter_field!r}); f.focus(); return document.activeElement === f && !f.matches(':disabled'); }})()")
    if not enter:
        fail(f"{name}: cannot focus #{enter_field}")
    start = time.monotonic()
    press_enter(browser)  # Enter in a field runs the job (the form's submit)
    wait_for(browser, "document.getElementById('report').dataset.shown === 'ready'", f"{name}: report drawn")
    seconds = time.monotonic() - start
    figures = int(browser.evaluate("document.getElementById('report').dataset.figures"))
    if figures < 1:
        fail(f"{name}: the report drew no figure")
    command_line = browser.evaluate("document.getElementById('command-line').textContent")
    links = browser.evaluate("[...document.querySelectorAll('#downloads a')].map((a) => [a.dataset.role, a.download])")
    roles = [role for role, _ in links]
    want = ["result", "xdts", "report"] if command == "lipblink" else ["result", "timing", "xdts", "report"]
    if roles != want:
        fail(f"{name}: downloads {roles}, want {want}")
    download_all(browser, downloads, [n for _, n in links])
    folder = cli_files(command_line, source)
    for role, file_name in links:
        with open(os.path.join(downloads, file_name), "rb") as f:
            page_bytes = f.read()
        with open(os.path.join(folder, file_name), "rb") as f:
            cli_bytes = f.read()
        if page_bytes != cli_bytes:
            fail(f"{name}: {role} {file_name}: {len(page_bytes)} bytes from the page, "
                 f"{len(cli_bytes)} from `{command_line}`: they differ")
    print(f"ok: {name}: {about}; `{command_line}`; {len(links)} downloads equal to the CLI's; "
          f"report with {figures} figures in {seconds:.2f} s")


def frame_strokes(browser, shot, orange_only):
    """A screenshot to `shot`, and the figure strokes drawn inside the report's frame: orange
    (#d2572b, the retimed figure) and, unless `orange_only`, blue (the input's). At a phone's
    width the report's before and after views sit side by side and the after one may be
    scrolled out of the frame."""
    from PIL import Image
    browser.screenshot(shot)
    image = Image.open(shot).convert("RGB")
    box = browser.evaluate("(() => { const r = document.getElementById('report').getBoundingClientRect();"
                           " return [r.left + scrollX, r.top + scrollY, r.width, r.height]; })()")
    x, y, w, h = (int(v) for v in box)
    return sum(1 for (r, g, bl) in image.crop((x, y, x + w, y + h)).getdata()
               if (r > 180 and 60 < g < 120 and bl < 80) or
               (not orange_only and bl > 140 and r < 90 and g < 150))


def check_error_shown(browser):
    """A value out of range: koma's own message in the status line, marked as an error."""
    set_file(browser, f"{samples}/arm_head.motion3.json")
    wait_for(browser, "document.querySelector('#about dd').textContent.startsWith('arm_head') && !document.getElementById('command').disabled",
             "arm_head.motion3.json: inspected")
    browser.evaluate("""(() => { const c = document.getElementById('command'); c.value = 'curves';
      c.dispatchEvent(new Event('change')); const t = document.getElementById('tame');
      t.value = '0.5'; t.focus(); return true; })()""")
    press_enter(browser)
    want = "--tame: 0.5 is out of range"
    status = wait_for(browser, f"(() => {{ const s = document.getElementById('status'); return s.className === 'error' && s.textContent.includes({want!r}) && s.textContent; }})()",
                      "the out-of-range --tame shown")
    if "--help" in status:
        fail(f"the status points at --help: {status}")
    browser.evaluate("document.getElementById('tame').value = ''; true")
    print(f"ok: an out-of-range value: the status says {status!r}")


def main():
    downloads = os.path.join(work, "downloads")
    os.makedirs(downloads, exist_ok=True)
    with Browser(width=1280, height=900, timeout_s=30) as b:
        browser_call(b, "Browser.setDownloadBehavior", behavior="allow", downloadPath=downloads)
        b.call("Page.navigate", url=url)
        wait_for(b, "document.readyState === 'complete' && !!document.getElementById('file')", "page loaded", 10)
        for source, command, fields, enter_field in CASES:
            run_case(b, downloads, source, command, fields, enter_field)
        check_error_shown(b)
        if b.errors:
            fail(f"script errors on the page: {b.errors}")
        # The last report (the voice's) and, re-run, the pitch's at both widths.
        run_case(b, downloads, *CASES[0])
        for width in (1280, 390):
            b.call("Emulation.setDeviceMetricsOverride", width=width, height=900,
                   deviceScaleFactor=1, mobile=width < 600)
            time.sleep(0.3)
            # The whole page in the window: chromium paints the report's frame (a process of
            # its own, being sandboxed) only within the window, not beyond it.
            height = min(8000, b.evaluate("document.documentElement.scrollHeight"))
            b.call("Emulation.setDeviceMetricsOverride", width=width, height=height,
                   deviceScaleFactor=1, mobile=width < 600)
            time.sleep(0.5)
            overflow = b.evaluate("document.documentElement.scrollWidth - document.documentElement.clientWidth")
            if overflow > 0:
                fail(f"{width} px: the page is {overflow} px wider than the window")
            shot = os.path.join(shots, f"page_{width}.png")
            # The frame repaints on its own after the resize: wait (bounded) for its strokes.
            wide = width >= 1000
            deadline = time.monotonic() + 15
            while frame_strokes(b, shot, wide) < 50 and time.monotonic() < deadline:
                time.sleep(0.25)
            if wide:
                check_screenshot(b, shot, "#report")  # the retimed figure's orange strokes
            else:
                check_screenshot(b, shot)
                strokes = frame_strokes(b, shot, False)
                if strokes < 50:
                    fail(f"{shot}: no figure strokes in the report's frame ({strokes} pixels)")
                print(f"ok: {shot}: {strokes} figure-stroke pixels in the report's frame")


shots = os.environ.get("KOMA_PAGE_SHOTS") or work
os.makedirs(shots, exist_ok=True)
main()
