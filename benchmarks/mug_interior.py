"""How much of the Azure Kinect mug's silhouette holds depth after ``run``, with and without ``--fill-holes``.

The shipped mug capture (``depthrefine.io.load_capture("mug")``) goes through
the chain as ``depthrefine run --depth-units 0.001`` does (factory rig,
NFOV_UNBINNED, 720P; ``rig.chain.align_pair``, ``refine_pair``,
``keep_unmeasured``). The mug's silhouette on the undistorted 1280x720 color
image is :data:`MUG_BODY` (a polygon) and :data:`MUG_HANDLE` (a polyline
drawn :data:`HANDLE_WIDTH` px wide along the handle), traced by hand on that
image and shrunk by :data:`MARGIN` px, so that it lies inside the mug: the
wall seen through the handle and the strip beside the mug that the depth
camera cannot see are not in it (a silhouette made by filling the holes of
the near depth counts them as the mug's inside). Printed per map: the share
of the silhouette's pixels that hold depth, the share that hold the mug's
depth (nearer than :data:`MUG_FAR_MM`), and the median depth there.
With ``--figure FILE`` it writes the color image with the silhouette's
pixels without depth in red, for the last method given, holes filled::

    python benchmarks/mug_interior.py [--methods gbp,bicubic] [--figure mug_interior.png]
"""

from __future__ import annotations

import argparse

import numpy as np

#: The mug's body on the undistorted 1280x720 color image, (x, y) pixels, traced by hand.
MUG_BODY = ((310, 385), (360, 378), (410, 378), (460, 387), (493, 397), (508, 407), (505, 427), (501, 460),
            (498, 493), (495, 527), (490, 560), (485, 593), (480, 627), (473, 642), (427, 650), (370, 648),
            (320, 642), (283, 630), (278, 610), (280, 577), (285, 543), (292, 510), (298, 477), (303, 443),
            (308, 410))
#: The handle's middle line, from its top attachment to its bottom one, (x, y) pixels.
MUG_HANDLE = ((502, 440), (527, 435), (550, 437), (568, 447), (578, 463), (578, 483), (570, 503), (557, 523),
              (540, 542), (523, 560), (510, 573), (498, 587), (493, 593))
#: Width of the band drawn along the handle's middle line, px (the handle is 8-12 px wide).
HANDLE_WIDTH = 6
#: The traced silhouette is shrunk by this many pixels (the tracing is good to about 2 px).
MARGIN = 2
#: Depth on the mug: nearer than this, mm (the mug at 245-300 mm, the wall behind it beyond 600 mm).
MUG_FAR_MM = 400.0


def silhouette(shape: tuple[int, int]) -> np.ndarray:
    """The mug's silhouette on a color image of ``shape`` = (720, 1280), bool."""
    import cv2

    mask = np.zeros(shape, np.uint8)
    cv2.fillPoly(mask, [np.array(MUG_BODY, np.int32)], 1)
    body = cv2.erode(mask, np.ones((2 * MARGIN + 1,) * 2, np.uint8))
    handle = np.zeros(shape, np.uint8)
    cv2.polylines(handle, [np.array(MUG_HANDLE, np.int32)], False, 1, thickness=HANDLE_WIDTH)
    return (body | handle) > 0


def main() -> None:
    from depthrefine.io import load_capture, read_calibration, sample_folder
    from depthrefine.rig.chain import AlignSettings, align_pair, keep_unmeasured, nearest_on_grid, refine_pair

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--methods", default="gbp,bicubic")
    parser.add_argument("--figure", metavar="FILE", help="write the silhouette's pixels without depth in red")
    args = parser.parse_args()
    capture = load_capture("mug")
    rig, _ = read_calibration(sample_folder("mug") / "calibration.json", depth_mode="NFOV_UNBINNED",
                              color_resolution="720P")
    pair = align_pair(capture.depth, capture.rgb, rig, settings=AlignSettings(depth_units=0.001))
    inside = silhouette(pair.rgb_hr.shape[:2])
    print(f"the mug's silhouette: {int(inside.sum())} color pixels (body and handle, {MARGIN} px inside the tracing)")

    def report(label: str, depth: np.ndarray) -> np.ndarray:
        measured = np.isfinite(depth) & (depth > 0)
        with np.errstate(invalid="ignore"):
            on_mug = measured & (depth < MUG_FAR_MM)
        print(f"  {label:<34} {100 * measured[inside].mean():5.1f} % with depth, {100 * on_mug[inside].mean():5.1f} % "
              f"nearer than {MUG_FAR_MM:.0f} mm, median {np.median(depth[inside & measured]):.0f} mm")
        return inside & ~measured

    report("aligned (nearest on the color grid)", nearest_on_grid(pair.depth_lr, pair.rgb_hr.shape[:2]))
    missing = None
    for method in args.methods.split(","):
        dense = refine_pair(pair.depth_lr, pair.rgb_hr, method=method)[0]
        report(f"{method}, holes kept (run)", keep_unmeasured(dense, pair.depth_lr, rgb_hr=pair.rgb_hr))
        missing = report(f"{method}, --fill-holes", keep_unmeasured(dense, pair.depth_lr, fill_enclosed=True,
                                                                    rgb_hr=pair.rgb_hr))
    if args.figure and missing is not None:
        import cv2

        picture = (pair.rgb_hr // 2).copy()
        picture[inside] = pair.rgb_hr[inside]
        picture[missing] = (255, 0, 0)
        cv2.imwrite(args.figure, cv2.cvtColor(picture[340:680, 240:640], cv2.COLOR_RGB2BGR))
        print(f"wrote {args.figure}")


if __name__ == "__main__":
    main()
