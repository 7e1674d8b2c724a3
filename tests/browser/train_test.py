#!/usr/bin/python3
"""The trainee's simulator in the browser (/train.html, issue 36) in headless Chromium.

A cathbox-server on a fresh SQLite store, serving the WebAssembly session (--wasm), with the
Y-bifurcation case assigned to a trainee. The trainee logs in, opens the assignment on
/train.html?clock=virtual (the worker has no clock of its own: the test advances it by exact tick
counts with the page's "Run N ticks" control, so the run is the same on any machine) and drives the guidewire with the native trainer's
keys, held as a person would: Shift+W to 40 mm, Shift+A a full turn, then W until the tip reaches
the target, while an instructor watches the browser's rig live (its tip moves on /live.html). The
page uploads the record; the server accepts it only if every state hash
replays (201), and `cathbox session replay --check` replays the stored record natively.
Screenshots (3D) go to --out. Any SEVERE console message fails the test. Last, on the server
restarted without --wasm, opening a case shows one line naming what is missing. On a two-tool
case (neuro), Tab hands over the other tool and Escape ends the run, uploaded. A native record
(`cathbox session run --virtual`) given to the page's "Check a record" file input replays in the
worker with every state hash checked (passed, all ticks); the same record with one byte changed
is refused, the page saying why, and so is the record against another case's (neuro) surface (a
state hash differs at a tick).

The box path (issue 36, "the emulated box in the browser's place"): cathbox-emu runs with its
scripted hand pushing the wire at 20 mm/s, cathbox-box-bridge puts it on a WebSocket, and the
page opened with ?box=ws://... reads the state reports through protocol/'s wasm codec: the held
tool follows the emulator's encoder (no key pressed), and the emulator's own reports show the
page's commands applied (its command echo, the command-fresh and output-enabled bits, the brake
mode, no latched fault: the watchdog fault latched before the first command was acknowledged).
The page runs on the worker's own clock here (the emulator runs in real time); every wait is for
an event, bounded. The longest gap between the page's commands is checked against the longest gap
between the box's reports (one send period more at most), not against the wall clock; both are
printed (the box's watchdog is 50 ms). Then GET_REPORT through the bridge by hand (an answer, a
refusal) and a 37-byte message from the page, refused by the bridge with one line naming its length.

The WebHID path (test_webhid): tests/browser/fake_webhid.js stands in for navigator.hid (no USB
here, no HID device in headless Chromium), speaking protocol/'s codec; in virtual time, the page
reads the box's feature reports, moves the tool by the box's own calibration, and sends the held
tool's law as the native driver shapes it; a box not calibrated is refused.

With --real-clock it also runs the page on the worker's own 1 kHz clock for a few seconds and
reports the tick-interval jitter and the first-frame time (a wall-clock figure: printed, never
asserted).

The page carries no test hook: the test reads it as a user does, from the page (the status, the
HUD's figures, the notes under the keys, the box's figures, the end card, the record check's line,
the record download) and from the server (the stored result, as the trainee's own API call). The
WebHID part also reads what the box received from window.fakeBox, the test's own stand-in.

  tests/browser/train_test.py --bin build/release/bin --wasm build/wasm/bin --source . --out build/release/browser
"""
import argparse
import json
import math
import os
import re
import subprocess
import sys
import tempfile
import time
import traceback

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from browser_test import Api, Browser, Centre, Failure, check, wait_until  # noqa: E402
from png_pixels import grey  # noqa: E402
from selenium.webdriver.common.action_chains import ActionChains  # noqa: E402
from selenium.webdriver.common.by import By  # noqa: E402
from selenium.webdriver.common.keys import Keys  # noqa: E402
from selenium.webdriver.support import expected_conditions as EC  # noqa: E402


def seed(centre):
    teacher = Api(centre.base).login("teacher")
    cases = os.path.join(centre.args.source, "cases")
    teacher.json("POST", "/cases", {
        "name": "ybif", "case_file": "y_bifurcation.case", "case": open(os.path.join(cases, "y_bifurcation.case")).read(),
        "hclm_file": "y_bifurcation.hclm", "hclm": open(os.path.join(cases, "y_bifurcation.hclm")).read()})
    _, a = teacher.json("POST", "/assignments", {
        "trainee": "ann", "case": "ybif", "note": "Left branch, in the browser.",
        "criteria": [{"metric": "peak_wall_force_mN", "op": "<=", "value": 400}]})
    # Two tools (catheter, guidewire): Tab hands over the other one.
    teacher.json("POST", "/cases", {
        "name": "neuro", "case_file": "neuro.case", "case": open(os.path.join(cases, "neuro.case")).read(),
        "hclm_file": "neuro.hclm", "hclm": open(os.path.join(cases, "neuro.hclm")).read()})
    _, two = teacher.json("POST", "/assignments", {"trainee": "ann", "case": "neuro", "criteria": []})
    return a["id"], two["id"]


STATE_JS = "return document.getElementById('status').textContent"
# The end of a run as the page shows it: 'done' (uploaded and checked), 'refused', 'error' (the
# page's error line), else null.
END_JS = ("const u = document.getElementById('upload').textContent; const e = document.getElementById('error');"
          "return u.startsWith('Uploaded and checked') ? 'done' : u.startsWith('The server refused') ? 'refused'"
          " : !e.hidden && e.textContent ? 'error' : null;")


def hud(b):
    """The HUD's figures: time_s, tool, insertion_mm, rotation_rad."""
    text = b.js("return document.getElementById('hud').textContent")
    f = dict(re.findall(r"^(time|tool|insertion|rotation) +(\S+)", text, re.M))
    return {"time_s": float(f["time"]), "tool": f["tool"], "insertion_mm": float(f["insertion"]), "rotation_rad": float(f["rotation"])}


