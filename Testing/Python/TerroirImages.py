"""The image comparison of the Python image tests (TestViewer.py, Examples/Testing/CheckExample.py):
the rule of Testing/Rendering/TerroirImageCompare.h, which the C++ rendering tests use. A pixel
matches when a pixel of the other image within one pixel of it has every channel within LEVELS
(8 of 255), looked at both ways; two images differ when more than DIFFERING_PIXELS (16) pixels
match nothing. VTK 9.1's legacy metric at 0.15, used before, passed whole images 30 % darker
or tinted."""
import numpy as np
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkIOImage import vtkPNGReader

LEVELS = 8              # per channel, of 255 (TerroirImageCompare.h)
DIFFERING_PIXELS = 16   # pixels allowed to match nothing within one pixel


def read_rgb(path):
    """The RGB pixels of a PNG, rows from the top, as an (h, w, 3) int32 array."""
    reader = vtkPNGReader()
    reader.SetFileName(path)
    reader.Update()
    image = reader.GetOutput()
    w, h, _ = image.GetDimensions()
    a = vtk_to_numpy(image.GetPointData().GetScalars()).reshape(h, w, -1)
    if a.shape[2] < 3:
        a = np.repeat(a[..., :1], 3, axis=2)
    return a[::-1, :, :3].astype(np.int32)


def compare_images(test, baseline):
    """The C++ tests' rule (Testing/Rendering/TerroirImageCompare.h): a pixel matches when a
    pixel of the other image within one pixel of it has every channel within LEVELS, looked at
    both ways. Returns (pixels that do not match, the largest difference to the best
    neighbour); a size mismatch counts every pixel."""
    if test.shape != baseline.shape:
        return test.shape[0] * test.shape[1], 255

    def nearest(one, other):
        h, w = one.shape[:2]
        pad = np.pad(other, ((1, 1), (1, 1), (0, 0)), constant_values=-1000)
        best = np.full((h, w), 1 << 20, dtype=np.int64)
        for dy in (0, 1, 2):
            for dx in (0, 1, 2):
                d = np.abs(one - pad[dy:dy + h, dx:dx + w]).max(axis=2)
                best = np.minimum(best, d)
        return best

    d = np.maximum(nearest(test, baseline), nearest(baseline, test))
    return int((d > LEVELS).sum()), int(d.max())
