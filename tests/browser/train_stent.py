"""The stent retriever's U and E keys on the trainee page (train_test.py): cathbox-trainer's
app::DeviceDrive in the haptic worker. The small Y of tests/host/session/stent_tube_case.hpp (a
3.6 mm parent, a 2.8 mm branch straight on with a 10 mm red-cell-rich clot 6 mm into it; balloon
guide > microcatheter > a 4 x 20 mm stent retriever, embedding cut to 0.5 s) is read from
tests/host/session/data/stent_tube.{case,hclm}, as the native tests read it. In virtual time,
keys only: the guide to 20 mm, the microcatheter across the clot to 56 mm, the stent to 50 mm;
U draws the microcatheter back at 5 mm/s until the whole stent is out and stops by itself; a
1 s dwell; E pulls the stent back at 10 mm/s until its pass ends.
The uploaded record (every state hash replayed by the server) holds one stent pass."""
import os

from browser_test import Api, check
from train_page import END_JS, advance, end_of_run, hold, hud, open_assignment
from selenium.webdriver.common.action_chains import ActionChains
from selenium.webdriver.common.keys import Keys


def stent_tube_case(source):
    """(case text, HCLM text): the Y and its stack, tests/host/session/data/stent_tube.{case,hclm},
    as the native stent-retriever tests read them (stent_tube_case.hpp)."""
    data = os.path.join(source, "tests", "host", "session", "data", "stent_tube.")
    return open(data + "case").read(), open(data + "hclm").read()


def seed_stent(centre):
    """The case on the server, assigned to ann; the assignment's id."""
    teacher = Api(centre.base).login("teacher")
    case, hclm = stent_tube_case(centre.args.source)
    teacher.json("POST", "/cases", {"name": "stent", "case_file": "stent_tube.case", "case": case, "hclm_file": "stent_tube.hclm", "hclm": hclm})
    _, a = teacher.json("POST", "/assignments", {"trainee": "ann", "case": "stent", "criteria": []})
    return a["id"]


def hud_lines(b):
    return b.js("return document.getElementById('hud').textContent").split("\n")


def press_until(b, key, line, what, step=250, steps=40):
    """Presses `key` once, then runs `step` ticks at a time until the HUD's last line is `line`;
    the ticks run."""
    ActionChains(b.driver).send_keys(key).perform()
    ran = 0
    for _ in range(steps):
        ran += advance(b, step)
        if hud_lines(b)[-1] == line:
            return ran
    check(False, "%s: the HUD after %d ticks: %r" % (what, ran, hud_lines(b)[-3:]))
    return ran


def push(b, tool, to_mm, tab):
    """Shift+W (40 mm/s) on the next tool (Tab first when `tab`) until `tool` is at `to_mm`."""
    if tab:
        ActionChains(b.driver).send_keys(Keys.TAB).perform()
    advance(b, 1)  # a frame after the key (and after the page knows the tools' names)
    at = hud(b)
    check(at["tool"] == tool, "the held tool: %s, %s expected" % (at["tool"], tool))
    hold(b, [Keys.SHIFT, "w"], round((to_mm - at["insertion_mm"]) / 40.0 * 1000))
    at = hud(b)
    check(abs(at["insertion_mm"] - to_mm) < 0.05, "%s to %.0f mm: %.3f mm" % (tool, to_mm, at["insertion_mm"]))


def test_stent_keys(b, centre, report):
    assignment = seed_stent(centre)
    open_assignment(b, assignment, "virtual")
    push(b, "guide", 20.0, False)
    push(b, "microcatheter", 56.0, True)
    push(b, "stent", 50.0, True)
    check("U: unsheathe the stent (0 / 20 mm out; the microcatheter back at 5 mm/s)" in hud_lines(b), "the HUD's U line: %r" % hud_lines(b)[-2:])
    before = hud(b)
    unsheathe_ticks = press_until(b, "u", "U: the stent is unsheathed (20 / 20 mm)", "U")
    after = hud(b)
    check(after["tool"] == "microcatheter", "U drew back the %s, not the microcatheter" % after["tool"])
    drawn_mm = 56.0 - after["insertion_mm"]
    check(drawn_mm > 19.0, "U: the microcatheter drawn back %.2f mm (the stent 20 mm long)" % drawn_mm)
    check(abs(after["time_s"] - before["time_s"] - unsheathe_ticks / 1000) < 0.002, "the virtual clock: %s -> %s" % (before, after))
    check("E: retrieve the stent (back at 10 mm/s into a catheter)" in hud_lines(b), "the HUD's E line: %r" % hud_lines(b)[-3:])
    advance(b, 1000)  # the dwell: the clot integrates (the case's embedding time, 0.5 s)
    retrieve_ticks = press_until(b, "e", "E: the stent is back in a catheter: the pass has ended", "E")
    at = hud(b)
    check(at["tool"] == "stent" and at["insertion_mm"] < 50.0 - 15.0, "E: the stent pulled back: %s" % at)
    ActionChains(b.driver).send_keys(Keys.ESCAPE).perform()
    state = b.wait_js(END_JS, "the stent run's upload")
    check(state == "done", "the stent run's upload: %s (%s)" % (state, b.js("return document.getElementById('error').textContent")))
    end, result, record_bytes = end_of_run(b, centre)
    m = result.get("metrics") or {}
    check(m.get("thrombectomy_passes") == 1 and (m.get("retrieval_force_peak_N") or 0) > 0,
          "the record's metrics: one stent pass with a pull expected: %s" % {k: m.get(k) for k in ("thrombectomy_passes", "retrieval_force_peak_N", "etici_final")})
    b.shot("train-stent-end")
    report["stent_keys"] = {"unsheathe_ticks": unsheathe_ticks, "microcatheter_drawn_mm": round(drawn_mm, 3), "retrieve_ticks": retrieve_ticks,
                            "stent_at_mm": at["insertion_mm"], "end": end, "record_bytes": record_bytes,
                            "metrics": {k: m.get(k) for k in ("thrombectomy_passes", "retrieval_force_peak_N", "etici_final", "emboli")}}
