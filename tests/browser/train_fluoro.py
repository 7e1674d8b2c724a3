"""The fluoroscopy in the trainee page (train_test.py): the monitor's image in virtual time."""
import base64
import os
import re
import time

from browser_test import Api, check
from png_pixels import grey
from train_page import end_run, hold
from selenium.webdriver.common.by import By
from selenium.webdriver.common.keys import Keys
from selenium.webdriver.support import expected_conditions as EC
from selenium.webdriver.support.ui import Select


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


def blocks(b, n=12, scale=0.1):
    """The monitor as n x n block means of its collimated square, from a screenshot of the canvas
    scaled down by Chromium (each pixel then averages ~100 of the canvas's, each block ~1600: the
    quantum noise averages out, the anatomy does not; and a small image decodes fast)."""
    r = b.driver.find_element(By.ID, "fluoro").rect
    shot = b.driver.execute_cdp_cmd("Page.captureScreenshot", {"format": "png", "clip": {
        "x": r["x"], "y": r["y"], "width": r["width"], "height": r["height"], "scale": scale}})
    w, h, rows = grey(base64.b64decode(shot["data"]))
    side = min(w, h)
    x0, y0 = (w - side) // 2, (h - side) // 2
    k = side // n
    return [sum(rows[y0 + by * k + y][x0 + bx * k + x] for y in range(k) for x in range(k)) / (k * k) for by in range(n) for bx in range(n)]


def block_difference(a, b):
    """The mean absolute difference of two images' block means (grey levels)."""
    return round(sum(abs(x - y) for x, y in zip(a, b)) / len(a), 2)


def turn_carm(b, projection):
    """Picks `projection` in the C-arm panel's list (as a trainee does), then holds the pedal 150
    ticks: the panel's line for the C-arm, and the monitor's block means."""
    pulse = int(re.search(r"pulse (\d+)", b.js(FLUORO_NOTE_JS)).group(1))
    select = Select(b.driver.find_element(By.ID, "carm-projection"))
    select.select_by_index(next(i for i, o in enumerate(select.options) if o.text.startswith(projection + " (")))
    hold(b, [Keys.SPACE], 150)
    b.wait_js("const m = document.getElementById('fluoro-note').textContent.match(/pulse (\\d+)/); return m && Number(m[1]) >= %d;" % (pulse + 2),
              "two pulses after turning the C-arm to %s" % projection)
    return b.js("return document.getElementById('carm-pose').textContent"), blocks(b)


def test_carm_panel(b):
    """The C-arm panel (js/carm_panel.js, the native panel's model in the worker): AP picked, then the
    lateral projection, the next pulses show another image of the head (block means, free
    of the noise, far from the AP image's), and AP picked again the same image as before (within
    the noise)."""
    start = time.monotonic()
    check(not b.js("return document.getElementById('carm').hidden"), "the C-arm panel is not shown beside the fluoroscopy")
    ap_line, ap = turn_carm(b, "AP")  # from the case's first working projection
    check(ap_line.startswith("AP, 0°, "), "the C-arm panel at AP: %r" % ap_line)
    lateral_line, lateral = turn_carm(b, "lateral")
    check(lateral_line.startswith("LAO 90°, 0°, "), "the C-arm panel after picking the lateral projection: %r" % lateral_line)
    b.shot("train-carm")
    back_line, back = turn_carm(b, "AP")
    check(back_line.startswith("AP, 0°, "), "the C-arm panel back at AP: %r" % back_line)
    turned, same = block_difference(ap, lateral), block_difference(ap, back)
    check(turned >= 8 and same <= 3 and turned >= 4 * same,
          "AP -> lateral must change the image (block means %.2f grey apart) far beyond AP -> AP (%.2f)" % (turned, same))
    return {"ap": ap_line, "lateral": lateral_line, "ap_to_lateral_grey": turned, "ap_to_ap_grey": same,
            "wall_s": round(time.monotonic() - start, 1)}


