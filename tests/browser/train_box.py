"""The trainee page's box paths (train_test.py): the WebHID box in the haptic worker (fake_webhid.js,
installed in the page and, through the DevTools protocol, in the worker) against protocol/'s codec
in virtual time and against cathbox-emu through cathbox-box-bridge on the worker's own clock; and
the page's WebSocket transport to the same bridge."""
import json
import math
import os
import re
import subprocess
import time

from browser_test import Failure, check, wait_until
from train_clock import CLOCK_NOTE
from train_page import END_JS, advance, end_of_run, end_run, hold, hud, open_assignment
from selenium.common.exceptions import WebDriverException
from selenium.webdriver.common.action_chains import ActionChains
from selenium.webdriver.common.by import By
from selenium.webdriver.common.keys import Keys
from selenium.webdriver.support import expected_conditions as EC


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
    const r = await window.fakeBox.emit({ insertion_count: Math.round(10 * f * cpm / 1000), rotation_count: Math.round(f * cpr / 4) });
    if (r !== true) throw new Error(r);
    await stepped(++k);
  }
  done(true);
})().catch((e) => done(String(e)));
"""
FAKE_BOX_JS = """const c = window.fakeBox.commands;
const stiff = c.map((x, i) => [x, i]).filter(([x]) => x.insertion.stiffness > 0).pop() || [null, -1];
return { commands: c.length, last: c[c.length - 1], last_stiff: stiff[0], from_end: c.length - 1 - stiff[1], refused: window.fakeBox.refused, features: window.fakeBox.features_read,
         underdamped: c.filter((x) => x.insertion.damping < x.insertion.stiffness * 0.005 / 2 - 1).length };"""


FAKE_SOURCE = os.path.join(os.path.dirname(os.path.abspath(__file__)), "fake_webhid.js")
CONFIGURE_JS = """const done = arguments[arguments.length - 1];
window.fakeBox.configure(arguments[0]).then(done, (e) => done(String(e)));"""


def fake_in_page(b):
    """fake_webhid.js's page half (the chooser, window.fakeBox) before the page's scripts; the
    DevTools script identifier, to take it off again."""
    return b.driver.execute_cdp_cmd("Page.addScriptToEvaluateOnNewDocument", {"source": open(FAKE_SOURCE).read()})


def fake_in_worker(b, backend, url=None):
    """fake_webhid.js's worker half, in the page's haptic worker (js/train_worker.js) through the
    DevTools protocol: the worker's target attached, the script evaluated in its global scope (the
    worker's own navigator.hid replaced), detached; its arrival is said on the fake's channel. The
    fake takes only in a worker whose session is open and running, which may come after its target
    is listed (a page still loading its session, under load): it is evaluated again, every half
    second, until it says it is in (fake_webhid.js takes it once per worker)."""
    def workers():
        targets = b.driver.execute_cdp_cmd("Target.getTargets", {})["targetInfos"]
        return [t for t in targets if t["type"] == "worker" and t["url"].endswith("/js/train_worker.js")]
    source = "self.FAKE_WEBHID = %s;\n%s" % (json.dumps({"backend": backend, "url": url}), open(FAKE_SOURCE).read())
    tried = [0.0]

    def installed(_):
        if b.js("return window.fakeBox.installed === %s" % json.dumps(backend)):
            return True
        if time.monotonic() - tried[0] < 0.5:
            return None
        tried[0] = time.monotonic()
        # Every haptic worker the browser lists (the previous pages' may linger, kept for going
        # back): the fake takes only in the one whose session is open and running.
        for target in workers():
            try:
                session = b.driver.execute_cdp_cmd("Target.attachToTarget", {"targetId": target["targetId"], "flatten": False})["sessionId"]
                b.driver.execute_cdp_cmd("Target.sendMessageToTarget", {"sessionId": session, "message": json.dumps(
                    {"id": 1, "method": "Runtime.evaluate", "params": {"expression": source}})})
                b.driver.execute_cdp_cmd("Target.detachFromTarget", {"sessionId": session})
            except WebDriverException:
                pass  # a worker gone meanwhile (a previous page's)
        return None
    b.wait(installed, "the fake WebHID box in the haptic worker")


def connect_box(b, expect):
    """'Connect box' (the page asks Chromium's chooser, then the worker opens the box): the box
    note once the worker says it is up or refused it."""
    b.driver.find_element(By.ID, "connect-box").click()
    return b.wait_js("const n = document.getElementById('box-note').textContent;"
                     "return n.startsWith(%s) || n.startsWith('no box') ? n : null;" % json.dumps(expect), "the WebHID box to connect")


def test_webhid(b, assignment, report):
    """The page's WebHID path against an emulated box (fake_webhid.js: headless Chromium has no USB
    or HID device, so navigator.hid is a stand-in speaking protocol/'s own codec), in virtual time:
    one IN report a tick. The box's feature reports are read on connect: a box calibrated otherwise
    than the reference box (200,000 counts/m, 8,192 counts/rev) moves the tool by its own
    calibration, and its limits (2,500 mN) bound the law the page sends. A box not calibrated is
    refused with one line and the keyboard stays."""
    started = time.monotonic()
    script = fake_in_page(b)
    try:
        open_assignment(b, assignment, "virtual")
        before = b.wait_js("return document.getElementById('box-report').textContent || null;", "the box line before a box")
        check(before == "No box connected: the keyboard drives the tool.", "the box line before a box is connected: %r" % before)
        fake_in_worker(b, "codec")
        configured = b.driver.execute_async_script(CONFIGURE_JS, {"calibration": {"insertion_counts_per_m": 200000, "rotation_counts_per_rev": 8192},
                                                                  "limits": {"max_force_mN": 2500}})
        check(configured is True, "the fake box's configuration: %r" % configured)
        note = connect_box(b, "box: WebHID Cathbox (fake WebHID) (waiting")
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
        # The output's range: within the box's limits (2,500 mN) and within one slew step of what the
        # box last rendered (passive_law.hpp's rule 2: 100 mN/ms over the page's 5 ms command period).
        out = last["insertion"]
        check(last["mode"] == 1 and -2500 <= out["out_min"] <= 0 <= out["out_max"] <= 2500
              and out["out_max"] - out["out_min"] <= 2 * 100 * 5 and last["seq"] == box["law"]["seq"],
              "the last command (brake mode, within the limits' 2500 mN and a 500 mN slew step of the readback): %s" % last)
        # The held tool's local law, shaped as BoxHand shapes it (session::PassiveLaw): its position
        # in the box's frame (the tool is where 10 mm of the box's counts put it), its stiffness,
        # and damping of at least K T / 2 for the page's 5 ms command period (Colgate & Schenkel
        # 1997, passive_law.hpp's rule 3); units of protocol/README.md (µm, mN/m, mN·s/m).
        ins = last["insertion"]
        check(abs(ins["pos0"] - moved_mm * 1000) <= 50, "the law's position in the box's frame: %d µm, the tool's %.0f expected" % (ins["pos0"], moved_mm * 1000))
        # At rest the session's law holds the tool (a stiffness) once its residual speed is under the
        # stick threshold; with the servo's tail it may flick back to sliding for a command or two.
        held = r["last_stiff"] and r["last_stiff"]["insertion"]
        check(held and r["from_end"] < 10 and held["damping"] >= held["stiffness"] * 0.005 / 2 - 1,
              "the law at rest: a stiffness among the last 10 commands, and damping b >= K T / 2: %s (%s from the end)" % (held, r["from_end"]))
        check(r["underdamped"] == 0, "%d of %d commands with damping under K T / 2" % (r["underdamped"], r["commands"]))
        # U while the box holds the hand: refused with one line on the HUD (app::DeviceDrive), as
        # in cathbox-trainer with a box.
        ActionChains(b.driver).send_keys("u").perform()
        advance(b, 1)
        line = b.js("return document.getElementById('hud').textContent.split('\\n').pop()")
        check(line == "U: refused while a box drives the tools (draw the catheter back on the box)", "U with a box: %r" % line)
        report["webhid_u_with_box"] = line
        end_run(b, "the WebHID run")
        # A box not calibrated: refused, one line, the keyboard drives.
        open_assignment(b, assignment, "virtual")
        fake_in_worker(b, "codec")
        check(b.driver.execute_async_script(CONFIGURE_JS, {"calibration": {"insertion_counts_per_m": 0}}) is True, "the fake box's configuration")
        refused = connect_box(b, "no box")
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


def start_emulated_box(centre, name, hand):
    """cathbox-emu (its scripted hand: `hand`, cathbox-emu's --hand-* options) behind
    cathbox-box-bridge on a free port: (emulator, bridge, the bridge's ws:// address, its stderr's file)."""
    sock = os.path.join(centre.tmp, name + ".sock")
    emu = subprocess.Popen([centre.program("cathbox-emu"), "--socket", sock, *hand, "--duration", "120"],
                           stdout=open(os.path.join(centre.tmp, name + ".log"), "w"), stderr=subprocess.STDOUT)
    centre.processes.append(emu)
    wait_until(lambda: os.path.exists(sock), "cathbox-emu's socket")
    bridge_err = os.path.join(centre.tmp, name + "-bridge.log")
    bridge = subprocess.Popen([centre.program("cathbox-box-bridge"), "--emu-socket", sock, "--port", "0"],
                              stdout=subprocess.PIPE, stderr=open(bridge_err, "w"), text=True)
    centre.processes.append(bridge)
    line = bridge.stdout.readline().strip()
    check(line.startswith("box-bridge: ws://127.0.0.1:"), "the bridge's first line: %r" % line)
    return emu, bridge, line.split(" ", 1)[1], bridge_err


def box_drives(b):
    """Waits for the page to say the box drives the held tool and to show its figures: the first ones."""
    note = b.wait_js("const n = document.getElementById('box-note').textContent; const e = document.getElementById('error');"
                     "return n.endsWith('drives the held tool') || n.startsWith('no box') || n.startsWith('box lost') ? n"
                     " : !e.hidden && e.textContent ? e.textContent : null;", "the box to drive the tool")
    check(note.endswith("drives the held tool"), "the page's box: %r (%s)" % (note, b.js(BOX_JS)))
    b.wait_js("return document.getElementById('box-report').textContent.startsWith('box ') && document.getElementById('hud').textContent !== ''",
              "the box's figures on the page")
    return {"box": box_report(b, law=False), "at": hud(b)}


def emulated_box_follows(b, first, steady=True):
    """The emulator's hand pushes: the tool follows its encoder 10 mm (no key pressed), and the
    emulator's own reports show the page's commands applied, as BoxClient's are: its calibration
    and limits read, the watchdog fed (command gaps), output enabled and fresh, the watchdog fault
    acknowledged, the brake rendering the law's force (steady: the hand pushing at a steady speed from
    the start, its offset; else resisting, within full scale). The figures then: {box, at}."""
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
    if steady:
        check(abs(s["insertion_force_mN"] - law["insertion_offset_mN"]) <= 10,
              "the emulator renders %d mN, the page commanded %d mN" % (s["insertion_force_mN"], law["insertion_offset_mN"]))
    else:  # the hand just set off: the law's stiffness adds the servo's lag (20 N/mm), still resisting, within full scale
        check(-config["full_scale_mN"] <= s["insertion_force_mN"] <= 0,
              "the emulator renders %d mN, the page commanded %d mN at its position" % (s["insertion_force_mN"], law["insertion_offset_mN"]))
    return box, at


def test_box_bridge(b, centre, assignment, report):
    """The page's box path against cathbox-emu through cathbox-box-bridge (see the docstring)."""
    emu, bridge, url, bridge_err = start_emulated_box(centre, "emu", ["--hand-insertion", "v:20mm/s:60s"])
    b.open("/train.html?box=" + url)
    b.wait(EC.element_to_be_clickable((By.CSS_SELECTOR, "button.open-case[data-id='%d']" % assignment)), "the assignment's Run button")
    b.driver.find_element(By.CSS_SELECTOR, "button.open-case[data-id='%d']" % assignment).click()
    first = box_drives(b)
    box, at = emulated_box_follows(b, first)
    s, config = box["state"], box["config"]
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


# The emulator's hand for a run to the Y's left branch (cases/y_bifurcation_left.actions, by hand):
# still for 3 s (the box connects and takes its zero), 40 mm into the parent at 20 mm/s, a full turn
# of the angled tip while still, then on at 20 mm/s until the page ends the run at the target.
HAND_TO_TARGET = ["--hand-insertion", "free:3s,v:20mm/s:2s,free:1.5s,v:20mm/s:8s,free:100s",
                  "--hand-rotation", "free:5.2s,v:6.2832rad/s:1s,free:100s"]


def test_webhid_emulated(b, centre, assignment, report):
    """The WebHID path end to end in the haptic worker, on its own clock: the page asks Chromium for
    the box (fake_webhid.js's chooser), the worker opens it from navigator.hid.getDevices() and owns
    its reports; behind the worker's navigator.hid is cathbox-emu's firmware through
    cathbox-box-bridge (fake_webhid.js's 'bridge' backend). As the bridge's own path: the emulator's
    calibration and limits read, the tool following its hand, the commands applied and the watchdog
    fed; then the hand takes the wire to the target, and the run is uploaded and checked."""
    started = time.monotonic()
    script = fake_in_page(b)
    try:
        open_assignment(b, assignment, "real")
        emu, bridge, url, bridge_err = start_emulated_box(centre, "emu-webhid", HAND_TO_TARGET)
        fake_in_worker(b, "bridge", url)
        note = connect_box(b, "box: WebHID Cathbox (fake WebHID) ")
        check(note.startswith("box: WebHID Cathbox (fake WebHID) "), "the page's box: %r" % note)
        first = box_drives(b)
        box, at = emulated_box_follows(b, first, steady=False)
        features = b.js("return window.fakeBox.features_read")
        check(features == [0x10, 0x11, 0x12], "feature reports read: %s (device info, calibration, limits expected)" % features)
        state = b.wait_js(END_JS, "the run's end and upload", timeout=60)
        check(state == "done", "the WebHID run's upload: %s (%s)" % (state, b.js("return document.getElementById('error').textContent")))
        end, result, _ = end_of_run(b, centre)
        b.shot("train-webhid-emulated-end")
        check(end == "target reached", "the emulated box's hand: the run ended by '%s', not at the target (%s)" % (end, hud(b)))
        check(result["complete"] is True, "the stored result: %s" % result)
        # The worker's clock told the session its dropped ticks: the record the server replayed
        # carries the page's own count.
        note = b.js("return document.getElementById('clock-note').textContent")
        clock = CLOCK_NOTE.match(note)
        check(clock is not None, "the page's clock note: %r" % note)
        dropped = int(clock.group(5))
        stored = (result.get("metrics") or {}).get("haptic_dropped_ticks")
        check(stored == dropped, "the result's haptic_dropped_ticks %r, the page's clock note %d" % (stored, dropped))
        wait_until(lambda: "page closed" in open(bridge_err).read(), "the bridge to see the page close")
        closed = [x for x in open(bridge_err).read().splitlines() if "page closed" in x][-1]
        bridge.terminate()
        emu.terminate()
        report["webhid_emulated"] = {"box_mm": round(box["box_mm"] - first["box"]["box_mm"], 2),
                                     "tool_mm": round(at["insertion_mm"] - first["at"]["insertion_mm"], 2), "state": box["state"],
                                     "law": box["law"], "stats": box["stats"], "config": box["config"], "end": end,
                                     "seconds_of_run": hud(b)["time_s"], "result": result["id"], "bridge": closed,
                                     "sent": b.js("return window.fakeBox.sent"), "dropped": dropped,
                                     "seconds": round(time.monotonic() - started, 1)}
    finally:
        b.driver.execute_cdp_cmd("Page.removeScriptToEvaluateOnNewDocument", {"identifier": script["identifier"]})
