#!/usr/bin/python3
"""The training centre's pages in a real browser (issue 15).

Headless Chromium (Debian's chromium + chromium-driver, driven by python3-selenium) against a
cathbox-server started here on a free loopback port with a fresh SQLite store, seeded with real
sessions recorded by `cathbox session run` and uploaded through the API:

  - an instructor logs in, sees a rig streamed by a headless cathbox-trainer appear live and its
    tip move; a steady 30 Hz stream is drawn as it comes and its frame rate measured;
  - a debrief opens and seeks (the time it takes is measured, first and cached);
  - a thrombectomy run's debrief (the carotid-T aspiration script) has its "eTICI per pass" row
    and flow-arrest rows read as `cathbox session metrics --json` grades the same record, and its
    one injection marked once;
  - a learning-curve plot has one point per attempt;
  - a trainee sees their own page, is refused the instructor pages and the API behind them.

Any SEVERE message on the browser console fails the test. Screenshots of every page go to
--out (the build folder). Every wait is bounded; nothing sleeps blindly.

With --https the server speaks HTTPS and wss:// with a certificate from a throwaway CA made here
with `openssl` (as tests/host/server/tls_test.cpp does); this script's own calls trust that CA,
Chromium pins the server key (--ignore-certificate-errors-spki-list: the SHA-256 of the
certificate's SubjectPublicKeyInfo, so any other certificate is still refused). It runs a subset
(CTest test_browser_https): log in, the live view's wss:// watcher socket showing a rig streamed
over wss://, a debrief.

  tests/browser/browser_test.py --bin build/release/bin --source . --out build/release/browser [--https]
"""
import argparse
import base64
import hashlib
import json
import os
import re
import shutil
import signal
import socket
import ssl
import statistics
import subprocess
import sys
import tempfile
import threading
import time
import traceback
import urllib.error
import urllib.request

from selenium import webdriver
from selenium.webdriver.chrome.service import Service
from selenium.webdriver.common.by import By
from selenium.webdriver.support import expected_conditions as EC
from selenium.webdriver.support.ui import WebDriverWait

PASSWORD = "browser-pass-1"
WAIT_S = 30
# The TLS context of this script's own calls (urllib, the publisher's socket) when the server
# speaks HTTPS: it trusts the throwaway CA only (Centre.make_certificate).
TLS = {"context": None}


class Failure(Exception):
    pass


def check(cond, message):
    if not cond:
        raise Failure(message)


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def wait_until(predicate, what, timeout=WAIT_S, every=0.05):
    """Polls predicate() until it returns something truthy; fails naming `what` after timeout."""
    deadline = time.monotonic() + timeout
    while True:
        value = predicate()
        if value:
            return value
        if time.monotonic() > deadline:
            raise Failure("timed out after %.0f s waiting for %s" % (timeout, what))
        time.sleep(every)


class Api:
    """The REST API over urllib, as one user."""

    def __init__(self, base):
        self.base = base
        self.token = None

    def call(self, method, path, body=None, raw=None, expect=(200, 201, 204)):
        headers = {}
        data = None
        if self.token:
            headers["Authorization"] = "Bearer " + self.token
        if raw is not None:
            headers["Content-Type"] = "application/octet-stream"
            data = raw
        elif body is not None:
            headers["Content-Type"] = "application/json"
            data = json.dumps(body).encode()
        req = urllib.request.Request(self.base + "/api/v1" + path, data=data, headers=headers, method=method)
        try:
            with urllib.request.urlopen(req, timeout=900, context=TLS["context"]) as res:
                status, payload, head = res.status, res.read(), dict(res.headers)
        except urllib.error.HTTPError as e:
            status, payload, head = e.code, e.read(), dict(e.headers)
        if status not in expect:
            raise Failure("%s %s: %d %s" % (method, path, status, payload[:300]))
        return status, payload, head

    def json(self, method, path, body=None, raw=None, expect=(200, 201, 204)):
        status, payload, _ = self.call(method, path, body=body, raw=raw, expect=expect)
        return status, (json.loads(payload) if payload else None)

    def login(self, name):
        _, r = self.json("POST", "/login", {"name": name, "password": PASSWORD})
        self.token = r["token"]
        return self


def ws_publisher(base, path, token):
    """A minimal WebSocket client (RFC 6455, text frames, masked) for a publishing rig."""
    host, port = base.split("//")[1].split(":")
    sock = socket.create_connection((host, int(port)), timeout=10)
    if base.startswith("https:"):
        sock = TLS["context"].wrap_socket(sock, server_hostname=host)
    key = base64.b64encode(os.urandom(16)).decode()
    sock.sendall(("GET %s HTTP/1.1\r\nHost: %s:%s\r\nUpgrade: websocket\r\nConnection: Upgrade\r\n"
                  "Sec-WebSocket-Key: %s\r\nSec-WebSocket-Version: 13\r\nAuthorization: Bearer %s\r\n\r\n"
                  % (path, host, port, key, token)).encode())
    answer = b""
    while b"\r\n\r\n" not in answer:
        chunk = sock.recv(4096)
        if not chunk:
            break
        answer += chunk
    check(answer.startswith(b"HTTP/1.1 101"), "publisher upgrade refused: %r" % answer[:200])

    def send(text):
        data = text.encode()
        mask = os.urandom(4)
        head = bytearray([0x81])
        n = len(data)
        if n < 126:
            head.append(0x80 | n)
        elif n < 65536:
            head += bytes([0x80 | 126]) + n.to_bytes(2, "big")
        else:
            head += bytes([0x80 | 127]) + n.to_bytes(8, "big")
        sock.sendall(bytes(head) + mask + bytes(b ^ mask[i % 4] for i, b in enumerate(data)))

    return sock, send


def end_publisher(sock, send):
    """Ends a publisher's stream ({"type": "end"}) and closes its socket (which may be gone)."""
    try:
        send(json.dumps({"type": "end"}))
    except OSError:
        pass
    sock.close()


