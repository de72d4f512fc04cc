# SPDX-License-Identifier: BSD-3-Clause
"""Writing the documentation's figures: one off-screen window per process, the PNG write.

The figure scripts of Examples/*/ import this (they put Examples/ on sys.path). It keeps a single
vtkRenderWindow for the whole script: one X connection, held from the first picture to the last.
A window per picture opens and closes a connection each time, and when the last client of an
Xvfb disconnects the server resets itself; a connection attempted during that reset fails and
vtkXOpenGLRenderWindow aborts the process ("bad X server connection"). The test command runs
Xvfb with -noreset for the same reason (scripts/test.sh).
"""
from vtkmodules.vtkIOImage import vtkPNGWriter
from vtkmodules.vtkRenderingCore import vtkRenderWindow, vtkWindowToImageFilter
import vtkmodules.vtkRenderingOpenGL2  # noqa: F401 (rendering backend)

_WINDOW = None


def figure_window(renderer, size):
    """The process's one off-screen render window, showing `renderer` alone at `size`.

    Set the renderer's camera after this call: the window's size is the aspect ResetCamera uses."""
    global _WINDOW
    if _WINDOW is None:
        _WINDOW = vtkRenderWindow()
        _WINDOW.SetOffScreenRendering(1)
    renderers = _WINDOW.GetRenderers()
    for index in reversed(range(renderers.GetNumberOfItems())):
        _WINDOW.RemoveRenderer(renderers.GetItemAsObject(index))
    _WINDOW.SetSize(*size)
    _WINDOW.AddRenderer(renderer)
    return _WINDOW


def save_png(window, path):
    """Renders `window` and writes it into the PNG file `path`."""
    window.Render()
    grab = vtkWindowToImageFilter()
    grab.SetInput(window)
    grab.Update()
    writer = vtkPNGWriter()
    writer.SetFileName(path)
    writer.SetInputConnection(grab.GetOutputPort())
    writer.Write()
