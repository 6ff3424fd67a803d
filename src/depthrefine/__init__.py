"""depthrefine: refine a low-resolution ToF depth map with a high-resolution color image.

The main entry point is :func:`refine`::

    import depthrefine
    depth_hr = depthrefine.refine(depth_lr, rgb_hr)                 # the thesis method
    depth_hr = depthrefine.refine(depth_lr, rgb_hr, method="bilinear")

Subpackages and modules, one per pipeline stage:

- ``io``          reading and writing depth, color, parameter and camera files
- ``calibrate``   checkerboard calibration: camera models and the depth + color rig
- ``align``       undistortion, the thesis's shift alignment, calibrated reprojection
- ``pointcloud``  metric depth, back-projection and projection, colored point clouds
- ``scale``       the thesis's scale step (integer depth factor)
- ``segment``     color clustering: median, L*a*b*, unified L*, k-means
- ``refinement``  the thesis refinement (chapter 4), with its intermediates
- ``baselines``   nearest, bilinear, bicubic
- ``methods``     the registry of methods that :func:`refine` looks up
- ``viz``         pictures: colorized depth, overlays, comparison figures
- ``peers``       OpenCV-contrib guided filters as methods: jbf, guided, fgs, wmf
- ``evaluate``    error metrics against ground truth (RMSE, MAE, edge RMSE, bad pixels)
- ``simulate``    a simulated low-resolution ToF sensor (our model) from ground truth
- ``bench``       the benchmark: protocols, cases, runs and scores
- ``report``      the benchmark report: tables, figures, HTML
- ``synthetic``   generated test scenes with known ground truth
- ``cli``         the ``depthrefine`` command
"""

from .methods import METHODS, Method, get_method, refine, register_method
from .params import RefineParams
from .refinement import Refinement, ScaleWarning, refine_with_intermediates

__version__ = "0.1.0"

__all__ = [
    "refine",
    "refine_with_intermediates",
    "RefineParams",
    "Refinement",
    "ScaleWarning",
    "METHODS",
    "Method",
    "get_method",
    "register_method",
    "__version__",
]
