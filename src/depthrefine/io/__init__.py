"""Reading and writing files: the only part of the library (with ``cli``) that touches disk.

See :mod:`depthrefine.io._images` for the representation rules (0 = no
measurement; the output keeps the input's dtype; color is RGB).
"""

from ._files import InputFileError, atomic_directory, atomic_write, check_output, check_output_dir
from ._images import (DEPTH_SUFFIXES, check_depth_format, depth_to_dtype, image_shape, read_depth, read_rgb,
                      scale_to_dtype, write_depth, write_figure, write_rgb)
from ._params import read_mapping, read_patch_layout
from ._camera import (
    ChainSettings, read_camera, read_chain_settings, read_rig, write_camera, write_chain_settings, write_rig,
)
from ._board import PAPER_SIZES_MM, write_board_pdf, write_board_png
from ._calibration import read_calibration
from ._ply import read_ply, write_ply
from ._sample import SAMPLE_SCALES, SCENES, RealCapture, SampleScene, load_capture, load_sample, sample_folder
from ._sequences import Frame, Sequence, open_sequence
from ._datasets import (DATASET_READERS, REAL_TOF_CAPTURES, TRIPLET_FOLDERS, DatasetScene, dataset_folder,
                        read_dataset, read_real_tof, read_rgbd_pairs, read_scene_folders, read_triplets)

__all__ = [
    "Frame",
    "Sequence",
    "open_sequence",
    "InputFileError",
    "atomic_directory",
    "atomic_write",
    "check_output",
    "check_output_dir",
    "image_shape",
    "DEPTH_SUFFIXES",
    "check_depth_format",
    "depth_to_dtype",
    "scale_to_dtype",
    "write_figure",
    "read_depth",
    "read_rgb",
    "write_depth",
    "write_rgb",
    "read_mapping",
    "read_patch_layout",
    "ChainSettings",
    "read_camera",
    "write_camera",
    "read_rig",
    "write_rig",
    "read_chain_settings",
    "write_chain_settings",
    "read_calibration",
    "PAPER_SIZES_MM",
    "write_board_png",
    "write_board_pdf",
    "read_ply",
    "write_ply",
    "SAMPLE_SCALES",
    "SampleScene",
    "load_sample",
    "sample_folder",
    "SCENES",
    "RealCapture",
    "load_capture",
    "DATASET_READERS",
    "DatasetScene",
    "REAL_TOF_CAPTURES",
    "read_real_tof",
    "dataset_folder",
    "read_dataset",
    "read_scene_folders",
    "read_rgbd_pairs",
    "read_triplets",
    "TRIPLET_FOLDERS",
]
