"""Reading and writing files: the only part of the library (with ``cli``) that touches disk.

See :mod:`depthrefine.io._images` for the representation rules (0 = no
measurement; the output keeps the input's dtype; color is RGB).
"""

from .._lazy import lazy_exports

#: The public names by module, each imported on first use (PEP 562), so that the command line can
#: read :mod:`._names` without importing the readers (fast start-up).
_EXPORTS = {
    "._files": ("InputFileError", "atomic_directory", "atomic_write", "check_distinct_inputs", "check_output",
                "check_output_dir"),
    "._images": ("DEPTH_SUFFIXES", "check_depth_format", "depth_to_dtype", "encode_depth", "encode_rgb", "image_shape",
                 "output_values", "read_depth", "read_rgb", "scale_to_dtype", "write_bytes", "write_depth",
                 "write_figure", "write_rgb"),
    "._params": ("read_mapping", "read_patch_layout"),
    "._confidence": ("CONFIDENCE_SUFFIXES", "check_confidence_format", "encode_confidence", "read_confidence",
                     "write_confidence"),
    "._intermediates": ("write_intermediates",),
    "._camera": ("ChainSettings", "read_camera", "read_chain_settings", "read_depth_units", "read_rig", "write_camera",
                 "write_chain_settings", "write_rig"),
    "._board": ("PAPER_SIZES_MM", "write_board_pdf", "write_board_png"),
    "._calibration": ("read_calibration",),
    "._ply": ("encode_ply", "read_ply", "write_ply"),
    "._sample": ("SAMPLE_SCALES", "SCENES", "RealCapture", "SampleScene", "load_capture", "load_sample",
                 "sample_folder"),
    "._sequences": ("Frame", "Sequence", "open_sequence"),
    "._catalog": ("DATASETS", "DataSource", "Dataset", "get_dataset"),
    "._fetch": ("DataProblem", "fetch_dataset", "file_sha256", "find_datasets", "verify_data", "verify_dataset"),
    "._video": ("VIDEO_SUFFIXES", "VideoWriter"),
    "._datasets": ("DATASET_READERS", "REAL_TOF_CAPTURES", "TRIPLET_FOLDERS", "DatasetScene", "dataset_folder",
                   "read_dataset", "read_real_tof", "read_rgbd_pairs", "read_scene_folders", "read_triplets"),
}
__all__ = [name for names in _EXPORTS.values() for name in names]

__getattr__, __dir__ = lazy_exports(__name__, _EXPORTS)
