"""Error metrics against ground truth: the public name of :mod:`depthrefine.bench.metrics`.

``depthrefine.evaluate.rmse(depth, gt)`` and the other metrics are the ones
``depthrefine bench`` reports.
"""

from .bench.metrics import *  # noqa: F401,F403
from .bench.metrics import __all__  # noqa: F401
