# SPDX-License-Identifier: BSD-3-Clause
"""The picture of Documentation/ParaView.md: ParaView's render view on a plugin pipeline.

fandisk (CGAL) through Patch Boundary Merge at 460 triangles, coloured by PatchId, with its
Profile Curves output in black: both output ports of a plugin filter shown in ParaView's own
render view. Needs an X display (e.g. xvfb-run -a).

  pvpython paraview_documentation_picture.py --plugin <SurfaceLOD.so> --mesh-dir <dir> --image <png>

Not a test of the suite: under Xvfb, ParaView 5.11's OpenGL probe aborts in about half the runs on
the project's loaded machine ("bad X server connection"), so a baseline comparison would be flaky.
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


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--plugin", required=True)
    parser.add_argument("--mesh-dir", required=True)
    parser.add_argument("--image", required=True)
    args = parser.parse_args()
    if not os.path.isfile(args.plugin):
        print("FAIL  the ParaView plugin was not built: %s is missing (run scripts/paraview-plugin.sh)" % args.plugin)
        return 1
    os.makedirs(os.path.dirname(os.path.abspath(args.image)), exist_ok=True)
    render(args.plugin, args.mesh_dir, args.image)
    print("wrote " + args.image)
    return 0


if __name__ == "__main__":
    sys.exit(main())
