"""Two cameras to one pixel grid (thesis chapter 3): models, calibration, undistortion, alignment.

- ``camera``      :class:`CameraModel` (pinhole + distortion) and :class:`StereoRig` (depth -> color)
- ``boards``      calibration boards (checkerboard, ChArUco): corner coordinates, detection, pictures
- ``calibrate``   single-camera and stereo calibration from board views
- ``coverage``    where a calibration's corners fell in the image, and their residuals
- ``formats``     calibrations of other tools: Azure Kinect factory (K4A), OpenCV YAML, ROS camera_info
                  and /tf_static, RealSense recordings
- ``undistort``   undistortion of depth maps and color images (spec step 1)
- ``shift``       the thesis's horizontal shift alignment (spec step 3)
- ``reproject``   calibrated reprojection of depth into the color camera
- ``pointcloud``  metric depth, back-projection, projection, colored point clouds
- ``chain``       the settings-driven chain: undistort + align a raw depth + color pair; unmeasured pixels
- ``edges``       does a depth map line up with its color image? (silhouette vs color edges)

Everything here is pure (arrays in, arrays out); files are read by :mod:`depthrefine.io`.
"""

from .._lazy import lazy_exports

#: The public names by module, each imported on first use (PEP 562), so that the command line can
#: read :mod:`._names` without importing the rig's modules (fast start-up).
_EXPORTS = {
    ".camera": ("CameraModel", "StereoRig", "check_camera_shape"),
    ".boards": ("BOARD_KINDS", "DICTIONARIES", "MIN_VIEW_CORNERS", "Board", "BoardView", "board_points", "to_gray8",
                "find_board_corners", "detect_board", "render_board"),
    ".calibrate": ("MIN_VIEWS", "LENS_MODELS", "RECOMMENDED_VIEWS", "CalibrationFit", "StereoFit", "lens_model",
                   "fit_camera", "fit_stereo", "calibrate_from_views", "calibrate_from_corners", "calibrate_camera",
                   "calibrate_stereo_from_views", "calibrate_stereo_from_corners", "calibrate_stereo"),
    ".formats": ("K4A_DEPTH_MODES", "K4A_COLOR_RESOLUTIONS", "rig_from_k4a", "camera_from_opencv", "camera_from_ros",
                 "camera_from_realsense", "rig_from_poses", "rig_from_ros", "rotation_from_quaternion",
                 "transform_between_frames"),
    ".undistort": ("undistort_maps", "distort_maps", "undistort_depth", "undistort_image", "distort_depth",
                   "distort_image"),
    ".shift": ("COLOR_SIDES", "ENCODINGS", "MAX_PARALLEL_ROTATION", "MAX_SHIFT_MISREGISTRATION",
               "AlignmentWarning", "background_depth", "align_shift", "ShiftModel", "shift_from_rig",
               "shift_misregistration"),
    ".reproject": ("reproject_camera", "default_factor", "align_reproject"),
    ".pointcloud": ("PLAUSIBLE_DEPTH_M", "median_metres", "implausible_units", "depth_to_metres", "metres_to_depth",
                    "pixel_rays", "backproject", "project_points", "depth_to_points", "color_grid_points"),
    ".coverage": ("COVERAGE_CELLS", "coverage_grid", "uncovered_share", "coverage_figure"),
    ".chain": ("ALIGN_METHODS", "AlignSettings", "AlignedPair", "align_depth", "align_pair", "upsampling_grid",
               "refine_pair", "nearest_on_grid", "keep_unmeasured", "unmeasured_along_color"),
}
__all__ = [name for names in _EXPORTS.values() for name in names]

__getattr__, __dir__ = lazy_exports(__name__, _EXPORTS, (
    "camera", "boards", "calibrate", "formats", "undistort", "shift", "reproject", "pointcloud", "chain", "edges",
    "coverage"))
