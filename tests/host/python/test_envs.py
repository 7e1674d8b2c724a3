"""The Gymnasium environments: Gymnasium's own checker, seeds, determinism, two envs side by
side, the vector env, bad actions."""
import math
import os
import unittest

import gymnasium
import numpy as np
from gymnasium.utils.env_checker import check_env

import cathbox.gym

ENV_IDS = ("cathbox/Navigate-v0", "cathbox/ArchVariety-v0", "cathbox/DualDevice-v0", "cathbox/Case-v0")
# (env, observation mode) pairs Gymnasium's checker runs on: every env in every mode it has.
# Under the sanitizers (the asan tree's CTest entry sets CATHBOX_SANITIZED) each mode once, on
# the cheapest env that has it: every observation path of the module still runs instrumented,
# and the other envs' episodes run in the tests below (the whole sweep is 18 CPU-s in the
# release tree, ~8x that instrumented).
MODES = ("tracking", "state", "nodes", "image")
CHECKED = [(env_id, mode) for env_id in ENV_IDS for mode in MODES
           if mode != "image" or env_id == "cathbox/Navigate-v0"]
if os.environ.get("CATHBOX_SANITIZED"):
    CHECKED = [("cathbox/ArchVariety-v0", mode) for mode in MODES[:3]] + [("cathbox/Navigate-v0", "image")]


def run(env, seed, steps, actions):
    obs, _ = env.reset(seed=seed)
    out = [obs.copy()]
    for k in range(steps):
        obs, reward, terminated, truncated, info = env.step(actions[k])
        out.append(obs.copy())
        out.append((reward, info["state_hash"]))
    return out


class EnvTest(unittest.TestCase):
    def test_gymnasium_checker_passes_every_env_and_mode(self):
        for env_id, mode in CHECKED:
            with self.subTest(env=env_id, observation=mode):
                env = gymnasium.make(env_id, observation=mode, step_s=0.02)
                check_env(env.unwrapped, skip_render_check=True)
                env.close()

    def test_nodes_observation_views_the_simulator_without_a_copy(self):
        env = gymnasium.make("cathbox/DualDevice-v0", observation="nodes", step_s=0.05)
        obs, _ = env.reset(seed=2)
        session = env.unwrapped.session
        self.assertEqual(list(obs), ["0:catheter", "1:guidewire", "target"])
        first = {k: v.__array_interface__["data"][0] for k, v in obs.items()}
        for t, key in enumerate(("0:catheter", "1:guidewire")):
            self.assertTrue(np.shares_memory(obs[key], session.node_buffer(t)))
            self.assertFalse(obs[key].flags.writeable)
        kept = {k: v.copy() for k, v in obs.items()}
        obs2, _, _, _, _ = env.step(np.array([[30.0, 0.0], [30.0, 1.0]], dtype=np.float32))
        for key in ("0:catheter", "1:guidewire"):
            self.assertEqual(obs2[key].__array_interface__["data"][0], first[key])  # the same memory...
            self.assertIs(obs2[key].base, session)
            self.assertFalse(np.array_equal(obs[key], kept[key]))  # ...showing the new state
            np.testing.assert_array_equal(obs[key], obs2[key])
        self.assertTrue(env.observation_space.contains(obs2))
        env.close()

    def test_same_seed_same_observations_bit_for_bit_and_two_envs_do_not_interfere(self):
        rng = np.random.default_rng(7)
        for env_id in ENV_IDS:
            with self.subTest(env=env_id):
                a = gymnasium.make(env_id, step_s=0.02)
                b = gymnasium.make(env_id, step_s=0.02)
                actions = [a.action_space.sample() for _ in range(25)]
                alone = run(a, 3, 25, actions)
                # The same episode with another env stepped in between every step.
                a.reset(seed=3)
                b.reset(seed=11)
                mixed = [a.unwrapped._observation().copy()]
                for k in range(25):
                    b.step(rng.uniform(b.action_space.low, b.action_space.high).astype(np.float32))
                    obs, reward, _, _, info = a.step(actions[k])
                    mixed.append(obs.copy())
                    mixed.append((reward, info["state_hash"]))
                self.assertEqual(len(alone), len(mixed))
                for x, y in zip(alone, mixed):
                    if isinstance(x, tuple):
                        self.assertEqual(x, y)
                    else:
                        self.assertEqual(x.tobytes(), y.tobytes())
                self.assertEqual(alone[0].tobytes(), run(b, 3, 0, [])[0].tobytes())
                a.close()
                b.close()

    def test_seeds_pick_the_episode(self):
        env = gymnasium.make("cathbox/ArchVariety-v0")
        cases = {str(env.reset(seed=s)[1]["case"]) for s in range(6)}
        self.assertGreater(len(cases), 1)
        self.assertEqual(str(env.reset(seed=4)[1]["case"]), str(env.reset(seed=4)[1]["case"]))
        env.close()

    def test_thread_vector_env_gives_what_the_envs_give_alone(self):
        fns = [lambda: gymnasium.make("cathbox/Navigate-v0", step_s=0.05) for _ in range(2)]
        vec = cathbox.gym.ThreadVectorEnv(fns)
        obs, _ = vec.reset(seed=5)
        singles = [gymnasium.make("cathbox/Navigate-v0", step_s=0.05) for _ in range(2)]
        for i, e in enumerate(singles):
            o, _ = e.reset(seed=5 + i)
            np.testing.assert_array_equal(obs[i], o)
        for _ in range(10):
            act = vec.action_space.sample()
            obs, rewards, term, trunc, _ = vec.step(act)
            for i, e in enumerate(singles):
                o, r, *_ = e.step(act[i])
                np.testing.assert_array_equal(obs[i], o)
                self.assertEqual(rewards[i], r)
        vec.close()

    def test_bad_actions_and_arguments_raise_one_line(self):
        env = gymnasium.make("cathbox/DualDevice-v0")
        env.reset(seed=0)
        for bad, text in ((np.zeros(3), "expected (2, 2)"), (np.array([[math.nan, 0], [0, 0]]), "not finite")):
            with self.assertRaises(ValueError) as e:
                env.step(bad)
            self.assertIn(text, str(e.exception))
            self.assertNotIn("\n", str(e.exception))
        env.step(np.zeros((2, 2), np.float32))  # still usable
        env.close()
        for kwargs, text in (({"case": "no_such_case"}, "no_such_case"), ({"observation": "sound"}, "observation"),
                             ({"targets": [("aorta_of_nowhere", 0.5)]}, "aorta_of_nowhere")):
            with self.assertRaises(ValueError) as e:
                gymnasium.make("cathbox/Navigate-v0", **kwargs)
            self.assertIn(text, str(e.exception))
            self.assertNotIn("\n", str(e.exception))
        with self.assertRaises(ValueError) as e:
            gymnasium.make("cathbox/ArchVariety-v0", arch_type="IV").reset(seed=0)
        self.assertIn("arch type 'IV'", str(e.exception))


if __name__ == "__main__":
    unittest.main()
