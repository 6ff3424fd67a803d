"""The benchmark: ground-truth metrics, protocols, the runner and the report.

- ``metrics``    error metrics against ground truth (RMSE, MAE, edge RMSE, bad pixels)
- ``simulate``   a simulated low-resolution ToF sensor (our model) from ground truth
- ``sensor``     ground truth seen by simulated real depth cameras beside the color camera (``sensor``)
- ``holes``      leave-out hole filling on real captures (real hole shapes hidden on valid depth)
- ``synthetic``  generated scenes with known ground truth, for tests
- ``protocols``  the protocol registry: datasets, case builders, tuning scenes, published rows
- ``runner``     runs methods x cases and scores them
- ``report``     tables and the HTML report
- ``figures``    the report's scene figures: error maps on a scale per protocol, details where methods differ
- ``suite``      the benchmark as ``depthrefine bench`` runs it: data folder, cases, case by case, report files
- ``demo``       the scenes of ``depthrefine demo``: the methods on the shipped data, as figures and a record

The files are read by :mod:`depthrefine.io` (the readers each protocol names).
"""

from .._lazy import lazy_exports

#: The public names by module, each imported on first use (PEP 562), so that ``depthrefine bench
#: --help`` reads the protocols without importing the runner, the metrics and numpy (fast start-up).
_EXPORTS = {
    ".protocols": ("Protocol", "PROTOCOLS", "register_protocol", "get_protocol", "load_cases", "TUNING_SCENES",
                   "LEFT_OUT_WHY", "left_out_reason", "tuned_on_scenes", "LU_BORDER", "bicubic_downsample",
                   "crop_to_multiple", "park_case", "lu_case", "tof_case", "tof_seed"),
    ".runner": ("DEFAULT_SCALES", "METRICS", "ROW_FIELDS", "BenchCase", "BenchResult", "BenchRow", "mean_and_count",
                "mean_or_nan", "parse_scales", "run_benchmark"),
}
__all__ = [name for names in _EXPORTS.values() for name in names]

__getattr__, __dir__ = lazy_exports(__name__, _EXPORTS, (
    "metrics", "simulate", "sensor", "holes", "synthetic", "protocols", "runner", "report", "figures", "suite",
    "demo"))
