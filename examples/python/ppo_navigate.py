"""PPO (examples/python/ppo.py, PyTorch) on cathbox/Navigate-v0, its learning curve beside a
random policy's return. Optional, not in CI (a short run of it is tests/host/python/test_ppo.py).

    build/venv/bin/python examples/python/ppo_navigate.py                       # neuro, left subclavian
    build/venv/bin/python examples/python/ppo_navigate.py --case y_bifurcation --target left_branch:0.8 \\
        --iterations 8 --episode-steps 20                                       # ~30 s

Writes OUT/curve.csv (iteration, env steps, episodes, mean return) and OUT/curve.svg (the curve,
the random policy's mean return as a line), and prints the trained policy's mean return (its mean
action, 5 seeds) beside the random policy's on the same seeds. stEVE's step (1/7.5 s), action
limits and reward terms; `--path-delta` scales the path-length term (stEVE's 0.001 per mm)."""
import argparse
import os
import sys

import gymnasium
import numpy as np

import cathbox.gym

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import ppo  # noqa: E402


def svg(curve, random_return, path):
    """The curve as a small SVG (no plotting library needed)."""
    xs = [c["env_steps"] for c in curve]
    ys = [c["mean_return"] for c in curve if c["mean_return"] == c["mean_return"]]
    lo, hi = min(ys + [random_return]), max(ys + [random_return])
    hi = hi if hi > lo else lo + 1.0
    w, h, m = 640, 360, 50

    def px(x, y):
        return m + (w - 2 * m) * x / max(xs), h - m - (h - 2 * m) * (y - lo) / (hi - lo)

    points = " ".join("%.1f,%.1f" % px(c["env_steps"], c["mean_return"]) for c in curve
                      if c["mean_return"] == c["mean_return"])
    _, ry = px(0, random_return)
    with open(path, "w") as f:
        f.write(f'<svg xmlns="http://www.w3.org/2000/svg" width="{w}" height="{h}" font-family="sans-serif" font-size="12">\n'
                f'<rect width="{w}" height="{h}" fill="white"/>\n'
                f'<line x1="{m}" y1="{h - m}" x2="{w - m}" y2="{h - m}" stroke="black"/>\n'
                f'<line x1="{m}" y1="{m}" x2="{m}" y2="{h - m}" stroke="black"/>\n'
                f'<text x="{w / 2}" y="{h - 15}" text-anchor="middle">env steps (0 .. {max(xs)})</text>\n'
                f'<text x="10" y="{m - 20}">mean episode return ({lo:.2f} .. {hi:.2f})</text>\n'
                f'<line x1="{m}" y1="{ry:.1f}" x2="{w - m}" y2="{ry:.1f}" stroke="gray" stroke-dasharray="4"/>\n'
                f'<text x="{w - m}" y="{ry - 4:.1f}" text-anchor="end" fill="gray">random policy</text>\n'
                f'<polyline points="{points}" fill="none" stroke="steelblue" stroke-width="2"/>\n'
                f'<text x="{w - m}" y="{m - 20}" text-anchor="end" fill="steelblue">PPO</text>\n</svg>\n')


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--case", default="neuro")
    p.add_argument("--target", default="left_subclavian_1:1.0", help="SEGMENT:FRACTION")
    p.add_argument("--iterations", type=int, default=40)
    p.add_argument("--steps-per-iteration", type=int, default=256)
    p.add_argument("--episode-steps", type=int, default=80)
    p.add_argument("--path-delta", type=float, default=0.01, help="reward per mm of path shortened")
    p.add_argument("--lr", type=float, default=1e-3)
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--out", default="ppo-navigate")
    a = p.parse_args(argv)
    segment, fraction = a.target.rsplit(":", 1)
    env = gymnasium.make("cathbox/Navigate-v0", case=a.case, targets=[(segment, float(fraction))],
                         max_episode_steps=a.episode_steps, reward=cathbox.gym.Reward(path_delta=a.path_delta))
    curve, trained = ppo.train(env, a.iterations, a.steps_per_iteration, seed=a.seed, lr=a.lr)
    seeds = range(10_000, 10_005)
    rng = np.random.default_rng(a.seed)
    random_return = ppo.evaluate(env, lambda _: rng.uniform(env.action_space.low, env.action_space.high)
                                 .astype(np.float32), seeds)
    learned_return = ppo.evaluate(env, trained.act, seeds)
    env.close()
    os.makedirs(a.out, exist_ok=True)
    with open(os.path.join(a.out, "curve.csv"), "w") as f:
        f.write("iteration,env_steps,episodes,mean_return\n")
        for c in curve:
            f.write(f"{c['iteration']},{c['env_steps']},{c['episodes']},{c['mean_return']:.6f}\n")
    svg(curve, random_return, os.path.join(a.out, "curve.svg"))
    print(f"mean return over seeds {seeds.start}..{seeds.stop - 1}: trained {learned_return:.3f}, "
          f"random {random_return:.3f}; curve in {a.out}/curve.csv and curve.svg")
    return curve, learned_return, random_return


if __name__ == "__main__":
    main()
