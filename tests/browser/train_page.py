"""The trainee page's (/train.html) common moves for its browser test (train_test.py): the seeded
centre, opening an assignment, the virtual clock's "Run N ticks", keys held for exact tick counts,
the HUD's figures and the end of a run, read from the page as a user reads them."""
import os
import re

from browser_test import Api, check
from selenium.webdriver.common.action_chains import ActionChains
from selenium.webdriver.common.by import By
from selenium.webdriver.common.keys import Keys
from selenium.webdriver.support import expected_conditions as EC


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


def open_assignment(b, assignment, clock, view=None, spin=None, extra=None):
    query = [("clock=virtual" if clock == "virtual" else None), ("view=" + view if view else None),
             ("spin=%g" % spin if spin is not None else None), extra]
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


def end_run(b, what):
    ActionChains(b.driver).send_keys(Keys.ESCAPE).perform()
    state = b.wait_js(END_JS, "the upload")
    check(state == "done", "%s: the upload: %s (%s)" % (what, state, b.js("return document.getElementById('error').textContent")))
