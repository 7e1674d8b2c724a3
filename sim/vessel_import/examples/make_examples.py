#!/usr/bin/env python3
"""Writes the example centreline files of sim/vessel_import/examples/ (one per format).

They are made up here, not taken from any data set: the shapes and sizes follow the anatomy
cited in sim/vessel/src/case_generator.cpp, and each carries what real exports carry (VMTK's
overlapping centrelines with measurement noise and a few outlier radii, branch-extracted tracts,
Slicer curves joined at shared points, an SWC tree with branching samples). Run it from anywhere;
the output is deterministic (fixed seeds).
"""
import json
import math
import os
import random

HERE = os.path.dirname(os.path.abspath(__file__))


def unit(v):
    n = math.sqrt(sum(c * c for c in v))
    return [c / n for c in v]


def along(start, direction, length, spacing, bend=(0.0, 0.0, 0.0)):
    """Points from start along direction, bending quadratically by `bend` at the far end."""
    d = unit(direction)
    n = max(2, int(round(length / spacing)))
    return [[start[k] + d[k] * length * i / n + bend[k] * (i / n) ** 2 for k in range(3)] for i in range(n + 1)]


def noisy(rng, value, rel):
    return value * (1.0 + rng.uniform(-rel, rel))


def vmtk_carotid(rng):
    """Two VMTK centrelines of a carotid bifurcation, both from the CCA inlet: to the ICA outlet
    (a 60 % stenosis 12 mm past the bifurcation) and to the ECA outlet. They share the CCA point for
    point, the second one with 0.02 mm of jitter, as vmtkcenterlines' backtracked paths do."""
    spacing = 0.4
    cca = along([0.0, 0.0, 0.0], [0.0, 0.05, 1.0], 60.0, spacing)
    fork = cca[-1]
    ica = along(fork, [math.sin(math.radians(15)), 0.0, math.cos(math.radians(15))], 45.0, spacing, bend=(-4.0, 2.0, 0.0))
    eca = along(fork, [-math.sin(math.radians(25)), 0.1, math.cos(math.radians(25))], 35.0, spacing, bend=(-2.0, -3.0, 0.0))

    def cca_radius(i):
        return 3.2 - 0.2 * i / len(cca)

    lines = []
    radii = []
    for which, branch in (("ica", ica), ("eca", eca)):
        pts, rs = [], []
        for i, p in enumerate(cca):
            jitter = 0.0 if which == "ica" else 0.02
            pts.append([c + rng.uniform(-jitter, jitter) for c in p])
            # The inscribed sphere swells where the branches part (VMTK's known overestimate).
            swell = 0.6 if i >= len(cca) - 3 else 0.0
            rs.append(noisy(rng, cca_radius(i) + swell, 0.02))
        for i, p in enumerate(branch[1:], start=1):
            s = i * spacing
            if which == "ica":
                r = 2.4 * (1.0 - 0.6 * math.exp(-((s - 12.0) / 3.0) ** 2))
            else:
                r = 2.0 - 0.3 * s / 35.0
            pts.append(p)
            rs.append(noisy(rng, r, 0.02))
        # The last point's sphere collapses at the outlet cap.
        rs[-1] *= 0.3
        lines.append(pts)
        radii.append(rs)
    # One bad measurement in the middle of the ECA.
    radii[1][len(cca) + 40] *= 1.8
    return lines, radii


def write_vtp(path, lines, radii, centerline_ids):
    points = [p for line in lines for p in line]
    radius = [r for rs in radii for r in rs]
    connectivity, offsets, at = [], [], 0
    for line in lines:
        connectivity += list(range(at, at + len(line)))
        at += len(line)
        offsets.append(at)
    def array(kind, name, values, components=1):
        return (f'        <DataArray type="{kind}" Name="{name}" NumberOfComponents="{components}" format="ascii">\n'
                + "".join(f"          {v}\n" for v in values) + "        </DataArray>\n")

    with open(path, "w") as f:
        f.write('<?xml version="1.0"?>\n<VTKFile type="PolyData" version="0.1" byte_order="LittleEndian">\n  <PolyData>\n')
        f.write(f'    <Piece NumberOfPoints="{len(points)}" NumberOfVerts="0" NumberOfLines="{len(lines)}" NumberOfStrips="0" NumberOfPolys="0">\n')
        f.write('      <PointData Scalars="MaximumInscribedSphereRadius">\n')
        f.write(array("Float64", "MaximumInscribedSphereRadius", (f"{r:.5f}" for r in radius)) + "      </PointData>\n")
        f.write("      <CellData>\n" + array("Int32", "CenterlineIds", centerline_ids) + "      </CellData>\n")
        f.write("      <Points>\n" + array("Float32", "Points", (f"{p[0]:.4f} {p[1]:.4f} {p[2]:.4f}" for p in points), 3))
        f.write("      </Points>\n      <Lines>\n" + array("Int64", "connectivity", connectivity) + array("Int64", "offsets", offsets))
        f.write("      </Lines>\n    </Piece>\n  </PolyData>\n</VTKFile>\n")