class Centre:
    """cathbox-server on a fresh SQLite store, with accounts, a case, an assignment, results."""

    def __init__(self, args, tmp):
        self.args = args
        self.tmp = tmp
        self.bin = args.bin
        self.db = "sqlite:" + os.path.join(tmp, "server.db")
        self.env = dict(os.environ, CATHBOX_PASSWORD=PASSWORD, XDG_DATA_HOME=os.path.join(tmp, "data"),
                        XDG_CACHE_HOME=os.path.join(tmp, "cache"), XDG_CONFIG_HOME=os.path.join(tmp, "config"))
        self.processes = []
        self.port = free_port()
        self.base = "http://127.0.0.1:%d" % self.port
        self.extra_args = []  # more cathbox-server options (train_test.py: --wasm)
        self.spki = None  # with HTTPS: the certificate key's pin for Chromium
        if getattr(args, "https", False):
            self.make_certificate()
        self.others = []  # results uploaded by other tests (not ann's assignment)

    def program(self, name):
        return os.path.join(self.bin, name)

    def make_certificate(self):
        """A throwaway CA and a certificate for 127.0.0.1 signed by it; the server serves HTTPS."""
        d = os.path.join(self.tmp, "tls")
        os.makedirs(d)
        at = lambda name: os.path.join(d, name)  # noqa: E731
        ec = ["-newkey", "ec", "-pkeyopt", "ec_paramgen_curve:P-256", "-nodes"]
        open(at("server.ext"), "w").write("subjectAltName=IP:127.0.0.1,DNS:localhost\nextendedKeyUsage=serverAuth\n")
        for argv in [["openssl", "req", "-x509"] + ec + ["-keyout", at("ca.key"), "-out", at("ca.pem"), "-subj", "/CN=browser-test-ca", "-days", "2"],
                     ["openssl", "req"] + ec + ["-keyout", at("server.key"), "-out", at("server.csr"), "-subj", "/CN=127.0.0.1"],
                     ["openssl", "x509", "-req", "-in", at("server.csr"), "-CA", at("ca.pem"), "-CAkey", at("ca.key"), "-CAcreateserial",
                      "-out", at("server.pem"), "-days", "2", "-extfile", at("server.ext")]]:
            self.run(argv, " ".join(argv[:3]))
        spki_der = subprocess.run("openssl x509 -in %s -pubkey -noout | openssl pkey -pubin -outform der" % at("server.pem"), shell=True,
                                  stdout=subprocess.PIPE, check=True).stdout
        self.spki = base64.b64encode(hashlib.sha256(spki_der).digest()).decode()
        self.ca_file = at("ca.pem")
        TLS["context"] = ssl.create_default_context(cafile=self.ca_file)
        self.extra_args += ["--tls-cert", at("server.pem"), "--tls-key", at("server.key")]
        self.base = "https://127.0.0.1:%d" % self.port

    def run(self, argv, what, timeout=300, merge=True):
        """Runs a program to its end; its output (with stderr unless not `merge`)."""
        r = subprocess.run(argv, env=self.env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT if merge else subprocess.PIPE,
                           timeout=timeout)
        check(r.returncode == 0, "%s failed (%d): %s" % (what, r.returncode, (r.stdout + (r.stderr or b"")).decode()[-2000:]))
        return r.stdout.decode()

    def start(self):
        for name, role in [("root", "admin"), ("teacher", "instructor"), ("ann", "trainee"), ("bob", "trainee")]:
            self.run([self.program("cathbox-server"), "--db", self.db, "admin", "create-user", name, "--role", role], "create-user " + name)
        self.launch()

    def restart(self, forget=False):
        """The server again on the same store and port: its memory cache empty, and with `forget`
        its disk cache (meshes, traces) too."""
        self.server.terminate()
        self.server.wait(timeout=30)
        if forget:
            shutil.rmtree(os.path.join(self.tmp, "data", "cache"), ignore_errors=True)
        self.launch()

    def launch(self):
        log = open(os.path.join(self.tmp, "server.log"), "a")
        self.server = subprocess.Popen([self.program("cathbox-server"), "--db", self.db, "--listen", "127.0.0.1:%d" % self.port,
                                        "--data", os.path.join(self.tmp, "data"), "--web", os.path.join(self.args.source, "host/server/web")] + self.extra_args,
                                       env=self.env, stdout=log, stderr=subprocess.STDOUT)
        self.processes.append(self.server)

        def up():
            check(self.server.poll() is None, "cathbox-server exited: " + open(log.name).read()[-2000:])
            try:
                with urllib.request.urlopen(self.base + "/", timeout=2, context=TLS["context"]) as r:
                    return r.status == 200
            except (urllib.error.URLError, ConnectionError):
                return False
        wait_until(up, "cathbox-server to listen")

    def seed(self, attempts=("3.5", "4.5", "6")):
        teacher = Api(self.base).login("teacher")
        cases = os.path.join(self.args.source, "cases")
        _, c = teacher.json("POST", "/cases", {
            "name": "ybif", "case_file": "y_bifurcation.case", "case": open(os.path.join(cases, "y_bifurcation.case")).read(),
            "hclm_file": "y_bifurcation.hclm", "hclm": open(os.path.join(cases, "y_bifurcation.hclm")).read()})
        check(c["version"] == 1, "case upload: %s" % c)
        _, a = teacher.json("POST", "/assignments", {
            "trainee": "ann", "case": "ybif", "note": "Left branch, gently.",
            "criteria": [{"metric": "peak_wall_force_mN", "op": "<=", "value": 200}, {"metric": "tip_path_mm", "op": ">=", "value": 80}]})
        self.assignment = a["id"]
        ann = Api(self.base).login("ann")
        # Three attempts, each a real session record: cut at 3.5 s, 4.5 s, then the whole script.
        self.results = []
        for i, seconds in enumerate(attempts):
            rec = os.path.join(self.tmp, "ann-%d.cbxrec" % i)
            self.run([self.program("cathbox"), "session", "run", "--case", os.path.join(cases, "y_bifurcation.case"),
                      "--script", os.path.join(cases, "y_bifurcation_left.actions"), "--record", rec, "--virtual",
                      "--seconds", seconds], "session run")
            _, r = ann.json("POST", "/results?assignment=%d" % self.assignment, raw=open(rec, "rb").read())
            self.results.append(r)
        return teacher, ann

    def stop(self):
        for p in reversed(self.processes):
            if p.poll() is None:
                p.terminate()
                try:
                    p.wait(timeout=10)
                except subprocess.TimeoutExpired:
                    p.kill()
                    p.wait(timeout=10)


