# SPDX-License-Identifier: BSD-3-Clause
"""The picture of Documentation/ParaView.md: ParaView's render view on a plugin pipeline.

fandisk (CGAL) through Patch Boundary Merge at 460 triangles, coloured by PatchId, with its
Profile Curves output in black: both output ports of a plugin filter shown in ParaView's own
render view. Needs an X display (e.g. xvfb-run -a -s "-screen 0 1280x1024x24 -noreset").

  pvpython paraview_documentation_picture.py --plugin <SurfaceLOD.so> --mesh-dir <dir> --image <png>
      [--baseline <png>]

With --baseline it is the suite's render-view image test (paraview.render-view-image): the picture
must match the baseline within vtkImageDifference's thresholded error of 0.05 (the threshold of the
C++ image tests). Run Xvfb with -noreset: ParaView's OpenGL probe closes its X connection, Xvfb
resets when its last client leaves, and the render view's connection made during that reset fails
("bad X server connection", about one run in six without -noreset).
"""
import argparse
import os
import sys

from paraview import simple


def render(plugin, meshes, output):
    simple.LoadPlugin(plugin, remote=False)
    mesh = simple.SurfaceLODOFFReader(FileName=os.path.join(meshes, "fandisk.off"))
    merge = simple.PatchBoundaryMerge(Input=mesh, TargetNumberOfTriangles=460)
    view = simple.CreateView("RenderView")
    view.ViewSize = [800, 600]
    view.OrientationAxesVisibility = 0
    view.Background = [1, 1, 1]
    view.UseColorPaletteForBackground = 0
    surface = simple.Show(simple.OutputPort(merge, 0), view)
    simple.ColorBy(surface, ("CELLS", "PatchId"))
    surface.LookupTable = simple.GetColorTransferFunction("PatchId")
    surface.LookupTable.ApplyPreset("Rainbow Uniform", True)
    curves = simple.Show(simple.OutputPort(merge, 1), view)
    curves.ColorArrayName = ["POINTS", ""]
    curves.AmbientColor = curves.DiffuseColor = [0, 0, 0]
    curves.LineWidth = 2
    view.CameraPosition = [2.5, -3.0, 2.5]
    view.CameraFocalPoint = [0, 0, 0]
    view.CameraViewUp = [0, 0, 1]
    view.ResetCamera()
    simple.SaveScreenshot(output, view, ImageResolution=[800, 600])
    # Release the view's OpenGL context while the X connection is still open (otherwise the
    # interpreter's teardown ends with an X error and a failing exit code).
    simple.Delete(view)


def image_difference(image, baseline):
    """vtkImageDifference's thresholded error between two PNG files (0 for identical images)."""
    from vtkmodules.vtkIOImage import vtkPNGReader
    from vtkmodules.vtkImagingCore import vtkImageDifference
    readers = []
    for path in (image, baseline):
        reader = vtkPNGReader()
        reader.SetFileName(path)
        reader.Update()
        readers.append(reader)
    difference = vtkImageDifference()
    difference.SetInputConnection(readers[0].GetOutputPort())
    difference.SetImageConnection(readers[1].GetOutputPort())
    difference.Update()
    return difference.GetThresholdedError()


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--plugin", required=True)
    parser.add_argument("--mesh-dir", required=True)
    parser.add_argument("--image", required=True)
    parser.add_argument("--baseline", help="compare the picture with this PNG (a test)")
    parser.add_argument("--threshold", type=float, default=0.05)
    args = parser.parse_args()
    if not os.path.isfile(args.plugin):
        print("FAIL  the ParaView plugin was not built: %s is missing (run scripts/paraview-plugin.sh)" % args.plugin)
        return 1
    os.makedirs(os.path.dirname(os.path.abspath(args.image)), exist_ok=True)
    render(args.plugin, args.mesh_dir, args.image)
    print("wrote " + args.image)
    if args.baseline:
        if not os.path.isfile(args.baseline):
            print("FAIL  baseline %s is missing" % args.baseline)
            return 1
        error = image_difference(args.image, args.baseline)
        print("image difference %.4f (threshold %.4f) against %s" % (error, args.threshold, args.baseline))
        if not error <= args.threshold:
            print("FAIL  the render view differs from its baseline")
            return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