def inject(b, name):
    """I (inject) with the pedal down for 50 ticks, then the pedal alone 1.5 s: a subtraction run
    (as the native unit starts one); its note and its monitor image, saved as `name`."""
    hold(b, [Keys.SPACE, "i"], 50)
    hold(b, [Keys.SPACE], 1500)
    note = b.wait_js("const n = document.getElementById('fluoro-note').textContent; const m = n.match(/pulse (\\d+)/);"
                     "return m && Number(m[1]) >= 25 ? n : null;", "the pulses after the injection")
    check(" subtraction run, " in note, "injecting with the pedal down starts a subtraction run (as the native unit): %r" % note)
    return note, monitor(b, name)


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
    carm = test_carm_panel(b)
    note, run = inject(b, "train-fluoro-subtraction")
    # The run's frame minus its mask: the anatomy cancels to the DSA background (0.72 of white),
    # only noise (and what changed) left.
    check(abs(run["median"] - 0.72 * 255) <= 12 and run["std"] < live["std"] / 2,
          "the subtraction image: the DSA background with the anatomy subtracted expected, %s (live %s)" % (run, live))
    end_run(b, "the fluoroscopy run")
    report["fluoroscopy"] = {"before_pedal": black, "live": live, "carm": carm, "subtraction": run, "note": note}


# The neuro tree entered at the left internal carotid (the entry of cases/neuro_thrombectomy_ica_t.case),
# without that case's clot: contrast injected through the catheter goes up the carotid into the tree.
ICA_ENTRY = "entry 26.39 15.64 127.65  0.1627 -0.1374 0.9771"


def seed_carotid(centre):
    """The neuro case entered at the left ICA, assigned to the trainee: its assignment's id."""
    cases = os.path.join(centre.args.source, "cases")
    text = re.sub(r"^entry .*$", ICA_ENTRY, open(os.path.join(cases, "neuro.case")).read(), count=1, flags=re.M)
    teacher = Api(centre.base).login("teacher")
    teacher.json("POST", "/cases", {"name": "neuro_ica", "case_file": "neuro_ica.case", "case": text,
                                    "hclm_file": "neuro.hclm", "hclm": open(os.path.join(cases, "neuro.hclm")).read()})
    _, a = teacher.json("POST", "/assignments", {"trainee": "ann", "case": "neuro_ica", "criteria": []})
    return a["id"]


def arteries(path):
    """The intracranial band of a saved monitor image (rows 30-55 % of its height, inside the
    collimated field: the carotid siphon, the ACA and MCA in the AP view, above the skull base):
    its median grey, and the fraction of its pixels darker than that by 40 (a vessel with iodine
    in a subtraction image; noise alone stays within ~3 standard deviations, ~25 grey)."""
    w, h, rows = grey(open(path, "rb").read())
    side = min(w, h)
    x0 = (w - side) // 2
    band = sorted(v for r in rows[int(0.3 * h):int(0.55 * h)] for v in r[x0 + side // 10:x0 + side - side // 10])
    median = band[len(band) // 2]
    return {"median": median, "dark_fraction": round(sum(1 for v in band if v < median - 40) / len(band), 4), "p01": band[len(band) // 1000]}


def test_contrast(b, centre, report):
    """Injected contrast shows in the lumen: on the neuro tree entered at the left internal carotid,
    I (6 mL at 3 mL/s) with the pedal down starts a subtraction run; within 1.5 s of session time
    the iodine has reached the intracranial arteries and their pixels are dark on the DSA
    background, where the same run injected at the aortic entry (test_fluoroscopy) shows none."""
    assignment = seed_carotid(centre)
    b.open("/train.html?clock=virtual&view=fluoro")
    b.wait(EC.element_to_be_clickable((By.CSS_SELECTOR, "button.open-case[data-id='%d']" % assignment)), "the assignment's Run button")
    b.driver.find_element(By.CSS_SELECTOR, "button.open-case[data-id='%d']" % assignment).click()
    b.wait_js("return document.getElementById('status').textContent === 'running'", "the session to start in the worker")
    hold(b, [Keys.SPACE], 200)
    note, run = inject(b, "train-fluoro-contrast")
    check(abs(run["median"] - 0.72 * 255) <= 12, "the subtraction image's background: %s" % run)
    lumen = arteries(os.path.join(b.out, b.prefix + "train-fluoro-contrast.png"))
    control = arteries(os.path.join(b.out, b.prefix + "train-fluoro-subtraction.png"))  # test_fluoroscopy's, injected at the aorta
    check(lumen["dark_fraction"] >= 0.005 and lumen["p01"] <= lumen["median"] - 80,
          "injected at the carotid, the arteries dark with iodine expected in the intracranial band: %s" % lumen)
    check(control["dark_fraction"] <= 0.001, "injected at the aortic entry, no artery expected there yet: %s" % control)
    end_run(b, "the contrast run")
    report["contrast"] = {"subtraction": run, "arteries": lumen, "aortic_injection": control, "note": note}
