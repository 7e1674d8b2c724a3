"""A small PPO (clipped surrogate, GAE) in PyTorch for the Cathbox environments.

    import gymnasium, cathbox.gym, ppo
    env = gymnasium.make("cathbox/Navigate-v0", max_episode_steps=60)
    curve, agent = ppo.train(env, iterations=20, steps_per_iteration=512, seed=0)

One env, on this thread; a Gaussian policy over the action Box (the network's output in [-1, 1]
scaled to the Box, so stEVE's 50 mm/s and 3.14 rad/s weigh alike), a separate value network,
observations normalised by running statistics. Deterministic for a seed (torch on one thread,
the env seeded per episode). `curve` holds per iteration the mean return of the episodes that
ended in it. PyTorch: Debian's python3-torch (scripts/setup)."""
import math

import numpy as np
import torch
from torch import nn


class RunningNorm:
    """Mean and variance of the observations seen so far (Chan's parallel update)."""

    def __init__(self, size):
        self.mean, self.var, self.count = np.zeros(size), np.ones(size), 1e-4

    def update(self, batch):
        m, v, n = batch.mean(0), batch.var(0), len(batch)
        delta, total = m - self.mean, self.count + n
        self.mean = self.mean + delta * n / total
        self.var = (self.var * self.count + v * n + delta**2 * self.count * n / total) / total
        self.count = total

    def __call__(self, obs):
        return np.clip((obs - self.mean) / np.sqrt(self.var + 1e-8), -10.0, 10.0)


def _mlp(inputs, outputs, hidden=64):
    return nn.Sequential(nn.Linear(inputs, hidden), nn.Tanh(), nn.Linear(hidden, hidden), nn.Tanh(),
                         nn.Linear(hidden, outputs))


class Agent(nn.Module):
    def __init__(self, obs_size, act_size):
        super().__init__()
        self.pi = _mlp(obs_size, act_size)
        self.v = _mlp(obs_size, 1)
        self.log_std = nn.Parameter(torch.full((act_size,), -0.5))

    def dist(self, obs):
        return torch.distributions.Normal(self.pi(obs), self.log_std.exp())


class Trained:
    """The policy after training: act(obs) gives the mean action in the env's Box."""

    def __init__(self, agent, norm, high):
        self.agent, self.norm, self.high = agent, norm, high

    def act(self, obs):
        with torch.no_grad():
            u = self.agent.pi(torch.as_tensor(self.norm(obs.ravel()), dtype=torch.float32)).numpy()
        return (np.clip(u, -1.0, 1.0) * self.high).reshape(self.high.shape).astype(np.float32)


def train(env, iterations, steps_per_iteration, seed=0, gamma=0.99, lam=0.95, clip=0.2, epochs=6,
          minibatch=64, lr=3e-4, log=print):
    torch.manual_seed(seed)
    torch.set_num_threads(1)
    high = env.action_space.high.astype(np.float64).ravel()
    obs_size, act_size = int(np.prod(env.observation_space.shape)), high.size
    agent = Agent(obs_size, act_size)
    opt = torch.optim.Adam(agent.parameters(), lr=lr)
    norm = RunningNorm(obs_size)
    episode = seed * 100_000
    obs, _ = env.reset(seed=episode)
    ret, curve = 0.0, []
    for it in range(iterations):
        raw, acts, logps, rews, dones, vals, returns = [], [], [], [], [], [], []
        for _ in range(steps_per_iteration):
            raw.append(obs.ravel().astype(np.float64))
            x = torch.as_tensor(norm(raw[-1]), dtype=torch.float32)
            with torch.no_grad():
                d = agent.dist(x)
                u = d.sample()
                logps.append(float(d.log_prob(u).sum()))
                vals.append(float(agent.v(x)))
            acts.append(u.numpy())
            action = (np.clip(u.numpy(), -1.0, 1.0) * high).reshape(env.action_space.shape).astype(np.float32)
            obs, r, terminated, truncated, _ = env.step(action)
            ret += r
            rews.append(r)
            # A cut episode (time limit) is bootstrapped from its last state's value; an ended one is not.
            if truncated and not terminated:
                with torch.no_grad():
                    rews[-1] += gamma * float(agent.v(torch.as_tensor(norm(obs.ravel()), dtype=torch.float32)))
            dones.append(terminated or truncated)
            if terminated or truncated:
                returns.append(ret)
                ret = 0.0
                episode += 1
                obs, _ = env.reset(seed=episode)
        with torch.no_grad():
            last = float(agent.v(torch.as_tensor(norm(obs.ravel()), dtype=torch.float32)))
        adv, gae = np.zeros(steps_per_iteration), 0.0
        for t in reversed(range(steps_per_iteration)):
            nxt = last if t + 1 == steps_per_iteration else vals[t + 1]
            live = 0.0 if dones[t] else 1.0
            delta = rews[t] + gamma * nxt * live - vals[t]
            gae = delta + gamma * lam * live * gae
            adv[t] = gae
        target = adv + np.array(vals)
        x = torch.as_tensor(np.array([norm(o) for o in raw]), dtype=torch.float32)
        norm.update(np.array(raw))
        a = torch.as_tensor(np.array(acts), dtype=torch.float32)
        old_logp = torch.as_tensor(logps, dtype=torch.float32)
        adv_t = torch.as_tensor((adv - adv.mean()) / (adv.std() + 1e-8), dtype=torch.float32)
        target_t = torch.as_tensor(target, dtype=torch.float32)
        order = np.random.default_rng(seed + it)
        for _ in range(epochs):
            for idx in np.array_split(order.permutation(steps_per_iteration), max(1, steps_per_iteration // minibatch)):
                i = torch.as_tensor(idx)
                ratio = (agent.dist(x[i]).log_prob(a[i]).sum(-1) - old_logp[i]).exp()
                surrogate = torch.min(ratio * adv_t[i], ratio.clamp(1 - clip, 1 + clip) * adv_t[i]).mean()
                value_loss = ((agent.v(x[i]).squeeze(-1) - target_t[i]) ** 2).mean()
                loss = -surrogate + 0.5 * value_loss
                opt.zero_grad()
                loss.backward()
                nn.utils.clip_grad_norm_(agent.parameters(), 0.5)
                opt.step()
        mean = float(np.mean(returns)) if returns else math.nan
        curve.append({"iteration": it, "env_steps": (it + 1) * steps_per_iteration, "episodes": len(returns),
                      "mean_return": mean})
        if log:
            log(f"iteration {it}: {(it + 1) * steps_per_iteration} steps, {len(returns)} episodes, mean return {mean:.3f}")
    return curve, Trained(agent, norm, high)


def evaluate(env, act, seeds):
    """Mean return of one episode per seed under `act(obs)`."""
    total = []
    for s in seeds:
        obs, _ = env.reset(seed=s)
        ret, done = 0.0, False
        while not done:
            obs, r, terminated, truncated, _ = env.step(act(obs))
            ret += r
            done = terminated or truncated
        total.append(ret)
    return float(np.mean(total))
