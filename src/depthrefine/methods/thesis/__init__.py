"""The thesis method (Chen 2014, chapter 4), faithful to the project's design note ``docs/algorithm.md``.

- ``params``    :class:`RefineParams`, the thesis's parameters and their defaults
- ``segment``   color clustering: 7x7 median, L*a*b* with unified L*, k-means (4.3)
- ``refine``    per patch: sparse depth, histogram correction, per-cluster interpolation (4.4-4.5)
"""

from .params import RefineParams
from .refine import Refinement, ScaleWarning, refine_thesis, refine_with_intermediates

__all__ = ["RefineParams", "Refinement", "ScaleWarning", "refine_thesis", "refine_with_intermediates"]