def end_of_run(b, centre):
    """After the upload: the end card's reason, the record's size, a metric, and the stored
    result the trainee's own API gives (the debrief link's id)."""
    title = b.js("return document.getElementById('end-title').textContent")
    end = re.match(r"End of run: (.*) \(", title).group(1)
    link = b.js("const a = document.querySelector('#upload a[href^=\"/debrief.html\"]'); return a ? a.getAttribute('href') : null;")
    check(link is not None, "the end card's debrief link: %r" % b.js("return document.getElementById('upload').textContent"))
    _, result = Api(centre.base).login("ann").json("GET", "/results/%s" % link.split("id=")[1])
    record_bytes = int(re.search(r"\((\d+) bytes\)", b.js("return document.getElementById('record-download').textContent")).group(1))
    return end, result, record_bytes


def open_assignment(b, assignment, clock, view=None):
    query = [("clock=virtual" if clock == "virtual" else None), ("view=" + view if view else None)]
    b.open("/train.html" + ("?" + "&".join(q for q in query if q) if any(query) else ""))
    b.wait(EC.element_to_be_clickable((By.CSS_SELECTOR, "button.open-case[data-id='%d']" % assignment)), "the assignment's Run button")
    check(b.js("return self.crossOriginIsolated"), "the page is not cross-origin isolated (COOP/COEP headers)")
    b.driver.find_element(By.CSS_SELECTOR, "button.open-case[data-id='%d']" % assignment).click()
    b.wait_js("return document.getElementById('status').textContent === 'running' && document.getElementById('hud').textContent !== ''",
              "the session to start in the worker")
    b.wait_js("return document.getElementById('frame-note').textContent.startsWith('First frame')", "the first frame")


def advance(b, ticks):
    """The page's virtual clock: N ticks run with its "Run N ticks" control; the ticks it ran."""
    note = b.js("return document.getElementById('step-note').textContent")
    k = int(note.split(":")[0].split()[1]) + 1 if note.startswith("step ") else 1
    b.js("document.getElementById('step-ticks').value = arguments[0]; document.getElementById('step').click();", ticks)
    done = b.wait_js("const n = document.getElementById('step-note').textContent; const m = n.match(/^step %d: (\\d+) ticks run/);"
                     "return m ? Number(m[1]) : null;" % k, "step %d of the virtual clock" % k)
    return done


def hold(b, keys, ticks):
    """Holds `keys` (selenium Keys or letters) for exactly `ticks` ticks of the session."""
    body = b.driver.find_element(By.TAG_NAME, "body")
    down = ActionChains(b.driver)
    for k in keys:
        down.key_down(k, body)
    down.perform()
    ran = advance(b, ticks)
    up = ActionChains(b.driver)
    for k in reversed(keys):
        up.key_up(k)
    up.perform()
    return ran


def test_keyboard_run(b, watcher, centre, assignment, report):
    # An instructor watches the browser's rig before it starts (as the live page's own test does).
    watcher.open("/live.html?rigs=browser-ann")
    watcher.wait_js("return document.getElementById('status').textContent === '(connected)'", "the instructor's watcher socket")
    open_assignment(b, assignment, "virtual")
    b.wait_js("return document.getElementById('live-note').textContent.startsWith('live as browser-ann')", "the page's live stream")
    b.shot("train-start")
    check(hold(b, [Keys.SHIFT, "w"], 1000) == 1000, "1000 ticks pushing")
    at = hud(b)
    check(abs(at["insertion_mm"] - 40.0) < 0.01, "Shift+W for 1 s: 40 mm expected, %.3f mm" % at["insertion_mm"])
    tip_js = "const e = document.querySelector(\"section[data-rig='browser-ann'] [data-stat='tip']\"); return e ? e.textContent : null;"
    first_tip = watcher.wait_js(tip_js, "the browser rig's first frame on the instructor's live page")
    turn_ticks = round(2 * math.pi / 6.0 * 1000)
    hold(b, [Keys.SHIFT, "a"], turn_ticks)
    at = hud(b)
    check(abs(at["rotation_rad"] - 6.0 * turn_ticks / 1000) < 0.01, "Shift+A: a full turn expected, %.3f rad" % at["rotation_rad"])
    b.shot("train-3d")
    watcher.wait_js(tip_js.replace("return e ? e.textContent : null;", "return e && e.textContent !== %s;" % json.dumps(first_tip)),
                    "the browser rig's tip to move on the instructor's page")
    watcher.shot("train-live-instructor")
    report["live_tip"] = "%s -> %s" % (first_tip, watcher.js(tip_js))
    # W (10 mm/s) until the run ends at the target (bounded: 12 s of session time).
    body = b.driver.find_element(By.TAG_NAME, "body")
    ActionChains(b.driver).key_down("w", body).perform()
    for _ in range(24):
        advance(b, 500)
        if b.js(STATE_JS) != "running":
            break
    ActionChains(b.driver).key_up("w").perform()
    state = b.wait_js(END_JS, "the record's upload")
    check(state == "done", "the upload: %s (%s)" % (state, b.js("return document.getElementById('error').textContent")))
    end, result, record_bytes = end_of_run(b, centre)
    check(end == "target reached", "the run ended by '%s', not at the target (%s)" % (end, hud(b)))
    check(result["complete"] is True and result["case"] == "ybif", "the stored result: %s" % json.dumps(result)[:400])
    b.wait(EC.visibility_of_element_located((By.ID, "metrics-table")), "the end-of-run metrics")
    b.shot("train-end")
    # The record the page offers for download: compared with the server's copy below.
    # As a user gets it: the link's download, in the browser's download folder.
    downloads = os.path.join(centre.tmp, "downloads")
    os.makedirs(downloads, exist_ok=True)
    b.driver.execute_cdp_cmd("Page.setDownloadBehavior", {"behavior": "allow", "downloadPath": downloads})
    link = b.driver.find_element(By.ID, "record-download")
    check(link.get_attribute("href").startswith("blob:"), "the page's record download: %r" % link.get_attribute("href"))
    saved = os.path.join(downloads, link.get_attribute("download"))
    link.click()
    wait_until(lambda: os.path.exists(saved) and os.path.getsize(saved) == record_bytes, "the record's download")
    kept = open(saved, "rb").read()
    centre.page_record = kept
    check(len(kept) == record_bytes, "the download link's size: %d bytes, the record %d" % (record_bytes, len(kept)))
    report["keyboard_run"] = {"seconds": hud(b)["time_s"], "end": end, "result_id": result["id"],
                              "passed": result["passed"], "record_bytes": record_bytes,
                              "tip_path_mm": (result.get("metrics") or {}).get("tip_path_mm")}
    return result["id"]


