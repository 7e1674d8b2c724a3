"""A scripted policy reaching targets in cathbox/Navigate-v0, each episode recorded.

    build/venv/bin/python examples/python/scripted_navigate.py [--episodes 3] [--records DIR]

Then watch one: build/release/bin/cathbox-trainer --replay DIR/episode-00001.cbxrec, or check it:
build/release/bin/cathbox session replay --check DIR/episode-00001.cbxrec.
The policy is cathbox.policies.Autopilot (privileged: it reads the route to the target)."""
import argparse
import os

import gymnasium

import cathbox.gym  # noqa: F401  (registers the envs)
from cathbox.policies import Autopilot


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--episodes", type=int, default=3)
    p.add_argument("--records", default="records-scripted")
    p.add_argument("--target", default="left_subclavian_1", help="a segment of the neuro vessel")
    a = p.parse_args()
    env = gymnasium.make("cathbox/Navigate-v0", targets=[(a.target, 1.0)], step_s=0.05, record_dir=a.records,
                         max_episode_steps=1200)
    for episode in range(a.episodes):
        env.reset(seed=episode)
        pilot = Autopilot(env)
        ret, steps = 0.0, 0
        while True:
            _, reward, terminated, truncated, info = env.step(pilot.act())
            ret += reward
            steps += 1
            if terminated or truncated:
                break
        print(f"episode {episode}: {'reached' if terminated else 'not reached'} in {info['time_s']:.1f} s "
              f"({steps} steps), return {ret:.3f}, peak wall force {info['peak_wall_force_mN']:.0f} mN, "
              f"record {os.path.abspath(env.unwrapped.record_path)}")
    env.close()


if __name__ == "__main__":
    main()
