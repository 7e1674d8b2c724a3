"""Aortic arches for ArchVariety: a new arch each episode, as an HCLM vessel file.

The arch is the bundled neuro case's (sim/vessel/src/neuro_case.cpp: an oblique half
circle, ascending aorta on the right and in front, descending behind on the left; patient
coordinates x left, y anterior, z superior; diameters from Hager 2002 and Gray's Anatomy) with
what varies between patients drawn from a seeded generator:

- arch type (the vertical distance d from the top of the arch to the origin of the
  brachiocephalic trunk, in common-carotid diameters, ~6.5 mm): type I d < 1, type II 1-2,
  type III > 2 (Madhwal S et al., J Invasive Cardiol 2008;20:22-5);
- bovine arch: the left common carotid arises from the brachiocephalic trunk
  (Layton KF et al., AJNR 2006;27:1541-2: ~13 % of people);
- the arch's height and width (x0.85-1.15), the spacing of the great vessels' origins;
- tortuosity: a lateral sine wave of random phase on the inner knots of the carotids and the
  left subclavian (not the first, which sets the way out of the parent), of amplitude
  `tortuosity` x 4 mm.

The tools enter at the bottom of the descending aorta, going up (a femoral approach, as the
bundled neuro case). Segments carry the neuro case's names, so targets name them.
"""
import math

import numpy as np

ARCH_TYPES = ("I", "II", "III")
CCA_DIAMETER_MM = 6.5
_BAND = {"I": (0.2, 0.9), "II": (1.1, 1.9), "III": (2.1, 2.8)}  # d / CCA diameter


def _catmull_rom(knots, spacing_radii):
    """Points (x, y, z, r) along a centripetal Catmull-Rom curve through the knots."""
    k = np.asarray(knots, dtype=float)
    ext = np.vstack([2 * k[0] - k[1], k, 2 * k[-1] - k[-2]])
    out = [k[0]]
    for i in range(1, len(ext) - 2):
        p0, p1, p2, p3 = ext[i - 1], ext[i], ext[i + 1], ext[i + 2]
        length = np.linalg.norm(p2[:3] - p1[:3])
        r = 0.5 * (p1[3] + p2[3])
        n = max(1, int(math.ceil(length / max(0.3, spacing_radii * r))))
        t = [0.0]
        for a, b in ((p0, p1), (p1, p2), (p2, p3)):
            t.append(t[-1] + math.sqrt(max(np.linalg.norm(b[:3] - a[:3]), 1e-9)))
        for j in range(1, n + 1):
            u = t[1] + (t[2] - t[1]) * j / n
            a1 = ((t[1] - u) * p0 + (u - t[0]) * p1) / (t[1] - t[0])
            a2 = ((t[2] - u) * p1 + (u - t[1]) * p2) / (t[2] - t[1])
            a3 = ((t[3] - u) * p2 + (u - t[2]) * p3) / (t[3] - t[2])
            b1 = ((t[2] - u) * a1 + (u - t[0]) * a2) / (t[2] - t[0])
            b2 = ((t[3] - u) * a2 + (u - t[1]) * a3) / (t[3] - t[1])
            out.append(((t[2] - u) * b1 + (u - t[1]) * b2) / (t[2] - t[1]))
    pts = np.array(out)
    pts[-1] = k[-1]  # exactly at the last knot (children start there)
    return pts


class _Network:
    def __init__(self):
        self.segments = []  # dicts: id, name, flow, parents, children, points

    def add(self, name, knots, parents, flow, spacing_radii=0.9):
        seg = {"id": len(self.segments) + 1, "name": name, "flow": flow, "parents": list(parents),
               "children": [], "points": _catmull_rom(knots, spacing_radii)}
        for p in parents:
            self.segments[p - 1]["children"].append(seg["id"])
        self.segments.append(seg)
        return seg["id"]

    def end(self, sid):
        return self.segments[sid - 1]["points"][-1][:3].copy()

    def hclm(self):
        lines = [f"s {len(self.segments)}", ""]
        for s in self.segments:
            lines += [f"g {s['id']}", f"l {s['name']}", f"f {s['flow']:g}",
                      "p " + " ".join(str(x) for x in [len(s["parents"])] + s["parents"]),
                      "c " + " ".join(str(x) for x in [len(s["children"])] + s["children"]),
                      f"n {len(s['points'])}"]
            lines += [f"v {p[0]!r} {p[1]!r} {p[2]!r} {p[3]!r}" for p in s["points"].tolist()]
            lines.append("")
        return "\n".join(lines)


