"""N environments in one process, stepped on a pool of threads: each Session.step releases the
GIL while the simulation runs, so N cases step in parallel on N cores. Autoreset as
gymnasium's SyncVectorEnv (the step after an episode ends resets that env: reward 0, not done).
The fluoroscopy image mode too: the envs' GL work (GLFW's one thread) is done on the thread
that steps the vector env, while the pool simulates (cathbox.fluoroscopy.GlThread)."""
from concurrent.futures import ThreadPoolExecutor

import numpy as np
from gymnasium.vector import VectorEnv
from gymnasium.vector.utils import batch_space, concatenate, create_empty_array

from .fluoroscopy import GlThread


class ThreadVectorEnv(VectorEnv):
    """Step and reset it from one thread, the one that made it: it draws the envs' fluoroscopy."""

    def __init__(self, env_fns, threads=None):
        self.envs = [fn() for fn in env_fns]
        self.num_envs = len(self.envs)
        if self.num_envs == 0:
            raise ValueError("ThreadVectorEnv: no environments")
        self._gl = GlThread()
        for e in self.envs:
            if hasattr(e.unwrapped, "gl_thread"):
                e.unwrapped.gl_thread = self._gl
        first = self.envs[0]
        self.metadata = first.metadata
        self.render_mode = first.render_mode
        self.single_observation_space = first.observation_space
        self.single_action_space = first.action_space
        for i, e in enumerate(self.envs[1:], 1):
            if e.observation_space != first.observation_space or e.action_space != first.action_space:
                raise ValueError(f"ThreadVectorEnv: environment {i} has other spaces than environment 0")
        self.observation_space = batch_space(self.single_observation_space, self.num_envs)
        self.action_space = batch_space(self.single_action_space, self.num_envs)
        self._pool = ThreadPoolExecutor(max_workers=threads or self.num_envs)
        self._obs = create_empty_array(self.single_observation_space, n=self.num_envs, fn=np.zeros)
        self._autoreset = np.zeros(self.num_envs, dtype=np.bool_)

    def reset(self, *, seed=None, options=None):
        if seed is None or isinstance(seed, int):
            seeds = [None if seed is None else seed + i for i in range(self.num_envs)]
        else:
            seeds = list(seed)
        results = self._gl.serve([self._pool.submit(e.reset, seed=s, options=options) for e, s in zip(self.envs, seeds)])
        infos = {}
        for i, (_, info) in enumerate(results):
            infos = self._add_info(infos, info, i)
        self._obs = concatenate(self.single_observation_space, [o for o, _ in results], self._obs)
        self._autoreset[:] = False
        return self._obs.copy(), infos

    def _one(self, i, action):
        env = self.envs[i]
        if self._autoreset[i]:
            obs, info = env.reset()
            return obs, 0.0, False, False, info
        return env.step(action)

    def step(self, actions):
        actions = np.asarray(actions)
        results = self._gl.serve([self._pool.submit(self._one, i, actions[i]) for i in range(self.num_envs)])
        obs = [r[0] for r in results]
        rewards = np.array([r[1] for r in results], dtype=np.float64)
        terminated = np.array([r[2] for r in results], dtype=np.bool_)
        truncated = np.array([r[3] for r in results], dtype=np.bool_)
        infos = {}
        for i, r in enumerate(results):
            infos = self._add_info(infos, r[4], i)
        self._obs = concatenate(self.single_observation_space, obs, self._obs)
        self._autoreset = terminated | truncated
        return self._obs.copy(), rewards, terminated, truncated, infos

    def close_extras(self, **kwargs):
        for e in self.envs:
            e.close()
        self._pool.shutdown()