def test_tab_and_escape(b, centre, assignment, report):
    """Two tools: W moves the held one only, Tab hands over the other, Escape ends the run; the
    upload is accepted."""
    open_assignment(b, assignment, "virtual")
    start = hud(b)
    hold(b, ["w"], 300)
    first = hud(b)
    check(abs(first["insertion_mm"] - start["insertion_mm"] - 3.0) < 0.01, "W for 300 ticks: 3 mm expected, %s -> %s" % (start, first))
    ActionChains(b.driver).send_keys(Keys.TAB).perform()
    advance(b, 1)
    second = hud(b)
    check(second["tool"] != first["tool"], "Tab did not hand over the other tool: %s -> %s" % (first, second))
    ActionChains(b.driver).send_keys(Keys.ESCAPE).perform()
    state = b.wait_js(END_JS, "the upload")
    check(state == "done", "Escape: the upload %s" % state)
    end, result, _ = end_of_run(b, centre)
    check(end == "ended by the trainee", "Escape: the run ended by '%s'" % end)
    report["tab_escape"] = {"held": [first["tool"], second["tool"]], "seconds": second["time_s"], "result": result["id"]}


# The WebHID box's hand, one IN report (window.fakeBox, the test's own stand-in) and one tick of
# the page's "Run N ticks" control (clicked as a user does; the step's note says when it ran) at a
# time. What the fake box received is read from it; the rest from the page, after.
WEBHID_RUN = """
const done = arguments[arguments.length - 1];
const [cpm, cpr] = arguments[0];
const note = document.getElementById('step-note');
const stepped = (k) => new Promise((resolve) => {
  const ran = () => new RegExp('^step ' + k + ': \\\\d+ ticks run').test(note.textContent);
  const watch = new MutationObserver(() => { if (ran()) { watch.disconnect(); resolve(); } });
  watch.observe(note, { childList: true, characterData: true, subtree: true });
  document.getElementById('step-ticks').value = 1;
  document.getElementById('step').click();
});
(async () => {
  const first = note.textContent.match(/^step (\\d+):/);
  let k = first ? Number(first[1]) : 0;
  for (let i = 0; i <= 700; ++i) {
    const f = Math.min(i, 300) / 300;  // 10 mm and a quarter turn in 0.3 s of the box's hand, then held 0.4 s
    await window.fakeBox.emit({ insertion_count: Math.round(10 * f * cpm / 1000), rotation_count: Math.round(f * cpr / 4) });
    await stepped(++k);
  }
  done(true);
})().catch((e) => done(String(e)));
"""
FAKE_BOX_JS = """const c = window.fakeBox.commands;
return { commands: c.length, last: c[c.length - 1], refused: window.fakeBox.refused, features: window.fakeBox.features_read,
         underdamped: c.filter((x) => x.insertion.damping < x.insertion.stiffness * 0.005 / 2 - 1).length };"""


def end_run(b, what):
    ActionChains(b.driver).send_keys(Keys.ESCAPE).perform()
    state = b.wait_js(END_JS, "the upload")
    check(state == "done", "%s: the upload: %s (%s)" % (what, state, b.js("return document.getElementById('error').textContent")))


