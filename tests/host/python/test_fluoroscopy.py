"""The image observation through the trainer's fluoroscopy renderer (host/app's FluoroRenderer,
offscreen: cathbox._fluoro), under Xvfb with Mesa's llvmpipe: Gymnasium's checker, the shape,
bit-for-bit determinism for a seed, the tools in the image, the pedal's pulses recorded and
cloned, and the monitor black before the first pulse."""
import unittest

import gymnasium
import numpy as np
from gymnasium.utils.env_checker import check_env

import cathbox
import cathbox.gym
from cathbox.fluoroscopy import Fluoroscopy

KW = dict(observation="image", image_renderer="fluoroscopy", image_size=(96, 96), step_s=0.05)


def episode(speed, steps=8, seed=4):
    # The y bifurcation: the fluoroscopy unit's field (centred on the target) holds the entry.
    env = gymnasium.make("cathbox/Navigate-v0", case="y_bifurcation", targets=[("left_branch", 0.8)],
                         **dict(KW, step_s=0.1))
    obs, _ = env.reset(seed=seed)
    frames = [obs]
    for _ in range(steps):
        obs, _, _, _, info = env.step(np.array([[speed, 0.0]], dtype=np.float32))
        frames.append(obs)
    env.close()
    return frames, info["state_hash"]


class FluoroscopyTest(unittest.TestCase):
    def test_gymnasium_checker_passes(self):
        env = gymnasium.make("cathbox/Navigate-v0", **KW)
        check_env(env.unwrapped, skip_render_check=True)
        env.close()

    def test_same_seed_same_images_and_the_wire_is_in_them(self):
        a, hash_a = episode(50.0)
        b, hash_b = episode(50.0)
        self.assertEqual(a[0].shape, (96, 96, 1))
        self.assertEqual(a[0].dtype, np.uint8)
        self.assertEqual(hash_a, hash_b)
        for x, y in zip(a, b):
            self.assertEqual(x.tobytes(), y.tobytes())
        self.assertGreater(a[-1].max(), a[-1].min())  # an image, not a flat field
        # Held still, the same pulses (the same noise) and the same anatomy: the frames differ
        # only where the pushed wire is.
        still, _ = episode(0.0)
        self.assertEqual(a[0].tobytes(), still[0].tobytes())
        moved = np.argwhere(a[-1][:, :, 0] != still[-1][:, :, 0])
        self.assertGreater(len(moved), 5)
        self.assertLess(len(moved), 0.2 * 96 * 96)

    def test_black_before_the_pedal_and_the_pedal_cloned(self):
        s = cathbox.Session(cathbox.case_path("neuro"))
        view = Fluoroscopy(s, 64, 64)
        s.step(100)
        self.assertEqual(view.image().max(), 0)  # no pulse yet: the monitor is black
        s.press_pedal()
        s.set_speeds([[20.0, 0.0], [20.0, 0.0]])
        s.step(200)
        self.assertGreater(view.image().max(), 0)
        c = s.clone()  # the pedal is an input: the clone pulses too and hashes the same
        self.assertEqual(c.state_hash(), s.state_hash())
        self.assertEqual(Fluoroscopy(c, 64, 64).image().tobytes(), view.image().tobytes())
        view.close()

    def test_the_record_with_its_pulses_replays_hash_checked(self):
        import os
        import shutil
        import subprocess
        import tempfile
        records = tempfile.mkdtemp(prefix="cathbox-fluoro-")
        env = gymnasium.make("cathbox/Navigate-v0", case="y_bifurcation", targets=[("left_branch", 0.8)],
                             record_dir=records, **dict(KW, step_s=0.1))
        env.reset(seed=1)
        for _ in range(12):
            env.step(np.array([[30.0, 0.5]], dtype=np.float32))
        record = env.unwrapped.record_path
        env.close()
        r = subprocess.run([os.path.join(os.environ["CATHBOX_BIN"], "cathbox"), "session", "replay", "--check", record],
                           capture_output=True, text=True, timeout=120)
        self.assertEqual(r.returncode, 0, r.stdout + r.stderr)
        self.assertIn("every state hash matches", r.stdout)
        self.assertIn("12 state hashes checked", r.stdout)
        shutil.rmtree(records)

    def test_thread_vector_env_draws_every_env_as_it_draws_alone(self):
        # Two envs stepping on pool threads, their views made, drawn and dropped on this thread
        # (GLFW's one thread), across an autoreset: the images are each env's alone, bit for bit.
        def make():
            return gymnasium.make("cathbox/Navigate-v0", case="y_bifurcation", targets=[("left_branch", 0.8)],
                                  max_episode_steps=3, **dict(KW, step_s=0.1))
        actions = np.array([[[40.0, 0.0]], [[20.0, 1.0]]], dtype=np.float32)
        vec = cathbox.gym.ThreadVectorEnv([make, make])
        obs, _ = vec.reset(seed=7)
        together = [obs]
        for _ in range(5):  # the third step truncates, the fourth resets
            obs, _, terminated, truncated, _ = vec.step(actions)
            together.append(obs)
        vec.close()
        for i in range(2):  # each env alone on this thread, with the vector env's seed and autoreset
            env = make()
            obs, _ = env.reset(seed=7 + i)
            alone, done = [obs], False
            for _ in range(5):
                if done:
                    (obs, _), done = env.reset(), False
                else:
                    obs, _, terminated, truncated, _ = env.step(actions[i])
                    done = terminated or truncated
                alone.append(obs)
            env.close()
            for k, (a, b) in enumerate(zip(together, alone)):
                self.assertEqual(a[i].tobytes(), b.tobytes(), f"env {i}, image {k}")
        self.assertGreater(together[3][0].max(), together[3][0].min())  # images, not a flat field

    def test_bad_arguments_raise_one_line(self):
        s = cathbox.Session(cathbox.case_path("y_bifurcation"))
        with self.assertRaisesRegex(RuntimeError, "size 4x64 outside 8..2048"):
            Fluoroscopy(s, 4, 64)
        with self.assertRaisesRegex(ValueError, "image_renderer 'gl'"):
            gymnasium.make("cathbox/Navigate-v0", observation="image", image_renderer="gl")
        # Without a display: one line saying what is needed, not a crash.
        import os
        import subprocess
        import sys
        env = {k: v for k, v in os.environ.items() if k not in ("DISPLAY", "WAYLAND_DISPLAY")}
        code = ("import cathbox\nfrom cathbox.fluoroscopy import Fluoroscopy\n"
                "try:\n    Fluoroscopy(cathbox.Session(cathbox.case_path('y_bifurcation')), 64, 64)\n"
                "except RuntimeError as e:\n    print(e)\n")
        r = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, timeout=120)
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertIn("a display is needed: run under xvfb-run", r.stdout)


if __name__ == "__main__":
    unittest.main()
