"""A scripted policy for the environments: the session's autopilot (host/session's
ScriptedHand) as speeds. It reads the privileged state (the route to the target, the lead tool's
tip and its bend, the hand force), pushes along the route, turns the curved tip towards where
the route bends a few millimetres ahead, slows while turned the wrong way, and when stuck (the
hand force high, or no progress for a second) pulls back and turns a quarter turn."""
import math

import numpy as np


class Autopilot:
    def __init__(self, env, push_mm_s=15.0, twist_gain_per_s=4.0, max_twist_rad_s=3.0, lookahead_mm=6.0,
                 stuck_force_mN=250.0, stuck_window_s=1.0, min_progress_mm=0.5, back_off_mm=6.0,
                 back_off_turn_rad=math.pi / 2):
        self.env = env.unwrapped
        self.push, self.gain, self.max_twist = push_mm_s, twist_gain_per_s, max_twist_rad_s
        self.lookahead, self.stuck_force, self.stuck_window = lookahead_mm, stuck_force_mN, stuck_window_s
        self.min_progress, self.back_off, self.back_off_turn = min_progress_mm, back_off_mm, back_off_turn_rad
        self.reset()

    def reset(self):
        route = np.asarray(self.env.session.route, dtype=np.float64) if self.env.session else np.zeros((0, 3))
        self.path = route
        self.s = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(route, axis=0), axis=1))]) \
            if len(route) > 1 else np.zeros(1)
        self.progress = None
        self.best = 0.0
        self.since_progress = 0.0
        self.back_left = 0.0
        self.turn_left = 0.0

    def _point(self, arc):
        arc = min(max(arc, 0.0), self.s[-1])
        return np.array([np.interp(arc, self.s, self.path[:, j]) for j in range(3)])

    def _closest(self, p):
        window = 3.0 if self.progress is not None else 1e300
        here = self.progress or 0.0
        a, b = self.path[:-1], self.path[1:]
        ab = b - a
        t = np.clip(np.einsum("ij,ij->i", p - a, ab) / np.maximum(np.einsum("ij,ij->i", ab, ab), 1e-12), 0, 1)
        arcs = self.s[:-1] + t * (self.s[1:] - self.s[:-1])
        d2 = np.einsum("ij,ij->i", p - (a + t[:, None] * ab), p - (a + t[:, None] * ab))
        near = (self.s[:-1] <= here + window) & (self.s[1:] >= here - window)
        d2 = np.where(near, d2, np.inf)
        return float(arcs[int(np.argmin(d2))])

    def act(self):
        """The action (tools, 2) for the next step: the lead tool moves, the others hold."""
        env = self.env
        dt = env.step_s
        action = np.zeros((env.n_tools, 2), dtype=np.float32)
        lead = env.task.lead_tool
        tip, _, bend = env.session.tip(lead)
        force = env.session.hand_force_mN(lead)
        first = self.progress is None
        self.progress = self._closest(tip)
        if first:
            self.best = self.progress
        if self.back_left > 0.0 or self.turn_left > 0.0:  # pulling back and turning
            pull = min(self.back_left, self.push * dt)
            turn = min(self.turn_left, self.max_twist * dt)
            self.back_left -= pull
            self.turn_left -= turn
            action[lead] = (-pull / dt, turn / dt)
            if self.back_left <= 0.0 and self.turn_left <= 0.0:
                self.best, self.since_progress = self.progress, 0.0
            return action
        here = self._point(self.progress)
        axis = self._point(self.progress + 1.0) - self._point(self.progress - 1.0)
        ahead = self._point(self.progress + self.lookahead) - here
        error = 0.0
        if np.linalg.norm(axis) > 1e-4:
            t = axis / np.linalg.norm(axis)
            lateral = ahead - np.dot(ahead, t) * t
            b = bend - np.dot(bend, t) * t
            if np.linalg.norm(lateral) > max(0.15 * np.linalg.norm(ahead), 0.2) and np.linalg.norm(b) > 1e-3:
                d = lateral / np.linalg.norm(lateral)
                b = b / np.linalg.norm(b)
                error = math.atan2(float(np.dot(t, np.cross(b, d))), float(np.dot(b, d)))
        twist = float(np.clip(self.gain * error, -self.max_twist, self.max_twist))
        align = 0.5 * (1.0 + math.cos(error))
        action[lead] = (self.push * (0.25 + 0.75 * align), twist)
        if self.progress > self.best + self.min_progress:
            self.best, self.since_progress = self.progress, 0.0
        else:
            self.since_progress += dt
        if force > self.stuck_force or self.since_progress > self.stuck_window:
            self.back_left, self.turn_left = self.back_off, self.back_off_turn
        return action