class Browser:
    def __init__(self, out, spki=None, extra_args=(), browser_log=None):
        """`browser_log`: a file that gets Chromium's own stdout and stderr (e.g. V8's
        `--js-flags=--trace-gc` lines), through chromedriver's --enable-chrome-logs."""
        self.out = out
        options = webdriver.ChromeOptions()
        options.binary_location = "/usr/bin/chromium"
        if spki:
            # Accept the one server key, nothing else (chromedriver gives a --user-data-dir, which
            # the flag needs).
            options.add_argument("--ignore-certificate-errors-spki-list=" + spki)
        for a in ["--headless=new", "--no-sandbox", "--disable-dev-shm-usage", "--window-size=1280,720",
                  "--use-angle=swiftshader", "--enable-unsafe-swiftshader", "--disable-gpu-vsync",
                  "--hide-scrollbars", "--mute-audio", "--no-first-run", "--disable-extensions", *extra_args]:
            options.add_argument(a)
        options.set_capability("goog:loggingPrefs", {"browser": "ALL"})
        service = Service("/usr/bin/chromedriver")
        if browser_log:
            # Line-buffered (coreutils' stdbuf library, inherited by every Chromium process), so that a
            # renderer ended by quit() leaves no lines in its stdio buffer.
            env = dict(os.environ, LD_PRELOAD="/usr/libexec/coreutils/libstdbuf.so", _STDBUF_O="L", _STDBUF_E="L")
            service = Service("/usr/bin/chromedriver", service_args=["--enable-chrome-logs"], log_file=open(browser_log, "wb"), env=env)
        self.driver = webdriver.Chrome(service=service, options=options)
        self.viewport(1280, 720)
        self.driver.set_page_load_timeout(WAIT_S)
        self.driver.set_script_timeout(WAIT_S)
        self.console = []
        self.prefix = ""  # of the screenshots' names ("https-" for the HTTPS run)

    def viewport(self, width, height, mobile=False):
        """The page's size (a 1280x720 screen; a tablet)."""
        self.driver.execute_cdp_cmd("Emulation.setDeviceMetricsOverride",
                                    {"width": width, "height": height, "deviceScaleFactor": 1, "mobile": mobile})

    def drain_console(self, expected=()):
        """Fails on any SEVERE console message since the last call, but for the network lines of
        the `expected` refusals (a URL part and its status, e.g. ("/api/v1/cases", 422))."""
        entries = self.driver.get_log("browser")
        self.console += entries

        def wanted(e):
            return e.get("source") == "network" and any(url in e["message"] and "status of %d" % status in e["message"] for url, status in expected)
        severe = [e for e in entries if e.get("level") == "SEVERE" and not wanted(e)]
        check(not severe, "browser console errors: %s" % json.dumps(severe, indent=1))

    def wait(self, condition, what, timeout=WAIT_S):
        try:
            return WebDriverWait(self.driver, timeout, poll_frequency=0.05).until(condition)
        except Exception as e:
            self.shot("failed")
            raise Failure("timed out waiting for %s (%s)" % (what, type(e).__name__)) from None

    def js(self, script, *args):
        return self.driver.execute_script(script, *args)

    def wait_js(self, script, what, timeout=WAIT_S):
        return self.wait(lambda d: d.execute_script(script), what, timeout)

    def shot(self, name):
        path = os.path.join(self.out, self.prefix + name + ".png")
        self.driver.save_screenshot(path)
        return path

    def open(self, path):
        self.driver.get(self.base + path)

    def login(self, name):
        self.open("/")
        self.js("sessionStorage.clear()")
        self.open("/")
        self.wait(EC.visibility_of_element_located((By.ID, "name")), "the login form")
        self.driver.find_element(By.ID, "name").send_keys(name)
        self.driver.find_element(By.ID, "password").send_keys(PASSWORD)
        self.driver.find_element(By.ID, "login-button").click()
        self.wait(EC.visibility_of_element_located((By.ID, "home")), "the home page of " + name)

    def quit(self):
        self.driver.quit()


# A live panel's readout for rig-12 (data-stat 'seq': the frame it drew last; 'drawn': how many).
RIG12_STAT_JS = "const e = document.querySelector(\"section[data-rig='rig-12'] [data-stat='%s']\"); return e ? Number(e.textContent) : null;"

def live_real_time_rig(b, centre, env, password_file):
    """A rig whose haptic thread runs in real time (cathbox-trainer --emu): its panel shows the
    ticks it has dropped so far (`rig dropped N ticks`), from its live frames' metrics."""
    b.open("/live.html?rigs=rig-08")
    b.wait_js("return document.getElementById('status').textContent === '(connected)'", "the watcher socket")
    rig = subprocess.Popen([centre.program("cathbox-trainer"), "--headless", "--emu", "--server", centre.base, "--user", "ann",
                            "--password-file", password_file, "--rig", "rig-08", "--no-record", "--seconds", "3"],
                           env=env, stdout=open(os.path.join(centre.tmp, "rig", "trainer-rig-08.log"), "w"), stderr=subprocess.STDOUT)
    centre.processes.append(rig)
    shown = b.wait_js("const e = document.querySelector(\"section[data-rig='rig-08'] [data-stat='dropped']\"); return e ? e.textContent : null;",
                      "rig-08's dropped ticks on its panel", timeout=60)
    check(re.fullmatch(r"\d+ ticks?", shown) is not None, "rig-08's dropped ticks: %r" % shown)
    b.shot("live-real-time-rig")
    rig.wait(timeout=120)
    return shown


