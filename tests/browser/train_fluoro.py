"""The fluoroscopy in the trainee page (train_test.py): the monitor's image in virtual time."""
import os
import re

from browser_test import check
from png_pixels import grey
from train_page import end_run, hold
from selenium.webdriver.common.by import By
from selenium.webdriver.common.keys import Keys
from selenium.webdriver.support import expected_conditions as EC


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
