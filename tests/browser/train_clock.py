"""The haptic worker's own 1 kHz clock (train_test.py --real-clock): its jitter, the first frame and
the page's WebGL frames (interval and drawing time), printed, never asserted."""
import os
import re
import subprocess

from browser_test import check
from train_fluoro import FLUORO_NOTE_JS
from train_page import END_JS, end_of_run, open_assignment
from selenium.webdriver.common.action_chains import ActionChains
from selenium.webdriver.common.by import By
from selenium.webdriver.common.keys import Keys


CLOCK_NOTE = re.compile(
    r"Haptic clock: (\d+) ticks, interval p50 ([0-9.]+) ms, p99 ([0-9.]+) ms, max ([0-9.]+) ms, (\d+) dropped; "
    r"lateness p50 ([0-9.]+) ms, p99 ([0-9.]+) ms, max ([0-9.]+) ms; a tick's run p50 ([0-9.]+) ms, p99 ([0-9.]+) ms; "
    r"late ticks after a sleep (\d+), after ticks (\d+), after the event loop (\d+), caught up (\d+)\.$")
DRAW_NOTE = re.compile(r"Page: (\d+) frames drawn, interval p50 ([0-9.]+) ms, p99 ([0-9.]+) ms; drawing p50 ([0-9.]+) ms, p99 ([0-9.]+) ms; "
                       r"(\d+) held back by the frame budget(?:; (?:at most (\d+) a second|no cap) \(WebGL: (.*)\))?\.$")
FRAME_NOTE = re.compile(r"First frame (\d+) ms after choosing the case(?: \(the session opened in (\d+) ms\))?\.$")


def clock_figures(b):
    """The page's clock note and first-frame note as figures (what scripts/bench train prints)."""
    text = b.js("return document.getElementById('clock-note').textContent")
    m = CLOCK_NOTE.match(text)
    check(m is not None, "the page's clock note: %r" % text)
    g = m.groups()
    jitter = {"ticks": int(g[0]), "p50_ms": float(g[1]), "p99_ms": float(g[2]), "max_ms": float(g[3]), "dropped": int(g[4]),
              "late_p50_ms": float(g[5]), "late_p99_ms": float(g[6]), "late_max_ms": float(g[7]), "tick_p50_ms": float(g[8]),
              "tick_p99_ms": float(g[9]), "late_ticks": {"after_sleep": int(g[10]), "after_ticks": int(g[11]),
                                                          "after_yield": int(g[12]), "catch_up": int(g[13])}}
    text = b.js("return document.getElementById('frame-note').textContent")
    f = FRAME_NOTE.match(text)
    check(f is not None, "the page's first-frame note: %r" % text)
    d = DRAW_NOTE.match(b.js("return document.getElementById('draw-note').textContent"))
    check(d is not None, "the page's drawing note: %r" % b.js("return document.getElementById('draw-note').textContent"))
    frames = {"frames": int(d.group(1)), "interval_p50_ms": float(d.group(2)), "interval_p99_ms": float(d.group(3)),
              "draw_p50_ms": float(d.group(4)), "draw_p99_ms": float(d.group(5)), "held_back": int(d.group(6)),
              "fps_cap": int(d.group(7)) if d.group(7) else None, "webgl": d.group(8)}
    return jitter, int(f.group(1)), int(f.group(2)) if f.group(2) else None, frames


def rig_priority(b, source, fifo=None, slice_us=None, gpu=None):
    """What a kiosk rig's launcher may do for the page (never the page itself, which cannot):
    scripts/rig-priority gives the browser's worker threads SCHED_FIFO `fifo`, as the native haptic
    thread runs (needs CAP_SYS_NICE), or keeps them SCHED_OTHER with an EEVDF slice of `slice_us`
    (no capability for the user's own browser), or lowers the GPU process (`gpu`: idle, SCHED_IDLE,
    or a nice value; no capability either; scripts/train-browser does it; with fifo or slice_us too).
    The threads changed."""
    changed = 0
    for how in (["--fifo", str(fifo)] if fifo else ["--slice", str(slice_us)] if slice_us else None, ["--gpu", str(gpu)] if gpu else None):
        if not how:
            continue
        out = subprocess.run([os.path.join(source, "scripts/rig-priority"), "--once", *how,
                              "--under", str(b.driver.service.process.pid)], capture_output=True, text=True)
        check(out.returncode == 0, "scripts/rig-priority: %s" % out.stderr.strip())
        changed += len(out.stdout.splitlines())
    return changed


def test_real_clock(b, centre, assignment, seconds, report, view, spin=None, fifo=None, query=None, slice_us=None, gpu=None):
    """The worker's own 1 kHz clock for `seconds`, W held (and Space, the pedal, in fluoroscopy),
    then Escape: jitter and first frame, with the machine's load average. `fifo`: the rig's
    launcher gives the workers' threads that real-time priority (rig_priority) once the run starts.
    `query`: more of the page's options (e.g. `frame_ms=50`). `slice_us`: the launcher gives them that
    EEVDF slice instead (rig_priority). `gpu`: the launcher lowers the GPU process instead (idle or a nice value)."""
    open_assignment(b, assignment, "real", view, spin, query)
    raised = rig_priority(b, centre.args.source, fifo, slice_us, gpu) if fifo or slice_us or gpu else 0
    body = b.driver.find_element(By.TAG_NAME, "body")
    keys = ["w", Keys.SPACE] if view == "fluoro" else ["w"]
    down = ActionChains(b.driver)
    for k in keys:
        down.key_down(k, body)
    down.perform()
    load_before = os.getloadavg()[0]
    b.wait_js("const m = document.getElementById('hud').textContent.match(/^time +([0-9.]+) s/m); return m && Number(m[1]) >= %d;" % seconds,
              "%d s of ticks on the worker's clock" % seconds, timeout=seconds * 10 + 30)
    up = ActionChains(b.driver)
    for k in reversed(keys):
        up.key_up(k)
    up.send_keys(Keys.ESCAPE).perform()
    state = b.wait_js(END_JS, "the upload")
    b.shot("train-real-clock-" + view)
    check(state == "done", "the real-clock run's upload: %s" % state)
    end, _, _ = end_of_run(b, centre)
    jitter, first_ms, open_ms, frames = clock_figures(b)
    report.setdefault("real_clock", {})[view] = {
        "jitter": jitter, "first_frame_ms": first_ms, "open_ms": open_ms, "frames": frames, "end": end,
        "load_average": [round(load_before, 2), round(os.getloadavg()[0], 2)], "spin_ms": spin, "fifo_threads": raised if fifo and not gpu else 0,
        "slice_us": slice_us, "slice_threads": raised if slice_us else 0, "gpu": gpu, "gpu_threads": raised if gpu else 0, "query": query,
        "fluoro": b.js(FLUORO_NOTE_JS) if view == "fluoro" else None}
