"""The trainer's fluoroscopic image of a Session: host/app's renderer (app::OffscreenFluoro,
the module cathbox._fluoro), drawn offscreen in a hidden GL 3.3 window. Needs a display: Xvfb
(Mesa's llvmpipe) on a machine without one, e.g. `xvfb-run -a python ...`.

GLFW wants every window made, drawn and destroyed on one thread. A `GlThread` lets other
threads use views anyway: their GL calls are posted to the thread that owns it, which runs them
while it waits for those threads (`serve`). cathbox.gym.ThreadVectorEnv owns one: its envs step
on a pool of threads, their images are drawn on the thread that steps the vector env."""
import queue
import threading
from concurrent.futures import Future


class GlThread:
    """Runs GL work on its owner (the thread that made it) for callers on any thread."""

    def __init__(self):
        self.owner = threading.get_ident()
        self._jobs = queue.SimpleQueue()

    def call(self, fn, *args):
        """fn(*args) on the owner thread: at once on it, else posted and waited for (the owner
        must be in `serve`); its exception is raised here."""
        if threading.get_ident() == self.owner:
            return fn(*args)
        done = Future()
        self._jobs.put((fn, args, done))
        return done.result()

    def serve(self, futures):
        """On the owner thread: runs the posted GL work until every future in `futures` is done;
        returns their results in order (a future's exception is raised)."""
        if threading.get_ident() != self.owner:
            raise RuntimeError("GlThread.serve: not on the thread that owns the GL work (GLFW's one thread)")
        self._run_posted()  # and the wake-ups a last round left (at most one per future)
        for f in futures:
            f.add_done_callback(lambda _: self._jobs.put(None))  # wakes the loop below
        while not all(f.done() for f in futures):
            job = self._jobs.get()
            if job is None:
                continue
            self._run(job)
        return [f.result() for f in futures]

    def _run_posted(self):
        while True:
            try:
                job = self._jobs.get_nowait()
            except queue.Empty:
                return
            if job is not None:
                self._run(job)

    @staticmethod
    def _run(job):
        fn, args, done = job
        try:
            done.set_result(fn(*args))
        except BaseException as e:  # noqa: BLE001  (handed to the posting thread)
            done.set_exception(e)


class Fluoroscopy:
    """Images of `session` (a cathbox.Session, kept alive here) through its C-arm, (height, width)
    uint8. The session's fluoroscopy unit pulses only while its pedal is down
    (Session.press_pedal()); before the first pulse the image is black, as on the monitor.
    With `gl` (a GlThread), the view is made, drawn and dropped on its owner thread."""

    def __init__(self, session, width, height, gl=None):
        try:
            from . import _fluoro
        except ImportError as e:
            raise RuntimeError(f"fluoroscopy: cathbox._fluoro is not built (host/app/python: GL, GLFW, pybind11): {e}") from None
        self.session = session
        self.gl = gl
        self.view = self._on_gl(_fluoro.View, session.session_capsule(), int(width), int(height))

    def _on_gl(self, fn, *args):
        return self.gl.call(fn, *args) if self.gl else fn(*args)

    def image(self):
        return self._on_gl(self.view.render, self.session.session_capsule(), *self.session.c_arm_pose)

    def _drop(self):
        self.view = None

    def close(self):
        if self.view is not None:
            self._on_gl(self._drop)  # the view's GL objects are deleted in its own context, on its thread
        self.session = None
