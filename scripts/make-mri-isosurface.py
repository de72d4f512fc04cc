#!/usr/bin/python3
# SPDX-License-Identifier: BSD-3-Clause
"""Marching-cubes isosurface of a NIfTI volume, as a real-input benchmark mesh for `surfacelod bench`.

The MRI templates come from Debian's mricron-data package (no root needed):

    apt-get download mricron-data
    dpkg -x mricron-data_*_all.deb mricron-root
    /usr/bin/python3 scripts/make-mri-isosurface.py \
        mricron-root/usr/share/mricron/templates/ch2better.nii.gz mri.vtp --iso 60
    build/bin/surfacelod bench --set real --input mri.vtp

With --labels LO-HI the volume is a label atlas (e.g. aal.nii.gz): the voxels with a label in
LO..HI become a 0/1 mask contoured at 0.5 (a segmentation surface: staircase, planar regions).

Pipeline: vtkNIFTIImageReader -> (vtkImageThreshold) -> vtkFlyingEdges3D -> the largest connected
region (vtkPolyDataConnectivityFilter; --all-regions keeps every piece) -> vtkCleanPolyData
(coincident points merged exactly; triangles made degenerate by the merge are dropped, not
turned into lines) -> binary VTP. Needs Debian's VTK Python (/usr/bin/python3, python3-vtk9).
"""
import argparse
import sys

import vtk


def label_mask(image_port, first, last):
    """The 0/1 mask of labels first..last (the filter: a port alone does not keep it alive)."""
    threshold = vtk.vtkImageThreshold()
    threshold.SetInputConnection(image_port)
    threshold.ThresholdBetween(first, last)
    threshold.SetInValue(1)
    threshold.SetOutValue(0)
    threshold.ReplaceInOn()
    threshold.ReplaceOutOn()
    threshold.SetOutputScalarTypeToUnsignedChar()
    return threshold


def isosurface(volume_port, iso, largest_only):
    contour = vtk.vtkFlyingEdges3D()
    contour.SetInputConnection(volume_port)
    contour.SetValue(0, iso)
    contour.ComputeNormalsOff()
    contour.ComputeGradientsOff()
    contour.ComputeScalarsOff()
    port = contour.GetOutputPort()
    if largest_only:
        largest = vtk.vtkPolyDataConnectivityFilter()
        largest.SetInputConnection(port)
        largest.SetExtractionModeToLargestRegion()
        port = largest.GetOutputPort()
    clean = vtk.vtkCleanPolyData()
    clean.SetInputConnection(port)
    clean.SetTolerance(0.0)
    clean.ConvertPolysToLinesOff()
    clean.ConvertLinesToPointsOff()
    clean.ConvertStripsToPolysOff()
    clean.Update()
    return clean.GetOutput()


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("volume", help="NIfTI volume (.nii or .nii.gz)")
    parser.add_argument("output", help="output surface (.vtp)")
    parser.add_argument("--iso", type=float, default=60.0, help="contour value (default 60; ignored with --labels)")
    parser.add_argument("--labels", help="LO-HI: contour the mask of the labels LO..HI at 0.5")
    parser.add_argument("--all-regions", action="store_true", help="keep every connected piece")
    args = parser.parse_args()

    reader = vtk.vtkNIFTIImageReader()
    reader.SetFileName(args.volume)
    reader.Update()
    if reader.GetErrorCode() != 0 or reader.GetOutput().GetNumberOfPoints() == 0:
        sys.exit("%s: cannot read the volume" % args.volume)
    port, iso = reader.GetOutputPort(), args.iso
    if args.labels:
        try:
            first, last = (int(v) for v in args.labels.split("-"))
        except ValueError:
            sys.exit("--labels: expected LO-HI, e.g. 1-4")
        mask = label_mask(port, first, last)
        port, iso = mask.GetOutputPort(), 0.5

    surface = isosurface(port, iso, not args.all_regions)
    if surface.GetNumberOfPolys() == 0:
        sys.exit("%s: no surface at %g" % (args.volume, iso))
    writer = vtk.vtkXMLPolyDataWriter()
    writer.SetInputData(surface)
    writer.SetFileName(args.output)
    writer.SetDataModeToBinary()
    if not writer.Write():
        sys.exit("%s: cannot write" % args.output)
    print("%s: %d triangles, %d points" % (args.output, surface.GetNumberOfPolys(), surface.GetNumberOfPoints()))


if __name__ == "__main__":
    main()
