"""Records across rigs (train_test.py): the page's upload replayed natively, a native record replayed
in the page's worker ("Check a record")."""
import json
import os
import re

from browser_test import Api, check
from selenium.webdriver.common.by import By


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
