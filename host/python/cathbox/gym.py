"""Gymnasium environments over Cathbox sessions (host/python/README.md).

    import gymnasium, cathbox.gym
    env = gymnasium.make("cathbox/Navigate-v0")  # observation="tracking" | "state" | "nodes" | "image"
    obs, info = env.reset(seed=1)
    obs, reward, terminated, truncated, info = env.step(env.action_space.sample())

Registered: cathbox/Navigate-v0 (a guidewire from the descending aorta into a supra-aortic
branch of the bundled neuro vessel), cathbox/ArchVariety-v0 (the same on a new arch each
episode, cathbox.arch), cathbox/DualDevice-v0 (a catheter and a guidewire in it, targets in the
carotids and the vertebrals of the neuro vessel). Actions: a Box (tools, 2) of insertion mm/s
and rotation rad/s per device, stEVE's limits (50 mm/s, 3.14 rad/s) by default. One env step is
`step_s` of simulated time (stEVE's 1/7.5 s by default) in 1 ms ticks of the session.
"""
import math
import os
import re

import gymnasium
import numpy as np
from gymnasium import spaces

from . import Session
from . import arch as arch_module
from .cases import EpisodeFiles, case_text, read_case, without_inside
from .fluoroscopy import Fluoroscopy

STEVE_VELOCITY_LIMIT = (50.0, 3.14)  # stEVE's devices: mm/s, rad/s
STEVE_STEP_S = 1.0 / 7.5
# stEVE's own physics time step: SofaBeamAdapter(dt_simulation=0.006), 22 SOFA steps per env
# step. The envs tick at 1 ms by default (the trainer's tick); period_us=STEVE_SIM_DT_US runs
# the session at stEVE's step (host/python/README.md, "Speed": its cost in fidelity).
STEVE_SIM_DT_US = 6000
API_VERSION = 0  # the -v0 of every env: observation layout, reward terms, action units
OBSERVATIONS = ("tracking", "state", "nodes", "image")


class Reward:
    """stEVE's reward: target reached (+target), a step penalty (step), and the change of the
    lead tip's remaining centreline path to the target (path_delta per mm shortened)."""

    def __init__(self, target=1.0, step=-0.005, path_delta=0.001):
        self.target, self.step, self.path_delta = float(target), float(step), float(path_delta)

    def __call__(self, reached, path_before_mm, path_after_mm):
        return (self.target if reached else 0.0) + self.step + self.path_delta * (path_before_mm - path_after_mm)