def test_webhid(b, assignment, report):
    """The page's WebHID path against an emulated box (fake_webhid.js: headless Chromium has no USB
    or HID device, so navigator.hid is a stand-in speaking protocol/'s own codec), in virtual time:
    one IN report a tick. The box's feature reports are read on connect: a box calibrated otherwise
    than the reference box (200,000 counts/m, 8,192 counts/rev) moves the tool by its own
    calibration, and its limits (2,500 mN) bound the law the page sends. A box not calibrated is
    refused with one line and the keyboard stays."""
    started = time.monotonic()
    source = open(os.path.join(os.path.dirname(os.path.abspath(__file__)), "fake_webhid.js")).read()
    script = b.driver.execute_cdp_cmd("Page.addScriptToEvaluateOnNewDocument", {"source": source})
    try:
        open_assignment(b, assignment, "virtual")
        before = b.wait_js("return document.getElementById('box-report').textContent || null;", "the box line before a box")
        check(before == "No box connected: the keyboard drives the tool.", "the box line before a box is connected: %r" % before)
        b.js("Object.assign(window.fakeBox.config.calibration, {insertion_counts_per_m: 200000, rotation_counts_per_rev: 8192});"
             "window.fakeBox.config.limits.max_force_mN = 2500;")
        b.driver.find_element(By.ID, "connect-box").click()
        note = b.wait_js("const n = document.getElementById('box-note').textContent;"
                         "return n.startsWith('box: WebHID') || n.startsWith('no box') ? n : null;", "the WebHID box to connect")
        check(note == "box: WebHID Cathbox (fake WebHID) (waiting for its first report)", "the page's box: %r" % note)
        start = hud(b)
        ran = b.driver.execute_async_script(WEBHID_RUN, [200000, 8192])
        check(ran is True, "the WebHID run: %r" % ran)
        # The page shows a law once it is sent; the last one the fake box got is the one shown.
        r = b.wait_js("const r = (() => { %s })(); const m = document.getElementById('box-report').textContent.match(/law seq (\\d+)/);"
                      "return r.last && m && Number(m[1]) === r.last.seq ? r : null;" % FAKE_BOX_JS, "the page's figures of its last law")
        box, at = box_report(b), hud(b)
        check(r["features"] == [0x10, 0x11, 0x12], "feature reports read: %s (device info, calibration, limits expected)" % r["features"])
        config = box["config"]
        check(config["source"] == "the box" and config["insertion_counts_per_m"] == 200000 and config["rotation_counts_per_rev"] == 8192
              and config["full_scale_mN"] == 2500 and config["serial"] == "FAKE-0001", "the box's configuration: %s" % config)
        moved_mm = at["insertion_mm"] - start["insertion_mm"]
        turned = at["rotation_rad"] - start["rotation_rad"]
        # With the reference box's calibration the same counts would be 18.4 mm and half a turn.
        # (The page shows the box to the µm, the tool to 0.01 mm.)
        check(abs(box["box_mm"] - start["insertion_mm"] - 10) < 0.006 and abs(moved_mm - 10) < 0.05,
              "10 mm of the box's hand: box %.3f mm, tool %.3f mm" % (box["box_mm"] - start["insertion_mm"], moved_mm))
        check(abs(turned - math.pi / 2) < 0.01, "a quarter turn of the box: the tool turned %.4f rad" % turned)
        check(box["stats"]["states"] == 701 and box["stats"]["rejected"] == 0 and box["stats"]["missed"] == 0, "decoding: %s" % box["stats"])
        last = r["last"]
        check(r["commands"] >= 1 and not r["refused"], "the page's commands: %d, refused %s" % (r["commands"], r["refused"]))
        check(last["mode"] == 1 and last["insertion"]["out_max"] == 2500 and -2500 <= last["insertion"]["out_min"] <= 0
              and last["seq"] == box["law"]["seq"], "the last command (brake mode, the limits' 2500 mN): %s" % last)
        # The held tool's local law, shaped as BoxHand shapes it (session::PassiveLaw): its position
        # in the box's frame (the tool is where 10 mm of the box's counts put it), its stiffness,
        # and damping of at least K T / 2 for the page's 5 ms command period (Colgate & Schenkel
        # 1997, passive_law.hpp's rule 3); units of protocol/README.md (µm, mN/m, mN·s/m).
        ins = last["insertion"]
        check(abs(ins["pos0"] - moved_mm * 1000) <= 50, "the law's position in the box's frame: %d µm, the tool's %.0f expected" % (ins["pos0"], moved_mm * 1000))
        check(ins["stiffness"] > 0 and ins["damping"] >= ins["stiffness"] * 0.005 / 2 - 1,
              "the law at rest: a stiffness, and damping b >= K T / 2: %s" % ins)
        check(r["underdamped"] == 0, "%d of %d commands with damping under K T / 2" % (r["underdamped"], r["commands"]))
        end_run(b, "the WebHID run")
        # A box not calibrated: refused, one line, the keyboard drives.
        open_assignment(b, assignment, "virtual")
        b.js("window.fakeBox.config.calibration.insertion_counts_per_m = 0;")
        b.driver.find_element(By.ID, "connect-box").click()
        refused = b.wait_js("const n = document.getElementById('box-note').textContent; return n.startsWith('no box') ? n : null;", "the refusal")
        check(refused == "no box: WebHID Cathbox (fake WebHID) is not calibrated (run 'cathbox calibrate') (the keyboard drives the tool)",
              "an uncalibrated box: %r" % refused)
        w0 = hud(b)["insertion_mm"]
        hold(b, ["w"], 100)
        check(abs(hud(b)["insertion_mm"] - w0 - 1.0) < 0.011, "the keyboard after the refusal")
        end_run(b, "the refused box's run")
        report["webhid"] = {"config": config, "box_mm": round(box["box_mm"] - start["insertion_mm"], 4), "tool_mm": round(moved_mm, 4),
                            "turned_rad": round(turned, 5), "commands": r["commands"], "last_command": last, "refused": refused,
                            "seconds": round(time.monotonic() - started, 1)}
    finally:
        b.driver.execute_cdp_cmd("Page.removeScriptToEvaluateOnNewDocument", {"identifier": script["identifier"]})


FLUORO_NOTE_JS = "return document.getElementById('fluoro-note').textContent"


