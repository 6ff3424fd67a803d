"""The benchmark: ground-truth metrics, protocols, the runner and the report.

- ``metrics``    error metrics against ground truth (RMSE, MAE, edge RMSE, bad pixels)
- ``simulate``   a simulated low-resolution ToF sensor (our model) from ground truth
- ``synthetic``  generated scenes with known ground truth, for tests
- ``runner``     protocols, cases, tuning scenes; runs methods x cases and scores them
- ``report``     tables, figures and the HTML report

Files are read by :mod:`depthrefine.io` (``load_cases``); this package is pure.
"""

from .runner import (
    PROTOCOLS,
    DEFAULT_SCALES,
    TUNING_SCENES,
    LEFT_OUT_WHY,
    left_out_reason,
    tuned_on_scenes,
    LU_BORDER,
    BenchCase,
    BenchRow,
    BenchResult,
    ROW_FIELDS,
    METRICS,
    bicubic_downsample,
    crop_to_multiple,
    park_case,
    lu_case,
    tof_case,
    tof_seed,
    run_benchmark,
    parse_scales,
    mean_or_nan,
    mean_and_count,
)

__all__ = [
    "PROTOCOLS",
    "DEFAULT_SCALES",
    "TUNING_SCENES",
    "LEFT_OUT_WHY",
    "left_out_reason",
    "tuned_on_scenes",
    "LU_BORDER",
    "BenchCase",
    "BenchRow",
    "BenchResult",
    "ROW_FIELDS",
    "METRICS",
    "bicubic_downsample",
    "crop_to_multiple",
    "park_case",
    "lu_case",
    "tof_case",
    "tof_seed",
    "run_benchmark",
    "parse_scales",
    "mean_or_nan",
    "mean_and_count",
]
