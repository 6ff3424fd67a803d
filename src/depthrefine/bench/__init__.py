"""The benchmark: ground-truth metrics, protocols, the runner and the report.

- ``metrics``    error metrics against ground truth (RMSE, MAE, edge RMSE, bad pixels)
- ``simulate``   a simulated low-resolution ToF sensor (our model) from ground truth
- ``synthetic``  generated scenes with known ground truth, for tests
- ``protocols``  the protocol registry: datasets, case builders, tuning scenes, published rows
- ``runner``     runs methods x cases and scores them
- ``report``     tables, figures and the HTML report

The files are read by :mod:`depthrefine.io` (the readers each protocol names).
"""

from .protocols import (
    LEFT_OUT_WHY,
    LU_BORDER,
    PROTOCOLS,
    TUNING_SCENES,
    Protocol,
    bicubic_downsample,
    crop_to_multiple,
    get_protocol,
    left_out_reason,
    load_cases,
    lu_case,
    park_case,
    register_protocol,
    tof_case,
    tof_seed,
    tuned_on_scenes,
)
from .runner import (
    DEFAULT_SCALES,
    METRICS,
    ROW_FIELDS,
    BenchCase,
    BenchResult,
    BenchRow,
    mean_and_count,
    mean_or_nan,
    parse_scales,
    run_benchmark,
)

__all__ = [
    "Protocol", "PROTOCOLS", "register_protocol", "get_protocol", "load_cases", "TUNING_SCENES", "LEFT_OUT_WHY",
    "left_out_reason", "tuned_on_scenes", "LU_BORDER", "bicubic_downsample", "crop_to_multiple", "park_case",
    "lu_case", "tof_case", "tof_seed", "DEFAULT_SCALES", "METRICS", "ROW_FIELDS", "BenchCase", "BenchResult",
    "BenchRow", "mean_and_count", "mean_or_nan", "parse_scales", "run_benchmark",
]
