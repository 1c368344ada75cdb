#!/usr/bin/python3
"""Writes VTK's wavelet source, cut into tetrahedra, as an unstructured grid (.vtu).

    /usr/bin/python3 bench/gen_wavelet_vtu.py OUT.vtu [--extent N]

The wavelet (vtkRTAnalyticSource: a smooth field of sines and a Gaussian, "RTData") on the
grid of (2N+1)^3 points over [-N, N]^3, each of its (2N)^3 voxels cut into 5 tetrahedra
by vtkDataSetTriangleFilter: N = 10 gives 40,000 tetrahedra, N = 30 1,080,000.
Needs Debian's python3-vtk9. Benchmarks and the accuracy charts generate it; nothing of it
is committed.
"""
import argparse

import vtk


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("out")
    parser.add_argument("--extent", type=int, default=10, help="half the grid's points per axis, N (default 10)")
    args = parser.parse_args()
    source = vtk.vtkRTAnalyticSource()
    n = args.extent
    source.SetWholeExtent(-n, n, -n, n, -n, n)
    tetrahedralise = vtk.vtkDataSetTriangleFilter()
    tetrahedralise.SetInputConnection(source.GetOutputPort())
    writer = vtk.vtkXMLUnstructuredGridWriter()
    writer.SetInputConnection(tetrahedralise.GetOutputPort())
    writer.SetFileName(args.out)
    writer.SetDataModeToAppended()
    writer.SetCompressorTypeToZLib()
    if not writer.Write():
        raise SystemExit(f"could not write {args.out}")
    grid = tetrahedralise.GetOutput()
    print(f"{args.out}: {grid.GetNumberOfCells()} tetrahedra, {grid.GetNumberOfPoints()} points, "
          f"RTData in {grid.GetPointData().GetArray('RTData').GetRange()}")


if __name__ == "__main__":
    main()