def vertebrobasilar_tracts(rng):
    """vmtkbranchextractor output for the vertebrobasilar system, inlet the left vertebral (V4):
    three centrelines (to the right vertebral, the left and the right posterior cerebral arteries),
    each cut into tracts at its branch points; tracts shared by several centrelines repeat. The
    vertebrals meet at 18 degrees (the narrow confluence of issue 17)."""
    spacing = 0.5
    half = math.radians(9.0)
    junction = [0.0, -6.0, 200.0]
    lv = along([junction[0] + 30.0 * math.sin(half), junction[1] - 4.0, junction[2] - 30.0 * math.cos(half)],
               [-math.sin(half), 4.0 / 30.0, math.cos(half)], 30.0, spacing)
    lv[-1] = list(junction)
    rv_up = along([junction[0] - 30.0 * math.sin(half), junction[1] - 4.0, junction[2] - 30.0 * math.cos(half)],
                  [math.sin(half), 4.0 / 30.0, math.cos(half)], 30.0, spacing)
    rv_up[-1] = list(junction)
    rv = list(reversed(rv_up))  # from the junction down the right vertebral
    basilar = along(junction, [0.0, 0.2, 1.0], 30.0, spacing)
    tip = basilar[-1]
    lp = along(tip, [1.0, -0.3, 0.25], 25.0, spacing, bend=(0.0, -6.0, 1.0))
    rp = along(tip, [-1.0, -0.3, 0.25], 25.0, spacing, bend=(0.0, -6.0, 1.0))

    def radii(pts, r0, r1):
        return [noisy(rng, r0 + (r1 - r0) * i / (len(pts) - 1), 0.015) for i in range(len(pts))]

    tracts = []  # (centerline id, tract id, points, radii)
    r_lv, r_rv, r_ba = radii(lv, 1.65, 1.6), radii(rv, 1.6, 1.6), radii(basilar, 1.65, 1.55)
    r_lp, r_rp = radii(lp, 1.05, 0.9), radii(rp, 1.05, 0.9)
    tracts.append((0, 0, lv, r_lv))
    tracts.append((0, 1, rv, r_rv))
    for cid, last, r_last in ((1, lp, r_lp), (2, rp, r_rp)):
        tracts.append((cid, 0, lv, r_lv))
        tracts.append((cid, 1, basilar, r_ba))
        tracts.append((cid, 2, last, r_last))
    return tracts


def write_legacy_vtk(path, tracts):
    points, radius, cells = [], [], []
    for _, _, pts, rs in tracts:
        start = len(points)
        points += pts
        radius += rs
        cells.append(list(range(start, start + len(pts))))
    with open(path, "w") as f:
        f.write("# vtk DataFile Version 4.2\nvmtkbranchextractor-style tracts (cathbox example)\nASCII\nDATASET POLYDATA\n")
        f.write(f"POINTS {len(points)} float\n")
        f.write("".join(f"{p[0]:.4f} {p[1]:.4f} {p[2]:.4f}\n" for p in points))
        f.write(f"LINES {len(cells)} {sum(len(c) + 1 for c in cells)}\n")
        f.write("".join(f"{len(c)} " + " ".join(str(i) for i in c) + "\n" for c in cells))
        f.write(f"CELL_DATA {len(cells)}\nFIELD FieldData 2\n")
        f.write(f"CenterlineIds 1 {len(cells)} int\n" + " ".join(str(t[0]) for t in tracts) + "\n")
        f.write(f"TractIds 1 {len(cells)} int\n" + " ".join(str(t[1]) for t in tracts) + "\n")
        f.write(f"POINT_DATA {len(points)}\nSCALARS MaximumInscribedSphereRadius double 1\nLOOKUP_TABLE default\n")
        f.write("".join(f"{r:.5f}\n" for r in radius))