def monitor(b, name):
    """The fluoroscopy canvas as the user sees it (an element screenshot, saved as `name`): grey
    statistics of its part under the HUD's lines (the lower 60 %), inside the collimated field (the
    central square) and outside it (the side columns, when the canvas is wider than high)."""
    png = b.driver.find_element(By.ID, "fluoro").screenshot_as_png
    open(os.path.join(b.out, b.prefix + name + ".png"), "wb").write(png)
    w, h, rows = grey(png)
    side = min(w, h)
    x0 = (w - side) // 2
    inside = [v for r in rows[int(0.4 * h):int(0.95 * h)] for v in r[x0 + side // 10:x0 + side - side // 10]]
    outside = [v for r in rows[int(0.4 * h):int(0.95 * h)] for v in r[8:max(8, x0 - 2)]]  # clear of the view's rounded corners
    inside.sort()
    n = len(inside)
    median = inside[n // 2]
    mean = sum(inside) / n
    return {"size": [w, h], "mean": round(mean, 1), "median": median, "p1": inside[n // 100], "p99": inside[99 * n // 100],
            "std": round((sum((v - mean) ** 2 for v in inside) / n) ** 0.5, 1),
            "dark_fraction": round(sum(1 for v in inside if v < median - 40) / n, 4),
            "outside_max": max(outside) if outside else None}


def test_fluoroscopy(b, assignment, report):
    """The fluoroscopic image in the page (js/fluoro_view.js, the native renderer's shaders in
    WebGL2), in virtual time on the neuro case (a catheter to inject through): black before the pedal; with Space held the
    pulses show the head phantom's grey with quantum noise inside the collimated field and black
    outside it; I (inject) with the pedal down starts a subtraction run, whose frames show the DSA
    background with the anatomy subtracted. (That the injected contrast shows in the lumen is not
    checked here: injected at the aortic entry it stays below the field's visibility within
    1.5 s; host/wasm/README.md says what was checked by hand.) The fluoroscopy keys are the session's controls: the run with them is uploaded and replayed by the
    server with every state hash."""
    b.open("/train.html?clock=virtual&view=fluoro")
    b.wait(EC.element_to_be_clickable((By.CSS_SELECTOR, "button.open-case[data-id='%d']" % assignment)), "the assignment's Run button")
    b.driver.find_element(By.CSS_SELECTOR, "button.open-case[data-id='%d']" % assignment).click()
    b.wait_js("return document.getElementById('status').textContent === 'running'", "the session to start in the worker")
    note = b.wait_js("const n = document.getElementById('fluoro-note').textContent; return n.startsWith('Fluoroscopy') || n.startsWith('this') ? n : null;",
                     "the fluoroscopy's note")
    check(note == "Fluoroscopy: no image yet (hold Space, the pedal)", "the fluoroscopy before the pedal: %r" % note)
    check(b.js("return !document.getElementById('fluoro').hidden"), "the fluoroscopy canvas is not shown with ?view=fluoro")
    black = monitor(b, "train-fluoro-black")
    check(black["p99"] <= 8, "the monitor before the first pulse is not black: %s" % black)
    hold(b, [Keys.SPACE, "w"], 400)
    pulses = re.match(r"Fluoroscopy: pulse (\d+), fluoroscopy, image (\d+) × (\d+) pixels, (\d+) images drawn$",
                      b.wait_js("const n = document.getElementById('fluoro-note').textContent; return / [1-9]\\d* images drawn$/.test(n) ? n : null;",
                                "the first fluoroscopic image drawn"))
    check(pulses is not None and int(pulses.group(1)) >= 4, "0.4 s with the pedal: at least 5 pulses at 15 /s expected: %r" % b.js(FLUORO_NOTE_JS))
    live = monitor(b, "train-fluoro")
    check(40 <= live["median"] <= 215 and live["std"] >= 2, "the pulses' image: a grey phantom with noise expected, %s" % live)
    check(live["outside_max"] is None or live["outside_max"] <= 8, "outside the collimated field the monitor is black: %s" % live)
    hold(b, [Keys.SPACE, "i"], 50)
    hold(b, [Keys.SPACE], 1500)
    note = b.wait_js("const n = document.getElementById('fluoro-note').textContent; const m = n.match(/pulse (\\d+)/);"
                     "return m && Number(m[1]) >= 25 ? n : null;", "the pulses after the injection")
    check(" subtraction run, " in note, "injecting with the pedal down starts a subtraction run (as the native unit): %r" % note)
    run = monitor(b, "train-fluoro-subtraction")
    # The run's frame minus its mask: the anatomy cancels to the DSA background (0.72 of white),
    # only noise (and what changed) left.
    check(abs(run["median"] - 0.72 * 255) <= 12 and run["std"] < live["std"] / 2,
          "the subtraction image: the DSA background with the anatomy subtracted expected, %s (live %s)" % (run, live))
    end_run(b, "the fluoroscopy run")
    report["fluoroscopy"] = {"before_pedal": black, "live": live, "subtraction": run, "note": note}


def test_native_replay(centre, result_id, report):
    """The record the page uploaded, from the server, replayed natively with every hash."""
    teacher = Api(centre.base).login("teacher")
    _, payload, _ = teacher.call("GET", "/results/%d/record" % result_id)
    path = os.path.join(centre.tmp, "browser.cbxrec")
    open(path, "wb").write(payload)
    check(payload == centre.page_record, "the server's record (%d bytes) is not the page's download (%d bytes)"
          % (len(payload), len(centre.page_record)))
    out = centre.run([centre.program("cathbox"), "session", "replay", path, "--check"], "native replay --check of the browser's record")
    check("every state hash matches" in out, "native replay: " + out[-400:])
    report["native_replay"] = out.strip().splitlines()[-1]


def replay_line(text):
    """The record check's line: passed (hashes checked over ticks of recorded ticks, ms) or FAILED
    with the reason."""
    m = re.match(r"passed: (\d+) state hashes checked over (\d+) of (\d+) ticks, all match \((\d+) ms\)", text)
    if m:
        return {"passed": True, "figures": {"hashes_checked": int(m.group(1)), "ticks": int(m.group(2)), "recorded_ticks": int(m.group(3))},
                "ms": int(m.group(4))}
    m = re.match(r"FAILED: (.*?)(?: \(\d+ hashes checked over \d+ ticks\))?$", text)
    return {"passed": False, "message": m.group(1) if m else text}


def test_native_record_in_page(b, centre, report):
    """A native record (`cathbox session run --virtual`) replayed in the page's worker with every
    state hash checked; the same record with one byte changed does not pass, nor does it against
    another case's surface (a state hash differs at a tick)."""
    rec = os.path.join(centre.tmp, "native.cbxrec")
    centre.run([centre.program("cathbox"), "session", "run", "--case", os.path.join(centre.args.source, "cases/y_bifurcation.case"),
                "--script", os.path.join(centre.args.source, "cases/y_bifurcation_left.actions"), "--record", rec,
                "--virtual", "--seconds", "2"], "native session run")
    data = bytearray(open(rec, "rb").read())
    data[len(data) // 2] ^= 0x40
    bad = os.path.join(centre.tmp, "native-changed.cbxrec")
    open(bad, "wb").write(bytes(data))
    b.open("/train.html?clock=virtual")
    b.wait_js("return document.querySelector('#replay-case option[value^=\"ybif/\"]') !== null", "the record check's case list")
    results = {}
    for name, path, case in (("native", rec, "ybif/"), ("changed", bad, "ybif/"), ("other_surface", rec, "neuro/")):
        b.js("const s = document.getElementById('replay-case'); s.value = [...s.options].find((o) => o.value.startsWith(arguments[0])).value;", case)
        before = b.js("return document.getElementById('replay-result').textContent")
        b.driver.find_element(By.ID, "replay-file").send_keys(path)
        text = b.wait_js("const t = document.getElementById('replay-result').textContent; const e = document.getElementById('error');"
                         "return (t.startsWith('passed') || t.startsWith('FAILED')) && t !== %s ? t"
                         " : !e.hidden && e.textContent ? 'error: ' + e.textContent : null;" % json.dumps(before), "the page's replay of " + name)
        results[name] = replay_line(text)
        results[name + "_text"] = text
        if name == "native":
            b.shot("train_record_check")
        b.js("document.getElementById('replay-file').value = '';")
    native = results["native"]
    check(native and native["passed"] and native["figures"]["hashes_checked"] > 0
          and native["figures"]["ticks"] == native["figures"]["recorded_ticks"],
          "the native record in the page: %r" % native)
    check(results["native_text"].startswith("passed:"), "the page shows: %r" % results["native_text"])
    changed = results["changed"]
    check(changed is not None and not changed["passed"] and changed["message"],
          "a changed record passed the page's check: %r" % changed)
    check(results["changed_text"].startswith("FAILED:"), "the page shows for the changed record: %r" % results["changed_text"])
    other = results["other_surface"]
    check(other is not None and not other["passed"] and "state hash differs at tick" in other["message"],
          "the native record against another vessel's surface: %r" % other)
    report["native_record_in_page"] = {"hashes_checked": native["figures"]["hashes_checked"], "ticks": native["figures"]["ticks"],
                                       "replay_ms": round(native["ms"]), "changed": changed["message"],
                                       "other_surface": other["message"]}


def test_without_wasm(b, centre, assignment, report):
    """A server started without --wasm: the page says so in one line, and nothing runs."""
    centre.extra_args = []
    centre.restart()
    b.open("/train.html?clock=virtual")
    b.wait(EC.element_to_be_clickable((By.CSS_SELECTOR, "button.open-case[data-id='%d']" % assignment)), "the assignment's Run button")
    b.driver.find_element(By.CSS_SELECTOR, "button.open-case[data-id='%d']" % assignment).click()
    line = b.wait_js("const e = document.getElementById('error'); return !e.hidden && e.textContent;", "the page's error line")
    check(line == "/wasm/cathbox-trainee.js: the WebAssembly session is not served here (cathbox-server --wasm DIR)",
          "the error line without --wasm: %r" % line)
    check(b.js(STATE_JS) == "", "the page's status without the session: %r" % b.js(STATE_JS))
    b.drain_console(expected=[("/wasm/cathbox-trainee.js", 404)])
    report["without_wasm"] = line


CLOCK_NOTE = re.compile(
    r"Haptic clock: (\d+) ticks, interval p50 ([0-9.]+) ms, p99 ([0-9.]+) ms, max ([0-9.]+) ms, (\d+) dropped; "
    r"lateness p50 ([0-9.]+) ms, p99 ([0-9.]+) ms, max ([0-9.]+) ms; a tick's run p50 ([0-9.]+) ms, p99 ([0-9.]+) ms; "
    r"late ticks after a sleep (\d+), after ticks (\d+), after the event loop (\d+), caught up (\d+)\.$")
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
    return jitter, int(f.group(1)), int(f.group(2)) if f.group(2) else None


def test_real_clock(b, centre, assignment, seconds, report, view):
    """The worker's own 1 kHz clock for `seconds`, W held (and Space, the pedal, in fluoroscopy),
    then Escape: jitter and first frame, with the machine's load average."""
    open_assignment(b, assignment, "real", view)
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
    jitter, first_ms, open_ms = clock_figures(b)
    report.setdefault("real_clock", {})[view] = {
        "jitter": jitter, "first_frame_ms": first_ms, "open_ms": open_ms, "end": end,
        "load_average": [round(load_before, 2), round(os.getloadavg()[0], 2)],
        "fluoro": b.js(FLUORO_NOTE_JS) if view == "fluoro" else None}


BOX_JS = "return document.getElementById('box-report').textContent"
BOX_REPORT = re.compile(
    r"box (-?[0-9.]+) mm (-?[0-9.]+) rad; states (\d+), missed (\d+), rejected (\d+), longest report gap ([0-9.]+) ms,"
    r" longest command gap ([0-9.]+) ms; (?:law seq (\d+), offset (-?[0-9.]+) mN|no law sent yet);"
    r" box status 0x([0-9a-f]+), faults (\d+), mode (\d+), rx errors (\d+), command echo (\d+), force (-?[0-9.]+) mN$")
BOX_CONFIG = re.compile(r"Box: (.*); (\d+) counts/m, (\d+) counts/rev, full scale (\d+) mN, (\d+) µN·m, slew (\d+) mN/ms, (brake|motor) mode$")


def box_report(b, law=True):
    """The box's figures the page shows under the keys (js/train.js showBoxReport): its position,
    the page's decoding and commands, the last law sent, the box's state, and what the box said of
    itself on connect (the line under them). law=False: before the first law ('no law sent yet')."""
    text = b.js(BOX_JS)
    m = BOX_REPORT.match(text)
    check(m is not None and (not law or m.group(8) is not None), "the page's box figures: %r" % text)
    g = list(m.groups())
    num = lambda v, f=int: None if v is None else f(v)  # noqa: E731
    r = {"box_mm": float(g[0]), "box_rad": float(g[1]),
         "stats": {"states": int(g[2]), "missed": int(g[3]), "rejected": int(g[4]), "max_report_gap_ms": float(g[5]), "max_send_gap_ms": float(g[6])},
         "law": {"seq": num(g[7]), "insertion_offset_mN": num(g[8], float)},
         "state": {"status": int(g[9], 16), "faults": num(g[10]), "mode": num(g[11]), "rx_errors": num(g[12]),
                   "command_seq_echo": num(g[13]), "insertion_force_mN": num(g[14], float)}}
    text = b.js("return document.getElementById('box-config').textContent")
    c = BOX_CONFIG.match(text)
    check(c is not None, "the page's line on the box's own figures: %r" % text)
    who = c.group(1)
    w = re.match(r"(\S+) (\S+), firmware (\S+)$", who)
    r["config"] = {"source": "the box" if w else who, "board": w.group(1) if w else None, "serial": w.group(2) if w else None,
                   "firmware": w.group(3) if w else None, "insertion_counts_per_m": int(c.group(2)),
                   "rotation_counts_per_rev": int(c.group(3)), "full_scale_mN": int(c.group(4)), "full_scale_uNm": int(c.group(5)),
                   "slew_mN_per_ms": int(c.group(6)), "mode": c.group(7)}
    return r


def test_box_bridge(b, centre, assignment, report):
    """The page's box path against cathbox-emu through cathbox-box-bridge (see the docstring)."""
    sock = os.path.join(centre.tmp, "emu.sock")
    emu_log = open(os.path.join(centre.tmp, "emu.log"), "w")
    emu = subprocess.Popen([centre.program("cathbox-emu"), "--socket", sock, "--hand-insertion", "v:20mm/s:60s", "--duration", "90"],
                           stdout=emu_log, stderr=subprocess.STDOUT)
    centre.processes.append(emu)
    wait_until(lambda: os.path.exists(sock), "cathbox-emu's socket")
    bridge_err = os.path.join(centre.tmp, "bridge.log")
    bridge = subprocess.Popen([centre.program("cathbox-box-bridge"), "--emu-socket", sock, "--port", "0"],
                              stdout=subprocess.PIPE, stderr=open(bridge_err, "w"), text=True)
    centre.processes.append(bridge)
    line = bridge.stdout.readline().strip()
    check(line.startswith("box-bridge: ws://127.0.0.1:"), "the bridge's first line: %r" % line)
    url = line.split(" ", 1)[1]
    b.open("/train.html?box=" + url)
    b.wait(EC.element_to_be_clickable((By.CSS_SELECTOR, "button.open-case[data-id='%d']" % assignment)), "the assignment's Run button")
    b.driver.find_element(By.CSS_SELECTOR, "button.open-case[data-id='%d']" % assignment).click()
    note = b.wait_js("const n = document.getElementById('box-note').textContent; const e = document.getElementById('error');"
                     "return n.endsWith('drives the held tool') || n.startsWith('no box') || n.startsWith('box lost') ? n"
                     " : !e.hidden && e.textContent ? e.textContent : null;", "the box to drive the tool")
    check(note.endswith("drives the held tool"), "the page's box: %r (%s)" % (note, b.js(BOX_JS)))
    b.wait_js("return document.getElementById('box-report').textContent.startsWith('box ') && document.getElementById('hud').textContent !== ''",
              "the box's figures on the page")
    first = {"box": box_report(b, law=False), "at": hud(b)}
    # 10 mm of the emulator's hand: the tool follows (no key is pressed).
    def followed(_):
        try:
            r, at = box_report(b), hud(b)
        except Failure:
            return None  # no law sent yet
        ok = r["box_mm"] - first["box"]["box_mm"] >= 10 and abs(at["insertion_mm"] - r["box_mm"]) < 2 and (r["state"]["status"] & 9) == 9
        return {"box": r, "at": at} if ok else None
    moved = b.wait(followed, "the tool to follow the emulator's encoder 10 mm, the box's output on", timeout=30)
    box, at = moved["box"], moved["at"]
    s = box["state"]
    check(box["stats"]["rejected"] == 0 and box["stats"]["states"] > 100, "the page's decoding: %s" % box["stats"])
    # The emulator's own feature reports, through the bridge (GET_REPORT by its one-byte ID).
    config = box["config"]
    check(config["source"] == "the box" and config["board"] == "cathbox-emu" and config["insertion_counts_per_m"] > 0
          and config["full_scale_mN"] > 0, "the emulator's device info, calibration and limits: %s" % config)
    # The worker sends a command on the report stream, at most one send period (5 ms) after a
    # report: the longest gap between commands is the stream's longest gap plus that, whatever the
    # machine's load (a relation, not a wall-clock figure: under 50 ms, the box's watchdog, on a
    # quiet machine; the page's thread, stalled by drawing, had 55-349 ms). Printed in the report.
    st = box["stats"]
    check(0 < st["max_send_gap_ms"] <= st["max_report_gap_ms"] + 5 + 2, "the longest gap between the page's commands: %s" % st)
    check(at["insertion_mm"] - first["at"]["insertion_mm"] >= 8, "the session's tool moved %.2f mm" % (at["insertion_mm"] - first["at"]["insertion_mm"]))
    # The emulator shows the page's commands applied (protocol/README.md's state bits).
    check(s["status"] & 0x1 and s["status"] & 0x8, "output enabled and command fresh expected: status 0x%x" % s["status"])
    check(s["faults"] == 0 and s["mode"] == 1 and s["rx_errors"] == 0, "the box's faults/mode/rx_errors: %s" % s)
    lag = (box["law"]["seq"] - s["command_seq_echo"]) & 0xffff
    check(lag < 64, "the box's command echo %d is not the page's last command %d" % (s["command_seq_echo"], box["law"]["seq"]))
    # The law's offset is the session's hand force (resisting the push); the emulator reports the
    # force its brake renders, which is that offset (the brake may only resist, and the hand pushes in).
    law = box["law"]
    check(law["insertion_offset_mN"] <= -5, "pushing the wire through the vessel: a resisting law expected, %s" % law)
    check(abs(s["insertion_force_mN"] - law["insertion_offset_mN"]) <= 10,
          "the emulator renders %d mN, the page commanded %d mN" % (s["insertion_force_mN"], law["insertion_offset_mN"]))
    ActionChains(b.driver).send_keys(Keys.ESCAPE).perform()
    state = b.wait_js(END_JS, "the upload")
    check(state == "done", "the box run's upload: %s (%s)" % (state, b.js("return document.getElementById('error').textContent")))
    wait_until(lambda: "page closed" in open(bridge_err).read(), "the bridge to see the page close")
    closed = [x for x in open(bridge_err).read().splitlines() if "page closed" in x][-1]
    # A message that is not a report: refused, the reason names its length.
    # First GET_REPORT by hand: device info (0x10) is answered with its 64 bytes, an ID the box
    # does not have (0x30) with the ID alone (the emulator stalls it); then the 37 bytes.
    got = b.driver.execute_async_script(
        "const done = arguments[arguments.length - 1]; const ws = new WebSocket(arguments[0]); ws.binaryType = 'arraybuffer';"
        "const answers = []; ws.onopen = () => { ws.send(new Uint8Array([0x10])); ws.send(new Uint8Array([0x30])); };"
        "ws.onmessage = (e) => { const a = new Uint8Array(e.data); if (a[0] === 0x01) return; answers.push([a.length, a[0]]);"
        "  if (answers.length === 2) ws.send(new Uint8Array(37)); };"
        "ws.onclose = (e) => done({answers, why: e.code + ' ' + e.reason});", url)
    why = got["why"]
    check(got["answers"] == [[64, 0x10], [1, 0x30]], "the bridge's answers to GET_REPORT 0x10 and 0x30: %s" % got["answers"])
    check(why == "1008 a 37-byte message (a report is 64 bytes, a feature request 1)", "the bridge's refusal: %r" % why)
    wait_until(lambda: "refused a 37-byte message (a report is 64 bytes, a feature request 1)" in open(bridge_err).read(), "the bridge's error line")
    bridge.terminate()
    emu.terminate()
    report["box_bridge"] = {"box_mm": round(box["box_mm"] - first["box"]["box_mm"], 2),
                            "tool_mm": round(at["insertion_mm"] - first["at"]["insertion_mm"], 2),
                            "state": s, "law": box["law"], "stats": box["stats"], "bridge": closed, "refusal": why, "config": config}


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--bin", required=True)
    parser.add_argument("--wasm", required=True, help="folder of cathbox-trainee.js (scripts/wasm-build DIR cathbox-trainee: DIR/bin)")
    parser.add_argument("--source", required=True)
    parser.add_argument("--out", required=True)
    parser.add_argument("--real-clock", type=int, default=0, metavar="SECONDS", help="also run on the worker's own clock and report its jitter")
    parser.add_argument("--keep", action="store_true")
    args = parser.parse_args()
    os.makedirs(args.out, exist_ok=True)
    tmp = tempfile.mkdtemp(prefix="cathbox-train-")
    centre = Centre(args, tmp)
    centre.extra_args = ["--wasm", args.wasm]
    b = None
    watcher = None
    report = {}
    try:
        centre.start()
        assignment, two_tools = seed(centre)
        watcher = Browser(args.out)
        watcher.base = centre.base
        watcher.login("teacher")
        b = Browser(args.out)
        b.base = centre.base
        b.login("ann")
        result_id = test_keyboard_run(b, watcher, centre, assignment, report)
        b.drain_console()
        watcher.drain_console()
        watcher.quit()
        watcher = None
        test_native_replay(centre, result_id, report)
        test_native_record_in_page(b, centre, report)
        b.drain_console()
        test_tab_and_escape(b, centre, two_tools, report)
        b.drain_console()
        test_webhid(b, assignment, report)
        b.drain_console()
        test_fluoroscopy(b, two_tools, report)
        b.drain_console()
        if args.real_clock:
            for view in ("3d", "fluoro"):
                test_real_clock(b, centre, assignment, args.real_clock, report, view)
                b.drain_console()
        test_box_bridge(b, centre, assignment, report)
        b.drain_console()
        test_without_wasm(b, centre, assignment, report)
        print(json.dumps(report, indent=1))
        json.dump(report, open(os.path.join(args.out, "train_report.json"), "w"), indent=1)
        return 0
    except Failure as e:
        print("FAIL: %s" % e)
        print(json.dumps(report, indent=1))
        return 1
    except Exception:
        traceback.print_exc()
        return 1
    finally:
        for browser in (b, watcher):
            if browser:
                browser.quit()
        centre.stop()
        if not args.keep:
            subprocess.run(["rm", "-rf", tmp])
        else:
            print("kept " + tmp)


if __name__ == "__main__":
    sys.exit(main())