class CathboxEnv(gymnasium.Env):
    """One Cathbox session per episode; the episode's case comes from `task` (below)."""

    metadata = {"render_modes": ["rgb_array"], "render_fps": 7.5}

    def __init__(self, task, observation="tracking", step_s=STEVE_STEP_S, period_us=1000,
                 velocity_limits=None, reward=None, target_threshold_mm=5.0, tracking_points=3,
                 tracking_spacing_mm=2.0, state_points=16, state_spacing_mm=5.0, image_size=(128, 128),
                 image_renderer="devices", record_dir=None, render_mode=None):
        if observation not in OBSERVATIONS:
            raise ValueError(f"observation {observation!r}: expected one of {', '.join(map(repr, OBSERVATIONS))}")
        if not (step_s > 0.0 and math.isfinite(step_s)):
            raise ValueError(f"step_s {step_s!r}: expected a positive number of seconds")
        if image_renderer not in ("devices", "fluoroscopy"):
            raise ValueError(f"image_renderer {image_renderer!r}: expected 'devices' or 'fluoroscopy'")
        if render_mode not in (None, "rgb_array"):
            raise ValueError(f"render_mode {render_mode!r}: expected None or 'rgb_array'")
        self.task = task
        self.observation_mode = observation
        self.step_s = float(step_s)
        if not (isinstance(period_us, (int, np.integer)) and 100 <= period_us <= 10_000):
            raise ValueError(f"period_us {period_us!r}: expected a whole number of microseconds in [100, 10000] "
                             f"(1000: the trainer's tick; {STEVE_SIM_DT_US}: stEVE's)")
        self.period_us = int(period_us)
        self.ticks_per_step = self.step_s * 1e6 / self.period_us
        if self.ticks_per_step < 1.0:
            raise ValueError(f"step_s {step_s}: shorter than one tick of {period_us} us")
        self.reward_fn = reward or Reward()
        self.target_threshold_mm = float(target_threshold_mm)
        self.tracking_points, self.tracking_spacing_mm = int(tracking_points), float(tracking_spacing_mm)
        self.state_points, self.state_spacing_mm = int(state_points), float(state_spacing_mm)
        self.image_size = (int(image_size[0]), int(image_size[1]))
        self.image_renderer = image_renderer
        self._fluoroscopy = None
        self.gl_thread = None  # a fluoroscopy.GlThread: the thread its views are drawn on (ThreadVectorEnv's)
        self.record_dir = record_dir
        self.render_mode = render_mode
        self.n_tools = task.tool_count
        limits = velocity_limits or [STEVE_VELOCITY_LIMIT] * self.n_tools
        limits = np.asarray(limits, dtype=np.float64).reshape(self.n_tools, 2)
        self.action_space = spaces.Box(low=(-limits).astype(np.float32), high=limits.astype(np.float32),
                                       dtype=np.float32)
        self.observation_space = self._make_observation_space()
        self.files = EpisodeFiles()
        self.session = None
        self.episode = 0
        self.record_path = None

    # ---- spaces and observations
    def _make_observation_space(self):
        n = self.n_tools
        if self.observation_mode == "nodes":
            # The rods' node counts are the tools' (fixed by the task): read from a first session.
            files = EpisodeFiles()
            try:
                case_file, _ = self.task.episode_case(np.random.default_rng(0), files, 0)
                probe = Session(case_file, end_at_target=False)
                self._node_keys = [f"{t}:{name}" for t, name in enumerate(probe.tool_names)]
                shapes = [probe.node_buffer(t).shape for t in range(n)]
                probe.close()
            finally:
                files.close()
            boxes = {k: spaces.Box(-1e4, 1e4, shape=shape, dtype=np.float64) for k, shape in zip(self._node_keys, shapes)}
            boxes["target"] = spaces.Box(-1e4, 1e4, shape=(3,), dtype=np.float64)
            return spaces.Dict(boxes)
        if self.observation_mode == "image":
            w, h = self.image_size
            return spaces.Box(0, 255, shape=(h, w, 1), dtype=np.uint8)
        if self.observation_mode == "tracking":
            size = n * self.tracking_points * 2 + 2 + n * 2
        else:
            size = n * (self.state_points * 3 + 3 + 2) + 3 + n * 2
        return spaces.Box(-1e4, 1e4, shape=(size,), dtype=np.float32)

    def _observation(self):
        s = self.session
        if self.observation_mode == "nodes":  # views of the rods' own buffers: no copy
            obs = {k: s.node_buffer(t) for t, k in enumerate(self._node_keys)}
            obs["target"] = self._target_view
            return obs
        if self.observation_mode == "image":
            w, h = self.image_size
            return (self._fluoroscopy.image() if self._fluoroscopy else s.image(w, h))[:, :, None]
        if self.observation_mode == "state":  # per tool points, tip direction, insertion, rotation; target; action
            return s.state_observation(self.state_points, self.state_spacing_mm, self._target, self._last_action)
        parts = []
        for t in range(self.n_tools):
            pts = s.points_from_tip(t, self.tracking_points, self.tracking_spacing_mm)
            parts.append(s.project(pts).ravel())
        parts.append(s.project(self._target[None, :]).ravel())
        parts.append(self._last_action.ravel())
        return np.clip(np.concatenate(parts), -1e4, 1e4).astype(np.float32)

    def _info(self):
        s = self.session
        m = s.metrics()
        tip = s.tip(self.task.lead_tool)[0]
        return {
            "time_s": s.time_s,
            "target_reached": bool(self._reached),
            "distance_to_target_mm": float(np.linalg.norm(tip - self._target)),
            "path_to_target_mm": self._path_mm,
            "wall_force_mN": m["wall_force_mN"],
            "peak_wall_force_mN": m["peak_wall_force_mN"],
            "time_above_threshold_s": m["time_above_threshold_s"],
            "unconverged_share": m["unconverged_share"],
            "tip_path_mm": m["tip_path_mm"],
            "state_hash": f"{s.state_hash():016x}",
            "case": self._case_description,
        }

    # ---- the Gymnasium API
    def reset(self, *, seed=None, options=None):
        super().reset(seed=seed)
        self._close_session()
        self.episode += 1
        self.record_path = None
        if self.record_dir:
            os.makedirs(self.record_dir, exist_ok=True)
            self.record_path = os.path.join(self.record_dir, f"episode-{self.episode:05d}.cbxrec")
        # A generated vessel the mesher refuses is drawn again (from the same seeded generator:
        # still deterministic), at most `redraws` times.
        for attempt in range(1 + getattr(self.task, "redraws", 0)):
            case_file, self._case_description = self.task.episode_case(self.np_random, self.files, self.episode)
            try:
                self.session = Session(case_file, record=self.record_path or "", period_us=self.period_us,
                                       end_at_target=False, who="cathbox.gym " + self.task.name)
                break
            except ValueError:
                if attempt == getattr(self.task, "redraws", 0):
                    raise
        self.session.set_c_arm(*self.task.c_arm)
        if self.observation_mode == "image" and self.image_renderer == "fluoroscopy":
            # The trainer's image: the pedal down and one tick run, so the first pulse is in it.
            self.session.press_pedal()
            self.session.step(1)
            self._fluoroscopy = Fluoroscopy(self.session, *self.image_size, gl=self.gl_thread)
        self._target = np.asarray(self.session.target, dtype=np.float64)
        self._target_view = self._target.view()
        self._target_view.flags.writeable = False
        self._steps = 0
        self._reached = False
        self._last_action = np.zeros((self.n_tools, 2), dtype=np.float64)
        self._path_mm = self.session.route_remaining_mm(self.task.lead_tool)
        return self._observation(), self._info()

    def step(self, action):
        if self.session is None:
            raise RuntimeError("step() before reset()")
        a = np.asarray(action, dtype=np.float64)
        if a.size != 2 * self.n_tools:
            raise ValueError(f"action: shape {a.shape}, expected ({self.n_tools}, 2): per tool insertion mm/s "
                             "and rotation rad/s")
        a = a.reshape(self.n_tools, 2)
        if not np.all(np.isfinite(a)):
            raise ValueError(f"action: not finite: {a.tolist()}")
        a = np.clip(a, self.action_space.low, self.action_space.high)
        self.session.set_speeds(a)
        # Whole ticks per step, keeping the long-run rate exact (133 or 134 ticks for 1/7.5 s).
        ticks = int(math.floor((self._steps + 1) * self.ticks_per_step + 1e-9)) - \
            int(math.floor(self._steps * self.ticks_per_step + 1e-9))
        self.session.step(ticks)
        self._steps += 1
        self._last_action = a
        tip = self.session.tip(self.task.lead_tool)[0]
        before = self._path_mm
        self._path_mm = self.session.route_remaining_mm(self.task.lead_tool)
        self._reached = bool(np.linalg.norm(tip - self._target) <= self.target_threshold_mm)
        reward = self.reward_fn(self._reached, before, self._path_mm)
        return self._observation(), float(reward), self._reached, False, self._info()

    def render(self):
        if self.render_mode != "rgb_array" or self.session is None:
            return None
        w, h = self.image_size
        image = self._fluoroscopy.image() if self._fluoroscopy else self.session.image(w, h)
        return np.repeat(image[:, :, None], 3, axis=2)

    def clone_session(self):
        """A copy of the episode's session in its present state (inputs replayed, hash-checked)."""
        return self.session.clone()

    def _close_session(self):
        if self._fluoroscopy is not None:
            self._fluoroscopy.close()
            self._fluoroscopy = None
        if self.session is not None:
            self.session.close()
            self.session = None

    def close(self):
        self._close_session()
        self.files.close()


