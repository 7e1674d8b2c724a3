"""An RL episode's record is a result on cathbox-server, filed under the library case a trainee's
run of the same case is filed under (so the pages compare them); a generated episode case is not
a library case and is filed apart as `unlisted:`.

The real cathbox-server on a fresh SQLite store and a free loopback port; accounts made by its
`admin create-user`; the case uploaded through the API from the bundled file, as an instructor
does; the trainee's run recorded by `cathbox session run --script`."""
import json
import os
import shutil
import socket
import subprocess
import tempfile
import time
import unittest
import urllib.error
import urllib.request

import gymnasium
import numpy as np

import cathbox
import cathbox.gym

PASSWORD = "upload-pass-1"
BIN = os.environ.get("CATHBOX_BIN", "")


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


class Api:
    def __init__(self, base, name):
        self.base = base
        self.token = None
        self.token = self.call("POST", "/login", {"name": name, "password": PASSWORD})["token"]

    def call(self, method, path, body=None, raw=None):
        headers = {"Authorization": "Bearer " + self.token} if self.token else {}
        data = raw
        if body is not None:
            headers["Content-Type"] = "application/json"
            data = json.dumps(body).encode()
        elif raw is not None:
            headers["Content-Type"] = "application/octet-stream"
        req = urllib.request.Request(self.base + "/api/v1" + path, data=data, headers=headers, method=method)
        try:
            with urllib.request.urlopen(req, timeout=300) as r:
                return json.loads(r.read() or b"null")
        except urllib.error.HTTPError as e:
            raise AssertionError(f"{method} {path}: {e.code} {e.read()[:300]!r}") from None


@unittest.skipUnless(os.path.exists(os.path.join(BIN, "cathbox-server")), "cathbox-server not built (CATHBOX_BIN)")
class UploadTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.mkdtemp(prefix="cathbox-upload-")
        cls.env = dict(os.environ, CATHBOX_PASSWORD=PASSWORD, XDG_DATA_HOME=os.path.join(cls.tmp, "data"),
                       XDG_CACHE_HOME=os.path.join(cls.tmp, "cache"), XDG_CONFIG_HOME=os.path.join(cls.tmp, "config"))
        server = os.path.join(BIN, "cathbox-server")
        db = "sqlite:" + os.path.join(cls.tmp, "server.db")
        for name, role in (("teacher", "instructor"), ("agent", "trainee"), ("ann", "trainee")):
            subprocess.run([server, "--db", db, "admin", "create-user", name, "--role", role], env=cls.env, check=True,
                           capture_output=True)
        port = free_port()
        cls.base = f"http://127.0.0.1:{port}"
        cls.log = open(os.path.join(cls.tmp, "server.log"), "w")
        cls.server = subprocess.Popen([server, "--db", db, "--listen", f"127.0.0.1:{port}", "--data",
                                       os.path.join(cls.tmp, "data")], env=cls.env, stdout=cls.log,
                                      stderr=subprocess.STDOUT)
        deadline = time.monotonic() + 60
        while True:  # bounded wait for the port
            assert cls.server.poll() is None, "cathbox-server exited: " + open(cls.log.name).read()[-2000:]
            try:
                with socket.create_connection(("127.0.0.1", port), timeout=1):
                    break
            except OSError:
                assert time.monotonic() < deadline, "cathbox-server did not listen within 60 s"
                time.sleep(0.05)

    @classmethod
    def tearDownClass(cls):
        cls.server.terminate()
        cls.server.wait(timeout=30)
        cls.log.close()
        shutil.rmtree(cls.tmp, ignore_errors=True)

    def rl_record(self, env_id, **kwargs):
        """A random policy's episode (3 s of simulated time), recorded; the record's path."""
        records = os.path.join(self.tmp, env_id.replace("/", "-"))
        env = gymnasium.make(env_id, record_dir=records, step_s=0.1, max_episode_steps=30, **kwargs)
        env.reset(seed=3)
        rng = np.random.default_rng(3)
        for _ in range(30):
            low, high = env.action_space.low, env.action_space.high
            _, _, terminated, truncated, _ = env.step(rng.uniform(0.2 * low, high).astype(np.float32))
            if terminated or truncated:
                break
        path = env.unwrapped.record_path
        env.close()
        return path

    def test_an_rl_episode_is_filed_under_the_library_case_beside_a_trainee_run(self):
        case_file = cathbox.case_path("y_bifurcation")
        hclm_file = os.path.join(os.path.dirname(case_file), "y_bifurcation.hclm")
        teacher = Api(self.base, "teacher")
        version = teacher.call("POST", "/cases", {
            "name": "ybif", "case_file": "y_bifurcation.case", "case": open(case_file).read(),
            "hclm_file": "y_bifurcation.hclm", "hclm": open(hclm_file).read()})
        self.assertEqual(version["version"], 1)

        # Graded on an assignment: the server demands the library's case byte for byte.
        assignment = teacher.call("POST", "/assignments", {
            "trainee": "agent", "case": "ybif", "criteria": [{"metric": "peak_wall_force_mN", "op": "<=", "value": 1e6}]})
        agent = Api(self.base, "agent")
        record = self.rl_record("cathbox/Case-v0", case="y_bifurcation")
        rl = agent.call("POST", f"/results?assignment={assignment['id']}", raw=open(record, "rb").read())
        print("RL result:", rl)
        self.assertTrue(rl["created"])
        self.assertEqual(rl["case"], "ybif")
        self.assertEqual(rl["assignment"], assignment["id"])
        self.assertTrue(rl["passed"])

        # A generated episode case (Navigate's: its own target and tool list) is not the library's.
        generated = agent.call("POST", "/results", raw=open(self.rl_record(
            "cathbox/Navigate-v0", case="y_bifurcation", targets=[("left_branch", 0.8)]), "rb").read())
        print("generated case's result:", generated)
        self.assertTrue(generated["case"].startswith("unlisted:"), generated["case"])

        # A trainee's scripted run of the same case.
        cases = os.path.dirname(case_file)
        rec = os.path.join(self.tmp, "ann.cbxrec")
        subprocess.run([os.path.join(BIN, "cathbox"), "session", "run", "--case", case_file, "--script",
                        os.path.join(cases, "y_bifurcation_left.actions"), "--record", rec, "--virtual", "--seconds",
                        "3"], env=self.env, check=True, capture_output=True)
        ann = Api(self.base, "ann")
        run = ann.call("POST", "/results", raw=open(rec, "rb").read())
        self.assertEqual(run["case"], "ybif")

        listed = teacher.call("GET", "/results?case=ybif")["results"]
        self.assertEqual(sorted(r["id"] for r in listed), sorted([rl["id"], run["id"]]))
        self.assertEqual({r["trainee"] for r in listed}, {"agent", "ann"})


if __name__ == "__main__":
    unittest.main()
