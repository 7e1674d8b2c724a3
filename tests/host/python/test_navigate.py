"""A scripted policy reaches the target in Navigate-v0; the recorded episode replays in
`cathbox session replay --check` with every state hash matching."""
import os
import shutil
import subprocess
import tempfile
import unittest

import gymnasium
import numpy as np

import cathbox.gym
from cathbox.policies import Autopilot


class NavigateTest(unittest.TestCase):
    def test_autopilot_reaches_the_target_and_the_record_replays(self):
        records = tempfile.mkdtemp(prefix="cathbox-nav-")
        env = gymnasium.make("cathbox/Navigate-v0", targets=[("left_subclavian_1", 1.0)], step_s=0.05,
                             record_dir=records, max_episode_steps=600)
        obs, info = env.reset(seed=1)
        pilot = Autopilot(env)
        total = 0.0
        for step in range(600):
            obs, reward, terminated, truncated, info = env.step(pilot.act())
            total += reward
            if terminated or truncated:
                break
        print(f"steps {step + 1}, simulated {info['time_s']:.2f} s, distance {info['distance_to_target_mm']:.1f} mm, "
              f"return {total:.3f}, peak wall force {info['peak_wall_force_mN']:.0f} mN, "
              f"unconverged {info['unconverged_share']:.3f}")
        self.assertTrue(terminated, f"not reached: {info['distance_to_target_mm']:.1f} mm short")
        self.assertLessEqual(info["distance_to_target_mm"], 5.0)
        self.assertGreater(total, 1.0 - 0.005 * (step + 1))  # the target's reward is in the return
        record = env.unwrapped.record_path
        env.close()
        cathbox_bin = os.path.join(os.environ["CATHBOX_BIN"], "cathbox")
        r = subprocess.run([cathbox_bin, "session", "replay", "--check", record], capture_output=True, text=True)
        print(r.stdout, r.stderr)
        self.assertEqual(r.returncode, 0)
        self.assertIn("every state hash matches", r.stdout)
        self.assertNotIn(" 0 state hashes checked", r.stdout)
        shutil.rmtree(records)


if __name__ == "__main__":
    unittest.main()
