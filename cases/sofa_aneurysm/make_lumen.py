#!/usr/bin/python3
"""Writes aneurysm3D_1.ply, the bundled lumen, from SOFA's share/mesh/aneurysm3D_1.off.

SOFA's mesh (14,186 triangles, 7,095 vertices, closed, 550 kB of text) is coarsened to 4,000
triangles by VTK's quadric decimation (vtkQuadricDecimation, volume preservation on) and written as
binary PLY (76 kB) with a comment saying where it comes from. The volume changes by 0.11 % and the
area by 0.01 %; the surface stays closed and manifold (checked below). Needs Debian's
python3-vtk9 (hence /usr/bin/python3). Deterministic.

    /usr/bin/python3 make_lumen.py PATH/TO/aneurysm3D_1.off

The source: repository sofa-framework/sofa, commit 2a278d891fe68ae5a835259bd62a2844df1670a1,
LGPL-2.1-or-later (NOTICE.md beside this file).
"""
import os
import sys

import vtk

HERE = os.path.dirname(os.path.abspath(__file__))
TRIANGLES = 4000


def read_off(path):
    lines = [line for line in open(path, encoding="ascii").read().split("\n") if line.strip()]
    if lines[0].strip() != "OFF":
        sys.exit(f"{path}: not an OFF file")
    nv, nf, _ = map(int, lines[1].split())
    points = vtk.vtkPoints()
    for line in lines[2:2 + nv]:
        points.InsertNextPoint(*map(float, line.split()[:3]))
    polys = vtk.vtkCellArray()
    for line in lines[2 + nv:2 + nv + nf]:
        ids = list(map(int, line.split()))
        polys.InsertNextCell(ids[0], ids[1:1 + ids[0]])
    mesh = vtk.vtkPolyData()
    mesh.SetPoints(points)
    mesh.SetPolys(polys)
    return mesh


def open_edges(mesh):
    edges = vtk.vtkFeatureEdges()
    edges.SetInputData(mesh)
    edges.BoundaryEdgesOn()
    edges.NonManifoldEdgesOn()
    edges.FeatureEdgesOff()
    edges.ManifoldEdgesOff()
    edges.Update()
    return edges.GetOutput().GetNumberOfLines()


def measure(mesh):
    m = vtk.vtkMassProperties()
    m.SetInputData(mesh)
    m.Update()
    return m.GetVolume(), m.GetSurfaceArea()


def main():
    source = read_off(sys.argv[1])
    decimate = vtk.vtkQuadricDecimation()
    decimate.SetInputData(source)
    decimate.SetTargetReduction(1.0 - TRIANGLES / source.GetNumberOfPolys())
    decimate.VolumePreservationOn()
    decimate.Update()
    lumen = decimate.GetOutput()
    if open_edges(lumen) != 0:
        sys.exit("the decimated lumen is not closed and manifold")
    (v0, a0), (v1, a1) = measure(source), measure(lumen)
    print(f"{source.GetNumberOfPolys()} -> {lumen.GetNumberOfPolys()} triangles; "
          f"volume {v0:.1f} -> {v1:.1f} mm3, area {a0:.1f} -> {a1:.1f} mm2")
    writer = vtk.vtkPLYWriter()
    writer.SetFileName(os.path.join(HERE, "aneurysm3D_1.ply"))
    writer.SetInputData(lumen)
    writer.SetFileTypeToBinary()
    writer.AddComment("SOFA share/mesh/aneurysm3D_1.off (c) 2006 INRIA, USTL, UJF, CNRS, MGH; LGPL-2.1-or-later")
    writer.AddComment("decimated to 4000 triangles for Cathbox by cases/sofa_aneurysm/make_lumen.py, 2026-11-30")
    writer.Write()


if __name__ == "__main__":
    main()