def generate(rng, arch_type=None, bovine=None, tortuosity=None):
    """An arch: returns (hclm text, entry line, description dict). `rng` is a numpy Generator;
    arguments left None are drawn from it (type uniformly, bovine with 13 %, tortuosity 0-1)."""
    arch_type = arch_type or ARCH_TYPES[int(rng.integers(0, 3))]
    if arch_type not in ARCH_TYPES:
        raise ValueError(f"arch type {arch_type!r}: expected one of {', '.join(ARCH_TYPES)}")
    bovine = bool(rng.random() < 0.13) if bovine is None else bool(bovine)
    tortuosity = float(rng.uniform(0.0, 1.0)) if tortuosity is None else float(tortuosity)
    if not 0.0 <= tortuosity <= 1.5:
        raise ValueError(f"tortuosity {tortuosity}: expected 0..1.5")
    width = float(rng.uniform(0.85, 1.15))
    height = float(rng.uniform(0.85, 1.15))
    lo, hi = _BAND[arch_type]
    d_mm = float(rng.uniform(lo, hi)) * CCA_DIAMETER_MM

    anterior = np.array([-0.35, 1.0, 0.0]) / np.linalg.norm([-0.35, 1.0, 0.0])
    up = np.array([0.0, 0.0, 1.0])
    radius_a = 30.0 * width   # horizontal semi-axis
    radius_h = 30.0 * height  # vertical semi-axis
    # The trunk's origin d below the top of the arch, on the ascending side: low origins come
    # with a taller (elongated) arch, keeping the origin at least 40 degrees up the arch, where
    # the trunk leaves the aorta across it (the mesher needs branches that do not overlap).
    bct_deg = math.degrees(math.asin(max(-1.0, 1.0 - d_mm / radius_h)))
    if bct_deg < 40.0:
        radius_h = d_mm / (1.0 - math.sin(math.radians(40.0)))
        bct_deg = 40.0
    center = np.array([0.0, 0.0, 18.0 - radius_h])  # the top of the arch where the neuro case has it

    def arch(deg):
        a = math.radians(deg)
        return center + radius_a * math.cos(a) * anterior + radius_h * math.sin(a) * up

    def normal(deg):
        a = math.radians(deg)
        v = math.cos(a) * anterior / radius_a + math.sin(a) * up / radius_h
        return v / np.linalg.norm(v)

    spacing = float(rng.uniform(36.0, 42.0))
    lcca_deg = bct_deg + spacing
    lsa_deg = lcca_deg + spacing

    def k(p, r):
        return [p[0], p[1], p[2], r]

    def wavy(start, knots, r0):
        """Knots with a lateral sine wave (tortuosity) added to the inner ones but the first."""
        pts = [np.asarray(start, float)] + [np.asarray(p, float) for p, _ in knots]
        amp = 4.0 * tortuosity
        phase = float(rng.uniform(0.0, 2.0 * math.pi))
        out = [k(pts[0], r0)]
        for i in range(1, len(pts)):
            p = pts[i]
            if 1 < i < len(pts) - 1 and amp > 0.0:  # not the first knot: it sets the way out of the parent
                t = pts[i + 1] - pts[i - 1]
                side = np.cross(t, [0.3, 0.2, 1.0])
                side /= max(np.linalg.norm(side), 1e-9)
                p = p + amp * math.sin(phase + 2.1 * i) * side
            out.append(k(p, knots[i - 1][1]))
        return out

    net = _Network()
    asc = net.add("ascending_aorta", [k(arch(0) - 60 * up, 15.0), k(arch(0) - 30 * up, 14.5), k(arch(0), 14.0),
                                      k(arch(0.5 * bct_deg), 13.7), k(arch(bct_deg), 13.5)], [], 5000)
    if bovine:
        arch1 = net.add("aortic_arch_1", [k(arch(bct_deg), 13.5), k(arch(0.5 * (bct_deg + lsa_deg)), 13.0),
                                          k(arch(lsa_deg), 12.5)], [asc], 4000)
        arch_last = arch1
    else:
        arch1 = net.add("aortic_arch_1", [k(arch(bct_deg), 13.5), k(arch(0.5 * (bct_deg + lcca_deg)), 13.2),
                                          k(arch(lcca_deg), 13.0)], [asc], 4200)
        arch_last = net.add("aortic_arch_2", [k(arch(lcca_deg), 13.0), k(arch(0.5 * (lcca_deg + lsa_deg)), 12.7),
                                              k(arch(lsa_deg), 12.5)], [arch1], 3800)
    net.add("descending_aorta", [k(arch(lsa_deg), 12.5), k(arch(0.5 * (lsa_deg + 180)), 12.2), k(arch(180), 12.0),
                                 k(arch(180) - 30 * up, 11.8), k(arch(180) - 70 * up, 11.5)], [arch_last], 3400)

    o = arch(bct_deg)
    bct_dir = normal(bct_deg)
    bct_top = np.array([-17.0, 22.0, 50.0])
    if bovine:
        bct1 = net.add("brachiocephalic_trunk", [k(o, 6.2), k(o + 15 * bct_dir, 6.15), k(o + 30 * bct_dir, 6.1)],
                       [asc], 1200)
        lcca_origin = net.end(bct1)
        # The trunk goes straight on and the left carotid leaves it across, to the left (as the
        # aorta and its branches: a turn at the junction folds rings into each other's).
        knots = [k(lcca_origin, 6.0), k(lcca_origin + 10.0 * bct_dir, 5.95)]
        if 38.0 > knots[-1][2] + 6.0:
            knots.append(k([-13, 24, 38], 5.9))
        bct = net.add("brachiocephalic_trunk_2", knots + [k(bct_top, 5.8)], [bct1], 800)
        lcca_parent = bct1
    else:
        # It leaves straight across the aorta (as the bovine trunk) before it bends to the neck.
        knots = [k(o, 6.2), k(o + 12 * bct_dir, 6.1), k(o + 24 * bct_dir, 6.0)]
        if 38.0 > (o + 24 * bct_dir)[2] + 6.0:
            knots.append(k([-13, 24, 38], 5.9))
        bct = net.add("brachiocephalic_trunk", knots + [k(bct_top, 5.8)], [asc], 800)
        lcca_origin = arch(lcca_deg)
        lcca_parent = arch1
    rsub = net.add("right_subclavian_1", wavy(net.end(bct), [([-28, 16, 56], 4.5), ([-40, 10, 58], 4.4)], 4.6),
                   [bct], 350)
    net.add("right_subclavian_2", [k(net.end(rsub), 4.4), k([-55, 6, 56], 4.2), k([-75, 4, 48], 4.0)], [rsub], 250)
    lsa_o = arch(lsa_deg)
    lsub = net.add("left_subclavian_1", wavy(lsa_o, [(lsa_o + 16 * normal(lsa_deg), 4.8), ([22, -30, 40], 4.6),
                                                     ([40, -20, 56], 4.4)], 5.0), [arch_last], 350)
    net.add("left_subclavian_2", [k(net.end(lsub), 4.4), k([55, -16, 55], 4.2), k([75, -12, 46], 4.0)], [lsub], 250)
    net.add("right_common_carotid", wavy(net.end(bct), [([-20, 18, 75], 3.25), ([-24, 17, 100], 3.2),
                                                        ([-26, 16, 125], 3.2)], 3.3), [bct], 420)
    # A bovine left carotid leaves the trunk across it, to the left and upwards.
    across = np.array([1.0, 0.0, 0.5])
    lcca_dir = across - np.dot(across, bct_dir) * bct_dir if bovine else normal(lcca_deg)
    lcca_dir = lcca_dir / np.linalg.norm(lcca_dir)
    net.add("left_common_carotid", wavy(lcca_origin, [(lcca_origin + 14 * lcca_dir, 3.35), ([8, -2, 50], 3.3),
                                                      ([16, 6, 75], 3.25), ([22, 12, 100], 3.2),
                                                      ([26, 16, 125], 3.2)], 3.4), [lcca_parent], 420)
    for side, parent in (("right", rsub), ("left", lsub)):
        s = -1.0 if side == "right" else 1.0
        net.add(f"{side}_vertebral", [k(net.end(parent), 1.9), k([38 * s, -8, 80], 1.85), k([30 * s, -12, 110], 1.8)],
                [parent], 100)

    entry = arch(180) - 66 * up
    entry_line = f"entry {entry[0]:.4f} {entry[1]:.4f} {entry[2]:.4f}  0 0 1"
    info = {"arch_type": arch_type, "bovine": bovine, "tortuosity": tortuosity, "width": width, "height": height,
            "bct_below_top_mm": d_mm}
    return net.hclm(), entry_line, info
