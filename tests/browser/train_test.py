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
case (neuro), Tab hands over the other tool and Escape ends the run, uploaded. On a stent
retriever's case (train_stent.py) U unsheathes the stent and E retrieves it, keys only, and the
uploaded record holds the pass; with a box connected U is refused on the HUD. A native record
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

The WebHID path (train_box.py), in the haptic worker, which owns the box: tests/browser/fake_webhid.js
stands in for navigator.hid (no USB here, no HID device in headless Chromium): on the page, the
chooser; in the worker (put there through the DevTools protocol), the box. In virtual time against
protocol/'s codec, the worker reads the box's feature reports, moves the tool by the box's own
calibration, and sends the held tool's law as the native driver shapes it; a box not calibrated is
refused. On the worker's own clock against cathbox-emu behind cathbox-box-bridge, the emulator's
scripted hand takes the wire to the target through the worker's WebHID path, and the run is uploaded.

With --real-clock it also runs the page on the worker's own 1 kHz clock for a few seconds and
reports the tick-interval jitter and the first-frame time (a wall-clock figure: printed, never
asserted); --spin MS and --rig-fifo PRIO (scripts/rig-priority) are the clock's options to measure,
--only real-clock|fluoroscopy runs that part alone (scripts/bench train: --only real-clock).

The page carries no test hook: the test reads it as a user does, from the page (the status, the
HUD's figures, the notes under the keys, the box's figures, the end card, the record check's line,
the record download) and from the server (the stored result, as the trainee's own API call). The
WebHID part also reads what the box received from window.fakeBox, the test's own stand-in.
The parts live by concept in train_page.py, train_box.py, train_fluoro.py, train_replay.py,
train_stent.py and train_clock.py.

  tests/browser/train_test.py --bin build/release/bin --wasm build/wasm/bin --source . --out build/release/browser
"""
import argparse
import json
import math
import os
import subprocess
import sys
import tempfile
import traceback

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from browser_test import Browser, Centre, Failure, check, wait_until  # noqa: E402
from train_box import test_box_bridge, test_webhid, test_webhid_emulated  # noqa: E402
from train_clock import test_real_clock  # noqa: E402
from train_fluoro import test_contrast, test_fluoroscopy  # noqa: E402
from train_page import END_JS, STATE_JS, advance, end_of_run, hold, hud, open_assignment, seed  # noqa: E402
from train_replay import test_native_record_in_page, test_native_replay  # noqa: E402
from train_stent import test_stent_keys  # noqa: E402
from selenium.webdriver.common.action_chains import ActionChains  # noqa: E402
from selenium.webdriver.common.by import By  # noqa: E402
from selenium.webdriver.common.keys import Keys  # noqa: E402
from selenium.webdriver.support import expected_conditions as EC  # noqa: E402


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
        # A step that ran short ended the run (its end message may still be on its way to the page).
        if advance(b, 500) < 500 or b.js(STATE_JS) != "running":
            break
    ActionChains(b.driver).key_up("w").perform()
    state = b.wait_js(END_JS, "the record's upload")
    check(state == "done", "the upload: %s (%s)" % (state, b.js("return document.getElementById('error').textContent")))
    end, result, record_bytes = end_of_run(b, centre)
    check(end == "target reached", "the run ended by '%s', not at the target (%s)" % (end, hud(b)))
    check(result["complete"] is True and result["case"] == "ybif", "the stored result: %s" % json.dumps(result)[:400])
    b.wait(EC.visibility_of_element_located((By.ID, "metrics-table")), "the end-of-run metrics")
    b.shot("train-end")
    # Headless Chromium draws WebGL with SwiftShader (on the CPU): the page caps its frames at 30 a second.
    draw = b.js("return document.getElementById('draw-note').textContent")
    check("at most 30 a second (WebGL: " in draw and "SwiftShader" in draw, "the page's drawing note on software GL: %r" % draw)
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


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--bin", required=True)
    parser.add_argument("--wasm", required=True, help="folder of cathbox-trainee.js (scripts/wasm-build DIR cathbox-trainee: DIR/bin)")
    parser.add_argument("--source", required=True)
    parser.add_argument("--out", required=True)
    parser.add_argument("--real-clock", type=int, default=0, metavar="SECONDS", help="also run on the worker's own clock and report its jitter")
    parser.add_argument("--only", choices=["real-clock", "fluoroscopy", "stent"],
                        help="only that part (after logging in), to measure or work on it; real-clock needs --real-clock")
    parser.add_argument("--spin", type=float, default=None, metavar="MS", help="the real-clock runs with /train.html?spin=MS")
    parser.add_argument("--rig-fifo", type=int, default=None, metavar="PRIO",
                        help="the real-clock runs with the browser's worker threads at SCHED_FIFO PRIO, as a kiosk rig's launcher may set them")
    parser.add_argument("--rig-slice", type=int, default=None, metavar="US",
                        help="the real-clock runs with the browser's worker threads at an EEVDF slice of US µs (scripts/rig-priority --slice)")
    parser.add_argument("--rig-gpu", default=None, metavar="idle|NICE",
                        help="the real-clock runs with the browser's GPU process at SCHED_IDLE or nice NICE (scripts/rig-priority --gpu)")
    parser.add_argument("--query", default=None, metavar="Q", help="the real-clock runs with /train.html?...&Q (e.g. frame_ms=50)")
    parser.add_argument("--chromium-arg", action="append", default=[], metavar="ARG",
                        help="one more Chromium switch for the trainee's browser (repeatable; e.g. --in-process-gpu)")
    parser.add_argument("--browser-log", default=None, metavar="FILE",
                        help="the trainee's Chromium's own output into FILE (e.g. with --chromium-arg=--js-flags=--trace-gc)")
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
        b = Browser(args.out, extra_args=args.chromium_arg, browser_log=args.browser_log)
        b.base = centre.base
        b.login("ann")
        if args.only:
            if args.only == "real-clock":
                for view in ("3d", "fluoro"):
                    test_real_clock(b, centre, assignment, args.real_clock, report, view, args.spin, args.rig_fifo, args.query, args.rig_slice,
                                    args.rig_gpu)
            elif args.only == "stent":
                test_stent_keys(b, centre, report)
            else:
                test_fluoroscopy(b, two_tools, report)
            b.drain_console()
            print(json.dumps(report, indent=1))
            json.dump(report, open(os.path.join(args.out, "train_report.json"), "w"), indent=1)
            return 0
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
        test_stent_keys(b, centre, report)
        b.drain_console()
        test_webhid(b, assignment, report)
        b.drain_console()
        test_fluoroscopy(b, two_tools, report)
        b.drain_console()
        test_contrast(b, centre, report)
        b.drain_console()
        if args.real_clock:
            for view in ("3d", "fluoro"):
                test_real_clock(b, centre, assignment, args.real_clock, report, view, args.spin, args.rig_fifo, args.query, args.rig_slice,
                                    args.rig_gpu)
                b.drain_console()
        test_box_bridge(b, centre, assignment, report)
        b.drain_console()
        test_webhid_emulated(b, centre, assignment, report)
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
