"""Env steps per second per core of the Cathbox Gymnasium environments, beside stEVE's.

    scripts/bench python [--seconds S] [--episodes N] [--envs cathbox/Navigate-v0,...] [--ticks-us 1000,6000]

For each env, each step length (stEVE's 1/7.5 s of simulated time, and 1 ms), each physics
tick (`period_us`: 1 ms, the trainer's and the envs' default; 6 ms, stEVE's own SOFA time step,
SofaBeamAdapter's dt_simulation = 0.006 s, 22 SOFA steps per env step), each
observation mode (state, nodes, image; fluoroscopy under xvfb-run) and each policy (random: seeded uniform actions in the action
space, as an RL agent explores; autopilot: cathbox.policies.Autopilot driving to the target,
the lead tool deep in the vessels): `--seconds` of simulated time from seed 0 (`--episodes N`: N such
episodes, seeds 0..N-1), the steps timed
(wall and the process's CPU time; resets excluded).
Per core = steps / CPU seconds of the process, all its threads (the simulation is single-threaded
per env; the fluoroscopy mode's llvmpipe rasterises on threads of its own, counted too). stEVE's figure is derived from its published training (stEVE_training README): 2e7
steps on 29 workers in 1-2 days = 4.0-8.0 steps/s per worker, SOFA BeamAdapter included.
At a coarser tick, each row also gives what it costs in fidelity: the share of ticks whose rod
solve did not converge, and (random policy: the same actions) the lead tip's largest and final
distance from where the 1 ms run had it after the same step.
"""
import argparse
import itertools
import time

import gymnasium
import numpy as np

import cathbox.gym  # noqa: F401  (registers the envs)
from cathbox.policies import Autopilot

STEVE_STEPS, STEVE_WORKERS = 2e7, 29
STEVE_LOW = STEVE_STEPS / STEVE_WORKERS / (2 * 86400)
STEVE_HIGH = STEVE_STEPS / STEVE_WORKERS / (1 * 86400)


def measure(env_id, step_s, period_us, mode, policy, sim_seconds, episodes=1):
    """Steps, wall seconds, CPU seconds, the unconverged share and the lead tip after every step,
    for `episodes` episodes (seeds 0, 1, ...) of `sim_seconds` of simulated time each (resets
    excluded: an episode that ends early is reset off the clock and the next one timed; the
    random policy's generator runs on across episodes)."""
    # "fluoroscopy": the image mode through the trainer's renderer (needs a display: xvfb-run).
    kwargs = dict(observation="image", image_renderer="fluoroscopy") if mode == "fluoroscopy" else dict(observation=mode)
    env = gymnasium.make(env_id, step_s=step_s, period_us=period_us, max_episode_steps=10**9, **kwargs)
    rng = np.random.default_rng(0)
    env.reset(seed=0)
    pilot = Autopilot(env) if policy == "autopilot" else None
    per_episode = max(20, int(round(sim_seconds / step_s)))
    steps = per_episode * episodes
    wall = cpu = 0.0
    episode = 0
    tips = []
    unconverged = []
    for i in range(steps):
        if i > 0 and i % per_episode == 0:  # the next episode of the sample (reset off the clock)
            unconverged.append(env.unwrapped.session.metrics()["unconverged_share"])
            episode += 1
            env.reset(seed=episode)
            if pilot:
                pilot.reset()
        action = pilot.act() if pilot else rng.uniform(env.action_space.low, env.action_space.high).astype(np.float32)
        wall0, cpu0 = time.perf_counter(), time.process_time()
        _, _, terminated, truncated, _ = env.step(action)
        wall += time.perf_counter() - wall0
        cpu += time.process_time() - cpu0
        session = env.unwrapped.session
        tips.append(session.tip(env.unwrapped.task.lead_tool)[0].copy())
        if terminated or truncated:
            unconverged.append(session.metrics()["unconverged_share"])
            episode += 1
            env.reset(seed=episode)
            if pilot:
                pilot.reset()
    unconverged.append(env.unwrapped.session.metrics()["unconverged_share"])
    env.close()
    return steps, wall, cpu, float(np.mean(unconverged)), np.array(tips)


