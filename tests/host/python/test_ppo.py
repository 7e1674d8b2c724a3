"""A short PPO run on Navigate-v0 learns (examples/python/ppo_navigate.py with PyTorch): the
y bifurcation's left branch, 6 iterations of 256 steps at stEVE's step. Deterministic for its
seed (torch on one thread, seeded episodes), so it fails only when learning stops working: the
mean return of the last iteration must beat the first by 0.3, and the trained policy's mean
action must beat a random policy by 0.5 on 5 unseen seeds (pushing in reaches the target, +1)."""
import os
import shutil
import sys
import tempfile
import unittest

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "..", "examples", "python"))
import ppo_navigate  # noqa: E402


class PpoTest(unittest.TestCase):
    def test_a_short_ppo_run_learns_to_beat_a_random_policy(self):
        out = tempfile.mkdtemp(prefix="cathbox-ppo-")
        curve, learned, random_return = ppo_navigate.main([
            "--case", "y_bifurcation", "--target", "left_branch:0.8", "--iterations", "6",
            "--episode-steps", "20", "--out", out])
        first, last = curve[0]["mean_return"], curve[-1]["mean_return"]
        print(f"curve {[round(c['mean_return'], 3) for c in curve]}, trained {learned:.3f}, random {random_return:.3f}")
        self.assertGreater(last, first + 0.3)
        self.assertGreater(learned, random_return + 0.5)
        self.assertTrue(os.path.getsize(os.path.join(out, "curve.svg")) > 0)
        with open(os.path.join(out, "curve.csv")) as f:
            self.assertEqual(len(f.read().splitlines()), 1 + len(curve))
        shutil.rmtree(out)


if __name__ == "__main__":
    unittest.main()