def test_live(b, centre, args, report):
    """A rig streamed by a headless trainer appears live and its tip moves; then a steady 30 Hz
    stream for the frame rate."""
    # The page is open before the rig starts; the address names the rig, so its panel opens
    # (and its frames flow) as soon as it starts.
    b.open("/live.html?rigs=rig-07")
    b.wait_js("return document.getElementById('status').textContent === '(connected)'", "the watcher socket")
    rig_home = os.path.join(centre.tmp, "rig")
    os.makedirs(rig_home, exist_ok=True)
    password_file = os.path.join(rig_home, "password")
    open(password_file, "w").write(PASSWORD + "\n")
    env = dict(centre.env, XDG_DATA_HOME=rig_home + "/data", XDG_CACHE_HOME=rig_home + "/cache", XDG_CONFIG_HOME=rig_home + "/config")
    trainer = subprocess.Popen([centre.program("cathbox-trainer"), "--headless", "--no-box", "--server", centre.base, "--user", "ann",
                                "--password-file", password_file, "--rig", "rig-07", "--no-record",
                                "--speed", "1", "--seconds", "8"],
                               env=env, stdout=open(os.path.join(rig_home, "trainer.log"), "w"), stderr=subprocess.STDOUT)
    centre.processes.append(trainer)
    # --speed 1: the run streams as a rig would (8 simulated seconds take 8 s), not faster than
    # the page can watch it.
    b.wait(EC.presence_of_element_located((By.CSS_SELECTOR, "button[data-rig='rig-07']")), "rig-07 to appear live")
    b.wait(EC.presence_of_element_located((By.CSS_SELECTOR, "section[data-rig='rig-07']")), "rig-07's panel")
    # The tip as the panel shows it: it must change while the run goes on.
    tip_js = "const e = document.querySelector(\"section[data-rig='rig-07'] [data-stat='tip']\"); return e ? e.textContent : null;"
    first = b.wait_js(tip_js, "the first frame of rig-07")
    b.wait_js("const e = document.querySelector(\"section[data-rig='rig-07'] [data-stat='tip']\"); return e && e.textContent !== %s;"
              % json.dumps(first), "rig-07's tip to move")
    second = b.js(tip_js)
    b.shot("live-trainer")
    report["live_tip_moved"] = "%s -> %s" % (first, second)
    b.wait_js("const c = document.querySelector(\"section[data-rig='rig-07'] canvas\"); return c && c.width > 100;", "the 3D view")
    trainer.wait(timeout=120)
    report["live_rig_dropped"] = live_real_time_rig(b, centre, env, password_file)

    # A second rig streaming at a steady 30 Hz of wall time (frames from a recorded run's trace)
    # for 5 s: the page must apply the frames as they come and show the last one sent. How fast it
    # draws is measured and reported (a wall-clock figure, so a check only with --strict-speed).
    teacher = Api(centre.base).login("teacher")
    _, t = teacher.json("GET", "/results/%d/trace" % centre.results[-1]["id"])
    tr = t["trace"]
    bob = Api(centre.base).login("bob")
    sock, send = ws_publisher(centre.base, "/api/v1/live/rigs/rig-12/stream?case=ybif", bob.token)
    stop = threading.Event()
    sent = [0]

    def stream():
        n = tr["samples"]
        start = time.monotonic()
        k = 0
        while not stop.is_set():
            i = (k * 2) % n  # trace samples are 50 ms apart: every 2nd at 30 Hz plays ~3x speed
            frame = {"type": "frame", "seq": k + 1, "t_ms": tr["t_ms"][i],
                     "tools": [{"name": "guidewire", "nodes_mm": [tr["nodes_mm"][i][j:j + 3] for j in range(0, len(tr["nodes_mm"][i]), 3)]}],
                     "tip_mm": tr["tip_mm"][3 * i:3 * i + 3],
                     "forces": {"hand_mN": tr["hand_mN"][i], "wall_peak_mN": tr["wall_peak_mN"][i]},
                     "contacts": [{"p_mm": tr["tip_mm"][3 * i:3 * i + 3], "f_mN": tr["wall_peak_mN"][i]}] if tr["wall_peak_mN"][i] > 0 else [],
                     "fluoro": {"on": k % 90 < 45, "time_s": k / 60.0},
                     "metrics": {"procedure_time_s": k / 30.0, "tip_path_mm": tr["insertion_mm"][i], "wall_contacts": k // 30}}
            send(json.dumps(frame))
            k += 1
            sent[0] = k
            delay = start + k / 30.0 - time.monotonic()
            if delay > 0:
                stop.wait(delay)
    streamer = threading.Thread(target=stream, daemon=True)
    streamer.start()
    try:
        chip = b.wait(EC.element_to_be_clickable((By.CSS_SELECTOR, "button[data-rig='rig-12']")), "rig-12 to appear live")
        chip.click()
        # What the panel shows: the seq of the frame it drew last and how many it drew; under the
        # title, the page's draws a second and stream frames drawn a second (renewed each second).
        stat_js = RIG12_STAT_JS
        rate_js = "return [document.getElementById('rate-fps').textContent, document.getElementById('rate-frames').textContent];"
        drawn0 = b.wait_js(stat_js % "drawn", "rig-12's frames to be drawn")
        samples = []
        seen = set()
        shown = b.js(rate_js)
        deadline = time.monotonic() + 5
        while time.monotonic() < deadline:
            shown = b.wait_js(rate_js.replace("return ", "const r = ") + " return r.join() !== %s && r;" % json.dumps(",".join(shown)),
                              "the frame rate to be renewed")
            if "–" not in shown:
                samples.append([float(shown[0]), float(shown[1])])
            seen.add(b.js(stat_js % "seq"))
        stop.set()
        streamer.join(timeout=5)
        check(not streamer.is_alive(), "the 30 Hz streamer did not stop")
        last = sent[0]
        # The page catches up: the last frame sent is the one shown, and frames were drawn as they
        # came (more than one between the first drawn and the end, different ones while it ran).
        b.wait_js(stat_js.replace("return e ? Number(e.textContent) : null;", "return e && Number(e.textContent) === %d;" % last) % "seq",
                  "the last frame sent (seq %d) to be shown" % last)
        applied = b.js(stat_js % "drawn") - drawn0
        check(applied > 1, "the live view drew %d frames of a %d-frame stream" % (applied, last))
        check(len(seen) > 1, "the live view showed frames %s while %d were streamed" % (sorted(seen), last))
        report["live_frames_sent"] = last
        report["live_frames_drawn"] = applied
        report["live_fps_samples"] = samples
        check(samples, "the live view's frame rate was never shown")
        # The first samples can cover the second before the click: the median is the figure.
        fps = statistics.median(s[0] for s in samples)
        rate = statistics.median(s[1] for s in samples)
        report["live_fps_median"] = round(fps, 1)
        report["live_frames_applied_per_s_median"] = round(rate, 1)
        print("speed: live view %.1f fps, %.1f stream frames drawn a second of a 30 Hz stream (medians of %d samples)"
              % (fps, rate, len(samples)))
        b.shot("live")
        if args.strict_speed:
            check(fps >= 30, "live view draws %.1f fps with a 30 Hz stream (>= 30 wanted)" % fps)
            check(rate >= 25, "live view applied %.1f frames a second of a 30 Hz stream" % rate)
    finally:
        stop.set()
        streamer.join(timeout=5)
        end_publisher(sock, send)
    b.drain_console()


def test_live_https(b, centre, report):
    """Over HTTPS: the live view's watcher socket (an https: page may only open wss://) shows a rig
    that streams over wss://, up to the last frame sent."""
    b.open("/live.html?rigs=rig-12")
    check(b.js("return location.protocol") == "https:", "the page is not on https:")
    b.wait_js("return document.getElementById('status').textContent === '(connected)'", "the wss:// watcher socket")
    teacher = Api(centre.base).login("teacher")
    _, t = teacher.json("GET", "/results/%d/trace" % centre.results[-1]["id"])
    tr = t["trace"]
    bob = Api(centre.base).login("bob")
    sock, send = ws_publisher(centre.base, "/api/v1/live/rigs/rig-12/stream?case=ybif", bob.token)
    # The panel's own readouts: the seq of the frame it drew last and how many it drew.
    stat_js = RIG12_STAT_JS
    try:
        # Frames at ~30 Hz until the panel has drawn some, then the last one must be what it shows.
        k = 0
        deadline = time.monotonic() + WAIT_S
        while True:
            i = k % tr["samples"]
            k += 1
            send(json.dumps({"type": "frame", "seq": k, "t_ms": tr["t_ms"][i],
                             "tools": [{"name": "guidewire", "nodes_mm": [tr["nodes_mm"][i][j:j + 3] for j in range(0, len(tr["nodes_mm"][i]), 3)]}],
                             "tip_mm": tr["tip_mm"][3 * i:3 * i + 3], "forces": {"hand_mN": tr["hand_mN"][i], "wall_peak_mN": tr["wall_peak_mN"][i]},
                             "contacts": [], "fluoro": {"on": False, "time_s": 0}, "metrics": {"procedure_time_s": k / 30.0}}))
            if k >= 10 and (b.js(stat_js % "drawn") or 0) >= 3:
                break
            check(time.monotonic() < deadline, "rig-12's frames over wss:// were not drawn (%d sent)" % k)
            threading.Event().wait(1 / 30)
        b.wait_js(stat_js.replace("return e ? Number(e.textContent) : null;", "return e && Number(e.textContent) === %d;" % k) % "seq",
                  "the last frame sent over wss:// (seq %d) to be shown" % k)
        report["https_live_frames_sent"] = k
        b.shot("live")
    finally:
        end_publisher(sock, send)
    b.drain_console()


def open_debrief(b, result_id, what):
    """Opens a result's debrief; the milliseconds from the page asking for the trace (its fetch in
    the page's resource timing) to the page showing the run (the cursor's tip readout)."""
    b.open("/debrief.html?id=%d" % result_id)
    b.driver.set_script_timeout(600)
    try:
        shown = b.driver.execute_async_script("""
            const done = arguments[arguments.length - 1];
            const trace = '/results/' + arguments[0] + '/trace';
            (function poll() {
              const error = document.getElementById('error');
              if (error && !error.hidden) return done({ error: error.textContent });
              if (!document.getElementById('now-tip')) return setTimeout(poll, 5);
              const at = performance.now();
              const asked = performance.getEntriesByType('resource').find((e) => e.name.includes(trace));
              done({ ms: asked ? at - asked.startTime : null });
            })();""", result_id)
    except Exception as e:
        b.shot("failed")
        raise Failure("timed out waiting for %s (%s)" % (what, type(e).__name__)) from None
    finally:
        b.driver.set_script_timeout(WAIT_S)
    check("error" not in shown, "%s: %s" % (what, shown.get("error")))
    check(shown["ms"] is not None, "%s: the page never fetched its trace" % what)
    return shown["ms"]


def shown_tip(b):
    return [float(v) for v in b.driver.find_element(By.ID, "now-tip").text.split(",")]


def test_debrief(b, centre, report):
    rid = centre.results[-1]["id"]
    report["debrief_open_ms_first"] = round(open_debrief(b, rid, "the debrief"), 1)
    report["debrief_open_ms_cached"] = round(open_debrief(b, rid, "the debrief again"), 1)
    # The trace the page draws, as the server gives it to the test.
    _, t = Api(centre.base).login("teacher").json("GET", "/results/%d/trace" % rid)
    tr = t["trace"]
    samples = tr["samples"]
    check(samples > 50, "debrief trace has %d samples" % samples)
    slider = b.driver.find_element(By.ID, "slider")
    check(int(slider.get_attribute("max")) == samples - 1, "the slider ends at %s for %d samples" % (slider.get_attribute("max"), samples))
    check(b.js("return document.querySelectorAll('#marks span').length") >= 1, "no event marked on the time line")
    tip0 = b.driver.find_element(By.ID, "now-tip").text
    # Seek with the slider (as a user drags it) to the middle, then play a little. The readout
    # shows that sample's tip and time (to 0.1 mm and 0.1 s).
    k = samples * 2 // 3
    want_tip = tr["tip_mm"][3 * k:3 * k + 3]
    b.js("arguments[0].value = arguments[1]; arguments[0].dispatchEvent(new Event('input'));", slider, k)
    b.wait(lambda d: all(abs(a - w) <= 0.0501 for a, w in zip(shown_tip(b), want_tip)), "the seek to sample %d (tip %s)" % (k, want_tip))
    clock = float(b.driver.find_element(By.ID, "clock").text.split(" / ")[0])
    check(abs(clock - tr["t_ms"][k] / 1000) <= 0.0501, "after the seek the clock shows %.1f s, sample %d is at %.3f s" % (clock, k, tr["t_ms"][k] / 1000))
    tip1 = b.driver.find_element(By.ID, "now-tip").text
    check(tip0 != tip1, "seeking did not move the tip (%s)" % tip0)
    report["debrief_seek"] = "sample 0 tip %s -> sample %d tip %s" % (tip0, k, tip1)
    # The plot's window: 10 s around the cursor (its x axis, as Chart.js holds it for the canvas).
    b.js("const w = document.getElementById('window'); w.value = '10'; w.dispatchEvent(new Event('change'));")
    b.wait_js("const x = Chart.getChart(document.getElementById('chart')).scales.x; return x.max - x.min <= 10.001", "the plot's 10 s window")
    b.shot("debrief")
    b.js("const w = document.getElementById('window'); w.value = '0'; w.dispatchEvent(new Event('change'));")
    # The same on a tablet (portrait, 820x1180): one column.
    b.viewport(820, 1180, mobile=True)
    b.wait_js("return document.querySelector('#view3d canvas').width <= 820", "the tablet layout")
    b.shot("debrief-tablet")
    b.viewport(1280, 720)
    b.driver.find_element(By.ID, "play").click()
    at = int(slider.get_attribute("value"))
    b.wait(lambda d: int(slider.get_attribute("value")) > at, "playback to advance")
    b.driver.find_element(By.ID, "play").click()
    b.drain_console()


class ThrombectomyRun:
    """The bundled carotid-T script (cases/neuro_thrombectomy_ica_t.actions) recorded by
    `cathbox session run`, graded by `cathbox session metrics --json` and uploaded by bob, in a
    thread: it runs while the live view's wall-clock-paced test waits, so it costs the test
    little time (its run and two replays take ~20 s of CPU)."""

    CASE = "neuro_thrombectomy_ica_t"

    def __init__(self, centre):
        self.centre = centre
        self.result = None
        self.metrics = None
        self.error = None
        self.thread = threading.Thread(target=self.guard, args=(self.work,), daemon=True)
        self.thread.start()

    def work(self):
        c = self.centre
        cases = os.path.join(c.args.source, "cases")
        # The case in the library first, so the run is filed under it and its debrief draws the
        # vessel (the mesh made here, cached for the page).
        teacher = Api(c.base).login("teacher")
        teacher.json("POST", "/cases", {
            "name": self.CASE, "case_file": self.CASE + ".case", "case": open(os.path.join(cases, self.CASE + ".case")).read(),
            "hclm_file": "neuro.hclm", "hclm": open(os.path.join(cases, "neuro.hclm")).read()})
        teacher.call("GET", "/cases/%s/versions/latest/mesh" % self.CASE)
        rec = os.path.join(c.tmp, "thrombectomy.cbxrec")
        c.run([c.program("cathbox"), "session", "run", "--case", os.path.join(cases, self.CASE + ".case"),
               "--script", os.path.join(cases, self.CASE + ".actions"), "--record", rec, "--virtual"],
              "thrombectomy session run")
        # The grading replay and the server's (the upload's check) side by side.
        grading = threading.Thread(target=self.guard, args=(lambda: self.grade(rec),), daemon=True)
        grading.start()
        try:
            _, self.result = Api(c.base).login("bob").json("POST", "/results", raw=open(rec, "rb").read())
        finally:
            grading.join()

    def grade(self, rec):
        self.metrics = json.loads(self.centre.run([self.centre.program("cathbox"), "session", "metrics", rec, "--json"],
                                                  "session metrics --json", merge=False))

    def guard(self, work):
        """Runs work(), keeping its first failure for wait() to report in the test's thread."""
        try:
            work()
        except Exception as e:
            self.error = self.error or "%s: %s" % (type(e).__name__, e)

    def wait(self):
        self.thread.join(timeout=600)
        check(not self.thread.is_alive(), "the thrombectomy run did not finish in 600 s")
        check(self.error is None, "thrombectomy run: %s" % self.error)
        return self.result, self.metrics


def test_thrombectomy_debrief(b, run, report):
    """The debrief of a thrombectomy run: the "eTICI per pass" row and the final grade read as the
    session's own metrics (`session metrics --json`) grade the record; the passes (with their
    eTICI) and lodged emboli are marks, the retrieval force a series on the plot."""
    started = time.monotonic()
    result, metrics = run.wait()
    report["thrombectomy_wait_s"] = round(time.monotonic() - started, 2)
    t = metrics["thrombectomy"]
    check(t is not None and t["passes"] >= 1, "the carotid-T script made no pass: %s" % t)
    want = " · ".join("%d: %s" % (i + 1, p["etici"]) for i, p in enumerate(t["etici_per_pass"]))
    check(result["case"] == run.CASE, "the thrombectomy run was filed under %r, not the library's %r" % (result["case"], run.CASE))
    open_debrief(b, result["id"], "the thrombectomy debrief")
    row = b.wait(EC.presence_of_element_located((By.ID, "etici-per-pass")), "the eTICI per pass row")
    got = row.text
    check(got == want, "debrief eTICI per pass %r, session metrics give %r" % (got, want))
    final = b.driver.find_element(By.CSS_SELECTOR, "tr[data-metric='etici_final'] td.num").text
    check(final == "eTICI " + t["etici_final"], "debrief eTICI final %r, session metrics give %r" % (final, t["etici_final"]))
    passes = b.driver.find_element(By.CSS_SELECTOR, "tr[data-metric='thrombectomy_passes'] td.num").text
    check(float(passes) == t["passes"], "debrief thrombectomy passes %r, session metrics give %d" % (passes, t["passes"]))
    # The balloon guide's flow arrest has its rows, as the session's metrics give them, and its mark.
    for name in ("balloon_guide_inflations", "flow_arrest_s"):
        shown = b.driver.find_element(By.CSS_SELECTOR, "tr[data-metric='%s'] td.num" % name).text
        check(abs(float(shown) - t[name]) < 0.01, "debrief %s %r, session metrics give %s" % (name, shown, t[name]))
    # One injection in the script (`inject 6 at 3`): one mark, not one per 10 ms contrast step.
    injections = b.js("return document.querySelectorAll(\"#marks span[data-kind='injection']\").length")
    check(injections == 1, "the debrief marks %d injections for the script's one" % injections)
    arrests = b.js("return document.querySelectorAll(\"#marks span[data-kind='flow_arrest']\").length")
    check(arrests == t["balloon_guide_inflations"], "the debrief marks %d flow arrests, session metrics give %d" % (arrests, t["balloon_guide_inflations"]))
    # Each pass is a mark with its eTICI, as the session's metrics grade it; each lodged embolus a
    # mark (the emboli still in transit at the end have no time: the metrics count them).
    titles = b.js("return [...document.querySelectorAll(\"#marks span[data-kind='pass']\")].map((e) => e.title)")
    check(len(titles) == t["passes"], "the debrief marks %d passes, session metrics give %d" % (len(titles), t["passes"]))
    for i, (title, p) in enumerate(zip(titles, t["etici_per_pass"])):
        check(title.startswith("pass %d: eTICI %s at " % (i + 1, p["etici"])), "pass mark %r, session metrics give eTICI %s" % (title, p["etici"]))
    emboli = b.js("return document.querySelectorAll(\"#marks span[data-kind='embolus']\").length")
    lodged = len(t["emboli_lodged"])
    check(emboli == lodged, "the debrief marks %d emboli, session metrics give %d lodged" % (emboli, lodged))
    # The retrieval force on the plot, as Chart.js holds it: a series of every sample, its peak the
    # session's retrieval_force_peak_N; an aspiration pass pulls no stent (null in the metrics): all zero.
    series = b.wait_js("const c = Chart.getChart(document.getElementById('chart'));"
                       "const d = c && c.data.datasets.find((s) => s.label.startsWith('retrieval force'));"
                       "return d && [d.label, d.data.map((p) => p.y), c.data.datasets[0].data.length];", "the retrieval force series")
    label, ys, samples = series
    check(len(ys) == samples, "the retrieval force has %d points, the hand force %d" % (len(ys), samples))
    peak_N = t["retrieval_force_peak_N"]
    if peak_N is None:
        check(max(ys) == 0 and "no stent pulled" in label, "retrieval force %r peak %s mN; the metrics say no stent pass" % (label, max(ys)))
    else:
        check(abs(max(ys) / 1000.0 - peak_N) < 1e-5, "retrieval force peak %s mN, session metrics give %s N" % (max(ys), peak_N))
    report["thrombectomy_retrieval_label"] = label
    b.js("arguments[0].scrollIntoView({block: 'center'})", row)
    b.shot("debrief-thrombectomy")
    report["thrombectomy_etici_per_pass"] = got
    report["thrombectomy_etici_final"] = final
    report["thrombectomy_debrief_s"] = round(time.monotonic() - started, 2)
    run.centre.others.append(result)
    b.drain_console()


def test_results(b, centre, report):
    b.open("/results.html")
    b.wait(EC.presence_of_element_located((By.CSS_SELECTOR, "#results-table tbody tr")), "the results table")
    rows = len(b.driver.find_elements(By.CSS_SELECTOR, "#results-table tbody tr"))
    uploaded = len(centre.results) + len(centre.others)
    check(rows == uploaded, "results table has %d rows, %d uploaded" % (rows, uploaded))
    # Sort by tip path (a click on its header), then filter on ann: learning curves appear.
    b.driver.find_element(By.CSS_SELECTOR, "th[data-key='m.tip_path_mm']").click()
    b.wait(EC.presence_of_element_located((By.CSS_SELECTOR, "th.sorted-desc[data-key='m.tip_path_mm']")), "sorting")
    b.shot("results")
    b.js("const s = document.getElementById('f-trainee'); s.value = 'ann'; s.dispatchEvent(new Event('change'));")
    # Each curve's points as Chart.js holds them for its canvas (one canvas per metric).
    counts = b.wait_js("const c = [...document.querySelectorAll('#curves canvas[data-metric]')]"
                       ".map((e) => [e.dataset.metric, Chart.getChart(e).data.datasets[0].data.length]); return c.length > 0 && c;",
                       "the learning curves")
    report["learning_curve_points"] = counts
    for metric, n in counts:
        check(n == len(centre.results), "learning curve of %s has %d points for %d attempts" % (metric, n, len(centre.results)))
    b.js("document.getElementById('curves-title').scrollIntoView()")
    b.shot("learning-curves")
    # The CSV export as a user gets it: the button's download, in the browser's download folder.
    downloads = os.path.join(centre.tmp, "downloads")
    os.makedirs(downloads, exist_ok=True)
    b.driver.execute_cdp_cmd("Page.setDownloadBehavior", {"behavior": "allow", "downloadPath": downloads})
    b.driver.find_element(By.ID, "csv").click()
    saved = os.path.join(downloads, "cathbox-results.csv")
    wait_until(lambda: os.path.exists(saved) and os.path.getsize(saved) > 0, "the CSV download")
    csv = open(saved).read().strip().split("\n")  # ann's rows: the filter is on
    check(len(csv) == 1 + len(centre.results) and csv[0].startswith("id,trainee,case"), "CSV export: %s" % csv[:2])
    report["csv_header"] = csv[0]
    b.drain_console()


def test_trainee(b, centre, report):
    b.login("ann")
    b.shot("home-trainee")
    b.open("/trainee.html")
    b.wait(EC.presence_of_element_located((By.CSS_SELECTOR, "#results-table tbody tr")), "the trainee's results")
    b.wait_js("return document.querySelectorAll('#curves canvas[data-metric]').length > 0", "the trainee's learning curves")
    b.shot("trainee")
    for page in ["/live.html", "/results.html", "/admin.html"]:
        b.open(page)
        b.wait(EC.presence_of_element_located((By.ID, "refused")), "the refusal on " + page)
    b.shot("trainee-refused")
    b.drain_console()
    # The API behind those pages refuses too.
    ann = Api(centre.base).login("ann")
    for method, path, status in [("GET", "/users", 403), ("POST", "/cases", 403), ("GET", "/results?trainee=bob", 403),
                                 ("GET", "/results", 200), ("GET", "/assignments?trainee=bob", 200)]:
        got, payload, _ = ann.call(method, path, body={} if method == "POST" else None, expect=(status,))
        if method == "GET" and status == 200:
            body = json.loads(payload)
            items = body.get("results", body.get("assignments", []))
            check(all(i.get("trainee") == "ann" for i in items), "a trainee saw someone else's %s" % path)
    bob = Api(centre.base).login("bob")
    bob.call("GET", "/results/%d/trace" % centre.results[0]["id"], expect=(404,))  # as if it did not exist
    _, payload, _ = Api(centre.base).call("GET", "/results/1/trace", expect=(401,))
    report["trainee_refused"] = ("pages live/results/admin refused in the page; API: /users 403, POST /cases 403, "
                                "/results?trainee=bob 403, bob's view of ann's trace 404")


def test_admin(b, centre, report):
    b.login("root")
    b.open("/admin.html")
    b.wait(EC.presence_of_element_located((By.CSS_SELECTOR, "select[data-user='ann']")), "the users table")
    # A case the validator refuses: its file:line line on the page, as the server wrote it.
    cases = os.path.join(centre.args.source, "cases")
    broken = os.path.join(centre.tmp, "broken")
    os.makedirs(broken, exist_ok=True)
    text = open(os.path.join(cases, "y_bifurcation.case")).read().replace("vessel y_bifurcation.hclm", "vessel other.hclm")
    open(os.path.join(broken, "y_bifurcation.case"), "w").write(text)
    shutil.copy(os.path.join(cases, "y_bifurcation.hclm"), broken)
    b.driver.find_element(By.ID, "c-name").send_keys("broken")
    b.driver.find_element(By.ID, "c-case").send_keys(os.path.join(broken, "y_bifurcation.case"))
    b.driver.find_element(By.ID, "c-hclm").send_keys(os.path.join(broken, "y_bifurcation.hclm"))
    b.driver.find_element(By.CSS_SELECTOR, "#upload button[type=submit]").click()
    line = b.wait(lambda d: d.find_element(By.ID, "error").text, "the validator's line")
    check(line.startswith("y_bifurcation.case:") and "other.hclm" in line, "upload error shown: %r" % line)
    report["admin_upload_error"] = line
    # A surface case: its wall (CBXMESH2 from `cathbox vessel mesh`) goes up beside the case.
    surf = os.path.join(centre.tmp, "surface_case")
    os.makedirs(surf, exist_ok=True)
    shutil.copy(os.path.join(cases, "y_bifurcation.hclm"), surf)
    open(os.path.join(surf, "ysurf.case"), "w").write(open(os.path.join(cases, "y_bifurcation.case")).read() + "surface lumen.cbxmesh\n")
    centre.run([centre.program("cathbox"), "vessel", "mesh", os.path.join(surf, "y_bifurcation.hclm"), "-o",
                os.path.join(surf, "lumen.cbxmesh")], "cathbox vessel mesh")
    b.driver.find_element(By.ID, "c-name").clear()
    b.driver.find_element(By.ID, "c-name").send_keys("ysurf")
    for field, name in (("c-case", "ysurf.case"), ("c-hclm", "y_bifurcation.hclm"), ("c-surface", "lumen.cbxmesh")):
        b.driver.find_element(By.ID, field).send_keys(os.path.join(surf, name))
    b.driver.find_element(By.CSS_SELECTOR, "#upload button[type=submit]").click()
    stored = b.wait(lambda d: d.find_element(By.ID, "upload-result").text, "the surface case's upload")
    check(stored == "stored as ysurf version 1", "surface case upload: %r" % stored)
    _, bundle = Api(centre.base).login("teacher").json("GET", "/cases/ysurf/versions/1/bundle")
    check(bundle.get("surface_file") == "lumen.cbxmesh" and bundle.get("surface_hex") ==
          open(os.path.join(surf, "lumen.cbxmesh"), "rb").read().hex(), "the bundle carries the uploaded surface's bytes")
    b.shot("admin")
    b.drain_console(expected=[("/api/v1/cases", 422)])


def measure_long(centre, args, report):
    """A 30-minute record: first and cached trace times (server side and in the browser)."""
    rec = os.path.join(centre.tmp, "long.cbxrec")
    script = os.path.join(centre.tmp, "long.actions")
    with open(script, "w") as f:
        t = 0
        f.write("0 select guidewire\n")
        while t < 1800_000:
            f.write("%d insert_to 90 at 20\n%d rotate_to %d at 90\n%d insert_to 30 at 20\n" % (t, t + 4000, (t // 1000) % 720, t + 6000))
            t += 10_000
        f.write("%d end\n" % 1800_000)
    started = time.monotonic()
    centre.run([centre.program("cathbox"), "session", "run", "--case", os.path.join(args.source, "cases/y_bifurcation.case"),
                "--script", script, "--record", rec, "--virtual", "--seconds", "1800"], "30-minute session run", timeout=3600)
    report["long_record_bytes"] = os.path.getsize(rec)
    report["long_record_run_s"] = round(time.monotonic() - started, 1)
    ann = Api(centre.base).login("ann")
    started = time.monotonic()
    _, r = ann.json("POST", "/results", raw=open(rec, "rb").read())
    report["long_upload_check_s"] = round(time.monotonic() - started, 1)
    # The upload's replay cached the trace (memory and disk): without both, the server replays.
    centre.restart(forget=True)
    return r["id"]


def measure_long_trace(centre, rid, report):
    """The 30-minute trace as the API sends it (after the browser opened it: cached)."""
    teacher = Api(centre.base).login("teacher")
    started = time.monotonic()
    _, payload, head = teacher.call("GET", "/results/%d/trace" % rid)
    report["long_trace_api_s"] = round(time.monotonic() - started, 3)
    report["long_trace_header"] = head.get("X-Cathbox-Trace")
    report["long_trace_bytes"] = len(payload)
    report["long_trace_samples"] = json.loads(payload)["trace"]["samples"]


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--bin", required=True)
    parser.add_argument("--source", required=True)
    parser.add_argument("--out", required=True)
    parser.add_argument("--long", action="store_true", help="also measure a 30-minute record's debrief")
    parser.add_argument("--keep", action="store_true", help="keep the temporary folder")
    parser.add_argument("--strict-speed", action="store_true", help="fail when the live view draws under 30 fps")
    parser.add_argument("--https", action="store_true", help="the HTTPS subset: a throwaway CA, log in, live over wss://, a debrief")
    args = parser.parse_args()
    # A CTest timeout (SIGTERM) still stops the server, the trainer and the browser.
    signal.signal(signal.SIGTERM, lambda *_: sys.exit(143))
    os.makedirs(args.out, exist_ok=True)
    tmp = tempfile.mkdtemp(prefix="cathbox-browser-")
    centre = Centre(args, tmp)
    browser = None
    report = {}
    ok = False
    failures = []
    try:
        if args.https:
            started = time.monotonic()
            centre.start()
            centre.seed(attempts=("6",))
            browser = Browser(args.out, spki=centre.spki)
            browser.prefix = "https-"
            browser.base = centre.base
            browser.login("teacher")
            browser.drain_console()
            test_live_https(browser, centre, report)
            test_debrief(browser, centre, report)
            report["https_s"] = round(time.monotonic() - started, 1)
        else:
            centre.start()
            centre.seed()
            thrombectomy = ThrombectomyRun(centre)
            browser = Browser(args.out)
            browser.base = centre.base
            browser.login("teacher")
            browser.shot("home-instructor")
            browser.drain_console()
            test_live(browser, centre, args, report)
            test_debrief(browser, centre, report)
            test_thrombectomy_debrief(browser, thrombectomy, report)
            test_results(browser, centre, report)
            test_admin(browser, centre, report)
            test_trainee(browser, centre, report)
            if args.long:
                rid = measure_long(centre, args, report)
                browser.login("teacher")
                # First: the server replays the record; then from its memory; then, restarted, from disk.
                for label in ["first", "cached"]:
                    report["long_debrief_open_ms_%s" % label] = round(open_debrief(browser, rid, "the 30-minute debrief"), 1)
                centre.restart()
                report["long_debrief_open_ms_after_restart"] = round(open_debrief(browser, rid, "the 30-minute debrief"), 1)
                browser.shot("debrief-30min")
                measure_long_trace(centre, rid, report)
                browser.drain_console()
        ok = True
    except Failure as e:
        failures.append(str(e))
    except Exception:
        traceback.print_exc()
        failures.append(traceback.format_exc().strip().splitlines()[-1])
    finally:
        if browser is not None:
            try:
                browser.drain_console()
            except Failure as e:
                failures.append(str(e))
                ok = False
            browser.quit()
        centre.stop()
        print(json.dumps(report, indent=1))
        with open(os.path.join(args.out, "report-https.json" if args.https else "report.json"), "w") as f:
            json.dump(report, f, indent=1)
        if args.keep or not ok:
            print("kept", tmp)
        else:
            shutil.rmtree(tmp, ignore_errors=True)
    # The reason last, where a log's tail shows it.
    for f in failures:
        print("FAIL:", f)
    print("browser test:", "passed" if ok else "FAILED", "(screenshots in %s)" % args.out)
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