def measure_vector(env_id, n, mode, sim_seconds):
    """Env steps per wall second of n envs stepped together by ThreadVectorEnv (random actions,
    1/7.5 s), against the same n envs stepped one after the other on this thread."""
    kwargs = dict(observation="image", image_renderer="fluoroscopy") if mode == "fluoroscopy" else dict(observation=mode)
    make = [lambda: gymnasium.make(env_id, max_episode_steps=10**9, **kwargs) for _ in range(n)]
    steps = max(10, int(round(sim_seconds / cathbox.gym.STEVE_STEP_S)))
    rng = np.random.default_rng(0)
    vec = cathbox.gym.ThreadVectorEnv(make)
    vec.reset(seed=0)
    actions = [rng.uniform(vec.action_space.low, vec.action_space.high).astype(np.float32) for _ in range(steps)]
    t0 = time.perf_counter()
    for a in actions:
        vec.step(a)
    threaded = n * steps / (time.perf_counter() - t0)
    vec.close()
    envs = [fn() for fn in make]
    for i, e in enumerate(envs):
        e.reset(seed=i)
    t0 = time.perf_counter()
    for a in actions:
        for i, e in enumerate(envs):
            e.step(a[i])
    serial = n * steps / (time.perf_counter() - t0)
    for e in envs:
        e.close()
    return threaded, serial


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--seconds", type=float, default=10.0, help="simulated seconds per measurement at 1/7.5 s, a quarter at 1 ms (default 10)")
    p.add_argument("--envs", default="cathbox/Navigate-v0,cathbox/ArchVariety-v0,cathbox/DualDevice-v0")
    p.add_argument("--modes", default="state,nodes,image",
                   help="state, nodes, tracking, image (the devices on the CPU), fluoroscopy (the trainer's image: xvfb-run)")
    p.add_argument("--policies", default="random,autopilot")
    p.add_argument("--ticks-us", default=f"1000,{cathbox.gym.STEVE_SIM_DT_US}",
                   help="physics ticks (period_us) at the 1/7.5 s step: 1000 (default of the envs), 6000 (stEVE's SOFA dt)")
    p.add_argument("--episodes", type=int, default=1,
                   help="episodes per row (seeds 0..N-1, each --seconds long): the random policy's cost per step "
                        "depends on how deep its walk takes the tools, so one episode is a sample of one (default 1)")
    p.add_argument("--vector", type=int, default=2, help="envs in the ThreadVectorEnv row, in the first mode (0: none)")
    a = p.parse_args()
    print(f"stEVE (derived from its published training: 2e7 steps, 29 workers, 1-2 days): "
          f"{STEVE_LOW:.1f}-{STEVE_HIGH:.1f} env steps/s per worker at 1/7.5 s, its physics step "
          f"{cathbox.gym.STEVE_SIM_DT_US / 1000:.0f} ms (SofaBeamAdapter dt_simulation)")
    print(f"{'env':26s} {'step':>8s} {'tick':>5s} {'mode':>11s} {'policy':>9s} {'steps':>6s} {'steps/s wall':>13s} "
          f"{'steps/s/core':>13s} {'x stEVE (per core)':>19s} {'sim x real':>11s} {'unconverged':>12s} "
          f"{'tip vs 1 ms: max / end mm':>26s}")
    ticks_us = [int(t) for t in a.ticks_us.split(",")]
    fine_tips = {}  # the 1 ms tick's tip after every step, per row
    for env_id in a.envs.split(","):
        rows = [(1.0 / 7.5, "1/7.5 s", t) for t in ticks_us] + [(0.001, "1 ms", 1000)]
        for step_s, label, period_us in rows:
            for mode, policy in itertools.product(a.modes.split(","), a.policies.split(",")):
                sim_seconds = a.seconds if step_s > 0.01 else a.seconds / 4
                n, wall, cpu, unconverged, tips = measure(env_id, step_s, period_us, mode, policy, sim_seconds, a.episodes)
                per_core = n / cpu
                key = (env_id, step_s, mode, policy)
                reference = fine_tips.setdefault(key, tips) if period_us == 1000 else fine_tips.get(key)
                drift = ""
                if period_us != 1000 and reference is not None and policy == "random" and len(reference) == len(tips):
                    d = np.linalg.norm(tips - reference, axis=1)
                    drift = f"{d.max():.2f} / {d[-1]:.2f}"
                print(f"{env_id:26s} {label:>8s} {period_us / 1000:3.0f}ms {mode:>11s} {policy:>9s} {n:6d} {n / wall:13.1f} "
                      f"{per_core:13.1f} {per_core / STEVE_HIGH:8.0f}-{per_core / STEVE_LOW:<10.0f} {n * step_s / cpu:11.2f} "
                      f"{unconverged:12.4f} {drift:>26s}", flush=True)
    if a.vector > 0:
        env_id, mode = a.envs.split(",")[0], a.modes.split(",")[0]
        threaded, serial = measure_vector(env_id, a.vector, mode, a.seconds)
        print(f"ThreadVectorEnv of {a.vector} x {env_id} ({mode}) at 1/7.5 s, random: {threaded:.1f} env steps/s (wall), "
              f"the same envs one after the other: {serial:.1f} ({threaded / serial:.2f}x)")


if __name__ == "__main__":
    main()
