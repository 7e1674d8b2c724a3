"""The trainer's fluoroscopic image of a Session: host/app's renderer (app::OffscreenFluoro,
the module cathbox._fluoro), drawn offscreen in a hidden GL 3.3 window. Needs a display: Xvfb
(Mesa's llvmpipe) on a machine without one, e.g. `xvfb-run -a python ...`."""


class Fluoroscopy:
    """Images of `session` (a cathbox.Session, kept alive here) through its C-arm, (height, width)
    uint8. The session's fluoroscopy unit pulses only while its pedal is down
    (Session.press_pedal()); before the first pulse the image is black, as on the monitor."""

    def __init__(self, session, width, height):
        try:
            from . import _fluoro
        except ImportError as e:
            raise RuntimeError(f"fluoroscopy: cathbox._fluoro is not built (host/app/python: GL, GLFW, pybind11): {e}") from None
        self.session = session
        self.view = _fluoro.View(session.session_capsule(), int(width), int(height))

    def image(self):
        return self.view.render(self.session.session_capsule(), *self.session.c_arm_pose)

    def close(self):
        self.view = None
        self.session = None