# ---- tasks: what an episode runs on
class NavigateTask:
    """A guidewire alone from the case's entry to a target picked per episode (seeded) among
    `targets`: (segment name, fraction of its length)."""

    name = "Navigate-v0"
    tool_count = 1
    lead_tool = 0
    c_arm = (0.0, 0.0, 300.0)

    def __init__(self, case="neuro", targets=None, tool="guidewire"):
        self.case = case
        _, _, self.vessel_path, self.entry_line, tools = read_case(case)
        if tool not in tools:
            raise ValueError(f"case {case!r}: no tool named {tool!r} (it has {', '.join(tools) or 'none'})")
        self.tools = [(tool, tools[tool][0], without_inside(tools[tool][1]))]
        self.targets = targets or [("brachiocephalic_trunk", 1.0), ("left_common_carotid", 0.35),
                                   ("left_subclavian_1", 1.0), ("right_common_carotid", 0.2),
                                   ("right_subclavian_1", 0.8)]
        self._ids = _segment_ids(self.vessel_path, [n for n, _ in self.targets])

    def episode_case(self, rng, files, episode):
        name, fraction = self.targets[int(rng.integers(0, len(self.targets)))]
        text = case_text(f"{self.name} to {name}", self.vessel_path, self.entry_line,
                         (self._ids[name], fraction), self.tools)
        return files.write(f"episode-{episode % 2}.case", text), {"target": name}


