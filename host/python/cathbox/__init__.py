"""Cathbox sessions from Python: load a case, move the tools in virtual time, read the state,
record a .cbxrec. The Gymnasium environments are in `cathbox.gym` (host/python/README.md)."""
import os

from ._cathbox import Session, vessel_segments

__all__ = ["Session", "vessel_segments", "cases_dir", "case_path"]

TOOL_KINDS = {0: "guidewire", 1: "catheter", 2: "coil", 3: "balloon"}


def cases_dir():
    """The bundled cases: $CATHBOX_CASES, else the source tree's cases/ the module was built from."""
    env = os.environ.get("CATHBOX_CASES")
    if env:
        return env
    from . import _config
    return _config.CASES_DIR


def case_path(name):
    """A bundled case by name ('neuro', 'library/arch_type1', ...) or a path as it is (a name
    ending in .case or .hclm)."""
    if name.endswith((".case", ".hclm")):
        return name
    return os.path.join(cases_dir(), name + ".case")