def slicer_mca(rng):
    """Slicer curves of a left ICA terminus (LPS): the ICA's last centimetre, M1, the two M2
    trunks and A1, joined at shared control points (as Extract Centerline writes them), with a
    per-point Radius measurement; plus a point list, which the importer skips."""
    t = [14.0, -14.0, 226.0]
    ica = along([14.0, -10.0, 214.0], [t[0] - 14.0, t[1] + 10.0, t[2] - 214.0], 12.6, 1.0)
    ica[-1] = list(t)
    m1_end = [31.0, -16.0, 239.0]
    m1 = along(t, [m1_end[k] - t[k] for k in range(3)], math.dist(t, m1_end), 1.0)
    m1[-1] = list(m1_end)
    m2s = along(m1_end, [0.45, -0.2, 1.0], 24.0, 1.0, bend=(3.0, -2.0, 0.0))
    m2i = along(m1_end, [0.6, 0.3, -0.75], 20.0, 1.0, bend=(1.0, 2.0, 0.0))
    a1 = along(t, [-0.6, -0.8, 0.25], 13.0, 1.0)

    def curve(name, pts, r0, r1, system="LPS"):
        sign = -1.0 if system == "RAS" else 1.0
        control = [{
            "id": str(i + 1), "label": f"{name}-{i + 1}", "description": "", "associatedNodeID": "",
            "position": [round(sign * p[0], 4), round(sign * p[1], 4), round(p[2], 4)],
            "orientation": [-1.0, -0.0, -0.0, -0.0, -1.0, -0.0, 0.0, 0.0, 1.0],
            "selected": True, "locked": False, "visibility": True, "positionStatus": "defined"}
            for i, p in enumerate(pts)]
        radius = [round(noisy(rng, r0 + (r1 - r0) * i / (len(pts) - 1), 0.02), 4) for i in range(len(pts))]
        return {
            "type": "Curve", "name": name, "coordinateSystem": system, "coordinateUnits": "mm",
            "locked": False, "fixedNumberOfControlPoints": False, "labelFormat": "%N-%d",
            "lastUsedControlPointNumber": len(pts), "controlPoints": control,
            "measurements": [
                {"name": "length", "enabled": False, "units": "mm", "printFormat": "%-#4.4g%s"},
                {"name": "Radius", "enabled": True, "units": "mm", "controlPointValues": radius}],
            "display": {"visibility": True, "opacity": 1.0, "color": [0.4, 1.0, 0.0]}}

    markups = [
        curve("Centerline curve (0)", ica, 2.0, 1.9),
        curve("Centerline curve (1)", m1, 1.45, 1.35),
        curve("Centerline curve (2)", m2s, 1.05, 0.95),
        curve("Centerline curve (3)", m2i, 1.05, 0.95),
        curve("Centerline curve (4)", a1, 1.2, 1.1, system="RAS"),
        {"type": "Fiducial", "name": "Endpoints", "coordinateSystem": "LPS", "coordinateUnits": "mm",
         "controlPoints": [{"id": "1", "label": "E-1", "position": [14.0, -10.0, 214.0], "positionStatus": "defined"}],
         "measurements": []},
    ]
    return {"@schema": "https://raw.githubusercontent.com/slicer/slicer/master/Modules/Loadable/Markups/Resources/Schema/markups-schema-v1.0.3.json#",
            "markups": markups}


def swc_tree(rng, branches, spacing=0.6):
    """A cortical artery tree in mm: a 1.2 mm root dividing (Murray's law, 20-60 degrees) until
    `branches` branches exist; one SWC sample every `spacing` mm."""
    samples = [(1, 0, 0.0, 0.0, 0.0, 1.2, -1)]
    queue = [(1, [0.0, 0.0, 1.0], 1.2, 12.0)]
    count = 1
    while queue:
        parent, direction, radius, length = queue.pop(0)
        tip = samples[parent - 1]
        pos = [tip[2], tip[3], tip[4]]
        n = max(2, int(length / spacing))
        last = parent
        for i in range(1, n + 1):
            pos = [pos[k] + direction[k] * length / n for k in range(3)]
            jitter = [rng.uniform(-0.05, 0.05) for _ in range(3)]
            sid = len(samples) + 1
            samples.append((sid, 0, pos[0] + jitter[0], pos[1] + jitter[1], pos[2] + jitter[2], noisy(rng, radius, 0.03), last))
            last = sid
        if count + 2 > branches:
            continue
        # The two children leave on opposite sides of one plane through the parent, so they are
        # 40-120 degrees apart.
        azimuth = rng.uniform(0.0, 2.0 * math.pi)
        side = unit([math.cos(azimuth), math.sin(azimuth), 0.0])
        for c in range(2):
            angle = math.radians(rng.uniform(20.0, 60.0))
            d = unit([direction[k] * math.cos(angle) + side[k] * math.sin(angle) * (1 if c == 0 else -1) for k in range(3)])
            child_r = max(0.15, radius * 0.79 * rng.uniform(0.95, 1.05))
            queue.append((last, d, child_r, child_r * rng.uniform(10.0, 16.0)))
            count += 1
    return samples


def write_swc(path, samples, comment):
    with open(path, "w") as f:
        f.write(f"# {comment}\n# id type x y z radius parent (millimetres)\n")
        for s in samples:
            f.write(f"{s[0]} {s[1]} {s[2]:.4f} {s[3]:.4f} {s[4]:.4f} {s[5]:.4f} {s[6]}\n")


def main():
    rng = random.Random(17)
    lines, radii = vmtk_carotid(rng)
    write_vtp(os.path.join(HERE, "carotid_bifurcation_centerlines.vtp"), lines, radii, [0, 1])
    write_legacy_vtk(os.path.join(HERE, "vertebrobasilar_tracts.vtk"), vertebrobasilar_tracts(rng))
    with open(os.path.join(HERE, "mca_bifurcation.mrk.json"), "w") as f:
        json.dump(slicer_mca(rng), f, indent=2)
        f.write("\n")
    write_swc(os.path.join(HERE, "cortical_tree.swc"), swc_tree(rng, 31),
              "cathbox example: a cortical artery tree of 31 branches (made up, see make_examples.py)")


if __name__ == "__main__":
    main()