class ArchVarietyTask(NavigateTask):
    """Navigate on a new aortic arch each episode (cathbox.arch: types I-III, bovine,
    tortuosity), the guidewire of the bundled neuro case, a target in one of the arch's branches."""

    name = "ArchVariety-v0"
    redraws = 8  # an arch the mesher refuses is drawn again (none of 240 draws in a row)

    def __init__(self, arch_type=None, bovine=None, tortuosity=None, targets=None):
        _, _, _, _, tools = read_case("neuro")
        self.tools = [("guidewire", tools["guidewire"][0], without_inside(tools["guidewire"][1]))]
        self.arch_type, self.bovine, self.tortuosity = arch_type, bovine, tortuosity
        self.targets = targets or [("right_common_carotid", 0.6), ("left_common_carotid", 0.6),
                                   ("right_subclavian_1", 1.0), ("left_subclavian_1", 1.0)]

    def episode_case(self, rng, files, episode):
        hclm, entry_line, info = arch_module.generate(rng, self.arch_type, self.bovine, self.tortuosity)
        vessel = files.write(f"arch-{episode % 2}.hclm", hclm)
        ids = _segment_ids(vessel, [n for n, _ in self.targets])
        name, fraction = self.targets[int(rng.integers(0, len(self.targets)))]
        text = case_text(f"{self.name} type {info['arch_type']} to {name}", vessel, entry_line,
                         (ids[name], fraction), self.tools)
        info["target"] = name
        return files.write(f"episode-{episode % 2}.case", text), info


class DualDeviceTask:
    """The bundled neuro case's catheter with its guidewire inside, from the descending aorta to
    a target in a carotid or a vertebral artery; the guidewire's tip is the one that must reach."""

    name = "DualDevice-v0"
    tool_count = 2
    c_arm = (0.0, 0.0, 300.0)

    def __init__(self, case="neuro", targets=None):
        _, _, self.vessel_path, self.entry_line, tools = read_case(case)
        if "catheter" not in tools or "guidewire" not in tools:
            raise ValueError(f"case {case!r}: DualDevice needs a 'catheter' and a 'guidewire' tool")
        self.tools = [("catheter", *tools["catheter"]), ("guidewire", *tools["guidewire"])]
        self.lead_tool = 1
        self.targets = targets or [("right_common_carotid", 0.9), ("left_common_carotid", 0.9),
                                   ("right_vertebral", 0.15), ("left_vertebral", 0.15)]
        self._ids = _segment_ids(self.vessel_path, [n for n, _ in self.targets])

    episode_case = NavigateTask.episode_case


class CaseTask:
    """A case file as it is: its tools (all of them, in the file's order), its entry and its
    target. The episode opens the file itself, not a copy, so the record carries the case's own
    bytes and cathbox-server files the run under the library case uploaded from the same file
    (a generated episode case is filed apart as `unlisted:`). The lead tool, whose tip must reach
    the target, is the last one (the innermost: the guidewire inside the catheter)."""

    name = "Case-v0"
    c_arm = (0.0, 0.0, 300.0)

    def __init__(self, case="y_bifurcation"):
        self.case_file, text, _, _, tools = read_case(case)
        if not tools:
            raise ValueError(f"case {case!r}: {self.case_file} has no tool")
        if not re.search(r"^target\s", text, re.M):
            raise ValueError(f"case {case!r}: {self.case_file} has no target")
        self.tool_count = len(tools)
        self.lead_tool = self.tool_count - 1

    def episode_case(self, rng, files, episode):
        return self.case_file, {"target": "the case's"}


def _segment_ids(vessel_path, names):
    from . import vessel_segments
    by_name = {s["name"]: s["id"] for s in vessel_segments(vessel_path)}
    missing = [n for n in names if n not in by_name]
    if missing:
        raise ValueError(f"vessel {vessel_path}: no segment named {', '.join(missing)}")
    return {n: by_name[n] for n in names}


def navigate(case="neuro", targets=None, **kwargs):
    return CathboxEnv(NavigateTask(case, targets), **kwargs)


def arch_variety(arch_type=None, bovine=None, tortuosity=None, targets=None, **kwargs):
    return CathboxEnv(ArchVarietyTask(arch_type, bovine, tortuosity, targets), **kwargs)


def dual_device(case="neuro", targets=None, **kwargs):
    return CathboxEnv(DualDeviceTask(case, targets), **kwargs)


def case(case="y_bifurcation", **kwargs):
    return CathboxEnv(CaseTask(case), **kwargs)


def _register():
    ids = gymnasium.envs.registration.registry
    for env_id, entry, steps in (("cathbox/Navigate-v0", navigate, 200),
                                 ("cathbox/ArchVariety-v0", arch_variety, 200),
                                 ("cathbox/DualDevice-v0", dual_device, 400),
                                 ("cathbox/Case-v0", case, 400)):
        if env_id not in ids:
            gymnasium.register(id=env_id, entry_point=entry, max_episode_steps=steps)


_register()

from .vector import ThreadVectorEnv  # noqa: E402  (after the envs it runs)

__all__ = ["CathboxEnv", "Reward", "NavigateTask", "ArchVarietyTask", "DualDeviceTask", "CaseTask", "ThreadVectorEnv",
           "navigate", "arch_variety", "dual_device", "case", "STEVE_STEP_S", "STEVE_SIM_DT_US", "STEVE_VELOCITY_LIMIT",
           "API_VERSION"]
