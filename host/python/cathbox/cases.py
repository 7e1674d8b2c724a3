"""Episode cases for the environments: a case file written per episode (the bundled vessel, its
entry, the episode's target, the tools the task uses). The session keeps the bytes in its
record, so an episode replays whatever the temporary files hold later."""
import os
import re

from . import case_path as _case_path

_TOOL_BLOCK = re.compile(r"^tool\s+(\S+)\s+(\S+)\s*\n(.*?)^end\s*$", re.S | re.M)


def read_case(name):
    """(path, text, vessel path, entry line or None, tool blocks {name: (kind, body)})."""
    path = _case_path(name)
    try:
        with open(path, encoding="utf-8") as f:
            text = f.read()
    except OSError as e:
        raise ValueError(f"case {name!r}: cannot read {path}: {e.strerror}") from None
    vessel = re.search(r"^vessel\s+(\S+)", text, re.M)
    if not vessel:
        raise ValueError(f"case {name!r}: {path} names no vessel file")
    vessel_path = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(path)), vessel.group(1)))
    entry = re.search(r"^entry\s+.*$", text, re.M)
    tools = {m.group(1): (m.group(2), m.group(3)) for m in _TOOL_BLOCK.finditer(text)}
    return path, text, vessel_path, entry.group(0) if entry else None, tools


def case_text(name, vessel_path, entry_line, target, tools):
    """A case file: `target` is (segment id, fraction); `tools` [(name, kind, body)] in order."""
    lines = ["cathbox-case 1", f"name {name}", f"vessel {vessel_path}"]
    if entry_line:
        lines.append(entry_line)
    lines.append(f"target {target[0]} {target[1]:.4f}")
    for tool_name, kind, body in tools:
        lines.append(f"tool {tool_name} {kind}")
        lines.append(body.rstrip("\n"))
        lines.append("end")
    return "\n".join(lines) + "\n"


def without_inside(body):
    """A tool block without its `inside` line (the tool alone, not in a catheter)."""
    return "".join(l + "\n" for l in body.splitlines() if not l.strip().startswith("inside"))


class EpisodeFiles:
    """A temporary folder holding the episode's case (and generated vessel) files."""

    def __init__(self):
        import shutil
        import tempfile
        import weakref
        self.dir = tempfile.mkdtemp(prefix="cathbox-env-")
        self._cleanup = weakref.finalize(self, shutil.rmtree, self.dir, True)  # also without close()

    def write(self, name, text):
        path = os.path.join(self.dir, name)
        with open(path, "w", encoding="utf-8") as f:
            f.write(text)
        return path

    def close(self):
        self._cleanup()
