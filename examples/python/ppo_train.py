"""A short PPO training on cathbox/Navigate-v0 with Stable-Baselines3, and its learning curve.

Optional, not run in CI. scripts/setup puts Stable-Baselines3 2.4.1 into the venv without its
dependencies (Debian's torch 1.13, pandas and matplotlib):
    build/venv/bin/python examples/python/ppo_train.py [--steps 50000] [--envs 2] [--out ppo_curve.png]

One target (the left subclavian, reached by the scripted policy in ~10 s) and stEVE's step
(1/7.5 s), reward and action limits; the tracked-point observation. The curve is the mean
episode return and success rate over training steps (Monitor's episode logs)."""
import argparse
import sys

try:
    from stable_baselines3 import PPO
    from stable_baselines3.common.env_util import make_vec_env
    from stable_baselines3.common.monitor import load_results
except ImportError:
    sys.exit("ppo_train: stable-baselines3 is not in this python (scripts/setup puts it into build/venv)")

import tempfile

import gymnasium

import cathbox.gym  # noqa: F401  (registers the envs)


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--steps", type=int, default=50_000)
    p.add_argument("--envs", type=int, default=2)
    p.add_argument("--out", default="ppo_curve.png")
    a = p.parse_args()
    logs = tempfile.mkdtemp(prefix="cathbox-ppo-")
    venv = make_vec_env(lambda: gymnasium.make("cathbox/Navigate-v0", targets=[("left_subclavian_1", 1.0)]),
                        n_envs=a.envs, seed=0, monitor_dir=logs, monitor_kwargs={"info_keywords": ("target_reached",)})
    model = PPO("MlpPolicy", venv, n_steps=512, batch_size=256, learning_rate=3e-4, gamma=0.99, verbose=1, seed=0)
    model.learn(total_timesteps=a.steps)
    df = load_results(logs).sort_values("t")
    df["steps"] = df["l"].cumsum()
    window = max(1, len(df) // 20)
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print(df[["steps", "r", "target_reached"]].to_string())
        return
    fig, ax = plt.subplots(figsize=(7, 4))
    ax.plot(df["steps"], df["r"].rolling(window).mean(), label="return (mean of %d episodes)" % window)
    ax.plot(df["steps"], df["target_reached"].astype(float).rolling(window).mean(), label="success rate")
    ax.set_xlabel("env steps")
    ax.set_title("PPO on cathbox/Navigate-v0 (left subclavian)")
    ax.legend()
    fig.tight_layout()
    fig.savefig(a.out)
    print(f"learning curve: {a.out}")


if __name__ == "__main__":
    main()
